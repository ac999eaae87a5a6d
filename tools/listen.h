// `quantum listen MATCH.wav EVENTS.jsonl`: would a listener understand the announcer? Every phrase
// the event log says was played (spoken in full or cut off) is cut out of the match's sound and
// run through a speech recognizer (pocketsphinx, US English) whose grammar is every phrase the
// match said; a phrase counts as heard when the recognizer picks exactly its words.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace quantum::tools {

struct Heard {
  double t = 0;             // when it was said
  double start = 0, end = 0;  // when it sounded
  std::string text;         // as said
  std::string words;        // as the recognizer spells them ("goal for red")
  std::string recognised;   // what it picked ("" for nothing)
  std::string fate;         // spoken or cut
  std::string event;        // the type of the event that said it ("goal", "timer", ...)
  // Its words, whole, among what was recognised.
  bool heard() const;
};

struct Listening {
  std::vector<Heard> played;            // in order
  int said = 0;                         // every phrase in the log, played or not
  std::vector<std::string> unknown_words;  // words the dictionary lacks (heard as espeak-ng says them)
  int heard() const;
  // Phrases of goals (goal and own_goal events' phrases): all played, and how many heard.
  int goal_calls = 0, goal_calls_heard = 0;
};

// Throws std::runtime_error naming the file for a WAV or log it cannot read, a WAV whose length
// is not the logged match's (it must end at most 0.25 s before the log's last event or phrase,
// and, when the log has the match's end, at most 1.5 s after it), and when the recognizer or its
// model is missing (Debian: pocketsphinx, pocketsphinx-en-us).
Listening listen(const std::string& wav, const std::string& events);

// One line per played phrase ("heard" or "MISSED", with what was recognised), then totals.
void report(const Listening& l, std::ostream& out);

}  // namespace quantum::tools

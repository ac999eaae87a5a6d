// `quantum play` and `quantum balance`: matches of a sport (rules/<sport>) run through a
// runtime::Session, told as a transcript and JSON-lines events, with a closing summary.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <exception>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "game/game.h"
#include "session.h"

namespace quantum::tools {

// What a sport's figures count, from its field: a sport of striking (air hockey) its contacts per
// rally, one of hitting (volleyball) its touches per rally, one of holding (handball, soccer) its
// passes per possession; goals per minute where the field has goals, and points per minute where
// its score is not its goals.
struct Counted {
  enum class Play : uint8_t { Strikes, Hits, Holds } play = Play::Strikes;
  bool goals = true;
};
Counted counted(const Field& field);

// A match's or a study's totals, as counted.
struct Figures {
  int rallies = 0, contacts = 0, goals = 0, passes = 0, possessions = 0, points = 0;
  double seconds = 0;
  Figures& operator+=(const Figures& o);
};
// "contacts per rally 4.72, goals per minute 10.07": what `counted` says the sport counts. Points
// per minute ("the sport's score") only where they are not the goals.
std::string describe(const Counted& counted, const Figures& figures);

struct PlayResult {
  std::map<std::string, int> score;
  std::string winner;  // "" for a draw
  game::RallyStats stats;
  int rule_errors = 0;
  bool finished = true;  // false when the match stopped before its end (a recording over, --until, a signal)
  Counted counted;
  int interrupted = 0;  // the signal that ended it early (SIGINT, SIGTERM), or 0
  // The first output that could not be written whole, thrown by play() once the transcript has
  // its final lines: a failing file never costs the transcript its score.
  std::exception_ptr unwritten;
  std::vector<runtime::Written> written;  // the files written whole, for their confirmation lines
  Figures figures() const;
};

// A match's result as its session ended it.
PlayResult result_of(const runtime::Session& session);
// Completes the session's files (Session::finish) and takes its result into `result`; a file that
// could not be written whole goes to result.unwritten (the first one) instead of being thrown.
void finish_and_keep(runtime::Session& session, PlayResult& result);

struct DeskOptions;

// What `quantum play` and `replay` tell on the error stream besides warnings (progress.h): a
// progress line while a match plays faster than the clock, and a line for every file written.
struct Telling {
  bool terminal = false;  // the error stream is a terminal: the progress line is drawn in place
  // The transcript is shown on that terminal, where its lines say how far the match is: no
  // progress line between them.
  bool transcript_there = false;
};

// The progress line of a match that plays faster than the clock ("video match.mp4: 2.5 of 6.0
// s"), told to `errors`; none for a match in real time (someone watches, listens or plays) or
// when `telling` is null.
std::unique_ptr<runtime::ProgressLine> match_progress(const runtime::Session& session, const Telling* telling,
                                                      std::ostream& errors, const std::string& what);

// Plays one match, at the desk when `desk` asks for a view, a video, a snapshot or the mouse
// (desk.h). The transcript and the closing summary go to `out` (none when `transcript` is
// false), rule errors and warnings to `errors`, and with `telling` the progress and a line for
// each file written after the summary. Throws on bad options, a sport that does not load or a
// bad field.
PlayResult play(const runtime::SessionOptions& options, std::ostream& out, std::ostream& errors, bool transcript = true,
                const DeskOptions* desk = nullptr, const Telling* telling = nullptr);

// "realtime" or "fast", as --pace says it.
runtime::SessionOptions::Pacing pacing(const std::string& pace);

// "0.3,0.9" -> {0.3, 0.9}; throws naming the option for anything else.
std::vector<double> parse_list(const std::string& text, const std::string& option);
// --skill: parse_list's, each in [0, 1]; throws std::invalid_argument naming the option.
std::vector<double> parse_skills(const std::string& text);

// --field-size "L,W" in metres (nothing for ""); throws for anything but two sizes > 0.
std::optional<Vec2> parse_field_size(const std::string& text);

}  // namespace quantum::tools

// What the desk's view plays: a match (live, or a recording's replay) that a person can seek in.
// A replay goes anywhere in its recording; a live match can be looked back at up to where it
// has got, from a recording the live session keeps as it plays (the one --record asks for, or
// a folder of the desk's own), and goes on where it was when the look back ends. Seeking is exact:
// forward plays the frames at once, back replays the recording from its start (a replay's
// frames and reloads are all it needs; a Lua state cannot be rewound). docs/desk.md.
#pragma once

#include <functional>
#include <iosfwd>
#include <memory>
#include <string>

#include "recording.h"
#include "session.h"

namespace quantum::tools {

class Playback {
 public:
  using Players = std::function<std::unique_ptr<runtime::PlayerSource>()>;
  // Opens the match of `options` (a replay when options.replay is set), with the players
  // `players` makes (null: those the options name), the transcript to `transcript` (null: none)
  // and errors to `errors`. `look_back`: a live match keeps a recording to look back at.
  Playback(runtime::SessionOptions options, std::ostream* transcript, std::ostream& errors, Players players = nullptr,
           bool look_back = true);
  ~Playback();

  // The match as it goes on (a replay: the replay), and what is shown: the look back, if any.
  runtime::Session& live() { return *live_; }
  runtime::Session& shown() { return past_ ? *past_ : *live_; }
  bool looking_back() const { return past_ != nullptr; }
  bool replay() const { return !options_.replay.empty(); }
  // The match's length, and how far it may be seen (a replay: all of it; a live match: as far
  // as it has got), in s.
  double length() const;
  double played() const;

  // One frame of what is shown. A look back that reaches the live match gives way to it. Returns
  // false once the match is over (a live match, or a replay, at its end).
  bool frame();
  // Shows match time `t` (within what has been played): forward by playing frames at once, back
  // by replaying from the start; a live match's look back ends at the live match. Writes nothing
  // twice: a replay that goes back starts its outputs (--events, ...) again.
  void seek(double t);
  // The match again from its start, as a new session (a replay too: going back is this).
  void restart();
  void set_speed(double speed);

 private:
  std::unique_ptr<runtime::Session> open_live();
  bool at_live(double t) const;  // match time t is the live match's moment

  runtime::SessionOptions options_;
  std::ostream* transcript_;
  std::ostream& errors_;
  Players players_;
  runtime::WorkFolder own_recording_;  // a live match's recording when --record named none
  std::unique_ptr<runtime::Session> live_, past_;
  double speed_ = 1;
};

}  // namespace quantum::tools

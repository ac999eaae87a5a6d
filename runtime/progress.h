// How far long work is (a video, a match played faster than the clock, a balance study), told
// on standard error, as the files it wrote are (output_files.h, say_written): standard output
// keeps what other tools read (the transcript, a summary, JSON lines), and --quiet takes the
// transcript away and leaves these (docs/desk.md, "Progress and outputs").
#pragma once

#include <functional>
#include <iosfwd>
#include <string>

namespace quantum::runtime {

// The steady clock, in seconds: what progress and pacing measure with.
double clock_seconds();

// One line that says how far a piece of work is and how long it has left: "video match.mp4: 2.5
// of 6.0 s (42 %), 0:12 left". On a terminal it is drawn again in place (\r) at most four times
// a second; elsewhere (a log, a pipe) a plain line is written each time another tenth of the
// work is done and kQuietFor has passed since the last one, so that work of a few seconds writes
// none and long work about ten.
class ProgressLine {
 public:
  static constexpr double kQuietFor = 5;  // s between two plain lines

  // `what` names the work ("video match.mp4"); `total` is counted in `unit`s ("s", "matches")
  // shown with `decimals` digits. `clock` is clock_seconds but in tests.
  ProgressLine(std::ostream& out, bool terminal, std::string what, double total, std::string unit, int decimals = 0,
               std::function<double()> clock = clock_seconds);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // `done` of the total is done.
  void operator()(double done);
  // Takes a terminal's line away (before other lines are written, and at the end); the next
  // call draws it again.
  void clear();

 private:
  std::string line(double done, double now) const;

  std::ostream& out_;
  bool terminal_;
  std::string what_, unit_;
  double total_;
  int decimals_;
  std::function<double()> clock_;
  double started_, last_drawn_ = -1e9, last_done_ = 0;
  size_t drawn_ = 0;  // the characters on a terminal's line, to clear
};

}  // namespace quantum::runtime

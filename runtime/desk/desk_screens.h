// What the desk's live view draws around and over the match's picture (picture.h): the time
// bar under it, the error screen over it (LÖVE's habit: an error is shown where the person
// looks, not only on a terminal), and the final whistle. The video and the snapshot have none
// of it: they show the match only.
#pragma once

#include <opencv2/core.hpp>

#include <span>
#include <string>

#include "session.h"

namespace quantum::runtime {

// The time bar: the match's length, what has been played of it, where the view is, and where
// the mouse points.
struct TimeBar {
  static constexpr int kHeight = 56;  // pixels: the bar, the times, the keys
  double length = 0;   // s: the match's (a replay's: its recording's)
  double played = 0;   // s: how far the match has got (a live match's view may look back)
  double now = 0;      // s: the moment shown
  double speed = 1;
  double pointed = -1;  // s: under the mouse, or < 0
  std::string note;     // "live", "looking back (the match waits)", ...
  std::string keys;     // the keys of the view, and the mouse's

  // The time at column x of a bar `width` pixels wide, within what has been played.
  double time_at(int x, int width) const;
};
void draw_time_bar(const TimeBar& bar, cv::Mat& strip);

// The problems standing (Session::problems), over the picture: kind, FILE:LINE and message, and
// how to go on.
void draw_problems(std::span<const Session::Problem> problems, cv::Mat& image);

// The end of the match, over its last frame: the final score, and how to close.
void draw_final_whistle(const std::string& score, cv::Mat& image);

// "1:05.20": a match time as the desk writes it.
std::string clock_text(double t);

}  // namespace quantum::runtime

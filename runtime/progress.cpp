#include "progress.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ostream>

namespace quantum::runtime {
namespace {

// "0:12", "1:02:03".
std::string clock_time(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char text[32];
  if (s >= 3600) std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  return text;
}

}  // namespace

double clock_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

ProgressLine::ProgressLine(std::ostream& out, bool terminal, std::string what, double total, std::string unit,
                           int decimals, std::function<double()> clock)
    : out_(out), terminal_(terminal), what_(std::move(what)), unit_(std::move(unit)), total_(total),
      decimals_(decimals), clock_(std::move(clock)), started_(clock_()) {
  // A log's first line comes once there is something to say: kQuietFor after the start.
  if (!terminal_) last_drawn_ = started_;
}

ProgressLine::~ProgressLine() { clear(); }

std::string ProgressLine::line(double done, double now) const {
  char text[256];
  const double share = total_ > 0 ? std::min(1.0, done / total_) : 1;
  std::snprintf(text, sizeof text, "%s: %.*f of %.*f %s (%.0f %%)", what_.c_str(), decimals_, done, decimals_, total_,
                unit_.c_str(), 100 * share);
  std::string said = text;
  // An estimate from the pace so far, once there is a pace to go by.
  const double took = now - started_;
  if (done > 0 && share < 1 && took >= 1) said += ", " + clock_time(took * (total_ - done) / done) + " left";
  return said;
}

void ProgressLine::operator()(double done) {
  const double now = clock_();
  if (terminal_) {
    // Four times a second is all a person reads; the last one always.
    if (now - last_drawn_ < 0.25 && done < total_) return;
    const std::string said = line(done, now);
    out_ << '\r' << said << std::string(drawn_ > said.size() ? drawn_ - said.size() : 0, ' ') << std::flush;
    drawn_ = said.size();
  } else {
    if (done - last_done_ < total_ / 10 || now - last_drawn_ < kQuietFor) return;
    out_ << "quantum: " << line(done, now) << '\n' << std::flush;
    last_done_ = done;
  }
  last_drawn_ = now;
}

void ProgressLine::clear() {
  if (!terminal_ || drawn_ == 0) return;
  out_ << '\r' << std::string(drawn_, ' ') << '\r' << std::flush;
  drawn_ = 0;
  last_drawn_ = -1e9;
}

}  // namespace quantum::runtime

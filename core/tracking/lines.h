// Lines of a file others wrote (a recording's INDEX.txt, an accelerometer's CSV), read through a
// descriptor with a cap on a line's length: a longer line is skipped whole, never held, so a
// gigabyte without a newline costs one buffer, not a gigabyte.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace quantum::tracking {

// The most bytes a line of an input file may have; a longer one is dropped and counted.
constexpr size_t kLongestLine = 4096;
// The most of an input file that is read: past it the rest is left unread, as if the file ended
// there (cut()), so that an endless pipe or a device cannot hold the match before it starts.
// An hour of a 100 Hz accelerometer on four players is 1.4 million lines.
constexpr size_t kMostLines = 5'000'000;
constexpr size_t kMostBytes = size_t(1) << 30;

class BoundedLines {
 public:
  enum class Line { Read, TooLong, End };
  // Takes `fd` (closed with this object); `max`: a line's most bytes, its newline not counted.
  explicit BoundedLines(int fd, size_t max = kLongestLine);
  ~BoundedLines();
  BoundedLines(const BoundedLines&) = delete;
  BoundedLines& operator=(const BoundedLines&) = delete;
  // The next line, without its newline, in `line` (Read); TooLong for one longer than `max`
  // (`line` then empty); End when the file is over (or cannot be read further, or is cut).
  Line next(std::string& line);
  // The file went on past kMostLines lines or kMostBytes bytes: the rest was not read.
  bool cut() const { return cut_; }

 private:
  int fd_;
  size_t max_;
  std::vector<char> buffer_;
  size_t at_ = 0, size_ = 0;
  size_t lines_ = 0, bytes_ = 0;
  bool end_ = false, cut_ = false;
};

}  // namespace quantum::tracking

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

class BoundedLines {
 public:
  enum class Line { Read, TooLong, End };
  // Takes `fd` (closed with this object); `max`: a line's most bytes, its newline not counted.
  explicit BoundedLines(int fd, size_t max = kLongestLine);
  ~BoundedLines();
  BoundedLines(const BoundedLines&) = delete;
  BoundedLines& operator=(const BoundedLines&) = delete;
  // The next line, without its newline, in `line` (Read); TooLong for one longer than `max`
  // (`line` then empty); End when the file is over (or cannot be read further).
  Line next(std::string& line);

 private:
  int fd_;
  size_t max_;
  std::vector<char> buffer_;
  size_t at_ = 0, size_ = 0;
  bool end_ = false;
};

}  // namespace quantum::tracking

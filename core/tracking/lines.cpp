#include "tracking/lines.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace quantum::tracking {

BoundedLines::BoundedLines(int fd, size_t max) : fd_(fd), max_(max), buffer_(64 * 1024) {}

BoundedLines::~BoundedLines() {
  if (fd_ >= 0) ::close(fd_);
}

BoundedLines::Line BoundedLines::next(std::string& line) {
  line.clear();
  if (lines_ == kMostLines) {
    if (at_ < size_ || !end_) cut_ = true;
    end_ = true, at_ = size_;
    return Line::End;
  }
  ++lines_;
  bool any = false, too_long = false;
  for (;;) {
    if (at_ == size_) {
      if (bytes_ >= kMostBytes) cut_ = end_ = true;
      ssize_t n = -1;
      while (!end_ && (n = ::read(fd_, buffer_.data(), buffer_.size())) < 0 && errno == EINTR) {
      }
      if (n > 0) bytes_ += size_t(n);
      if (end_ || n <= 0) {
        end_ = true;
        if (!any) return Line::End;
        return too_long || cut_ ? Line::TooLong : Line::Read;  // a line the cut went through is not whole
      }
      at_ = 0, size_ = size_t(n);
    }
    any = true;
    const char* from = buffer_.data() + at_;
    const char* newline = static_cast<const char*>(std::memchr(from, '\n', size_ - at_));
    const size_t n = newline ? size_t(newline - from) : size_ - at_;
    if (!too_long && line.size() + n > max_) too_long = true, line.clear(), line.shrink_to_fit();
    if (!too_long) line.append(from, n);
    at_ += n;
    if (newline) {
      ++at_;
      return too_long ? Line::TooLong : Line::Read;
    }
  }
}

}  // namespace quantum::tracking

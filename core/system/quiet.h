// Silencing libraries that print their own diagnostics (OpenAL Soft, ALSA, libfreenect, OpenCV's
// camera backends) where the engine's output goes: stdout carries JSON lines, stderr one line per
// problem, said by the caller.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <initializer_list>
#include <vector>

namespace quantum::system {

// While it lives, the given descriptors (1 stdout, 2 stderr) write to /dev/null.
class Quiet {
 public:
  explicit Quiet(std::initializer_list<int> fds) {
    std::fflush(stdout), std::fflush(stderr);
    const int null = open("/dev/null", O_WRONLY);
    if (null < 0) return;
    for (int fd : fds) {
      const int saved = dup(fd);
      if (saved >= 0 && dup2(null, fd) >= 0) saved_.push_back({fd, saved});
      else if (saved >= 0) close(saved);
    }
    close(null);
  }
  ~Quiet() {
    std::fflush(stdout), std::fflush(stderr);
    for (auto [fd, saved] : saved_) dup2(saved, fd), close(saved);
  }
  Quiet(const Quiet&) = delete;
  Quiet& operator=(const Quiet&) = delete;

 private:
  struct Saved {
    int fd, saved;
  };
  std::vector<Saved> saved_;
};

}  // namespace quantum::system

// The fakenect reader on any recording: frames come out with finite times that never go back, or
// the recording is refused with a RecordingError; never a crash or another exception.
//
// An input is a recording packed in one buffer: INDEX.txt up to the first blank line, then the
// files INDEX.txt names, in its order, separated by lines of "--". A name with a slash stays
// unwritten (the reader then finds it missing).
#include <cmath>
#include <string_view>

#include "fuzz_support.h"
#include "tracking/fakenect.h"

namespace fs = std::filesystem;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const fs::path dir = quantum::fuzz::scratch() / "recording";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const size_t blank = input.find("\n\n");
  const std::string_view index = input.substr(0, blank);
  quantum::fuzz::write_file(dir / "INDEX.txt", data, index.size());
  std::string_view files = blank == std::string_view::npos ? std::string_view{} : input.substr(blank + 2);
  for (size_t line = 0; line < index.size() && !files.empty();) {
    const size_t end = std::min(index.find('\n', line), index.size());
    const std::string name(index.substr(line, end - line));
    line = end + 1;
    const size_t next = files.find("\n--\n");
    const std::string_view body = files.substr(0, next);
    files = next == std::string_view::npos ? std::string_view{} : files.substr(next + 4);
    if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..") continue;
    quantum::fuzz::write_file(dir / name, reinterpret_cast<const uint8_t*>(body.data()), body.size());
  }
  try {
    quantum::tracking::FakenectReader reader(dir.string());
    quantum::tracking::RecordedFrame frame;
    double last = 0;
    while (reader.next(frame)) {
      if (!std::isfinite(frame.t) || frame.t < last) __builtin_trap();  // a frame the match cannot place
      last = frame.t;
    }
  } catch (const quantum::tracking::RecordingError&) {
  }
  return 0;
}

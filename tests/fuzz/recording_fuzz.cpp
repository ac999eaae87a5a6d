// A recording's recording.json, any bytes, opened as `quantum replay` opens it, in a recording
// of a small sport: the replay opens with its sport inside its own copy of the recording, or is
// refused with a std::runtime_error; never a crash, a hang or another exception, and its copy is
// gone either way. The files it names at their original places are read no further than their
// copies go (a few bytes here), whatever they are.
#include "fuzz_support.h"
#include "recording.h"

namespace fs = std::filesystem;

namespace {

// The recording's files but recording.json: a sport "small" (its sport.lua and field.lua), one
// script of the engine's, and frames.bin with no frame.
const fs::path& recording() {
  static const fs::path dir = [] {
    const fs::path d = quantum::fuzz::scratch() / "recording";
    fs::create_directories(d / "sport" / "small");
    fs::create_directories(d / "engine" / "lib");
    std::ofstream(d / "sport" / "small" / "sport.lua") << "return { name = 'Small' }\n";
    std::ofstream(d / "sport" / "small" / "field.lua") << "return { name = 'Small field' }\n";
    std::ofstream(d / "engine" / "lib" / "helper.lua") << "return {}\n";
    std::ofstream(d / "frames.bin") << "QGFRAMES3\n";
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fs::path& dir = recording();
  quantum::fuzz::write_file(dir / "recording.json", data, size);
  fs::path work;
  try {
    const quantum::runtime::Replay replay = quantum::runtime::open_replay(dir);
    work = replay.work.path();
    const fs::path inside = replay.sport.lexically_relative(work);
    if (inside.empty() || *inside.begin() != "sport" || !fs::is_directory(replay.sport)) __builtin_trap();
  } catch (const std::runtime_error&) {
  }
  if (!work.empty() && fs::exists(work)) __builtin_trap();  // the replay's copy outlived it
  return 0;
}

// A recording's frames.bin, any bytes, replayed over handball's field (it has throws) as
// `quantum replay` reads it: what reaches the match is what the match accepts (every body within
// the field's bounds and speed, every throw one it can make), or the frames are refused with a
// std::runtime_error when they open; never a crash or another exception. The replay ends, as
// every frame takes bytes.
#include <sstream>

#include "fuzz_support.h"
#include "field_loader.h"
#include "recording.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace quantum;
  static const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/rules/handball");
  static fuzz::NoRules rules;
  static game::Match match(field, game::MatchConfig{}, rules);
  const std::filesystem::path dir = fuzz::scratch() / "recording";
  std::filesystem::create_directories(dir);
  fuzz::write_file(dir / "frames.bin", data, size);
  std::ostringstream warnings;
  try {
    runtime::RecordedPlayers players(dir, runtime::WorkFolder(), field, &warnings);
    double t = 0;
    while (players.advance(t += 1.0 / 60, match, false) != runtime::PlayerSource::Status::Ended) {
      for (const BodyInput& b : players.bodies())
        if (body_fault(field, b) != BodyFault::None) __builtin_trap();
      for (const game::Throw& th : players.throws())
        if (!throw_fault({th.velocity.x, th.velocity.y, th.up}, field.has_height()).empty()) __builtin_trap();
    }
    players.finish(t);
  } catch (const std::runtime_error&) {
  }
  return 0;
}

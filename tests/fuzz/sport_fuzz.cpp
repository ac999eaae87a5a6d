// Sport loading on any sport.lua beside air hockey's field: it loads, or refuses with the errors
// lua::ScriptedRules documents; it never crashes, hangs or lets another exception out. A sport that loads
// plays a second of a match, so its handlers run too.
#include <filesystem>

#include "fuzz_support.h"
#include "scripted_rules.h"

namespace fs = std::filesystem;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fs::path dir = quantum::fuzz::scratch() / "sport";
  if (!fs::exists(dir / "field.lua")) {
    fs::create_directories(dir);
    fs::copy_file(QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua", dir / "field.lua");
  }
  quantum::fuzz::write_file(dir / "sport.lua", data, size);
  try {
    // Loaded as a reload would be, within a frame's budget: an input that loops while loading
    // costs the fuzzer a frame's budget (80 ms under the address sanitizer), not a second.
    quantum::lua::ScriptedRules sport(dir.string(), quantum::lua::engine_rules_folder(), {}, quantum::lua::Limits{});
    quantum::game::MatchConfig config;
    config.particles = 50;
    config.seconds = 1;
    quantum::game::Match match(sport.spec().field, config, sport, sport.spec().handicaps);
    std::vector<quantum::BodyInput> still;
    for (const quantum::BodySpec& b : sport.spec().field.bodies) still.push_back({b.start, {0, 0}});
    while (!match.finished()) {
      match.step(still);
      match.clear_news();
    }
  } catch (const quantum::lua::ScriptError&) {
  } catch (const quantum::FieldError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

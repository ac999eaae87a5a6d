// Hostile rule scripts: each thing a designer's script must not do is refused with a clear error,
// and the match goes on. Scripts run in the sandbox (bindings/lua_sandbox.h): no io, os but its
// clock, debug, ffi, jit, native modules or bytecode; 10 million instructions per callback; 64 MiB.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

// Air hockey whose drop handler runs `body` first.
std::string hostile_sport(const std::string& name, const std::string& body) {
  const fs::path dir = fs::temp_directory_path() / ("quantum_hostile_" + name);
  fs::create_directories(dir);
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua", dir / "field.lua", fs::copy_options::overwrite_existing);
  fs::create_directories(dir / "powerups");  // the sport's own power-ups come first
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/powerups/attract.lua", dir / "powerups" / "attract.lua",
                fs::copy_options::overwrite_existing);
  std::ifstream in(QUANTUM_SOURCE_DIR "/rules/airhockey/sport.lua");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  s.replace(s.rfind("return sport"), 12,
            "local drop = sport.on.drop\nsport.on.drop = function(game, e)\n  " + body + "\n  drop(game, e)\nend\nreturn sport");
  std::ofstream(dir / "sport.lua") << s;
  return dir.string();
}

// A match of the sport at 200 particles, its players standing where they start.
struct Played {
  explicit Played(lua::Sport& sport) : match(sport.field(), config(), sport) {
    for (const BodySpec& b : sport.field().bodies) still.push_back({b.start, {0, 0}});
  }
  static game::MatchConfig config() {
    game::MatchConfig c;
    c.particles = 200;
    return c;
  }
  void step() { match.step(still); }
  game::Match match;
  std::vector<BodyInput> still;
};

struct Case {
  const char* name;
  const char* body;
  const char* error;  // what the reported error must say
};

TEST(Hostile, EveryForbiddenThingIsRefusedAndTheMatchGoesOn) {
  const Case cases[] = {
      {"io", "io.open('/etc/passwd')", "global 'io'"},
      {"os_execute", "os.execute('true')", "field 'execute'"},
      {"os_exit", "os.exit(1)", "field 'exit'"},
      {"debug", "debug.sethook()", "global 'debug'"},
      {"ffi", "require('ffi')", "no module 'ffi': the sandbox loads only"},
      {"jit", "jit.on()", "global 'jit'"},
      {"native", "package.loadlib('libc.so.6', 'system')", "global 'package'"},
      {"bytecode", "load(string.dump(function() end))()", "global 'load'"},
      {"loadstring", "loadstring('return 1')()", "global 'loadstring'"},
      {"dofile", "dofile('/etc/passwd')", "global 'dofile'"},
      {"gc", "collectgarbage('stop')", "global 'collectgarbage'"},
      {"endless", "while true do end", "script runs too long"},
      {"endless_after_grant", "game.grant('Red\\'s mallet', 'attract') while true do end", "script runs too long"},
      {"recursion", "local function f() return 1 + f() end f()", "stack overflow"},
      {"string_bomb", "local s = string.rep('x', 2^30)", "not enough memory"},
      {"table_bomb", "local t = {} while true do t[#t + 1] = string.rep('y', 2^20) .. #t end", "not enough memory"},
  };
  for (const Case& c : cases) {
    lua::Sport sport(hostile_sport(c.name, c.body));
    Played played(sport);
    game::Match& match = played.match;
    for (int frame = 0; frame < 30; ++frame) played.step();
    const std::span<const std::string> errors = match.errors();
    ASSERT_EQ(errors.size(), 1u) << c.name;
    EXPECT_NE(errors[0].find(c.error), std::string::npos) << c.name << ": " << errors[0];
    EXPECT_NE(errors[0].find("(on.drop skipped)"), std::string::npos) << errors[0];
    EXPECT_NEAR(match.time(), 0.5, 1e-6) << c.name << ": the match went on";
    EXPECT_TRUE(match.world().live()) << c.name;
  }
}

TEST(Hostile, OsClockIsThere) {
  lua::Sport sport(hostile_sport("clock", "assert(type(os.clock()) == 'number')"));
  Played played(sport);
  played.step();
  EXPECT_TRUE(played.match.errors().empty());
}

// A power-up's factor that loops forever: its factor is skipped each frame, reported, and the
// match goes on.
TEST(Hostile, AnEndlessPowerUpIsSkipped) {
  const fs::path root = fs::temp_directory_path() / "quantum_hostile_powerup";
  fs::remove_all(root);
  fs::create_directories(root / "powerups");
  fs::copy(QUANTUM_SOURCE_DIR "/rules/airhockey", root / "airhockey", fs::copy_options::recursive);
  std::ofstream(root / "powerups" / "spin.lua") << "return { duration = 5, factor = function() while true do end end }\n";
  lua::Sport sport((root / "airhockey").string());
  Played played(sport);
  game::Match& match = played.match;
  played.step();
  sport.grant(match, 0, "spin", {});
  for (int frame = 0; frame < 3; ++frame) played.step();
  const std::span<const std::string> errors = match.errors();
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors[0].find("script runs too long"), std::string::npos) << errors[0];
  EXPECT_NE(errors[0].find("power-up spin skipped"), std::string::npos) << errors[0];
  EXPECT_NEAR(match.time(), 4 / 60.0, 1e-6);
  fs::remove_all(root);
}

}  // namespace
}  // namespace quantum

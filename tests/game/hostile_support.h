// What the hostile-script tests share: a sport built from air hockey with a hostile piece of Lua
// in it, a match of it with its players standing still, and a check of the error's wording.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "game/game.h"
#include "sport.h"

namespace quantum::hostile {

namespace fs = std::filesystem;

// `from` (a sport.lua) with `lua` run just before its closing `return sport`, written to `to`.
inline void write_with_before_return(const fs::path& from, const fs::path& to, const std::string& lua) {
  std::ifstream in(from);
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  s.replace(s.rfind("return sport"), 12, lua + "\nreturn sport");
  std::ofstream(to) << s;
}

// Air hockey whose drop handler runs `body` first, with `extra` Lua before its `return sport`, and
// `powerup` (when given) as its own power-up "evil".
inline std::string hostile_sport(const std::string& name, const std::string& body, const std::string& extra = "",
                          const std::string& powerup = "") {
  const fs::path dir = fs::temp_directory_path() / ("quantum_hostile_" + name);
  fs::create_directories(dir);
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua", dir / "field.lua", fs::copy_options::overwrite_existing);
  fs::create_directories(dir / "powerups");  // the sport's own power-ups come first
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/powerups/attract.lua", dir / "powerups" / "attract.lua",
                fs::copy_options::overwrite_existing);
  write_with_before_return(QUANTUM_SOURCE_DIR "/rules/airhockey/sport.lua", dir / "sport.lua",
                           "local drop = sport.on.drop\nsport.on.drop = function(game, e)\n  " + body +
                               "\n  drop(game, e)\nend\n" + extra);
  if (!powerup.empty()) std::ofstream(dir / "powerups" / "evil.lua") << powerup;
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
  const char* error;  // what the reported error must say (one of them, between '|')
};

inline bool says_one_of(const std::string& error, const std::string& alternatives) {
  for (size_t from = 0; from <= alternatives.size();) {
    const size_t bar = std::min(alternatives.find('|', from), alternatives.size());
    if (error.find(alternatives.substr(from, bar - from)) != std::string::npos) return true;
    from = bar + 1;
  }
  return false;
}

}  // namespace quantum::hostile

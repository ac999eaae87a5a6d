// What the hostile-script tests share: a sport built from air hockey with a hostile piece of Lua
// in it, a match of it with its players standing still, a match of it played out by simulated
// players with the bound on a frame's Lua, and a check of the error's wording.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "game/bots.h"
#include "game/game.h"
#include "scripted_rules.h"

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
  explicit Played(lua::ScriptedRules& sport) : match(sport.spec().field, config(), sport) {
    for (const BodySpec& b : sport.spec().field.bodies) still.push_back({b.start, {0, 0}});
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

// A whole match between simulated players (20 s, or first to seven), and what it left.
struct Finished {
  std::vector<std::string> errors;
  int goals = 0;  // goal and own_goal events
  int scored = 0;  // the final score's sum
  bool finished = false;
  int holds_after_disabled = 0;  // give, catch, pass and intercept events once the sport was disabled
};

// Long enough that a match has goals whatever the seed and the compiler's floating point make of
// it (20 s had none in a clang build).
inline Finished play_out(lua::ScriptedRules& sport, double seconds = 40, int particles = 300) {
  game::MatchConfig config;
  config.particles = particles;
  config.seconds = seconds;
  config.seed = 5;
  game::Match match(sport.spec().field, config, sport, sport.spec().handicaps);
  auto bots = game::make_bots(sport.spec().field, std::vector<double>(sport.spec().field.bodies.size(), 0.9), 11, sport.spec().match.throw_speed);
  Finished out;
  for (int frame = 0; frame < 60 * (seconds + 10) && !match.finished(); ++frame) {
    const std::vector<BodyInput>& moves = bots->move(match.time(), 1 / match.fps(), match.players());
    for (const game::Throw& t : bots->throws())  // as the match runtime does: only the holder's arm throws
      if (t.player == match.holder()) match.throw_ball(t.player, {t.velocity.x, t.velocity.y, t.up});
    match.step(moves);
    for (const game::GameEvent& e : match.events()) {
      bots->hear(e);
      out.goals += e.type == game::EventKind::Goal || e.type == game::EventKind::OwnGoal;
      using enum game::EventKind;
      out.holds_after_disabled += sport.disabled() && (e.type == Give || e.type == Catch || e.type == Pass || e.type == Intercept);
    }
    for (const std::string& e : match.errors()) out.errors.push_back(e);
    match.clear_news();
  }
  for (const auto& [team, goals] : match.score()) out.scored += goals;
  out.finished = match.finished();
  return out;
}

// The bound on a frame's Lua CPU: the 20 ms budget, then at most one instruction or library call
// that cannot be interrupted. Under the address sanitizer both run two to three times slower and the
// budget is four times a frame's (lua::kCpuScale), and so is the bound; the product's is checked
// in the optimized build.
inline constexpr double kFrameBound = 0.05 * lua::kCpuScale;

struct Attack {
  const char* name;
  const char* drop;     // Lua run first in the drop handler
  const char* extra;    // Lua before `return sport`
  const char* powerup;  // the sport's power-up "evil.lua" ("" for none)
  const char* error;    // what the first error says
};

// Every class of attack on the sandbox (docs/lua-api.md, "The sandbox"): the match is played to
// its end, every goal counts, the first error names the script's file and line, and no frame's
// Lua took more CPU than the bound (kFrameBound: 50 ms, the 20 ms budget then at most one library call or
// instruction that cannot be interrupted; four times both under the address sanitizer).
inline void expect_survived(const Attack& a) {
  SCOPED_TRACE(a.name);
  lua::ScriptedRules sport(hostile_sport(a.name, a.drop, a.extra, a.powerup));
  const Finished f = play_out(sport);
  EXPECT_TRUE(f.finished);
  EXPECT_GT(f.goals, 0);
  EXPECT_EQ(f.scored, f.goals) << "a goal went uncounted";
  ASSERT_FALSE(f.errors.empty());
  EXPECT_TRUE(std::regex_search(f.errors[0], std::regex(R"(^/\S+/(sport|evil)\.lua:\d+: )"))) << f.errors[0];
  EXPECT_TRUE(says_one_of(f.errors[0], a.error)) << f.errors[0];
  EXPECT_LE(sport.sandbox().longest_period_cpu(), kFrameBound);
}

}  // namespace quantum::hostile

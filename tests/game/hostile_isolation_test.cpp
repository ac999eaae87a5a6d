// Scripts that share a Lua state (a sport, its modules, its power-ups) cannot change what the
// others run: each script file has its own globals and module cache, the libraries and the `game`
// table are read-only, the string metatable is protected, and modifiers and power-up factors
// only compute. Every attack here plays a whole match: it ends, every goal counts, the first
// error names the script's file and line (expect_survived).
#include <gtest/gtest.h>

#include "hostile_support.h"

namespace quantum {
namespace {

using namespace hostile;

// The power-up "evil" granted at the first drop; its factor runs for every fate of every frame.
constexpr const char* kGrantEvil = "game.grant(\"Red's mallet\", 'evil', { seconds = 60 })";

std::string evil_factor(const std::string& body) {
  return "return { duration = 60, factor = function(fate, holder, game)\n" + body + "\nreturn 1 end }\n";
}

TEST(Isolation, TheGameTableAndTheLibrariesAreReadOnly) {
  const std::string replace_award = evil_factor("game.award = function() end");
  const std::string rawset_award = evil_factor("rawset(game, 'award', function() end)");
  const std::string unseal_game = evil_factor("setmetatable(game, nil)");
  const std::string replace_format = evil_factor("string.format = function() return '' end");
  const std::string replace_floor = evil_factor("math.floor = function() return 0 end");
  const std::string rawset_table = evil_factor("rawset(table, 'concat', print)");
  const Attack attacks[] = {
      {"replace_award", kGrantEvil, "", replace_award.c_str(), "game is read-only"},
      {"rawset_award", kGrantEvil, "", rawset_award.c_str(), "rawset: the table is read-only"},
      {"unseal_game", kGrantEvil, "", unseal_game.c_str(), "cannot change a protected metatable"},
      {"replace_format", kGrantEvil, "", replace_format.c_str(), "string is read-only"},
      {"replace_floor", kGrantEvil, "", replace_floor.c_str(), "math is read-only"},
      {"rawset_table", kGrantEvil, "", rawset_table.c_str(), "rawset: the table is read-only"},
      // The sport's own script is held to the same: the libraries are every script's.
      {"sport_replaces_say", "game.say = print", "", "", "game is read-only"},
  };
  for (const Attack& a : attacks) expect_survived(a);
}

TEST(Isolation, TheStringMetatableCannotBeChanged) {
  // getmetatable("") gives the protection's marker, a string: indexing it for assignment fails.
  const std::string set_index = evil_factor("getmetatable('').__index = { format = function() return '' end }");
  const std::string set_method = evil_factor("getmetatable('').__index.rep = function() return '' end");
  const Attack attacks[] = {
      {"string_meta_index", kGrantEvil, "", set_index.c_str(), "attempt to index a string value"},
      {"string_meta_method", kGrantEvil, "", set_method.c_str(), "attempt to index"},
      {"string_meta_unset", "setmetatable('', nil)", "", "", "bad argument #1 to 'setmetatable'"},
  };
  for (const Attack& a : attacks) expect_survived(a);
}

// A power-up's globals and its copy of a module are its own: the sport's handlers do not see
// them. Were they shared, the drop handler below would hand Red five goals or lose Blue's.
TEST(Isolation, APowerUpsGlobalsAndModulesAreItsOwn) {
  const std::string check_then_grant =
      std::string("if hijacked or type(pairs) ~= 'function' then game.award('red', 5) end ") + kGrantEvil;
  const Attack attacks[] = {
      {"globals", check_then_grant.c_str(), "",
       "hijacked = true pairs = nil tostring = nil\n"
       "return { duration = 60, factor = function() error('evil ran') end }\n",
       "evil ran"},
      {"module", kGrantEvil, "",
       "local two_teams = require 'two_teams'\n"
       "two_teams.goal = function() end two_teams.other = function() return 'red' end\n"
       "return { duration = 60, factor = function() error('evil ran') end }\n",
       "evil ran"},
  };
  for (const Attack& a : attacks) expect_survived(a);
}

// The fate and player tables a power-up's factor is handed are the ones the sport's modifiers
// get next: what the power-up leaves on them (a metatable, a field gone) the sport never sees.
TEST(Isolation, APowerUpCannotPoisonTheTablesTheSportIsHanded) {
  const char* check = "sport.modifiers = { function(fate) if type(fate.kind) ~= 'string' or getmetatable(fate) then "
                      "error('poisoned') end return 1 end }";
  const std::string poison = evil_factor(
      "fate.kind = nil setmetatable(fate, { __index = function() error('boo') end, "
      "__newindex = function() error('no writes') end }) error('evil ran')");
  const std::string poison_holder = evil_factor(
      "holder.name = nil setmetatable(holder, { __index = function() while true do end end }) error('evil ran')");
  const Attack attacks[] = {
      {"poison_fate", kGrantEvil, check, poison.c_str(), "evil ran"},
      {"poison_holder", kGrantEvil, check, poison_holder.c_str(), "evil ran"},
  };
  for (const Attack& a : attacks) {
    SCOPED_TRACE(a.name);
    lua::ScriptedRules sport(hostile_sport(a.name, a.drop, a.extra, a.powerup));
    const Finished f = play_out(sport);
    EXPECT_TRUE(f.finished);
    EXPECT_EQ(f.scored, f.goals) << "a goal went uncounted";
    ASSERT_FALSE(f.errors.empty());
    EXPECT_TRUE(says_one_of(f.errors[0], a.error)) << f.errors[0];
    for (const std::string& e : f.errors) EXPECT_EQ(e.find("poisoned"), std::string::npos) << e;
  }
}

// Modifiers and factors compute a number; acting from one is refused, also when the frame's
// factors are worked out inside a handler (game.wormhole asks for a fresh prediction), and the
// handler's own actions after it still work.
TEST(Isolation, ModifiersAndFactorsOnlyCompute) {
  const std::string award_in_factor = evil_factor("game.award('red', 1)");
  const std::string say_in_factor = evil_factor("game.say('goal')");
  const Attack attacks[] = {
      {"modifier_awards", "", "sport.modifiers = { function(fate, game) game.award('red', 1) return 1 end }", "",
       "only compute"},
      {"modifier_grants", "", "sport.modifiers = { function(fate, game) game.grant(\"Red's mallet\", 'attract') return 1 end }",
       "", "only compute"},
      {"modifier_during_wormhole", "game.wormhole(0.3, 0.3, -0.3, -0.3) game.wormhole()",
       "sport.modifiers = { function(fate, game) game.finish('red') return 1 end }", "", "only compute"},
      {"factor_awards", kGrantEvil, "", award_in_factor.c_str(), "only compute"},
      {"factor_says", kGrantEvil, "", say_in_factor.c_str(), "only compute"},
  };
  for (const Attack& a : attacks) expect_survived(a);
  // The refusal ends the modifier's call, not the handler that asked for the prediction.
  lua::ScriptedRules sport(hostile_sport("handler_after_refusal", "game.wormhole(0.3, 0.3, -0.3, -0.3) game.wormhole()",
                                 "sport.modifiers = { function(fate, game) game.award('red', 1) return 1 end }"));
  const Finished f = play_out(sport);
  for (const std::string& e : f.errors) EXPECT_EQ(e.find("on.drop skipped"), std::string::npos) << e;
  EXPECT_EQ(f.scored, f.goals);
}

}  // namespace
}  // namespace quantum

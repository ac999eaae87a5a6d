// Every error names its place (docs/reliability.md, "Faults"): nesting limits, format and pattern
// callbacks and engine-side type errors carry the file:line of the script that caused them; a
// repeated error is told once and counted; the score stays within its documented bounds.
#include <gtest/gtest.h>

#include <regex>

#include "fault_sport.h"
#include "game/game.h"
#include "scripted_rules.h"

namespace quantum {
namespace {

using namespace fault;

constexpr const char* kFirst = "quantum: rules error: ";

// The session's first reports of rule errors, each "quantum: rules error: FILE:LINE: ...".
std::vector<std::string> first_reports(const Played& p) { return lines_starting(p.errors, kFirst); }

// Keep-away with `lua` added: its match starts with a `give` to Ann.
struct Keepaway {
  TempFolder folder;
  std::string file;
  explicit Keepaway(const std::string& lua) : file(sport_with(folder.path, "keepaway", lua)) {}
  std::string at(const std::string& text) const { return kFirst + place_of(file, text); }
};

// on.give throws, on.throw gives: 64 calls deep the next one is refused, at the line of the
// handler that made it, and each such error is told once.
TEST(FaultErrors, HandlersThatCallEachOtherAreStoppedAtTheLineThatNestsThem) {
  const Keepaway k(R"(
sport.on.give = function(game, e)
  game.throw(e.actor, { 1, 0 })  -- nests a throw
end
sport.on.throw = function(game, e)
  game.give(e.actor)  -- nests a give
end)");
  const Played p = play(k.folder.path);
  const std::vector<std::string> reports = first_reports(p);
  ASSERT_FALSE(reports.empty()) << p.errors;
  for (const std::string& r : reports) {
    EXPECT_TRUE(r.starts_with(k.at("nests a throw")) || r.starts_with(k.at("nests a give"))) << r;
    EXPECT_NE(r.find("calls into the scripts nested more than 64 deep"), std::string::npos) << r;
  }
  // Told once each, then counted: a handful of lines, not one per refusal.
  EXPECT_LE(reports.size(), 8u) << p.errors;
}

// The first error of keep-away with `lua` added starts at the line of `lua` holding `marker`,
// with `error`.
void expect_first_error_at(const std::string& lua, const std::string& marker, const std::string& error) {
  const Keepaway k(lua);
  const std::vector<std::string> reports = first_reports(play(k.folder.path));
  ASSERT_FALSE(reports.empty());
  EXPECT_TRUE(reports[0].starts_with(k.at(marker) + error)) << reports[0];
}

// A __tostring that returns string.format("%s", self) recurses through C, its own frame gone
// (a tail call): the error names the handler the engine called.
TEST(FaultErrors, AFormatCallbackThatRecursesNamesTheScriptThatCalledIt) {
  expect_first_error_at(R"(
local loops = setmetatable({}, { __tostring = function(self) return string.format("%s", self) end })
sport.on.give = function(game, e)  -- formats
  return tostring(loops)
end)",
                        "formats", "string.format: callbacks nested more than 64 deep");
}

// string.gsub calling a function that calls string.gsub again, by tail calls, is stopped at the
// sandbox's depth with the place of the handler.
TEST(FaultErrors, APatternCallbackThatRecursesNamesTheScriptThatCalledIt) {
  expect_first_error_at(R"(
local function again(s) return string.gsub(s, ".", again) end
sport.on.give = function(game, e)  -- matches
  return again("ab")
end)",
                        "matches", "string.gsub: callbacks nested more than 64 deep");
}

// A modifier whose callback recurses the same way: the modifier's place, which a modifier call
// has even though the engine, not a script, called it.
TEST(FaultErrors, ACallbackThatRecursesInAModifierNamesTheModifier) {
  expect_first_error_at(R"(
local loops = setmetatable({}, { __tostring = function(self) return string.format("%s", self) end })
sport.modifiers = { function(fate, game) return tostring(loops) end }  -- modifies)",
                        "modifies", "string.format: callbacks nested more than 64 deep");
}

// The one report of `error` and its count at the end of the session ("N times in all").
struct Counted {
  int reports = 0, times = 0;
};
Counted counted(const Played& p, const std::string& error) {
  Counted c;
  for (const std::string& r : first_reports(p)) c.reports += r == kFirst + error;
  const std::regex times(R"(^quantum: rules error, (\d+) times in all: (.*)$)");
  for (const std::string& line : lines_starting(p.errors, "quantum: rules error, ")) {
    std::smatch m;
    if (std::regex_match(line, m, times) && m[2] == error) c.times = std::stoi(m[1]);
  }
  return c;
}

// A handler that replaces sport.modifiers with a list of things that are not functions: each
// frame's factors skip them, with one error naming the handler's line, told once and counted
// (it was "attempt to call a table value", no file, 1,039 times in a match).
TEST(FaultErrors, ModifiersThatAreNotFunctionsAreOneErrorNamingTheHandlerThatMadeThem) {
  const Keepaway k(R"(
sport.on.give = function(game, e)  -- breaks
  sport.modifiers = { {}, {}, 5 }
end)");
  const Played p = play(k.folder.path);
  const std::string error = place_of(k.file, "breaks") + "since this function ran, modifiers[1] is a table, not a function (skipped)";
  const Counted c = counted(p, error);
  EXPECT_EQ(c.reports, 1) << p.errors;
  EXPECT_GT(c.times, 10) << p.errors;
  EXPECT_EQ(first_reports(p).size(), 1u) << p.errors;
  EXPECT_EQ(p.rule_errors, c.times);
}

// The same from a timer, with a value that is not even a list.
TEST(FaultErrors, ModifiersThatAreNotAListNameTheTimerThatMadeThem) {
  const Keepaway k(R"(
sport.on.give = function(game, e)
  game.after(0.5, function(game) sport.modifiers = 5 end)  -- later
end)");
  const Played p = play(k.folder.path);
  const Counted c = counted(p, place_of(k.file, "later") + "since this function ran, modifiers is a number, not a list of functions (skipped)");
  EXPECT_EQ(c.reports, 1) << p.errors;
  EXPECT_GT(c.times, 10) << p.errors;
}

// A modifier that replaces another in place is named as the one that did it.
TEST(FaultErrors, AModifierThatReplacesAnotherIsNamed) {
  const Keepaway k(R"(
sport.modifiers = {
  function(fate, game) sport.modifiers[2] = "nothing"; return 1 end,  -- replaces
  function(fate, game) return 1 end,
})");
  const Played p = play(k.folder.path);
  const Counted c = counted(p, place_of(k.file, "replaces") + "since this function ran, modifiers[2] is a string, not a function (skipped)");
  EXPECT_EQ(c.reports, 1) << p.errors;
  EXPECT_GT(c.times, 10) << p.errors;
}

// Air hockey's match, its scripts never run: the score as game.award leaves it.
struct Scored {
  lua::ScriptedRules sport{"airhockey"};
  game::Match match;
  explicit Scored(game::MatchConfig config = {}) : match(sport.spec().field, config, sport) {}
  // Awards `team` kMostAward points at a time until its score would pass 2^31 either way.
  void award_past_the_bound(const std::string& team, double sign) {
    for (int64_t k = 0; k * int64_t(game::kMostAward) <= int64_t(1) << 31; ++k) match.award(team, sign * game::kMostAward);
  }
};

// docs/lua-api.md: "a score saturates at ±2,147,483,647". The floor was one below it.
TEST(FaultErrors, AScoreSaturatesAtItsDocumentedBoundsBothWays) {
  Scored s;
  s.award_past_the_bound("blue", 1);
  s.award_past_the_bound("red", -1);
  EXPECT_EQ(s.match.score().at("blue"), 2'147'483'647);
  EXPECT_EQ(s.match.score().at("red"), -2'147'483'647);
  s.match.award("red", 1000);  // back up from the floor, by what was awarded
  EXPECT_EQ(s.match.score().at("red"), -2'147'482'647);
}

// The automatic balance reads how far a team trails: from one bound to the other is beyond an
// int, and the trailing team's boost is the most the sport allows, not a wrapped-around penalty.
TEST(FaultErrors, ATeamTrailingFromBoundToBoundGetsTheMostBalance) {
  game::MatchConfig config;
  config.balance_per_goal = 0.5;
  config.balance_most = 2;
  Scored s(config);
  s.award_past_the_bound("blue", 1);
  s.award_past_the_bound("red", -1);
  const int red = s.match.field().bodies[0].team == "red" ? 0 : 1;
  EXPECT_DOUBLE_EQ(s.match.handicap_now(red), 2 * s.match.players()[size_t(red)].handicap);
  EXPECT_DOUBLE_EQ(s.match.handicap_now(1 - red), s.match.players()[size_t(1 - red)].handicap);
}

// Time up with every score below 0: the leader (the least behind) wins, as with any other score.
TEST(FaultErrors, TheLeaderWinsWhenEveryScoreIsBelowZero) {
  game::MatchConfig config;
  config.seconds = 0.5;
  config.particles = 200;
  Scored s(config);
  s.match.award("blue", -3);
  s.match.award("red", -50);
  std::vector<BodyInput> still;
  for (const BodySpec& b : s.sport.spec().field.bodies) still.push_back({b.start, {0, 0}});
  for (int frame = 0; frame < 120 && !s.match.finished(); ++frame) s.match.step(still);
  ASSERT_TRUE(s.match.finished());
  EXPECT_EQ(s.match.winner(), "blue");
}

}  // namespace
}  // namespace quantum

// Sports in Lua: loading errors name the file and line; a rule that fails during play is
// reported and skipped while the match goes on; the air hockey match runs end to end.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "play.h"
#include "scripted_rules.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

// A sport folder holding the air hockey table and the given sport.lua.
std::string sport_with(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("quantum_sport_" + name);
  fs::create_directories(dir);
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua", dir / "field.lua", fs::copy_options::overwrite_existing);
  std::ofstream(dir / "sport.lua") << text;
  return dir.string();
}

std::string load_error(const std::string& name, const std::string& text) {
  try {
    lua::ScriptedRules sport(sport_with(name, text));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

game::MatchConfig small_match() {
  game::MatchConfig config;
  config.particles = 100;
  return config;
}

// One frame (the first: the ball drops) with every player standing where the field starts it.
void step_standing(game::Match& match, const Field& field) {
  std::vector<BodyInput> still;
  for (const BodySpec& b : field.bodies) still.push_back({b.start, {0, 0}});
  match.step(still);
}

TEST(Sport, SyntaxErrorNamesFileAndLine) {
  const std::string e = load_error("syntax", "return {\n name = 'x',\n on = { goal = function( }\n}");
  EXPECT_NE(e.find("sport.lua:3:"), std::string::npos) << e;
}

// A sport may change a handicap during the match: here the drop handler hands Red a handicap of
// 3, and a bad value is refused as a rule error.
TEST(Sport, RulesMayChangeAHandicap) {
  lua::ScriptedRules sport(sport_with("handicap", "local s = { on = { drop = function(game, e)\n"
                                          "  game.handicap(\"Red's mallet\", 3)\n"
                                          "  game.handicap(\"Blue's mallet\", -1)\n"
                                          "end } }\nreturn s"));
  game::Match match(sport.spec().field, small_match(), sport);
  step_standing(match, sport.spec().field);
  EXPECT_DOUBLE_EQ(match.players()[1].handicap, 3.0);
  EXPECT_DOUBLE_EQ(match.players()[0].handicap, 1.0);
  const std::span<const std::string> errors = match.errors();
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("a handicap must be in (0, 1000]"), std::string::npos) << errors[0];
}

// A team the sport's `teams` does not name is called by its own name. (The name was once handed
// back as a reference to the argument's temporary: the sport fuzzer found the read after its end.)
TEST(Sport, ATeamWithoutANameIsCalledByItself) {
  lua::ScriptedRules sport(sport_with("team_name", "return { teams = { blue = 'The Blues' }, on = { drop = function(game, e)\n"
                                           "  game.say(game.team_name('blue') .. ', ' .. game.team_name('red') .. ', ' .. "
                                           "game.team_name('a team nobody named, longer than a short string'))\n"
                                           "end } }"));
  game::Match match(sport.spec().field, small_match(), sport);
  step_standing(match, sport.spec().field);
  ASSERT_EQ(match.said().size(), 1u);
  EXPECT_EQ(match.said()[0].text, "The Blues, red, a team nobody named, longer than a short string");
}

TEST(Sport, BadHandlerIsNamed) {
  const std::string e = load_error("handler", "return { on = { gaol = function() end } }");
  EXPECT_NE(e.find("sport.lua: on: unknown event 'gaol' (did you mean 'goal'?"), std::string::npos) << e;
  const std::string f = load_error("factor", "return { factors = { goal = 'five' } }");
  EXPECT_NE(f.find("factors.goal: expected a number"), std::string::npos) << f;
}

TEST(Sport, RuntimeErrorInARuleIsReportedAndTheMatchGoesOn) {
  runtime::SessionOptions o;
  o.sport = sport_with("runtime", R"(
return {
  match = { seconds = 60 },
  on = {
    shot = function(game, e) error("boom in the shot rule") end,
    goal = function(game, e) game.award(e.team == "blue" and "red" or "blue"); game.respawn(e.team, 1) end,
    own_goal = function(game, e) game.award(e.team == "blue" and "red" or "blue"); game.respawn(e.team, 1) end,
  },
})");
  o.seed = 3;
  std::ostringstream out, errors;
  const tools::PlayResult r = tools::play(o, out, errors);
  EXPECT_GT(r.rule_errors, 0);
  EXPECT_NE(errors.str().find("sport.lua:5: boom in the shot rule (on.shot skipped)"), std::string::npos) << errors.str();
  EXPECT_GE(r.stats.seconds, 60 - 1e-6);  // played to the time limit regardless
  int goals = 0;
  for (const auto& [team, n] : r.score) goals += n;
  EXPECT_GT(goals, 0);  // the goal rules kept working
  EXPECT_EQ(goals, r.stats.goals);
}

TEST(Sport, ARepeatingRuleErrorIsReportedOnceWithItsCount) {
  runtime::SessionOptions o;
  o.sport = sport_with("repeating", "return { on = { bounce = function(game, e) error('bad bounce') end } }");
  o.seconds = 20;
  std::ostringstream out, errors;
  const tools::PlayResult r = tools::play(o, out, errors, false);
  const std::string e = errors.str();
  ASSERT_GT(r.rule_errors, 3);
  EXPECT_EQ(std::count(e.begin(), e.end(), '\n'), 2) << e;  // the first time, and the count at the end
  EXPECT_NE(e.find("quantum: rules error, " + std::to_string(r.rule_errors) + " times in all: "), std::string::npos) << e;
}

TEST(Sport, AirHockeyMatchIsPlayedAndRepeatable) {
  runtime::SessionOptions o;
  o.seconds = 60;
  o.seed = 5;
  std::ostringstream a, b, errors;
  const tools::PlayResult r = tools::play(o, a, errors);
  tools::play(o, b, errors);
  EXPECT_EQ(a.str(), b.str());
  EXPECT_EQ(errors.str(), "");
  EXPECT_GT(r.stats.rallies, 0);
  EXPECT_GT(r.stats.contacts, 0);
  EXPECT_NE(a.str().find("Puck to Blue"), std::string::npos);
  EXPECT_NE(a.str().find("final score:"), std::string::npos);
}

TEST(Sport, BadSkillAndHandicapAreRefused) {
  runtime::SessionOptions o;
  o.skills = {0.5};
  std::ostringstream out, errors;
  EXPECT_THROW(tools::play(o, out, errors), std::invalid_argument);
  o.skills = {0.5, 1.5};
  EXPECT_THROW(tools::play(o, out, errors), std::invalid_argument);
  o.skills = {};
  o.handicaps = {1, 0};
  EXPECT_THROW(tools::play(o, out, errors), std::invalid_argument);
  EXPECT_THROW(tools::parse_list("0.5,x", "--skill"), std::invalid_argument);
}

}  // namespace
}  // namespace quantum

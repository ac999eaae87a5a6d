// Hostile values (issue 19): numbers and text a script gives the engine that are out of bounds.
// Each is refused when the sport loads, naming the file and the key, or while it plays, clamped or
// refused with one error naming the file and the line (or the key), and the match plays on to a
// correct score. The bounds are in docs/lua-api.md ("Values").
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <climits>
#include <cstdio>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <regex>

#include "hostile_support.h"

namespace quantum {
namespace {

using namespace hostile;

// A `quantum play` of a sport to its end, as a venue runs it, and what it left.
struct MatchRun {
  int status = -1;
  std::string out, err;                // stdout (the transcript, the final score), stderr
  std::vector<nlohmann::json> events;  // every line of --events, each one parsed
  int goals = 0;                       // goal and own_goal events
  int scored = -1;                     // the final score's sum, -1 when it was not printed
};

std::string text_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

MatchRun play(const std::string& sport, const std::string& audio = "none") {
  const fs::path dir = fs::path(sport);
  const fs::path events = dir / "events.jsonl", err = dir / "stderr.txt";
  const std::string cmd = "ALSOFT_DRIVERS=null " QUANTUM_BINARY " play " + sport +
                          " --pace fast --seconds 30 --particles 300 --audio " + audio + " --events " +
                          events.string() + " 2>" + err.string();
  MatchRun run;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buf;
  for (size_t n; (n = fread(buf.data(), 1, buf.size(), pipe)) > 0;) run.out.append(buf.data(), n);
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.err = text_of(err);
  std::istringstream lines(text_of(events));
  for (std::string line; std::getline(lines, line);) {
    run.events.push_back(nlohmann::json::parse(line));  // throws on a line that is not JSON (or not UTF-8)
    const std::string type = run.events.back()["type"];
    run.goals += type == "goal" || type == "own_goal";
  }
  std::smatch score;
  if (std::regex_search(run.out, score, std::regex(R"(final score: blue (-?\d+) red (-?\d+))")))
    run.scored = std::stoi(score[1]) + std::stoi(score[2]);
  return run;
}

// How many lines of stderr report `error` the first time ("quantum: rules error: ..."): a value
// out of bounds every frame must be one of them, not one a frame.
int first_reports(const std::string& err, const std::regex& error) {
  int n = 0;
  std::istringstream lines(err);
  for (std::string line; std::getline(lines, line);)
    n += line.starts_with("quantum: rules error: ") && std::regex_search(line, error);
  return n;
}

// The match was played to its end with every goal counted, and `error` reported once.
void expect_played_on(const MatchRun& run, const std::string& error) {
  EXPECT_EQ(run.status, 0) << run.err;
  ASSERT_FALSE(run.events.empty());
  EXPECT_EQ(run.events.back()["type"], "match_end");
  EXPECT_GT(run.goals, 0);
  EXPECT_EQ(run.scored, run.goals) << run.out.substr(run.out.size() - std::min<size_t>(run.out.size(), 300));
  EXPECT_EQ(first_reports(run.err, std::regex(error)), 1) << run.err.substr(0, 2000);
}

// A file's place as an error names it: /tmp/quantum_hostile_NAME/sport.lua:LINE:
std::string at_line(const std::string& name) { return "quantum_hostile_" + name + R"(/sport\.lua:\d+: )"; }

TEST(HostileValues, ModifierResultsOutOfBoundsAreClampedOrSkippedOnce) {
  const struct {
    const char* name;
    const char* result;
    const char* error;
  } cases[] = {
      {"modifier_1e308", "1e308", "more than 1e6, the most a factor may be \\(taken as 1e6\\)"},
      {"modifier_huge", "math.huge", "more than 1e6, the most a factor may be \\(taken as 1e6\\)"},
      {"modifier_nan", "0/0", "nan, not a factor in \\[0, 1e6\\] \\(skipped\\)"},
      {"modifier_negative", "-1", "a number below 0, not a factor in \\[0, 1e6\\] \\(skipped\\)"},
      // A result that changes every frame is still one error: the message names no value.
      {"modifier_varying", "1e7 + fate.mass * 1e300", "more than 1e6"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string sport = hostile_sport(
        c.name, "", std::string("sport.modifiers = {\n  function(fate, game) return ") + c.result + " end,\n}");
    const MatchRun run = play(sport);
    expect_played_on(run, at_line(c.name) + R"(modifiers\[1\] returned )" + c.error);
    EXPECT_EQ(run.err.find("fate factors refused"), std::string::npos);
  }
}

// A power-up's factor is bounded as a modifier's result is; the error names the line where its
// `factor` is defined.
TEST(HostileValues, PowerUpFactorsOutOfBoundsAreClampedOrSkippedOnce) {
  const struct {
    const char* name;
    const char* result;
    const char* error;
  } cases[] = {
      {"powerup_1e308", "1e308", "more than 1e6, the most a factor may be"},
      {"powerup_nan", "0/0", "nan, not a factor in \\[0, 1e6\\] \\(skipped\\)"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string sport =
        hostile_sport(c.name, "game.grant(\"Red's mallet\", 'evil')", "",
                      std::string("return { duration = 60,\n  factor = function() return ") + c.result + " end }\n");
    expect_played_on(play(sport), "quantum_hostile_" + std::string(c.name) +
                                      R"(/powerups/evil\.lua:2: power-up evil: factor returned )" + c.error);
  }
}

TEST(HostileValues, FactorsSetWhilePlayingAreCheckedWithTheirKeyNamed) {
  const struct {
    const char* name;
    const char* value;
    const char* error;
  } cases[] = {
      {"factor_nan", "0/0", "is nan, not a factor"},
      {"factor_negative", "-1", "is a number below 0, not a factor"},
      {"factor_1e308", "1e308", "is more than 1e6, the most a factor may be"},
      {"factor_text", "'lots'", "is a string, not a factor"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string sport = hostile_sport(c.name, std::string("sport.factors.own_goal = ") + c.value);
    expect_played_on(play(sport),
                     "quantum_hostile_" + std::string(c.name) + R"(/sport\.lua: factors\.own_goal )" + c.error);
  }
}

// Loading the sport fails with an error naming its file ("sport" for sport.lua) and `error`.
void expect_refused(const std::string& sport, const std::string& file, const std::string& error) {
  try {
    lua::ScriptedRules loaded(sport);
    ADD_FAILURE() << "loaded";
  } catch (const std::exception& e) {
    EXPECT_TRUE(std::regex_search(e.what(), std::regex("/" + file + R"(\.lua: )" + error))) << e.what();
  }
}

// A line of Lua added to air hockey's sport.lua, and the error (a pattern) that refuses it.
struct SportLine {
  const char* lua;
  const char* error;
};

// Each line, added alone to the sport `name`, is refused when it loads.
void expect_each_refused(const char* name, std::initializer_list<SportLine> lines) {
  for (const SportLine& c : lines) {
    SCOPED_TRACE(c.lua);
    expect_refused(hostile_sport(name, "", c.lua), "sport", c.error);
  }
}

// A balance that multiplies handicaps without end would overflow a factor as surely.
TEST(HostileValues, FactorsOutOfBoundsAreRefusedWhenTheSportLoads) {
  expect_each_refused("factor_load", {
      {"sport.factors.goal = math.huge", R"(factors\.goal: must be a number in \[0, 1e6\])"},
      {"sport.factors.goal = 1e7", R"(factors\.goal: must be a number in \[0, 1e6\])"},
      {"sport.factors.goal = 0/0", R"(factors\.goal: must be a number in \[0, 1e6\])"},
      {"sport.factors.own_goal = -1", R"(factors\.own_goal: must be a number in \[0, 1e6\])"},
      {"sport.balance = { per_goal = 1, most = 1e308 }", R"(balance\.most: must be in \[1, 1000\])"},
  });
}

// An award that is no whole number in [-1000, 1000] is refused at the caller's line; the rest of
// its handler is skipped, and every goal counts as before.
TEST(HostileValues, AwardsOutOfBoundsAreRefusedAtTheCallersLine) {
  const struct {
    const char* name;
    const char* points;
  } cases[] = {{"award_nan", "0/0"},
               {"award_1e300", "1e300"},
               {"award_fraction", "2.9"},
               {"award_2_31", "2^31"},
               {"award_below", "-1001"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.points);
    const std::string sport = hostile_sport(c.name, std::string("game.award('blue', ") + c.points + ")");
    expect_played_on(play(sport), at_line(c.name) + "game.award: points must be a whole number from -1000 to 1000");
  }
}

TEST(HostileValues, AScoreSaturatesRatherThanWrapping) {
  lua::ScriptedRules sport(QUANTUM_SOURCE_DIR "/rules/airhockey");
  Played played(sport);
  for (int k = 0; k < (INT_MAX / 1000) + 10; ++k) played.match.award("blue", 1000);
  EXPECT_EQ(played.match.score().at("blue"), INT_MAX);
  for (int k = 0; k < 2 * (INT_MAX / 1000) + 20; ++k) played.match.award("red", -1000);
  EXPECT_EQ(played.match.score().at("red"), -INT_MAX);  // the floor mirrors the ceiling (docs/lua-api.md)
  played.match.award("red", 1000);  // and counts again from there
  EXPECT_EQ(played.match.score().at("red"), -INT_MAX + 1000);
}

// A phrase that is not UTF-8 is refused when the sport loads, naming its key.
TEST(HostileValues, APhraseThatIsNotUtf8IsRefusedWithItsKey) {
  for (const char* bytes :
       {"\\255", "\\192\\128", "\\237\\160\\128", "\\226\\130"}) {  // stray, overlong, surrogate, cut
    SCOPED_TRACE(bytes);
    const std::string sport =
        hostile_sport("phrase_bytes", "", std::string("sport.phrases.drop = 'Puck to {team}") + bytes + "'");
    expect_refused(sport, "sport", R"(phrases\.drop: byte 15 is not UTF-8)");
  }
}

// A value said at run time may carry any byte (it may come from anywhere): the match goes on, and
// every event line is JSON (invalid bytes written as U+FFFD), with sound on too. Text said as it
// is, is a phrase: refused at the line that says it.
TEST(HostileValues, InvalidBytesSaidWhilePlayingKeepTheEventLogJson) {
  const std::string sport = hostile_sport("said_bytes",
                                          "game.say('drop', { team = 'Blue' .. string.char(255, 192, 128) .. 'x' })\n"
                                          "  game.say('Puck ' .. string.char(237, 160, 128, 226, 130))");
  for (const std::string& audio : {std::string("none"), "wav:" + (fs::path(sport) / "match.wav").string()}) {
    SCOPED_TRACE(audio);
    const MatchRun run = play(sport, audio);
    expect_played_on(run, at_line("said_bytes") + "game.say: byte 6 is not UTF-8");
    ASSERT_EQ(run.events.front()["said"].size(), 1u);
    EXPECT_EQ(run.events.front()["said"][0], "Puck to Blue\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBDx");
  }
}

TEST(HostileValues, AListenerOffTheFieldOrNotANumberIsRefusedWithItsKey) {
  expect_each_refused("listener", {
      {"sport.audio.listener = { 0/0, 0 }", "audio.listener: must be within 10 m of the field's bounds"},
      {"sport.audio.listener = { 0, math.huge }", "audio.listener: must be within 10 m of the field's bounds"},
      {"sport.audio.listener = { 50, 0 }", "audio.listener: must be within 10 m of the field's bounds"},
      {"sport.audio.facing = { 0/0, 1 }", "audio.facing: must be a direction: finite and not \\{0, 0\\}"},
      {"sport.audio.facing = { 0, 0 }", "audio.facing: must be a direction: finite and not \\{0, 0\\}"},
  });
  // Beside the field is a place to listen from: a commentator's box 5 m behind Blue's end.
  EXPECT_NO_THROW(lua::ScriptedRules(hostile_sport("listener", "", "sport.audio.listener = { -6, 0 }")));
}

// The announcer's numbers become ints: one beyond an int's range (the fuzzer's 4.4e104) or not
// whole is refused at load, naming the key and the range, rather than narrowed to nonsense.
TEST(HostileValues, AudioNumbersThatAreNoWholeNumberInRangeAreRefusedWithTheirKey) {
  expect_each_refused("audio_numbers", {
      {"sport.audio.rate = 4.4e104", R"(audio\.rate: expected a whole number from 80 to 450, got 4\.4e\+104)"},
      {"sport.audio.rate = 79", R"(audio\.rate: expected a whole number from 80 to 450, got 79)"},
      {"sport.audio.rate = 170.5", R"(audio\.rate: expected a whole number from 80 to 450, got 170\.5)"},
      {"sport.audio.volume = -1", R"(audio\.volume: expected a whole number from 0 to 200, got -1)"},
      {"sport.audio.volume = 0/0", R"(audio\.volume: expected a whole number from 0 to 200, got -?nan)"},
      {"sport.audio.keep = 1e300", R"(audio\.keep: expected a whole number from 0 to 100, got 1e\+300)"},
      {"sport.audio.priorities = { goal = -2^63 }", R"(audio\.priorities\.goal: expected a whole number from 0 to 100)"},
      {"sport.audio.priorities = { shot = 2.5 }", R"(audio\.priorities\.shot: expected a whole number from 0 to 100)"},
  });
  lua::ScriptedRules edges(hostile_sport("audio_numbers", "", "sport.audio.rate = 450; sport.audio.volume = 0; sport.audio.keep = 100"));
  EXPECT_EQ(edges.spec().audio.rate, 450);
  EXPECT_EQ(edges.spec().audio.volume, 0);
  EXPECT_EQ(edges.spec().audio.keep, 100);
}

// A number beyond a float's range in a game call is a value like any other that cannot be: the
// call is refused (or, for a timer id, names no timer) and the match plays on.
TEST(HostileValues, NumbersBeyondAFloatInGameCallsAreRefusedAndPlayGoesOn) {
  const std::string sport = hostile_sport("beyond_float",
                                          "game.cancel(1e300); game.cancel(-1e300); game.cancel(0.5)\n"
                                          "  game.aim('blue', { 1e300, 0 })");
  expect_played_on(play(sport), at_line("beyond_float") + "game.aim: a point to aim at must be finite");
}

// The bounds are the walls' and goals' (docs/field-files.md): a spot or a player's start beyond
// them is refused, naming it, rather than a ball dropped where nobody can reach it.
TEST(HostileValues, ASpotOrAStartOffTheFieldIsRefusedWithItsKey) {
  const struct {
    const char* from;
    const char* to;
    const char* error;
  } cases[] = {
      {"at = { 0.5, 0 } }", "at = { 50, 0 } }", R"(spots\[2\] \(in front of Red's goal\): lies outside the bounds)"},
      {"at = { -0.5, 0 } }", "at = { -0.5, 3 } }",
       R"(spots\[1\] \(in front of Blue's goal\): lies outside the bounds)"},
      {"at = { 0.85, 0 } }", "at = { 50, 0 } }", R"(bodies\[2\] \(Red's mallet\): starts outside the field)"},
      // Beyond a float: refused as off the field, never narrowed with undefined behaviour.
      {"at = { 0.5, 0 } }", "at = { 1e300, 0 } }", R"(spots\[2\] \(in front of Red's goal\): coordinates beyond \+-1000 m)"},
      {"at = { 0.85, 0 } }", "at = { 0, -1e39 } }", R"(bodies\[2\] \(Red's mallet\): coordinates beyond \+-1000 m)"},
      {"at = { 0.85, 0 } }", "at = { 0/0, 0 } }", R"(bodies\[2\] \(Red's mallet\): coordinates must be numbers, not NaN)"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.to);
    const std::string sport = hostile_sport("spot", "");
    std::string field = text_of(fs::path(sport) / "field.lua");
    field.replace(field.find(c.from), std::string(c.from).size(), c.to);
    std::ofstream(fs::path(sport) / "field.lua") << field;
    expect_refused(sport, "field", c.error);
  }
}

}  // namespace
}  // namespace quantum

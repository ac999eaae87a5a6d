// The table of the engine's ranges (quantum/limits.h): every message built from it names the
// bounds it checks, and each way a value enters (a sport's file, a Lua call, a device's throw;
// the command line in tests/quantum/cli_test.cpp) takes a value just inside a range and refuses
// one just outside it, naming the table's range.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "field_loader.h"
#include "quantum/limits.h"
#include "fault_sport.h"
#include "hostile_support.h"
#include "recorder.h"
#include "scripted_rules.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;
using limits::Range;

// Numbers either side of a bound, as near as a double gets.
double below(double v) { return std::nextafter(v, -std::numeric_limits<double>::infinity()); }
double above(double v) { return std::nextafter(v, std::numeric_limits<double>::infinity()); }

std::string refusal(const Range& r, double v) {
  try {
    limits::check(r, v, "the value");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(LimitsTable, EveryMessageNamesTheBoundsItChecks) {
  for (const Range* r : limits::kRanges) {
    SCOPED_TRACE(r->name);
    // Each end in or out as the range says, and the numbers just past it out.
    EXPECT_EQ(r->contains(r->lo), !r->lo_open);
    EXPECT_EQ(r->contains(r->hi), !r->hi_open);
    EXPECT_TRUE(r->contains((r->lo + r->hi) / 2));
    const std::string interval = limits::interval(*r);
    for (double out : {below(r->lo), above(r->hi), std::nan(""), std::numeric_limits<double>::infinity()}) {
      EXPECT_FALSE(r->contains(out)) << out;
      const std::string said = refusal(*r, out);
      // The message states the range the check used, its unit, and the value refused.
      EXPECT_NE(said.find("the value must be in " + limits::stated(*r) + ", got " + limits::number_text(out)),
                std::string::npos)
          << said;
    }
    EXPECT_EQ(refusal(*r, r->hi_open ? below(r->hi) : r->hi), "");
    EXPECT_EQ(refusal(*r, r->lo_open ? above(r->lo) : r->lo), "");
    // The interval is written from the bounds themselves.
    EXPECT_EQ(interval.front(), r->lo_open ? '(' : '[');
    EXPECT_EQ(interval.back(), r->hi_open ? ')' : ']');
  }
}

TEST(LimitsTable, RangesReadAsTheDocsWriteThem) {
  EXPECT_EQ(limits::stated(limits::kThrowSpeed), "(0, 1000] m/s");
  EXPECT_EQ(limits::stated(limits::kMatchSeconds), "(0, 86400] s");
  EXPECT_EQ(limits::stated(limits::kElevationDegrees), "(0, 90) degrees");
  EXPECT_EQ(limits::interval(limits::kFactor), "[0, 1e6]");
  EXPECT_EQ(limits::interval(limits::kSpreadRadians), "[0, 1.6]");
  EXPECT_EQ(limits::must_be_in(limits::kHandicap, 2000), "must be in (0, 1000], got 2000");
  // The factor's own words (game::bounded_factor, a script's modifier) quote the same range.
  for (double v : {-1.0, std::nan("")})
    EXPECT_NE(std::string(game::bounded_factor(v).problem).find(limits::interval(limits::kFactor)), std::string::npos);
}

// --- A sport's file.

// The air hockey table with `sport` as its sport.lua, in a folder of its own: the load's error,
// "" for none.
std::string load_error(const std::string& sport) {
  const fault::TempFolder folder;
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua", folder.path / "field.lua");
  std::ofstream(folder.path / "sport.lua") << sport;
  try {
    lua::ScriptedRules loaded(folder.path.string());
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(LimitsFieldFile, ASportsRangesTakeTheirEndsAndRefuseBeyondNamingTheRange) {
  struct Case {
    std::string key;
    const Range& range;
    double inside, outside;
  };
  const Case cases[] = {
      {"throws = { speed = %g }", limits::kThrowSpeed, 1000, 1000.5},
      {"handicaps = { [\"Blue's mallet\"] = %g }", limits::kHandicap, 1000, 1000.5},
      {"match = { seconds = %g }", limits::kMatchSeconds, 86400, 86400.5},
      {"tackles = { rate = %g }", limits::kTackleRate, 0, -0.5},
      {"balance = { per_goal = 1, most = %g }", limits::kBalanceMost, 1, 0.5},
  };
  for (const Case& c : cases) {
    char inside[128], outside[128];
    std::snprintf(inside, sizeof inside, ("return { " + c.key + " }").c_str(), c.inside);
    std::snprintf(outside, sizeof outside, ("return { " + c.key + " }").c_str(), c.outside);
    EXPECT_EQ(load_error(inside), "") << inside;
    const std::string e = load_error(outside);
    EXPECT_NE(e.find(limits::must_be_in(c.range, c.outside)), std::string::npos) << outside << ": " << e;
  }
}

// --- A Lua call.

TEST(LimitsLuaCall, GameHandicapTakesTheMostAndRefusesMoreNamingTheRange) {
  const fault::TempFolder folder;
  fault::sport_with(folder.path, "airhockey",
                    "sport.on.drop = function(game, e)\n"
                    "  game.handicap(\"Blue's mallet\", 1000)\n"
                    "  game.handicap(\"Red's mallet\", 1000.5)\n"
                    "end");
  lua::ScriptedRules sport(folder.path.string());
  hostile::Played played(sport);
  played.step();
  const game::Match& match = played.match;
  EXPECT_DOUBLE_EQ(match.players()[0].handicap, 1000);
  EXPECT_DOUBLE_EQ(match.players()[1].handicap, 1);
  ASSERT_EQ(match.errors().size(), 1u);
  EXPECT_NE(match.errors()[0].find("game.handicap: a handicap " + limits::must_be_in(limits::kHandicap, 1000.5)),
            std::string::npos)
      << match.errors()[0];
}

// --- A device's throw (an accelerometer's whip, over the network): Match::let_go.

TEST(LimitsNetwork, ADevicesThrowAtTheMostSpeedGoesAndOneFasterIsRefusedNamingTheRange) {
  const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/rules/handball");
  int catcher = 0;
  while (!field.bodies[size_t(catcher)].catches) ++catcher;
  const auto thrown = [&](float speed) {
    test::Recorder rules;
    game::MatchConfig config;
    config.particles = 100;
    config.first_holder = catcher;
    game::Match match(field, config, rules);
    std::vector<BodyInput> still;
    for (const BodySpec& b : field.bodies) still.push_back({b.start, {0, 0}});
    match.step(still);  // the ball comes into the catcher's hands
    match.let_go({catcher, {speed, 0}, 0});
    return rules.first(game::EventKind::Throw) != nullptr;
  };
  EXPECT_TRUE(thrown(1000));
  try {
    thrown(1000.5f);
    ADD_FAILURE() << "a throw at 1000.5 m/s went";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("a throw's speed " + limits::must_be_in(limits::kThrowSpeed, 1000.5)),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace quantum

// Issue 19, native resources: the work the engine does on a script's behalf (a phrase filled in,
// a field's contact grid and walls) is bounded by the limits of core/quantum/limits.h, checked
// before anything is allocated for it. A hostile phrase is an error at its line and the match
// goes on; a hostile field is refused at once with its key named, or loads with a bounded grid.
#include <gtest/gtest.h>

#include <time.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "field_loader.h"
#include "hostile_support.h"
#include "quantum/contact.h"
#include "quantum/limits.h"
#include "scripted_rules.h"

namespace quantum {
namespace {

using namespace hostile;

// A field file's own Lua gets a second of CPU: what the engine does for it, refusing it or
// building its geometry, stays within the same.
constexpr double kLoadBound = 1.0;

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Phrases: values of 20 MB, and text of two million '{', built when the sport loads (its budget
// is larger than a frame's) and said at every drop.
TEST(HostileLimits, AHugePhraseIsAnErrorAtItsLineAndTheMatchGoesOn) {
  const Attack attacks[] = {
      // Before the limit, seventy copies of a 20 MB value peaked at 1.4 GB outside the script's 64 MiB.
      {"say_20mb_values", "game.say(string.rep('{x}', 70), { x = hostile_big })", "hostile_big = string.rep('a', 2e7)",
       "", "longer than 1000 bytes"},
      {"say_20mb_key_value", "game.say('goal', { team = hostile_big })", "hostile_big = string.rep('a', 2e7)", "",
       "phrase 'goal': {team} makes the phrase longer than 1000 bytes"},
      {"say_value_just_over", "game.say('Goal for {team}', { team = string.rep('b', 992) })", "", "",
       "{team} makes the phrase longer than 1000 bytes"},
      // Refused by their length before any parse or lookup (a phrase of 700,000 placeholders
      // spent a frame's whole budget looking their values up).
      {"say_2m_braces", "game.say(hostile_braces)", "hostile_braces = string.rep('{', 2e6)", "",
       "longer than 1000 bytes"},
      {"say_700k_placeholders", "game.say(hostile_braces)", "hostile_braces = string.rep('{a}', 7e5)", "",
       "longer than 1000 bytes"},
  };
  for (const Attack& a : attacks) expect_survived(a);
}

// "Goal for " and 991 bytes: 1000.
TEST(HostileLimits, APhraseJustWithinTheLimitIsSaid) {
  lua::ScriptedRules sport(hostile_sport("say_1000", "game.say('Goal for {team}', { team = string.rep('b', 991) })"));
  Played played(sport);
  bool said = false;
  for (int frame = 0; frame < 30; ++frame) {
    played.step();
    for (const game::Said& s : played.match.said()) said |= s.text.size() == limits::kMaxPhraseBytes;
    EXPECT_TRUE(played.match.errors().empty()) << played.match.errors()[0];
    played.match.clear_news();
  }
  EXPECT_TRUE(said);
}

// Each phrase is parsed and kept outside the script's memory: a long one, or 100,000 keys
// naming one text, are refused when the sport loads.
void expect_sport_refused(const std::string& name, const std::string& extra, const std::string& error) {
  SCOPED_TRACE(name);
  const std::string dir = hostile_sport(name, "", extra);
  const double start = thread_cpu_seconds();
  try {
    lua::ScriptedRules sport(dir);
    ADD_FAILURE() << "loaded";
  } catch (const std::exception& e) {
    EXPECT_TRUE(says_one_of(e.what(), error)) << e.what();
  }
  std::cout << "  " << name << ": refused in " << (thread_cpu_seconds() - start) * 1e3 << " ms of CPU\n";
}

TEST(HostileLimits, ASportOfTooLongOrTooManyPhrasesIsRefusedWhenItLoads) {
  expect_sport_refused("long_phrase", "sport.phrases.long = string.rep('a', 1001)",
                       "phrases.long: the text is longer than 1000 bytes (1001)");
  expect_sport_refused("many_phrases", "local s = string.rep('a', 1000) for i = 1, 1e5 do sport.phrases['p' .. i] = s end",
                       "phrases: more than the 1000 entries allowed");
}

// A sport of air hockey whose field.lua is the table's with `lua` run on it (`field`) before it
// is returned.
std::string sport_with_field(const std::string& name, const std::string& lua) {
  const fs::path dir = hostile_sport(name, "");
  std::ifstream in(QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  s.replace(s.find("return {"), 8, "local field = {");
  std::ofstream(dir / "field.lua") << s << "\n" << lua << "\nreturn field\n";
  return dir.string();
}

struct Loaded {
  Field field;
  double cpu_seconds;  // loading the file and building its contact geometry
  size_t grid_bytes;
};

Loaded load_with_geometry(const std::string& sport_dir) {
  const double start = thread_cpu_seconds();
  Field field = lua::load_field(sport_dir);
  const size_t bytes = detail::Geometry(field).grid_bytes();
  return {std::move(field), thread_cpu_seconds() - start, bytes};
}

// Loads, builds a contact grid of at most 64 MiB, and plays.
void expect_playable(const std::string& sport_dir) {
  const Loaded loaded = load_with_geometry(sport_dir);
  EXPECT_LE(loaded.grid_bytes, limits::kMaxGridBytes);
  EXPECT_LT(loaded.cpu_seconds, kLoadBound);
  std::cout << "  " << fs::path(sport_dir).filename().string() << ": grid " << loaded.grid_bytes << " bytes, loaded in "
            << loaded.cpu_seconds * 1e3 << " ms of CPU\n";
  lua::ScriptedRules sport(sport_dir);
  Played played(sport);
  for (int frame = 0; frame < 120; ++frame) played.step();
  EXPECT_TRUE(played.match.errors().empty()) << played.match.errors()[0];
  EXPECT_NEAR(played.match.time(), 2.0, 1e-6);
}

// Before the limit, bounds of +-1000 m built 1.6e9 cells (2.3 GB, then std::bad_alloc).
TEST(HostileLimits, AFieldOfTheLargestBoundsKeepsItsGridSmall) {
  expect_playable(sport_with_field("bounds_1000", "field.bounds = { { -1000, -1000 }, { 1000, 1000 } }"));
}

TEST(HostileLimits, AFieldOfTheLargestBoundsAndTheMostSpotsPlays) {
  expect_playable(sport_with_field("spots_999", R"(
    field.bounds = { { -999, -999 }, { 999, 999 } }
    for i = #field.spots + 1, 1000 do
      field.spots[i] = { at = { (i * 37) % 1997 - 998, (i * 53) % 1997 - 998 } }
    end)"));
}

// The most wall pieces there may be, each across the whole field: every piece's reach covers the
// grid, so the grid's cells grow until it fits.
TEST(HostileLimits, TheMostWallPiecesAcrossTheLargestFieldKeepTheGridSmall) {
  const Loaded loaded = load_with_geometry(sport_with_field("long_walls", R"(
    field.bounds = { { -1000, -1000 }, { 1000, 1000 } }
    for i = #field.walls + 1, 10000 do
      local y = -990 + i * 0.198
      field.walls[i] = { name = "diagonal", points = { { -990, y }, { 990, -y } } }
    end)"));
  EXPECT_LE(loaded.grid_bytes, limits::kMaxGridBytes);
  EXPECT_LT(loaded.cpu_seconds, kLoadBound);
  std::cout << "  10,000 pieces across 2 km: grid " << loaded.grid_bytes << " bytes, loaded in "
            << loaded.cpu_seconds * 1e3 << " ms of CPU\n";
}

// A field that holds too much is refused before anything is built for it, naming the key.
void expect_refused(const std::string& name, const std::string& lua, const std::string& key) {
  SCOPED_TRACE(name);
  const std::string dir = sport_with_field(name, lua);
  const double start = thread_cpu_seconds();
  try {
    lua::load_field(dir);
    ADD_FAILURE() << "loaded";
  } catch (const FieldError& e) {
    EXPECT_TRUE(says_one_of(e.what(), dir + "/field.lua: " + key + ": ")) << e.what();
  }
  const double seconds = thread_cpu_seconds() - start;
  std::cout << "  " << name << ": refused in " << seconds * 1e3 << " ms of CPU\n";
  // What the field file itself runs (filling a list of a million) is most of it.
  EXPECT_LT(seconds, kLoadBound);
}

TEST(HostileLimits, AFieldOfTooManyWallsIsRefusedAtOnce) {
  // Before the limit, each of these hung the load in an O(n^2) search of the walls' names.
  expect_refused("million_walls", "local w = { points = { { 0, 0 }, { 0.5, 0 } } } "
                                  "for i = #field.walls + 1, 1e6 do field.walls[i] = w end", "walls");
  expect_refused("million_pieces", "local a, b = { 0, 0 }, { 0.5, 0 } local p = {} "
                                   "for i = 1, 1e6 + 1 do p[i] = i % 2 == 1 and a or b end "
                                   "field.walls[1] = { points = p }", "walls[1].points");
  // The table's 6 pieces, then 100 a wall: the 106th wall makes 10,006.
  expect_refused("pieces_in_all", "for i = #field.walls + 1, 106 do "
                                  "local p = {} for k = 1, 101 do p[k] = { k * 0.01, i * 0.001 } end "
                                  "field.walls[i] = { points = p } end", "walls[106].points");
  // The table's 4 names, then one a wall.
  expect_refused("named_walls", "for i = #field.walls + 1, 1003 do "
                                "field.walls[i] = { name = 'w' .. i, points = { { 0, 0 }, { 0.5, 0 } } } end", "walls");
  expect_refused("spots", "local s = { at = { 0, 0 } } for i = 1, 1001 do field.spots[i] = s end", "spots");
  expect_refused("goals", "local g = field.goals[1] for i = 1, 1001 do field.goals[i] = g end", "goals");
  expect_refused("bodies", "local b = field.bodies[1] for i = 1, 1001 do field.bodies[i] = b end", "bodies");
  expect_refused("areas", "field.areas = {} local a = { at = { 0, 0 }, radius = 1 } "
                          "for i = 1, 1e6 do field.areas[i] = a end", "areas");
}

// A field built in C++ meets the same limits before the engine builds anything for it.
TEST(HostileLimits, AFieldBuiltInCppIsHeldToTheSameLimits) {
  Field f = lua::load_field(QUANTUM_SOURCE_DIR "/rules/airhockey");
  const Segment piece = f.segments[0];
  f.segments.assign(limits::kMaxSegments + 1, piece);
  try {
    finish_field(f);
    FAIL() << "finished";
  } catch (const FieldError& e) {
    EXPECT_EQ(std::string(e.what()), "walls: 10001 wall pieces, more than the 10000 allowed");
  }
}

// The shipped sports load as they did, each with the 5 cm cells of its contact grid.
TEST(HostileLimits, TheShippedSportsLoadWithTheirOwnGrids) {
  for (const auto& entry : fs::directory_iterator(QUANTUM_SOURCE_DIR "/rules")) {
    if (!fs::exists(entry.path() / "sport.lua")) continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(lua::ScriptedRules sport(entry.path().string()));
    const Field field = lua::load_field(entry.path().string());
    const detail::Geometry geometry(field);
    EXPECT_EQ(geometry.cell, 0.05f);
    std::cout << "  " << entry.path().filename().string() << ": grid " << geometry.cols << " x " << geometry.rows
              << " cells, " << geometry.grid_bytes() << " bytes\n";
  }
}

}  // namespace
}  // namespace quantum

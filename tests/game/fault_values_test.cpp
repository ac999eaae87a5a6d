// Values from scripts (docs/reliability.md, "Faults"): NaN or infinite throw arguments are
// refused naming the argument. Those from the network: tests/tracking/fault_tracking_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "fault_sport.h"

namespace quantum {
namespace {

using namespace fault;

// The errors of a match on the basketball court (a field with height) whose first `give`, to
// Maya at the start, runs `call`; and the place of that call.
struct Thrown {
  std::string errors, place;
};
Thrown throw_with(const std::string& call) {
  const TempFolder folder;
  std::filesystem::copy_file(QUANTUM_SOURCE_DIR "/rules/basketball/field.lua", folder.path / "field.lua");
  const std::string file = (folder.path / "sport.lua").string();
  std::ofstream(file) << "local given = 0\nreturn { match = { start = 'Maya' }, on = { give = function(game, e)\n"
                      << "  given = given + 1\n  if given > 1 then return end\n  " << call << "  -- throws\nend } }\n";
  return {play(folder.path, 1).errors, place_of(file, "-- throws")};
}

void expect_refused(const std::string& call, const std::string& error) {
  SCOPED_TRACE(call);
  const Thrown t = throw_with(call);
  EXPECT_NE(t.errors.find("quantum: rules error: " + t.place + error), std::string::npos) << t.errors;
}

// elevation = 0/0 was taken as "none given", and the throw made.
TEST(FaultValues, ANaNOrInfiniteElevationIsRefusedNamingIt) {
  expect_refused("game.throw('Maya', 'basket', { elevation = 0/0 })",
                 "game.throw: argument 3.elevation: expected a finite number, got nan");
  expect_refused("game.throw('Maya', 'basket', { elevation = 1/0 })",
                 "game.throw: argument 3.elevation: expected a finite number, got inf");
  expect_refused("game.kick('Maya', 'Noah', { elevation = -1/0 })",
                 "game.kick: argument 3.elevation: expected a finite number, got -inf");
}

TEST(FaultValues, ANaNOrInfiniteSpeedOrSpreadIsRefusedNamingIt) {
  expect_refused("game.throw('Maya', 'Noah', { speed = 0/0 })", "game.throw: argument 3.speed: expected a finite number, got nan");
  expect_refused("game.throw('Maya', 'Noah', { spread = 1/0 })", "game.throw: argument 3.spread: expected a finite number, got inf");
  expect_refused("game.throw('Maya', 'Noah', { elevation_spread = 0/0 })",
                 "game.throw: argument 3.elevation_spread: expected a finite number, got nan");
}

// A direction or point not finite (a float's range passed is infinite) is the argument's fault,
// not "a throw's speed must be in (0, 1000] m/s, got nan".
TEST(FaultValues, ANaNOrInfiniteDirectionIsRefusedNamingIt) {
  expect_refused("game.throw('Maya', { 0/0, 1, 2 })", "game.throw: argument 2: a velocity must be finite, got {nan, 1, 2}");
  expect_refused("game.throw('Maya', { x = 1e300, y = 0 })", "game.throw: argument 2: a point must be finite, got {inf, 0, 0}");
  expect_refused("game.kick('Maya', { 3, 1/0 })", "game.kick: argument 2: a velocity must be finite, got {3, inf, 0}");
}

}  // namespace
}  // namespace quantum

// Field files: the air hockey table loads, and every kind of mistake names its file and place.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>

#include "quantum/contact.h"
#include "test_scenes.h"
#include "../shipped_sports.h"

namespace quantum {
namespace {

class FieldFile : public ::testing::Test {
 protected:
  std::string write(const std::string& text) {
    path_ = (std::filesystem::temp_directory_path() /
             ("field_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + ".lua"))
                .string();
    std::ofstream(path_) << text;
    return path_;
  }
  void TearDown() override { std::filesystem::remove(path_); }

  // The message load_field throws for `text`.
  std::string error_for(const std::string& text) {
    const std::string file = write(text);
    try {
      lua::load_field(file);
    } catch (const FieldError& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
      return e.what();
    }
    ADD_FAILURE() << "no error for: " << text;
    return "";
  }

  std::string path_;
};

const char* kValid = R"(return {
  walls = { { name = "north", points = { {-1, 0.5}, {1, 0.5} } } },
  goals = { { team = "a", from = {-1, -0.1}, to = {-1, 0.1} } },
  spots = { { at = {0, 0} } },
  bodies = { { team = "a", radius = 0.05, at = {-0.5, 0} } },
})";

TEST(Field, AirHockeyTableLoadsFromItsSportFolder) {
  const Field f = test::airhockey();
  EXPECT_EQ(f.name, "Quantum air hockey table");
  EXPECT_EQ(f.wall_names.size(), 4u);  // left, right and the two ends, each end in two pieces
  EXPECT_EQ(f.segments.size(), 6u);
  ASSERT_EQ(f.goals.size(), 2u);
  EXPECT_EQ(f.goals[0].team, "blue");
  EXPECT_EQ(f.spots.size(), 2u);
  ASSERT_EQ(f.bodies.size(), 2u);
  EXPECT_FLOAT_EQ(f.bodies[1].radius, 0.048f);
  EXPECT_FLOAT_EQ(f.ball_radius, 0.0315f);
  // Bounds derived from the walls, two ball radii out.
  EXPECT_NEAR(f.bounds_min.x, -1.063f, 1e-4);
  EXPECT_NEAR(f.bounds_max.y, 0.563f, 1e-4);
  EXPECT_EQ(lua::field_file(QUANTUM_SOURCE_DIR "/rules/airhockey"), QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua");
}

TEST_F(FieldFile, ValidMinimalFieldLoads) {
  const Field f = lua::load_field(write(kValid));
  EXPECT_EQ(f.wall_names[0], "north");
  EXPECT_EQ(f.goals[0].name, "a goal");
}

TEST_F(FieldFile, SyntaxErrorNamesFileAndLine) {
  const std::string e = error_for("return {\n  walls = {\n    { points = { {0, 0} {1, 1} } },\n}");
  EXPECT_NE(e.find(":3:"), std::string::npos) << e;
}

TEST_F(FieldFile, RuntimeErrorNamesFileAndLine) {
  const std::string e = error_for("local x = nil\n\nreturn { spots = { { at = { x.y, 0 } } } }");
  EXPECT_NE(e.find(":3:"), std::string::npos) << e;
}

TEST_F(FieldFile, WrongTypeNamesThePlace) {
  const std::string e = error_for(R"(return { walls = { { points = { {0, 0}, {1, "north"} } } }, spots = { { at = {0, 0} } } })");
  EXPECT_NE(e.find("walls[1].points[2]"), std::string::npos) << e;
  EXPECT_NE(e.find("expected a number for y, got string"), std::string::npos) << e;
}

TEST_F(FieldFile, ABoxAreaIsARectangleAndLandingsNeedHeight) {
  const Field f = lua::load_field(write(R"(return {
    gravity = 9.81, landings = true, bounds = { {-5, -5}, {5, 5} }, spots = { { at = {0, 0} } },
    areas = { { name = "court", team = "a", box = { {-2, -1}, {0, 1} } } },
  })"));
  ASSERT_EQ(f.areas.size(), 1u);
  EXPECT_TRUE(f.landings);
  EXPECT_TRUE(f.areas[0].box);
  EXPECT_EQ(f.area_at({-1.9f, 0.9f}), 0) << "a box holds its corners, not a capsule's round ends";
  EXPECT_EQ(f.area_at({0.1f, 0}), -1);
  EXPECT_NE(error_for(R"(return { spots = { { at = {0, 0} } }, areas = { { name = "x", box = { {0, 0}, {1, 1} }, radius = 1 } } })")
                .find("areas[1]: give either 'box' (a rectangle) or 'at' / 'from' and 'to' with 'radius'"),
            std::string::npos);
  EXPECT_NE(error_for(R"(return { spots = { { at = {0, 0} } }, areas = { { name = "x", box = { {0, 0} } } } })")
                .find("areas[1].box: expected two corners"),
            std::string::npos);
  EXPECT_NE(error_for(R"(return { spots = { { at = {0, 0} } }, landings = "yes" })").find("landings"), std::string::npos);
  EXPECT_NE(error_for(R"(return { spots = { { at = {0, 0} } }, landings = true })")
                .find("a ball lands only on a field with height"),
            std::string::npos);
}

TEST_F(FieldFile, ABodysZoneIsARectangle) {
  const Field f = lua::load_field(write(R"(return { spots = { { at = {0, 0} } }, bounds = { {-10, -6}, {10, 6} }, bodies = {
    { name = "Ann", team = "a", radius = 0.5, at = {-3, 0}, zone = { {-10, -6}, {0, 6} } },
    { name = "Bo", team = "a", radius = 0.5, at = {3, 0} } } })"));
  ASSERT_EQ(f.bodies.size(), 2u);
  EXPECT_TRUE(f.bodies[0].zoned);
  EXPECT_EQ(f.bodies[0].zone_min.x, -10.0f);
  EXPECT_EQ(f.bodies[0].zone_max.y, 6.0f);
  EXPECT_FALSE(f.bodies[1].zoned) << "no zone: the whole field";
  EXPECT_NE(error_for(R"(return { spots = { { at = {0, 0} } }, bodies = { { team = "a", radius = 1, at = {0, 0}, zone = { {1, 1}, {0, 2} } } } })")
                .find("bodies[1] (a body).zone: the first corner must be below and left of the second"),
            std::string::npos);
  EXPECT_NE(error_for(R"(return { spots = { { at = {0, 0} } }, bodies = { { team = "a", radius = 1, at = {0, 0}, zone = "left" } } })")
                .find("bodies[1].zone: expected two corners"),
            std::string::npos);
}

TEST_F(FieldFile, UnknownKeyIsReported) {
  const std::string e = error_for(R"(return { wals = {}, spots = { { at = {0, 0} } } })");
  EXPECT_NE(e.find("unknown key 'wals'"), std::string::npos) << e;
}

TEST_F(FieldFile, MissingRadiusNamesTheBody) {
  const std::string e = error_for(R"(return { spots = { { at = {0, 0} } }, bodies = { { team = "a", at = {0, 0} } } })");
  EXPECT_NE(e.find("bodies[1]: missing 'radius'"), std::string::npos) << e;
}

TEST_F(FieldFile, NumbersAreCheckedAfterReading) {
  const std::string e = error_for(R"(return { walls = { { name = "stub", points = { {0, 0}, {0, 0} } } }, spots = { { at = {0.5, 0} } } })");
  EXPECT_NE(e.find("walls[1] (stub)"), std::string::npos) << e;
  EXPECT_NE(e.find("shorter than 0.1 mm"), std::string::npos) << e;
  EXPECT_NE(error_for(R"(return { spots = {} })").find("at least one respawn spot"), std::string::npos);
  EXPECT_NE(error_for(R"(return { ball = { radius = -1 }, spots = { { at = {0, 0} } } })").find("ball.radius"),
            std::string::npos);
  EXPECT_NE(error_for(R"(return { ball = { audible_bounce = -0.1 }, spots = { { at = {0, 0} } } })")
                .find("ball.audible_bounce"),
            std::string::npos);
}

// A field of players who catch, with a spot but no walls, goals or bounds: the field is the spot
// alone, and a player standing elsewhere is named with what is missing.
TEST_F(FieldFile, APlayerOutsideTheFieldAsksForBounds) {
  const std::string e = error_for(R"(return { spots = { { at = {0, 0} } },
    bodies = { { name = "Alice", team = "a", radius = 0.7, catches = true, at = {-4, -3} } } })");
  EXPECT_NE(e.find("bodies[1] (Alice): starts outside the field (give the field `bounds`"), std::string::npos) << e;
  const std::string bounded = error_for(R"(return { bounds = { {-2, -2}, {2, 2} }, spots = { { at = {0, 0} } },
    bodies = { { name = "Alice", team = "a", radius = 0.7, catches = true, at = {-4, -3} } } })");
  EXPECT_NE(bounded.find("bodies[1] (Alice): starts outside the bounds"), std::string::npos) << bounded;
}

TEST_F(FieldFile, MustReturnATable) {
  EXPECT_NE(error_for("return 42").find("must return a table, returned number"), std::string::npos);
}

TEST_F(FieldFile, SandboxHasNoIo) {
  EXPECT_NE(error_for("io.open('/etc/passwd')").find("io"), std::string::npos);
  EXPECT_NE(error_for("return os.exit(1)").find("field 'exit'"), std::string::npos);  // os has only its clock
}

TEST_F(FieldFile, MathIsAvailable) {
  const Field f = lua::load_field(write("return { spots = { { at = { math.cos(0), 0 } } } }"));
  EXPECT_FLOAT_EQ(f.spots[0].at.x, 1.0f);
}

TEST_F(FieldFile, EndlessLoopIsStopped) {
  EXPECT_NE(error_for("while true do end").find("runs too long"), std::string::npos);
}

TEST_F(FieldFile, MemoryBombIsStopped) {
  EXPECT_NE(error_for("local s = 'x' for i = 1, 40 do s = s .. s end return {}").find("memory"), std::string::npos);
}

TEST_F(FieldFile, BytecodeIsRefused) {
  // LuaJIT bytecode starts with ESC 'L' 'J'; text mode loading must refuse it.
  const std::string e = error_for(std::string("\x1bLJ\x02\x00", 5));
  EXPECT_NE(e.find("binary"), std::string::npos) << e;
}

float distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
  const double t = l2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
  return float(std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy)));
}

// The contact grid is built per wall and goal over the cells near it, and the safe box grows in
// bulk: every point of every shipped field's grid must still list each wall and goal line that a
// ball there can reach within the grid's reach, and no ball inside the safe box may touch one.
TEST(Field, TheContactGridListsEveryWallABallCanReach) {
  std::mt19937 rng(7);
  int near_walls = 0;
  for (const std::string sport : quantum::test::kShippedSports) {
    SCOPED_TRACE(sport);
    const Field f = lua::load_field(QUANTUM_SOURCE_DIR "/rules/" + sport);
    const detail::Geometry g(f);
    std::uniform_real_distribution<float> x(f.bounds_min.x, f.bounds_max.x), y(f.bounds_min.y, f.bounds_max.y);
    for (int draw = 0; draw < 200000; ++draw) {
      const Vec2 p{x(rng), y(rng)};
      const detail::Geometry::Candidates c = g.candidates(p.x, p.y, 0);
      const std::vector<uint16_t> segments(c.segments, c.segments + c.n_segments), goals(c.goals, c.goals + c.n_goals);
      for (size_t k = 0; k < f.segments.size(); ++k) {
        if (distance_to_segment(p, f.segments[k].a, f.segments[k].b) > g.r + g.grid_reach) continue;
        ++near_walls;
        ASSERT_NE(std::find(segments.begin(), segments.end(), k), segments.end())
            << "wall " << k << " missing at (" << p.x << ", " << p.y << ")";
      }
      for (size_t k = 0; k < g.goal_id.size(); ++k) {
        const Goal& gl = f.goals[size_t(g.goal_id[k])];
        if (distance_to_segment(p, gl.a, gl.b) > g.grid_reach) continue;
        ASSERT_NE(std::find(goals.begin(), goals.end(), k), goals.end())
            << "goal line " << k << " missing at (" << p.x << ", " << p.y << ")";
      }
      if (g.safe.contains(p.x, p.y)) {
        for (const Segment& s : f.segments) ASSERT_GT(distance_to_segment(p, s.a, s.b), g.r) << "in the safe box";
      }
    }
    EXPECT_LT(g.safe.x0, g.safe.x1);
  }
  EXPECT_GT(near_walls, 1000);  // the draws did come near walls
}

TEST(Field, MissingFileIsNamed) {
  try {
    lua::load_field("/nonexistent/sport");
    FAIL() << "no error";
  } catch (const FieldError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/sport: no such field file"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace quantum

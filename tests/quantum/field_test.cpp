// Field files: the air hockey table loads, and every kind of mistake names its file and place.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_scenes.h"

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

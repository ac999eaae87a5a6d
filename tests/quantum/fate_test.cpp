// Fate prediction: terminal and path of single shots, report bookkeeping, tweaking.
#include <gtest/gtest.h>

#include "test_scenes.h"

namespace quantum {
namespace {

constexpr float kDt = 1.0f / 60;

// The fate of one particle shot from (x, y) with velocity (vx, vy); bodies at rest at `at`.
Fate fate_of(float x, float y, float vx, float vy, std::vector<Vec2> at = {}) {
  Field f = test::quiet_airhockey();
  if (at.empty()) f.bodies.clear();
  for (size_t k = 0; k < at.size(); ++k) f.bodies[k].start = at[k];
  World world(f, WorldConfig{.particles = 1});
  world.set_cloud(test::single(x, y, vx, vy));
  const FateReport r = world.predict();
  EXPECT_EQ(r.groups.size(), 1u);
  return r.groups[0].fate;
}

TEST(Fate, StraightShotScores) {
  const Fate f = fate_of(0, 0, 2, 0);
  EXPECT_EQ(f.kind, FateKind::Goal);
  EXPECT_EQ(f.target, 1);
  EXPECT_EQ(f.path_len, 0);
  EXPECT_EQ(describe(f, test::airhockey()), "goal (Red's goal)");
}

TEST(Fate, BankShotNamesTheWall) {
  // From (0, 0) to the red mouth's centre (1, 0) via the left wall (y = 0.5): the ball's centre
  // turns at y = 0.5 - r, halfway along x.
  const float turn_y = 0.5f - 0.0315f;
  const Fate f = fate_of(0, 0, 0.5f, turn_y);
  EXPECT_EQ(f.kind, FateKind::Goal);
  ASSERT_EQ(f.path_len, 1);
  EXPECT_EQ(describe(f, test::airhockey()), "goal (Red's goal) via left wall");
}

TEST(Fate, MalletInTheWayIntercepts) {
  const Fate f = fate_of(0, 0, 2, 0, {{-0.85f, 0}, {0.85f, 0}});
  EXPECT_EQ(f.kind, FateKind::Body);
  EXPECT_EQ(f.target, 1);
  EXPECT_EQ(describe(f, test::airhockey()), "Red's mallet");
}

TEST(Fate, SlowBallStaysInTheField) {
  const Fate f = fate_of(0, 0, 0.1f, 0);  // 30 cm in 3 s
  EXPECT_EQ(f.kind, FateKind::Field);
  EXPECT_EQ(describe(f, test::airhockey()), "stays in field");
}

TEST(Fate, LongRallyPathIsCappedAndMarked) {
  // Almost straight up and down: bounces between the side walls for the whole horizon.
  const Fate f = fate_of(0, 0, 0.02f, 3.0f);
  EXPECT_EQ(f.kind, FateKind::Field);
  EXPECT_EQ(f.path_len, kMaxPath);
  EXPECT_TRUE(f.path_more);
  EXPECT_EQ(describe(f, test::airhockey()), "stays in field via left wall, right wall, left wall, right wall, ...");
}

TEST(Fate, ShotIntoOwnGoalAfterATouchIsAnOwnGoal) {
  // Blue's mallet hits a resting puck toward Blue's own goal.
  Field f = test::quiet_airhockey();
  f.bodies[0].start = {-0.5f, 0};
  World world(f, WorldConfig{.particles = 1});
  world.set_cloud(test::single(-0.7f, 0, 0, 0));
  std::vector<BodyInput> in;
  std::vector<Event> events = test::strike(world, 0, {-0.5f, 0.0f}, {-1.5f, 0}, in);
  ASSERT_EQ(world.last_touch(), 0);
  in[0].velocity = {0, 0};
  world.step(kDt, in, events);  // the mallet stops; the puck flies on
  const FateReport r = world.predict();
  ASSERT_EQ(r.groups.size(), 1u);
  EXPECT_EQ(r.groups[0].fate.kind, FateKind::OwnGoal);
  EXPECT_EQ(describe(r.groups[0].fate, f), "own goal (Blue's goal)");
  // And the step agrees.
  events.clear();
  for (int s = 0; s < 60 && events.empty(); ++s) world.step(kDt, in, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::OwnGoal);
}

TEST(Fate, BodiesAreExtrapolatedForTheLookaheadThenHeld) {
  // A slow shot along y = 0 toward Red's goal, Red's mallet at y = -0.3 moving up at 1 m/s.
  // With a 0.25 s lookahead it stops at y = -0.05: still in the way (reach 0.0795).
  Field f = test::quiet_airhockey();
  WorldConfig config;
  config.particles = 1;
  World world(f, config);
  world.set_cloud(test::single(0.3f, 0, 1.0f, 0));
  std::vector<Event> events;
  std::vector<BodyInput> in = test::resting(f);
  in[1] = {{0.85f, -0.3f}, {0, 1.0f}};
  world.step(kDt, in, events);
  EXPECT_EQ(world.predict().groups[0].fate.kind, FateKind::Body);
  // With a 0.1 s lookahead it holds at y = -0.2: the shot goes past it.
  config.body_lookahead = 0.1f;
  World short_sighted(f, config);
  short_sighted.set_cloud(test::single(0.3f, 0, 1.0f, 0));
  short_sighted.step(kDt, in, events);
  EXPECT_EQ(short_sighted.predict().groups[0].fate.kind, FateKind::Goal);
}

// Prediction replays the next step's Brownian offsets: a ball at rest 3 cm from Red's mallet
// reaches it in the next step only when its noise pushes it that way, and the prediction must
// say so exactly, seed by seed (decisions draw on the particles that met something).
TEST(Fate, NextStepsNoiseDecidesAsPredicted) {
  Field f = test::airhockey();
  f.brownian = 0.3f;  // offsets of up to 6.7 cm a step
  const float gap = 0.03f, reach = f.bodies[1].radius + f.ball_radius;
  int met = 0;
  for (uint64_t seed = 1; seed <= 200; ++seed) {
    WorldConfig config;
    config.particles = 1;
    config.seed = seed;
    World world(f, config);
    world.set_cloud(test::single(0.85f - reach - gap, 0, 0, 0));
    const bool predicted = world.predict().groups[0].fate.kind == FateKind::Body;
    std::vector<Event> events;
    world.step(kDt, test::resting(f), events);
    const bool hit = !events.empty() && events[0].type == EventType::Hit && events[0].actor == 1;
    EXPECT_EQ(predicted, hit) << "seed " << seed;
    met += hit;
  }
  // Both ways happen often: the noise, not the scene, decides.
  EXPECT_GT(met, 20);
  EXPECT_LT(met, 180);
}

// Chunks of a large cloud are shared between two threads; which thread traces a chunk must not
// change a particle's fate or a group's mass.
TEST(Fate, ALargeCloudIsPredictedTheSameOnOneThreadOrTwo) {
  const Field f = test::airhockey();  // with its Brownian motion: the next step's noise is per particle
  std::vector<FateReport> reports;
  for (uint32_t threads : {1u, 2u, 2u}) {
    WorldConfig config;
    config.particles = 40'000, config.threads = threads, config.seed = 3;
    World world(f, config);
    Cloud cloud = test::fan(0.0f, 0.1f, 2.0f, -3.1f, 3.1f, 20'000);
    const Cloud slow = test::fan(-0.3f, -0.2f, 0.4f, -3.1f, 3.1f, 20'000);
    for (size_t i = 0; i < slow.size(); ++i) cloud.push_from(slow, i);
    world.set_cloud(cloud);
    std::vector<BodyInput> in = test::resting(f);
    in[0].velocity = {1.5f, 0.5f}, in[1].velocity = {-1.0f, -0.8f};  // extrapolated for the lookahead
    world.place_bodies(in);
    reports.push_back(world.predict(3.0f));
  }
  const FateReport& one = reports[0];
  ASSERT_GE(one.groups.size(), 6u) << "a fan all round meets walls, goals and both mallets";
  for (const FateReport& r : {reports[1], reports[2]}) {
    ASSERT_EQ(r.groups.size(), one.groups.size());
    ASSERT_EQ(r.group_of, one.group_of);
    for (size_t g = 0; g < one.groups.size(); ++g) {
      EXPECT_EQ(r.groups[g].fate.key(), one.groups[g].fate.key());
      EXPECT_EQ(r.groups[g].mass, one.groups[g].mass);
      EXPECT_EQ(r.groups[g].tweaked_mass, one.groups[g].tweaked_mass);
      EXPECT_EQ(r.groups[g].count, one.groups[g].count);
      EXPECT_EQ(r.groups[g].representative, one.groups[g].representative);
    }
  }
}

TEST(Fate, ReportGroupsCountsMassesAndPaths) {
  const Field f = test::quiet_airhockey();
  WorldConfig config;
  config.particles = 300;
  World world(f, config);
  world.set_cloud(test::fan(0.2f, 0, 2.0f, -1.2f, 1.2f, 300));
  const FateReport r = world.predict(3.0f);
  ASSERT_GE(r.groups.size(), 3u);
  double mass = 0, tweaked = 0;
  uint32_t count = 0;
  for (size_t g = 0; g < r.groups.size(); ++g) {
    const FateGroup& group = r.groups[g];
    mass += group.mass, tweaked += group.tweaked_mass, count += group.count;
    EXPECT_DOUBLE_EQ(group.mass, group.tweaked_mass);  // nothing tweaked yet
    EXPECT_EQ(r.group_of[group.representative], g);
    // The representative's path, drawn on demand, shows the group's way.
    const std::vector<Vec3> path = world.predict_path(group.representative, 3.0f);
    ASSERT_GE(path.size(), 2u);
    EXPECT_FLOAT_EQ(path.front().x, 0.2f);
    EXPECT_GE(path.size(), size_t(group.fate.path_len) + 2);  // start, walls, end
    if (group.fate.kind == FateKind::Goal) {
      EXPECT_NEAR(std::fabs(path.back().x), 1.0f, 1e-4);
    }
  }
  EXPECT_NEAR(mass, 1.0, 1e-12);
  EXPECT_NEAR(tweaked, 1.0, 1e-12);
  EXPECT_EQ(count, 300u);
  for (size_t i = 0; i < world.cloud().size(); ++i) EXPECT_LT(r.group_of[i], r.groups.size());
}

TEST(Fate, TweakMultipliesByFateAndKeepsTheNewtonianMass) {
  const Field f = test::quiet_airhockey();
  World world(f, WorldConfig{.particles = 300});
  world.set_cloud(test::fan(0.2f, 0, 2.0f, -1.2f, 1.2f, 300));
  FateReport r = world.predict();
  const std::vector<double> newtonian = world.cloud().w;
  const KindFactors paper;
  const std::vector<double> factors = factors_by_kind(r, paper);
  world.tweak(r, factors);
  double norm = 0;
  for (size_t g = 0; g < r.groups.size(); ++g) norm += r.groups[g].mass * factors[g];
  double tweaked = 0;
  for (size_t g = 0; g < r.groups.size(); ++g) {
    EXPECT_NEAR(r.groups[g].tweaked_mass, r.groups[g].mass * factors[g] / norm, 1e-12);
    tweaked += r.groups[g].tweaked_mass;
  }
  EXPECT_NEAR(tweaked, 1.0, 1e-12);
  EXPECT_EQ(world.cloud().w, newtonian);
  EXPECT_NEAR(test::tweaked_sum(world.cloud()), 1.0, 1e-12);
  // A new prediction sees the tweak as tweaked mass and the untouched Newtonian mass.
  const FateReport again = world.predict();
  for (size_t g = 0; g < r.groups.size(); ++g) {
    EXPECT_NEAR(again.groups[g].mass, r.groups[g].mass, 1e-12);
    EXPECT_NEAR(again.groups[g].tweaked_mass, r.groups[g].tweaked_mass, 1e-12);
  }
}

TEST(Fate, BadTweaksAreRefused) {
  World world(test::quiet_airhockey(), WorldConfig{.particles = 10});
  world.set_cloud(test::fan(0.2f, 0, 2.0f, -1.2f, 1.2f, 10));
  FateReport r = world.predict();
  EXPECT_THROW(world.tweak(r, std::vector<double>(r.groups.size() + 1, 1.0)), std::invalid_argument);
  EXPECT_THROW(world.tweak(r, std::vector<double>(r.groups.size(), -1.0)), std::invalid_argument);
  EXPECT_THROW(world.tweak(r, std::vector<double>(r.groups.size(), NAN)), std::invalid_argument);
  EXPECT_THROW(world.tweak(r, std::vector<double>(r.groups.size(), 0.0)), std::invalid_argument);
  EXPECT_NEAR(test::tweaked_sum(world.cloud()), 1.0, 1e-12);
  std::vector<Event> events;
  world.step(kDt, test::resting(world.field()), events);
  EXPECT_THROW(world.tweak(r, std::vector<double>(r.groups.size(), 1.0)), std::logic_error);
  EXPECT_THROW(world.predict(-1), std::invalid_argument);
}

}  // namespace
}  // namespace quantum

namespace quantum {
namespace {

// Wormholes: a ball whose centre enters one mouth leaves the other at the same offset and
// velocity. A shot along the left side (y = 0.35, at Red's end wall, no goal) goes through a
// mouth at (-0.2, 0.35) and comes out of one at (0.7, 0), straight at Red's goal: prediction
// says goal, and stepping scores it. Without the wormhole the same shot bounces off the end wall.
TEST(Wormhole, ABallGoesThroughAndPredictionKnows) {
  Field f = test::quiet_airhockey();
  f.bodies.clear();
  World world(f, WorldConfig{.particles = 1});
  world.set_cloud(test::single(-0.5f, 0.35f, 2.0f, 0));
  EXPECT_EQ(world.predict().groups.at(0).fate.kind, FateKind::Field);  // off the end wall, and on
  world.set_wormholes({{{-0.2f, 0.35f}, {0.7f, 0.0f}, 0.05f}});
  const FateReport r = world.predict();
  ASSERT_EQ(r.groups.size(), 1u);
  EXPECT_EQ(r.groups[0].fate.kind, FateKind::Goal);
  EXPECT_EQ(r.groups[0].fate.target, 1);
  EXPECT_EQ(r.groups[0].fate.path_len, 0);  // a wormhole is no wall
  std::vector<Event> events;
  for (int s = 0; s < 60 && events.empty(); ++s) world.step(kDt, {}, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Goal);
  EXPECT_NEAR(events[0].at.y, 0.0f, 1e-3);  // it came out of the mouth at (0.7, 0)
}

TEST(Wormhole, ComingOutOfAMouthIsNotGoingBackIn) {
  Field f = test::quiet_airhockey();
  f.bodies.clear();
  World world(f, WorldConfig{.particles = 1});
  world.set_wormholes({{{-0.5f, 0.0f}, {0.3f, 0.2f}, 0.08f}});
  world.set_cloud(test::single(-0.8f, 0.0f, 1.0f, 0));
  std::vector<Event> events;
  for (int s = 0; s < 30; ++s) world.step(kDt, {}, events);
  // Entered at x = -0.58 after 0.22 s, out at x = 0.22 on y = 0.2, then straight on through the
  // exit mouth and beyond it (0.28 s at 1 m/s).
  const Cloud& c = world.cloud();
  EXPECT_NEAR(c.y[0], 0.2f, 1e-4);
  EXPECT_NEAR(c.x[0], 0.22f + 1.0f * (30 * kDt - 0.22f), 2e-3);
  EXPECT_NEAR(c.vx[0], 1.0f, 1e-6);
  EXPECT_TRUE(events.empty());
}

TEST(Wormhole, BadMouthsAreRefused) {
  Field f = test::quiet_airhockey();
  World world(f, WorldConfig{.particles = 1});
  EXPECT_THROW(world.set_wormholes({{{0.0f, 0.48f}, {0.3f, 0.0f}, 0.05f}}), std::invalid_argument);  // at a wall
  EXPECT_THROW(world.set_wormholes({{{0.0f, 3.0f}, {0.3f, 0.0f}, 0.05f}}), std::invalid_argument);   // off the field
  EXPECT_THROW(world.set_wormholes({{{0.0f, 0.0f}, {0.3f, 0.0f}, 0.0f}}), std::invalid_argument);    // no radius
  EXPECT_NO_THROW(world.set_wormholes({}));
}

}  // namespace
}  // namespace quantum

// The particle rules of the paper, one at a time: initialization, splitting, Brownian motion,
// walls, goal mouths, bodies, purgatory, deletion, variation at a collision, no interaction.
#include <gtest/gtest.h>

#include <algorithm>

#include "test_scenes.h"

namespace quantum {
namespace {

constexpr float kDt = 1.0f / 60;

TEST(Step, DropStartsOneParticleThatSplitsUpToTheTarget) {
  WorldConfig config;
  config.particles = 1000;
  World world(test::airhockey(), config);
  std::vector<Event> events;
  world.drop(0, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Drop);
  ASSERT_EQ(world.cloud().size(), 1u);
  EXPECT_DOUBLE_EQ(world.cloud().weight(0), 1.0);
  EXPECT_FLOAT_EQ(world.cloud().x[0], -0.5f);
  // One split round per step: 2, 4, ... 512, then the last round stops at the target.
  for (size_t k = 1; k <= 9; ++k) {
    world.step(kDt, test::resting(world.field()), events);
    EXPECT_EQ(world.cloud().size(), size_t(1) << k);
    EXPECT_NEAR(test::weight_sum(world.cloud()), 1.0, 1e-12);
  }
  world.step(kDt, test::resting(world.field()), events);
  EXPECT_EQ(world.cloud().size(), 1000u);
  world.step(kDt, test::resting(world.field()), events);
  EXPECT_EQ(world.cloud().size(), 1000u);
  // Only particles above the threshold (1/1000) split: 24 of weight 1/512 stayed whole... and
  // then split too once the cloud had room; weights stay within a factor of two of each other.
  const auto [lo, hi] = std::minmax_element(world.cloud().w.begin(), world.cloud().w.end());
  EXPECT_LE(*hi / *lo, 2.0 + 1e-9);
}

TEST(Step, BrownianMotionSpreadsLikeDiffusion) {
  // 20,000 resting particles in the middle of a table with Brownian motion D = 0.05 m/sqrt(s):
  // after 1 s each axis has variance D^2 t = 0.0025 m^2. The sample variance of 20,000 draws has
  // a relative standard error of 1%; the bound is 5%.
  Field f = test::airhockey();
  f.bodies.clear();
  WorldConfig config;
  config.particles = 20000;
  World world(f, config);
  Cloud c;
  for (int i = 0; i < 20000; ++i) c.push(0, 0, 0, 0, 1, 1);
  world.set_cloud(c);
  std::vector<Event> events;
  for (int s = 0; s < 60; ++s) world.step(kDt, {}, events);
  double mx = 0, my = 0, vx = 0, vy = 0;
  const Cloud& out = world.cloud();
  for (size_t i = 0; i < out.size(); ++i) mx += out.x[i], my += out.y[i];
  mx /= out.size(), my /= out.size();
  for (size_t i = 0; i < out.size(); ++i) vx += (out.x[i] - mx) * (out.x[i] - mx), vy += (out.y[i] - my) * (out.y[i] - my);
  vx /= out.size() - 1, vy /= out.size() - 1;
  EXPECT_NEAR(vx, 0.0025, 0.05 * 0.0025);
  EXPECT_NEAR(vy, 0.0025, 0.05 * 0.0025);
  EXPECT_NEAR(mx, 0.0, 0.002);  // standard error 0.00035
  EXPECT_TRUE(events.empty());
}

TEST(Step, WallReflectsWithRestitution) {
  Field f = test::quiet_airhockey();
  f.bodies.clear();
  World world(f, WorldConfig{.particles = 1});
  world.set_cloud(test::single(0, 0.3f, 0, 2.0f));  // toward the left wall at y = 0.5
  std::vector<Event> events;
  for (int s = 0; s < 12; ++s) world.step(kDt, {}, events);
  const Cloud& c = world.cloud();
  EXPECT_NEAR(c.vy[0], -2.0f * f.wall_restitution, 1e-5);
  EXPECT_NEAR(c.vx[0], 0.0f, 1e-6);
  EXPECT_LE(c.y[0], 0.5f - f.ball_radius + 1e-5f);
  // It touched the wall after (0.5 - r - 0.3) / 2 s and then came back at 1.8 m/s.
  const float t_hit = (0.5f - f.ball_radius - 0.3f) / 2.0f;
  EXPECT_NEAR(c.y[0], 0.5f - f.ball_radius - 1.8f * (12 * kDt - t_hit), 1e-4);
  // The whole ball bounced, so the bounce is certain, announced once, at the wall.
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Bounce);
  EXPECT_EQ(f.wall_names[events[0].actor], "left wall");
  EXPECT_DOUBLE_EQ(events[0].p, 1.0);
  EXPECT_NEAR(events[0].t, std::ceil(t_hit / kDt) * kDt, 1e-6);
  EXPECT_NEAR(events[0].at.y, 0.5f - f.ball_radius, 2.0f * kDt);
  EXPECT_NEAR(events[0].velocity.y, -1.8f, 1e-4);
}

TEST(Step, CrossingAGoalMouthIsAGoal) {
  Field f = test::quiet_airhockey();
  f.bodies.clear();
  World world(f, WorldConfig{.particles = 1});
  world.set_cloud(test::single(0.5f, 0.0f, 3.0f, 0));
  std::vector<Event> events;
  for (int s = 0; s < 30 && events.empty(); ++s) world.step(kDt, {}, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Goal);
  EXPECT_EQ(f.goals[events[0].actor].name, "Red's goal");
  EXPECT_DOUBLE_EQ(events[0].p, 1.0);  // the whole ball went in
  EXPECT_NEAR(events[0].at.x, 1.0f, 1e-4);
  EXPECT_FALSE(world.live());
  EXPECT_TRUE(world.cloud().empty());
}

TEST(Step, BallBesideTheMouthBouncesOffTheEndWall) {
  Field f = test::quiet_airhockey();
  f.bodies.clear();
  World world(f, WorldConfig{.particles = 1});
  world.set_cloud(test::single(0.5f, 0.3f, 3.0f, 0));
  std::vector<Event> events;
  for (int s = 0; s < 20; ++s) world.step(kDt, {}, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Bounce);
  EXPECT_EQ(f.wall_names[events[0].actor], "Red's end");
  EXPECT_LT(world.cloud().vx[0], 0);
}

TEST(Step, MovingMalletTransfersItsVelocity) {
  // A resting puck, Red's mallet coming at it at 2 m/s along -x. Head on, an infinitely heavy
  // mallet with restitution e sends it off at (1 + e) * 2 m/s.
  const Field f = test::quiet_airhockey();
  World world(f, WorldConfig{.particles = 1});
  world.set_cloud(test::single(0.5f, 0.0f, 0, 0));
  std::vector<BodyInput> in;
  const std::vector<Event> events = test::strike(world, 1, {0.7f, 0.0f}, {-2.0f, 0}, in);
  const Vec2 red = in[1].position;
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Hit);
  EXPECT_EQ(events[0].actor, 1);
  EXPECT_DOUBLE_EQ(events[0].p, 1.0);
  EXPECT_EQ(world.last_touch(), 1);
  const Cloud& c = world.cloud();
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c.vx[0], -2.0f * (1 + f.body_restitution), 1e-4);
  EXPECT_NEAR(c.vy[0], 0.0f, 1e-5);
  EXPECT_LT(c.x[0], red.x - f.bodies[1].radius - f.ball_radius + 1e-5f);
}

// A column of resting particles in front of Blue's goal that Blue's mallet sweeps up through.
// Their tweaked weight is zero and so is the mallet's contact factor, so every draw is a
// rejection and purgatory and deletion can be watched; one far-away particle carries all the
// tweaked weight.
struct Sweep {
  explicit Sweep(uint32_t purgatory_frames) : world(test::quiet_airhockey(), config(purgatory_frames)) {
    Cloud c;
    c.push(0.5f, 0, 0, 0, 1, 1);
    for (int i = 1; i < 100; ++i) c.push(-0.6f, -0.3f + 0.006f * float(i), 0, 0, 1, 0);
    world.set_cloud(c);
    std::vector<double> contacts = world.contact_factors();
    contacts[0] = 0;  // Blue's mallet
    world.set_contact_factors(contacts);
  }
  static WorldConfig config(uint32_t frames) {
    WorldConfig c;
    c.particles = 100;
    c.purgatory_frames = frames;
    return c;
  }
  // The mallet moves up the line x = -0.6 at 3 m/s, or holds.
  void step(std::vector<Event>& events, bool moving = true) {
    std::vector<BodyInput> in = test::resting(world.field());
    if (moving) y += 3.0f * kDt;
    in[0] = {{-0.6f, y}, {0, moving ? 3.0f : 0.0f}};
    world.step(kDt, in, events);
  }
  World world;
  float y = -0.4f;
};

TEST(Step, SweptParticlesWaitInPurgatoryForTheConfiguredFrames) {
  Sweep sweep(5);
  std::vector<Event> events;
  for (int s = 0; s < 10; ++s) sweep.step(events);
  EXPECT_TRUE(events.empty());
  EXPECT_GT(sweep.world.purgatory_size(0), 0u);
  // The mallet stops: nothing new is touched, and the last contacts fall out after five steps.
  for (int s = 0; s < 4; ++s) sweep.step(events, false);
  EXPECT_GT(sweep.world.purgatory_size(0), 0u);
  sweep.step(events, false);
  EXPECT_EQ(sweep.world.purgatory_size(0), 0u);
}

TEST(Step, PurgatoryLengthIsConfigurable) {
  Sweep one(1), six(6);
  std::vector<Event> events;
  for (int s = 0; s < 4; ++s) one.step(events), six.step(events);
  EXPECT_GT(one.world.purgatory_size(0), 0u);
  EXPECT_LT(one.world.purgatory_size(0), six.world.purgatory_size(0));
}

TEST(Step, RejectedContactsLeaveTheCloudAndSplittingRefillsIt) {
  Sweep sweep(3);
  std::vector<Event> events;
  for (int s = 0; s < 3; ++s) sweep.step(events);
  ASSERT_TRUE(events.empty());
  ASSERT_GT(sweep.world.purgatory_size(0), 0u);
  // Deleted, then split rounds bring the count back.
  EXPECT_EQ(sweep.world.cloud().size(), 100u);
  EXPECT_NEAR(test::weight_sum(sweep.world.cloud()), 1.0, 1e-12);
  EXPECT_NEAR(test::tweaked_sum(sweep.world.cloud()), 1.0, 1e-12);
  // No survivor sits where the mallet is: the players know the ball is not there.
  for (size_t i = 0; i < sweep.world.cloud().size(); ++i) {
    const float dx = sweep.world.cloud().x[i] + 0.6f;
    const float dy = sweep.world.cloud().y[i] - sweep.y;
    EXPECT_GE(std::hypot(dx, dy), 0.048f + 0.0315f - 1e-5f);
  }
}

TEST(Step, ParticlesSplitAtACollisionLeaveInSlightlyDifferentDirections) {
  const Field f = test::quiet_airhockey();
  WorldConfig config;
  config.particles = 200;
  config.split_jitter = 0.05f;
  World world(f, config);
  world.set_cloud(test::single(0.5f, 0.0f, 0, 0));
  std::vector<BodyInput> in;
  ASSERT_EQ(test::strike(world, 1, {0.7f, 0.0f}, {-2.0f, 0}, in).size(), 1u);
  const Cloud& c = world.cloud();
  ASSERT_EQ(c.size(), 200u);  // split back to the target at once
  float lo = 10, hi = -10;
  for (size_t i = 0; i < c.size(); ++i) {
    const float a = std::atan2(c.vy[i], -c.vx[i]);
    lo = std::min(lo, a), hi = std::max(hi, a);
    EXPECT_NEAR(std::hypot(c.vx[i], c.vy[i]), 3.6f, 1e-3);  // turned, not slowed
  }
  // Up to eight generations of splits, each turning by at most 0.05 rad.
  EXPECT_GT(hi - lo, 0.02f);
  EXPECT_LT(std::max(-lo, hi), 8 * 0.05f + 1e-4f);
}

TEST(Step, ParticlesDoNotInteract) {
  // Two particles on crossing paths move exactly as each does alone.
  Field f = test::quiet_airhockey();
  f.bodies.clear();
  auto run = [&](const Cloud& c) {
    World world(f, WorldConfig{.particles = uint32_t(c.size())});
    world.set_cloud(c);
    std::vector<Event> events;
    for (int s = 0; s < 30; ++s) world.step(kDt, {}, events);
    return world.cloud();
  };
  Cloud both;
  both.push(-0.3f, 0, 1.0f, 0, 0.5, 0.5);
  both.push(0.3f, 0, -1.0f, 0, 0.5, 0.5);
  const Cloud together = run(both);
  const Cloud a = run(test::single(-0.3f, 0, 1.0f, 0)), b = run(test::single(0.3f, 0, -1.0f, 0));
  EXPECT_EQ(together.x[0], a.x[0]);
  EXPECT_EQ(together.x[1], b.x[0]);
  EXPECT_EQ(together.vx[0], a.vx[0]);
  EXPECT_EQ(together.vx[1], b.vx[0]);
}

TEST(Step, BadBodyInputIsRejectedAndChangesNothing) {
  World world(test::airhockey(), WorldConfig{});
  std::vector<Event> events;
  world.drop(0, events);
  world.step(kDt, test::resting(world.field()), events);
  const Cloud before = world.cloud();
  auto expect_error = [&](std::vector<BodyInput> in, float dt, const std::string& words) {
    try {
      world.step(dt, in, events);
      ADD_FAILURE() << "accepted: " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  std::vector<BodyInput> in = test::resting(world.field());
  in[1].position.x = NAN;
  expect_error(in, kDt, "body 1 (Red's mallet): position (nan, 0.000000) is not finite");
  in[1].position = {INFINITY, 0};
  expect_error(in, kDt, "is not finite");
  in[1].position = {500, 0};
  expect_error(in, kDt, "is far outside the field");
  in[1] = {{0.8f, 0}, {0, 1e6f}};
  expect_error(in, kDt, "above the field's max_body_speed");
  in[1].velocity = {NAN, 0};
  expect_error(in, kDt, "velocity is not finite");
  expect_error(test::resting(world.field()), NAN, "step length");
  expect_error(test::resting(world.field()), -1, "step length");
  expect_error({}, kDt, "the field has 2 bodies but the input moves 0");
  EXPECT_EQ(world.cloud().x, before.x);
  EXPECT_EQ(world.cloud().w, before.w);
  EXPECT_EQ(world.steps(), 1u);
}

TEST(Step, BadCloudIsRejected) {
  World world(test::airhockey(), WorldConfig{});
  EXPECT_THROW(world.set_cloud(test::single(NAN, 0, 0, 0)), std::invalid_argument);
  EXPECT_THROW(world.set_cloud(test::single(5, 0, 0, 0)), std::invalid_argument);
  EXPECT_THROW(world.set_cloud(test::single(0, 0.49f, 0, 0)), std::invalid_argument);  // inside the left wall
  EXPECT_THROW(world.set_cloud(Cloud{}), std::invalid_argument);
  std::vector<Event> events;
  EXPECT_THROW(world.drop(7, events), std::invalid_argument);
}

}  // namespace
}  // namespace quantum

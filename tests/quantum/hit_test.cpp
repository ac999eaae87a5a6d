// Hits (BodySpec::hits): a touch that sends the ball on at once without holding it (a dig, a
// header). The hitter's plan (World::plan_hit) or else its motion says where the ball goes, and
// the ball passes through the hitter for Field::rehit seconds afterwards.
#include <gtest/gtest.h>

#include <cmath>

#include "field_loader.h"
#include "test_scenes.h"

namespace quantum {
namespace {

constexpr float kDt = 1.0f / 60;

// An open floor 20 m square with two players who hit, A above the middle line and B below it.
Field floor_of_hitters(bool hits = true) {
  Field f;
  f.name = "hitters";
  f.ball_radius = 0.1f;
  f.bounds_min = {-10, -10}, f.bounds_max = {10, 10}, f.has_bounds = true;
  f.spots.push_back({"middle", "", {0, 0}});
  for (const auto& [name, team, y] : {std::tuple{"A", "blue", 1.0f}, {"B", "red", -1.0f}}) {
    BodySpec b;
    b.name = name, b.team = team, b.radius = 0.6f, b.start = {0, y}, b.hits = hits;
    f.bodies.push_back(b);
  }
  return f;
}

std::vector<BodyInput> standing(const Field& f) { return test::resting(f); }

// The velocity of a cloud's particles: weighted mean, and the spread of their directions (rad).
struct Motion {
  Vec2 mean;
  double direction_sd = 0;
};
Motion motion_of(const Cloud& c) {
  Motion m;
  for (size_t i = 0; i < c.size(); ++i) m.mean.x += float(c.weight(i) * c.vx[i]), m.mean.y += float(c.weight(i) * c.vy[i]);
  const double heading = std::atan2(m.mean.y, m.mean.x);
  double var = 0;
  for (size_t i = 0; i < c.size(); ++i) {
    const double d = std::remainder(std::atan2(c.vy[i], c.vx[i]) - heading, 2 * M_PI);
    var += c.weight(i) * d * d;
  }
  m.direction_sd = std::sqrt(var);
  return m;
}

// Steps until the first event that ends a flight or touches the ball; a Drop when none came.
Event first_event(World& world, const std::vector<BodyInput>& bodies, int steps = 300) {
  std::vector<Event> events;
  for (int s = 0; s < steps; ++s) {
    events.clear();
    world.step(kDt, bodies, events);
    for (const Event& e : events)
      if (e.type == EventType::Hit || e.type == EventType::Out || e.type == EventType::Catch) return e;
  }
  return {0, EventType::Drop, -1, 0, 0, 0, {}, {}};
}

TEST(Hit, APlannedHitSendsTheBallOnAtOnceScatteredByTheSpread) {
  const Field f = floor_of_hitters();
  World world(f, WorldConfig{.particles = 2000, .seed = 3});
  world.place_bodies(standing(f));
  world.set_cloud(test::single(-4, 1, 6, 0));  // straight at A
  HitPlan plan;
  plan.kind = HitPlan::Kind::Velocity, plan.velocity = {0, 7, 0}, plan.spread = {0.05f, 0.1f, 0};
  world.plan_hit(0, plan);
  const FateReport report = world.predict(3.0f);
  ASSERT_EQ(report.groups.size(), 1u);
  EXPECT_EQ(report.groups[0].fate.kind, FateKind::Hit);
  EXPECT_EQ(describe(report.groups[0].fate, f), "hit by A");
  const Event e = first_event(world, standing(f));
  ASSERT_EQ(e.type, EventType::Hit);
  EXPECT_EQ(e.actor, 0);
  EXPECT_TRUE(world.live()) << "a hit holds nothing: the ball flies on";
  EXPECT_EQ(world.holder(), -1);
  EXPECT_EQ(world.last_touch(), 0);
  const Motion m = motion_of(world.cloud());
  EXPECT_NEAR(m.mean.x, 0, 0.1);
  EXPECT_NEAR(m.mean.y, 7, 0.1);
  EXPECT_NEAR(e.velocity.y, 7, 0.1) << "the event says where the ball went";
  EXPECT_NEAR(m.direction_sd, 0.05, 0.005) << "the spread scatters every particle afresh";
  EXPECT_EQ(world.planned_hit(0).kind, HitPlan::Kind::Motion) << "one touch uses the plan up";
  EXPECT_TRUE(world.passes_now(0));
}

// A point aimed at, with height: a dig met anywhere on the way goes to the other court.
TEST(Hit, APointPlannedWithHeightComesDownThere) {
  Field f = lua::load_field(QUANTUM_SOURCE_DIR "/tests/sports/court");
  for (BodySpec& b : f.bodies) b.catches = false, b.hits = true;
  World world(f, WorldConfig{.particles = 1000, .seed = 5});
  const std::vector<BodyInput> bodies = {{{-3, 0}, {0, 0}}, {{9, 6}, {0, 0}}};
  world.place_bodies(bodies);
  Cloud c;
  c.push(Vec3{-5, 0, 2}, Vec3{3, 0, 1}, 1, 1);  // a serve dropping onto Ada
  world.set_cloud(c);
  HitPlan plan;
  plan.kind = HitPlan::Kind::Point, plan.point = {3, 0, 0}, plan.elevation = 0.8f;  // a lob over the net
  world.plan_hit(0, plan);
  const Event e = first_event(world, bodies);
  ASSERT_EQ(e.type, EventType::Hit);
  const FateReport report = world.predict(5.0f);
  double red = 0;
  for (const FateGroup& g : report.groups)
    if (g.fate.kind == FateKind::Landing && g.fate.target == 1) red += g.mass;
  EXPECT_GT(red, 0.8) << "most of the hit comes down in Red's court";
}

// Without a plan a hit is a mallet's shot: the particles bounce off the hitter's motion, and the
// cloud keeps the variation it came with, particle for particle.
TEST(Hit, AnUnplannedHitIsAShotOffTheHittersMotion) {
  auto after = [](bool hits) {
    const Field f = floor_of_hitters(hits);
    World world(f, WorldConfig{.particles = 500, .seed = 9});
    std::vector<BodyInput> bodies = standing(f);
    bodies[0].velocity = {-2, 0};
    world.place_bodies(bodies);
    world.set_cloud(test::fan(-4, 1, 6, -0.1f, 0.1f, 500));
    const Event e = first_event(world, bodies);
    EXPECT_EQ(e.type, EventType::Hit);
    return world.cloud();
  };
  const Cloud hit = after(true), shot = after(false);
  ASSERT_EQ(hit.size(), shot.size());
  for (size_t i = 0; i < hit.size(); ++i) {
    ASSERT_EQ(hit.x[i], shot.x[i]) << i;
    ASSERT_EQ(hit.vx[i], shot.vx[i]) << i;
    ASSERT_EQ(hit.vy[i], shot.vy[i]) << i;
    ASSERT_EQ(hit.w[i], shot.w[i]) << i;
  }
  EXPECT_GT(motion_of(hit).direction_sd, 0.05) << "the fan's spread is kept";
}

// A hitter running with the ball it just hit does not meet it again within the field's rehit
// window; once the window closes it does.
TEST(Hit, TheBallPassesThroughTheHitterForTheRehitWindow) {
  Field f = floor_of_hitters();
  f.rehit = 0.4f;
  World world(f, WorldConfig{.particles = 200, .seed = 2});
  std::vector<BodyInput> bodies = standing(f);
  world.place_bodies(bodies);
  world.set_cloud(test::single(-4, 1, 6, 0));
  HitPlan plan;
  plan.kind = HitPlan::Kind::Velocity, plan.velocity = {1, 0, 0}, plan.spread = {0, 0, 0};
  world.plan_hit(0, plan);
  const Event first = first_event(world, bodies);
  ASSERT_EQ(first.type, EventType::Hit);
  // A walks on after the ball, slower than it: the ball comes back into A.
  std::vector<Event> events;
  double again = -1;
  for (int s = 0; s < 60 && again < 0; ++s) {
    bodies[0].position.x += 0.5f * kDt, bodies[0].velocity = {0.5f, 0};
    events.clear();
    world.step(kDt, bodies, events);
    for (const Event& e : events)
      if (e.type == EventType::Hit && again < 0) again = e.t;
  }
  ASSERT_GT(again, 0) << "the hitter meets the ball again once the window closes";
  EXPECT_GE(again - first.t, f.rehit - 1e-6);
  EXPECT_LT(again - first.t, f.rehit + 2 * kDt);
}

// Realized hits follow the tweaked probabilities: A's hit three times likelier, B's as it is, a
// ball between them half as likely, over 2,000 seeded worlds; chi-square goodness of fit,
// rejected only at p < 0.001.
TEST(Hit, RealizedHitsFollowTheTweakedProbabilities) {
  const Field f = floor_of_hitters();
  const Cloud fan = test::fan(-4, 0, 6, -0.45f, 0.45f, 301);
  WorldConfig config;
  config.particles = uint32_t(fan.size());
  World scene(f, config);
  scene.place_bodies(standing(f));
  scene.set_cloud(fan);
  FateReport report = scene.predict(3.0f);
  test::tweak_by(scene, report, [](const Fate& fate) { return fate.kind == FateKind::Hit ? fate.target == 0 ? 3 : 1 : 0.5; });
  auto what = [&](FateKind kind, int target) { return kind == FateKind::Hit ? f.bodies[size_t(target)].name : "out"; };
  std::map<std::string, double> expected;
  for (const FateGroup& g : report.groups) {
    ASSERT_TRUE(g.fate.kind == FateKind::Hit || g.fate.kind == FateKind::Out) << describe(g.fate, f);
    expected[what(g.fate.kind, g.fate.target)] += g.tweaked_mass;
  }
  ASSERT_EQ(expected.size(), 3u);
  const int kWorlds = 2000;
  std::map<std::string, double> seen;
  for (int seed = 0; seed < kWorlds; ++seed) {
    const auto world = test::scene_world(f, config, uint64_t(seed) + 1, standing(f), scene.cloud(), -1, scene.contact_factors());
    const Event e = first_event(*world, standing(f));
    ASSERT_TRUE(e.type == EventType::Hit || e.type == EventType::Out) << "seed " << seed;
    seen[what(e.type == EventType::Hit ? FateKind::Hit : FateKind::Out, e.actor)] += 1;
  }
  const double p_value = test::fit_p(expected, seen, kWorlds);
  EXPECT_GT(p_value, 0.001);
}

TEST(Hit, ABodyEitherCatchesOrHitsAndOnlyAHitterPlans) {
  Field both = floor_of_hitters();
  both.bodies[0].catches = true;
  try {
    World world(both, WorldConfig{});
    ADD_FAILURE() << "a body that catches and hits was taken";
  } catch (const FieldError& e) {
    EXPECT_EQ(e.place, "bodies[1] (A)");
  }
  World mallets(floor_of_hitters(false), WorldConfig{});
  EXPECT_THROW(mallets.plan_hit(0, HitPlan{}), std::invalid_argument);
  World world(floor_of_hitters(), WorldConfig{});
  HitPlan up;
  up.kind = HitPlan::Kind::Velocity, up.velocity = {1, 0, 2};
  EXPECT_THROW(world.plan_hit(0, up), std::invalid_argument) << "a flat field has no upward hits";
  HitPlan nowhere;
  nowhere.kind = HitPlan::Kind::Point, nowhere.point = {NAN, 0, 0};
  EXPECT_THROW(world.plan_hit(0, nowhere), std::invalid_argument);
  EXPECT_THROW(world.plan_hit(5, HitPlan{}), std::invalid_argument);
  FateReport one;
  one.groups.push_back(FateGroup{.fate = {.kind = FateKind::Hit, .target = 0}});
  EXPECT_EQ(factors_by_kind(one, KindFactors{.hits = 4})[0], 4);
}

// A ball a hitter sends straight up comes back down onto its hands and is met again, as a
// volleyball player's touch to itself is: the top of the body meets a falling ball after a hit
// as before one.
TEST(Hit, ABallHitStraightUpComesDownOntoTheHittersHandsAgain) {
  Field f = lua::load_field(QUANTUM_SOURCE_DIR "/rules/volleyball");
  finish_field(f);
  World world(f, WorldConfig{.particles = 200, .seed = 3});
  std::vector<BodyInput> bodies = standing(f);
  bodies[0].position = {-6, 0};
  world.place_bodies(bodies);
  world.set_cloud(test::one_ball({-6, 0, 4}, {0, 0, 0}));
  HitPlan up;
  up.kind = HitPlan::Kind::Velocity, up.velocity = {0.2f, 0, 6}, up.spread = {0, 0, 0};
  world.plan_hit(0, up);
  std::vector<Event> events;
  std::vector<double> hits;
  for (int s = 0; s < 4 * 60 && hits.size() < 2; ++s) {
    events.clear();
    world.step(kDt, bodies, events);
    for (const Event& e : events) {
      if (e.type == EventType::Hit) hits.push_back(e.t);
      ASSERT_NE(e.type, EventType::Landing) << "the ball came down through the hitter at " << e.t;
    }
  }
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_NEAR(hits[1] - hits[0], 2 * 6 / 9.81, 0.1) << "up and down again: 2 v / g";
}

}  // namespace
}  // namespace quantum

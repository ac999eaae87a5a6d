// A ball with height (fields with gravity), on the basketball half court
// (rules/basketball/field.lua): arcs, the floor, the rim, the backboard, players as cylinders,
// and the fates of a shot.
#include <gtest/gtest.h>

#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <iostream>
#include <map>

#include "test_scenes.h"

namespace quantum {
namespace {

constexpr float kDt = 1.0f / 60;
constexpr float kG = 9.81f;

Field court() { return test::quiet("basketball"); }

int body(const Field& f, const std::string& name) { return test::body_named(f, name); }

const Goal& hoop(const Field& f) { return f.goals.at(0); }

// The same arc on a floor with friction: friction is the floor's, and slows no ball in the air.
TEST(Height, AFlightFollowsTheClosedForm) {
  for (const float friction : {0.0f, 0.5f}) {
    Field f = court();
    f.friction = friction;
    World world(f, WorldConfig{.particles = 1});
    const std::vector<BodyInput> in = test::parked_in_corner(f);
    world.place_bodies(in);
    const Vec3 p0{-3, 8, 1.5f}, v0{2, -1, 6};
    world.set_cloud(test::one_ball(p0, v0));
    std::vector<Event> events;
    for (int s = 1; s <= 60; ++s) {  // one second: up to 3.3 m and back to 1.6 m, nothing in the way
      world.step(kDt, in, events);
      const float t = float(s) * kDt;
      ASSERT_EQ(world.cloud().size(), 1u);
      EXPECT_NEAR(world.cloud().x[0], p0.x + v0.x * t, 1e-4f) << "friction " << friction;
      EXPECT_NEAR(world.cloud().y[0], p0.y + v0.y * t, 1e-4f);
      EXPECT_NEAR(world.cloud().z[0], p0.z + v0.z * t - 0.5f * kG * t * t, 1e-4f) << "at " << t << " s";
      EXPECT_NEAR(world.cloud().vz[0], v0.z - kG * t, 1e-4f);
      EXPECT_EQ(world.cloud().vx[0], v0.x);
    }
    EXPECT_TRUE(events.empty());
  }
}

TEST(Height, TheFloorSendsTheBallBackWithItsRestitution) {
  const Field f = court();
  World world(f, WorldConfig{.particles = 1});
  const std::vector<BodyInput> in = test::parked_in_corner(f);
  world.place_bodies(in);
  const float drop = 2.0f, r = f.ball_radius;
  world.set_cloud(test::one_ball({3, 8, drop}, {0, 0, 0}));
  std::vector<Event> events;
  float highest_after = 0;
  bool bounced = false;
  for (int s = 0; s < 90; ++s) {
    world.step(kDt, in, events);
    bounced = bounced || !events.empty();
    if (bounced) highest_after = std::max(highest_after, world.cloud().z[0]);
  }
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0].type, EventType::Bounce);
  EXPECT_EQ(f.wall_names[size_t(events[0].actor)], "floor");
  // Up again to e^2 of the fall, within the frame's sampling of the apex.
  const float apex = r + f.floor_restitution * f.floor_restitution * (drop - r);
  EXPECT_NEAR(highest_after, apex, 0.01f);
  EXPECT_LE(highest_after, apex + 1e-4f);
}

TEST(Height, ABallAtRestOnTheFloorRollsAndStaysThere) {
  const Field f = court();
  World world(f, WorldConfig{.particles = 1});
  const std::vector<BodyInput> in = test::parked_in_corner(f);
  world.place_bodies(in);
  world.set_cloud(test::one_ball({0, 8, f.ball_radius}, {1, 0, 0}));
  std::vector<Event> events;
  for (int s = 0; s < 60; ++s) world.step(kDt, in, events);
  EXPECT_TRUE(events.empty());
  EXPECT_EQ(world.cloud().z[0], f.ball_radius);
  EXPECT_NEAR(world.cloud().x[0], 1.0f, 1e-4f);
}

TEST(Height, ASwishGoesThroughTheRing) {
  const Field f = court();
  World world(f, WorldConfig{.particles = 1});
  const std::vector<BodyInput> in = test::parked_in_corner(f);
  world.place_bodies(in);
  const Vec2 c = hoop(f).a;
  world.set_cloud(test::one_ball({c.x, c.y, 4.0f}, {0, 0, 0}));
  std::vector<Event> events;
  for (int s = 0; s < 60 && events.empty(); ++s) world.step(kDt, in, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Goal);
  EXPECT_EQ(f.goals[size_t(events[0].actor)].name, "basket");
  // Prediction says the same, with nothing on the way.
  world.set_cloud(test::one_ball({c.x, c.y, 4.0f}, {0, 0, 0}));
  const FateReport report = world.predict(2.0f);
  ASSERT_EQ(report.groups.size(), 1u);
  EXPECT_EQ(report.groups[0].fate.kind, FateKind::Goal);
  EXPECT_EQ(report.groups[0].fate.path_len, 0);
}

TEST(Height, ABallDroppedOnTheRimBouncesOff) {
  const Field f = court();
  World world(f, WorldConfig{.particles = 1});
  const std::vector<BodyInput> in = test::parked_in_corner(f);
  world.place_bodies(in);
  const Goal& h = hoop(f);
  // Straight down onto the rod's top on the court side, a little outside its middle line: it
  // must glance off outward, away from the basket.
  world.set_cloud(test::one_ball({h.a.x, h.a.y + h.rim_radius + 0.02f, 4.0f}, {0, 0, 0}));
  std::vector<Event> events;
  for (int s = 0; s < 60 && events.empty(); ++s) world.step(kDt, in, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Bounce);
  EXPECT_EQ(f.wall_names[size_t(events[0].actor)], "rim");
  EXPECT_GT(world.cloud().vy[0], 0.1f);  // out toward the court
  EXPECT_GT(world.cloud().vz[0], 0.0f);  // and up
  // On its way down it misses the basket: the next thing it meets is the floor.
  events.clear();
  for (int s = 0; s < 120 && events.empty(); ++s) world.step(kDt, in, events);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(f.wall_names[size_t(events[0].actor)], "floor");
}

TEST(Height, TheBackboardReflects) {
  const Field f = court();
  World world(f, WorldConfig{.particles = 1});
  const std::vector<BodyInput> in = test::parked_in_corner(f);
  world.place_bodies(in);
  const Board& b = f.boards.at(0);
  // Level at the board's middle height, flying straight at it from 2 m out, to the side of the ring.
  const float z = 0.5f * (b.bottom + b.top) + 0.3f, speed = 8;
  world.set_cloud(test::one_ball({0.6f, b.a.y + 2, z}, {0, -speed, 0}));
  std::vector<Event> events;
  for (int s = 0; s < 30 && events.empty(); ++s) world.step(kDt, in, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Bounce);
  EXPECT_EQ(f.wall_names[size_t(events[0].actor)], "backboard");
  EXPECT_NEAR(world.cloud().vy[0], speed * b.restitution, 1e-3f);
  EXPECT_NEAR(world.cloud().vx[0], 0.0f, 1e-6f);
  // Below the board the ball flies on under it.
  world.set_cloud(test::one_ball({0.6f, b.a.y + 2, b.bottom - 0.5f}, {0, -speed, 2}));
  events.clear();
  for (int s = 0; s < 20; ++s) world.step(kDt, in, events);
  for (const Event& e : events) EXPECT_NE(f.wall_names[size_t(e.actor)], "backboard");
}

// A player is a cylinder up to its reach: a ball over it flies on, one lower is caught, and a
// jump (a raised reach) catches the high one.
TEST(Height, APlayerCatchesWhatComesWithinReach) {
  const Field f = court();
  const int pia = body(f, "Pia");
  const std::vector<BodyInput> in = test::parked_in_corner(f, {{"Pia", {0, 8}}});
  auto fly_past = [&](float z, float reach) {
    World world(f, WorldConfig{.particles = 1});
    world.place_bodies(in);
    world.set_reach(pia, reach);
    world.set_cloud(test::one_ball({-3, 8, z}, {8, 0, 0.5f * kG * (3.0f / 8)}));  // level as it passes Pia
    std::vector<Event> events;
    for (int s = 0; s < 40 && events.empty(); ++s) world.step(kDt, in, events);
    return !events.empty() && events[0].type == EventType::Catch && events[0].actor == pia;
  };
  const float reach = f.reach_of(pia);
  EXPECT_TRUE(fly_past(reach - 0.3f, reach));
  EXPECT_FALSE(fly_past(reach + 0.4f, reach));
  EXPECT_TRUE(fly_past(reach + 0.4f, reach + 0.6f));
}

TEST(Height, AFlatFieldRefusesHeightAndAHoopNeedsGravity) {
  Field flat = test::airhockey();
  World world(flat, WorldConfig{});
  EXPECT_THROW(world.set_cloud(test::one_ball({0, 0, 1}, {0, 0, 0})), std::invalid_argument);
  EXPECT_THROW(world.set_reach(0, 2), std::logic_error);
  Field f = court();
  f.gravity = 0;
  EXPECT_THROW(finish_field(f), FieldError);
}

// Maya, at (-3, 5.5) in `in`, shoots at the ring with a person's scatter; `world` holds the shot
// as it leaves her hand.
void shoot_from_five_metres(const Field& f, const std::vector<BodyInput>& in, int maya, World& world) {
  world.place_bodies(in);
  world.give(maya);
  std::vector<Event> thrown;
  const Vec2 arm = f.release_point(maya, in[size_t(maya)].position, hoop(f).a);
  const Vec3 hand{arm.x, arm.y, f.reach_of(maya)}, ring{hoop(f).a.x, hoop(f).a.y, hoop(f).rim_height};
  world.release(maya, f.arc_velocity(hand, ring, 0.9f), ThrowSpread{0.03f, 0.04f, 0.04f}, thrown);
}

// The shot's Figure 4: a jump shot from 5 m with a person's scatter. Its fates are the ones the
// issue names (basket, off the board, rim and out, rebounds by the players who are there), and
// realized outcomes follow the tweaked probabilities over 2,000 seeded worlds: chi-square
// goodness of fit, rejected only at p < 0.001.
TEST(Height, RealizedShotsFollowTheTweakedProbabilities) {
  const Field f = court();
  const int maya = body(f, "Maya"), pia = body(f, "Pia"), noah = body(f, "Noah");
  const std::vector<BodyInput> in =
      test::parked_in_corner(f, {{"Maya", {-3, 5.5f}}, {"Pia", {1.2f, 2.2f}}, {"Noah", {-1.3f, 2.4f}}});
  WorldConfig config;
  config.particles = 400;
  World scene(f, config);
  shoot_from_five_metres(f, in, maya, scene);
  FateReport report = scene.predict(3.0f);
  test::tweak_by(scene, report, [](const Fate& fate) { return fate.kind == FateKind::Goal ? 3 : 1; });

  auto what_of = [&](const Fate& fate) -> std::string {
    if (fate.kind == FateKind::Goal) return "basket";
    if (at_body(fate.kind)) return "by " + f.bodies[size_t(fate.target)].name;
    return fate.kind == FateKind::Out ? "out" : "none";
  };
  std::map<std::string, double> expected, newtonian;
  for (const FateGroup& g : report.groups) {
    expected[what_of(g.fate)] += g.tweaked_mass, newtonian[what_of(g.fate)] += g.mass;
    std::cout << describe(g.fate, f) << ": " << g.mass << " -> " << g.tweaked_mass << '\n';
  }
  EXPECT_GT(expected["basket"], newtonian["basket"]);
  EXPECT_GT(expected["by " + f.bodies[size_t(pia)].name] + expected["by " + f.bodies[size_t(noah)].name], 0.05)
      << "the players under the basket get rebounds";

  const int kWorlds = 2000;
  std::map<std::string, double> seen;
  for (int seed = 0; seed < kWorlds; ++seed) {
    const std::unique_ptr<World> scene_of_seed = test::scene_world(f, config, uint64_t(seed) + 1, in, scene.cloud(), maya,
                                                                    scene.contact_factors());
    World& world = *scene_of_seed;
    std::vector<Event> events;
    std::string outcome = "none";
    for (int s = 0; s < 180 && outcome == "none"; ++s) {
      events.clear();
      world.step(kDt, in, events);
      for (const Event& e : events) {
        if (e.type == EventType::Goal) outcome = "basket";
        if (e.type == EventType::Catch) outcome = "by " + f.bodies[size_t(e.actor)].name;
        if (e.type == EventType::Out) outcome = "out";
      }
    }
    seen[outcome] += 1;
  }
  for (const auto& [what, n] : seen) EXPECT_TRUE(expected.count(what)) << "unpredicted outcome " << what << " x" << n;
  // Outcomes too rare for the chi-square approximation (expected fewer than 5 times) are pooled.
  std::map<std::string, double> e_cell, o_cell;
  for (const auto& [what, p] : expected) {
    const std::string cell = p * kWorlds < 5 ? "rare" : what;
    e_cell[cell] += p * kWorlds, o_cell[cell] += seen[what];
    std::cout << what << ": Newtonian " << newtonian[what] << ", tweaked " << p << ", seen " << seen[what] / kWorlds << '\n';
  }
  double chi2 = 0;
  int cells = 0;
  for (const auto& [cell, e] : e_cell) chi2 += (o_cell[cell] - e) * (o_cell[cell] - e) / e, ++cells;
  ASSERT_GE(cells, 3);
  const double p_value = 1 - boost::math::cdf(boost::math::chi_squared(cells - 1), chi2);
  std::cout << "chi2 = " << chi2 << " with " << cells - 1 << " degrees of freedom, p = " << p_value << '\n';
  EXPECT_GT(p_value, 0.001);
}

// A cloud large enough for the prediction to share its chunks with a second thread gets the same
// fate for every particle as on one thread, as a small cloud (never shared) does, and twice over.
TEST(Height, ALargeCloudsFatesAreEachParticlesOwn) {
  Field f = test::quiet("basketball");
  f.brownian = 0.05f;  // the next step's noise, which depends on each particle's index, is replayed too
  const int maya = body(f, "Maya");
  const std::vector<BodyInput> in = test::parked_in_corner(f, {{"Maya", {-3, 5.5f}}, {"Pia", {1.2f, 2.2f}}, {"Noah", {-1.3f, 2.4f}}});
  WorldConfig config;
  config.particles = 20'000;
  World thrower(f, config);
  shoot_from_five_metres(f, in, maya, thrower);
  const Cloud& all = thrower.cloud();
  Cloud few;
  for (size_t i = 0; i < 2'000; ++i) few.push_from(all, i);

  const std::unique_ptr<World> large = test::scene_world(f, config, 9, in, all, maya);
  const std::unique_ptr<World> small = test::scene_world(f, config, 9, in, few, maya);
  WorldConfig alone = config;
  alone.threads = 1;
  const std::unique_ptr<World> single = test::scene_world(f, alone, 9, in, all, maya);
  const FateReport big = large->predict(3.0f), again = large->predict(3.0f), little = small->predict(3.0f);
  const FateReport one_thread = single->predict(3.0f);
  std::map<std::string, int> kinds;
  for (size_t i = 0; i < few.size(); ++i) {
    const std::string fate = describe(big.groups[big.group_of[i]].fate, f);
    ASSERT_EQ(fate, describe(little.groups[little.group_of[i]].fate, f)) << "particle " << i;
    ++kinds[fate];
  }
  EXPECT_GE(kinds.size(), 4u) << "a shot with a person's scatter has several fates";
  ASSERT_EQ(big.groups.size(), again.groups.size());
  for (size_t i = 0; i < all.size(); ++i) {
    const uint64_t key = big.groups[big.group_of[i]].fate.key();
    ASSERT_EQ(key, again.groups[again.group_of[i]].fate.key()) << "particle " << i;
    ASSERT_EQ(key, one_thread.groups[one_thread.group_of[i]].fate.key()) << "particle " << i;
  }
  EXPECT_THROW(World(f, WorldConfig{.threads = 3}), std::invalid_argument);
}

}  // namespace
}  // namespace quantum

// Who gets a ball nobody holds and who takes one somebody does: pickups of a loose ball
// (FateKind::Pickup, World::loose) and tackles (World::challenge), on the keep-away court
// (rules/keepaway: Ann, Bo and Dee pass, Cy is in the middle).
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "test_scenes.h"

namespace quantum {
namespace {

constexpr float kDt = 1.0f / 60;

Field court() {
  Field f = lua::load_field(QUANTUM_SOURCE_DIR "/rules/keepaway");
  f.brownian = 0;
  return f;
}

// Steps until a player gets the ball; a Drop when nobody did.
Event first_catch(World& world, const std::vector<BodyInput>& bodies) {
  std::vector<Event> events;
  for (int s = 0; s < 600; ++s) {
    events.clear();
    world.step(kDt, bodies, events);
    for (const Event& e : events)
      if (e.type == EventType::Catch || e.type == EventType::Pickup || e.type == EventType::Out) return e;
  }
  return {0, EventType::Drop, -1, 0, 0, 0, {}, {}};
}

// A ball rolling from 1 m in front of Ann straight at her, last touched by `last`.
std::unique_ptr<World> toward_ann(const Field& f, float speed, int last) {
  return test::scene_world(f, WorldConfig{.particles = 50}, 1, test::resting(f), test::single(-2.3f, 0, -speed, 0), last);
}

TEST(Pickup, ALooseBallSomeoneTouchedIsPickedUpAndAFastOneCaught) {
  const Field f = court();
  const int ann = test::body_named(f, "Ann"), bo = test::body_named(f, "Bo"), cy = test::body_named(f, "Cy");
  struct Case {
    float speed;
    int last;
    FateKind kind;
    EventType event;
  };
  for (const Case& c : {Case{0.3f, cy, FateKind::Pickup, EventType::Pickup}, Case{0.3f, bo, FateKind::Pickup, EventType::Pickup},
                        Case{0.3f, -1, FateKind::Catch, EventType::Catch}, Case{3, bo, FateKind::Pass, EventType::Catch},
                        Case{3, cy, FateKind::Intercept, EventType::Catch}}) {
    const auto world = toward_ann(f, c.speed, c.last);
    EXPECT_EQ(world->loose(), c.speed < kLooseSpeed);
    const FateReport report = world->predict(5.0f);
    ASSERT_EQ(report.groups.size(), 1u);
    EXPECT_EQ(report.groups[0].fate.kind, c.kind) << describe(report.groups[0].fate, f);
    EXPECT_EQ(report.groups[0].fate.target, ann);
    const Event e = first_catch(*world, test::resting(f));
    EXPECT_EQ(e.type, c.event) << "speed " << c.speed << ", last touched by " << c.last;
    EXPECT_EQ(e.actor, ann);
    EXPECT_EQ(world->holder(), ann);
  }
  EXPECT_EQ(describe(Fate{.kind = FateKind::Pickup, .target = ann}, f), "picked up by Ann");
}

// Realized pickups follow the tweaked probabilities: a slow fan from the middle toward Ann and
// Cy, Cy's pickup three times likelier, over 2,000 seeded worlds; chi-square goodness of fit,
// rejected only at p < 0.001.
TEST(Pickup, RealizedPickupsFollowTheTweakedProbabilities) {
  const Field f = court();
  const int cy = test::body_named(f, "Cy");
  std::vector<BodyInput> bodies = test::resting(f);
  bodies[size_t(test::body_named(f, "Ann"))].position = {-0.9f, 0.5f};
  bodies[size_t(cy)].position = {-0.9f, -0.5f};
  const Cloud fan = test::fan(0, 0, 0.45f, 2.5f, 3.8f, 301);
  WorldConfig config;
  config.particles = uint32_t(fan.size());
  World scene(f, config);
  scene.place_bodies(bodies);
  scene.set_cloud(fan);
  scene.set_last_touch(test::body_named(f, "Bo"));
  ASSERT_TRUE(scene.loose());
  FateReport report = scene.predict(10.0f);
  test::tweak_by(scene, report, [&](const Fate& fate) { return fate.kind == FateKind::Pickup && fate.target == cy ? 3 : 1; });
  auto what = [&](bool picked, int who) { return picked ? f.bodies[size_t(who)].name : std::string("none"); };
  std::map<std::string, double> expected;
  for (const FateGroup& g : report.groups) {
    ASSERT_EQ(g.fate.kind, FateKind::Pickup) << describe(g.fate, f);
    expected[what(true, g.fate.target)] += g.tweaked_mass;
  }
  ASSERT_EQ(expected.size(), 2u);
  const int kWorlds = 2000;
  std::map<std::string, double> seen;
  for (int seed = 0; seed < kWorlds; ++seed) {
    const auto world = test::scene_world(f, config, uint64_t(seed) + 1, bodies, scene.cloud(), test::body_named(f, "Bo"),
                                         scene.contact_factors());
    const Event e = first_catch(*world, bodies);
    ASSERT_EQ(e.type, EventType::Pickup) << "seed " << seed;
    seen[what(true, e.actor)] += 1;
  }
  EXPECT_GT(test::fit_p(expected, seen, kWorlds), 0.001);
}

// A held ball taken: each challenger with its chance, over 6,000 seeded draws; chi-square
// goodness of fit of (Bo, Cy, nobody), rejected only at p < 0.001.
TEST(Tackle, ChallengesTakeTheBallWithTheirChances) {
  const Field f = court();
  const int ann = test::body_named(f, "Ann"), cy = test::body_named(f, "Cy"), dee = test::body_named(f, "Dee");
  const std::vector<Challenge> challengers = {{cy, 0.3, 0.1}, {dee, 0.15, 0.1}};
  const int kDraws = 6000;
  std::map<std::string, double> seen;
  for (int seed = 0; seed < kDraws; ++seed) {
    World world(f, WorldConfig{.particles = 10, .seed = uint64_t(seed) + 1});
    world.give(ann);
    std::vector<Event> events;
    world.step(kDt, test::resting(f), events);
    world.challenge(challengers, events);
    const Decision* d = world.decision();
    ASSERT_NE(d, nullptr);
    ASSERT_EQ(d->options.size(), 2u);
    EXPECT_EQ(d->options[0].target.kind, TargetKind::Tackle);
    EXPECT_EQ(target_name(d->options[1].target, f), "Dee");
    if (events.empty()) {
      EXPECT_EQ(d->realized, -1);
      EXPECT_EQ(world.holder(), ann);
      seen["nobody"] += 1;
      continue;
    }
    ASSERT_EQ(events.size(), 1u);
    const Event& e = events[0];
    EXPECT_EQ(e.type, EventType::Tackle);
    EXPECT_EQ(world.holder(), e.actor) << "the tackler holds the ball now";
    EXPECT_EQ(world.last_touch(), e.actor);
    EXPECT_EQ(e.p, e.actor == cy ? 0.3 : 0.15);
    seen[f.bodies[size_t(e.actor)].name] += 1;
  }
  EXPECT_GT(test::fit_p({{"Cy", 0.3}, {"Dee", 0.15}, {"nobody", 0.55}}, seen, kDraws), 0.001);
}

TEST(Tackle, OnlyAnotherPlayerWhoCatchesTakesAHeldBallWithAChanceInZeroOne) {
  const Field f = court();
  const int ann = test::body_named(f, "Ann"), cy = test::body_named(f, "Cy");
  World world(f, WorldConfig{});
  std::vector<Event> events;
  EXPECT_THROW(world.challenge(std::vector<Challenge>{{cy, 0.1, 0.1}}, events), std::invalid_argument) << "nobody holds it";
  world.give(ann);
  EXPECT_THROW(world.challenge(std::vector<Challenge>{{ann, 0.1, 0.1}}, events), std::invalid_argument);
  EXPECT_THROW(world.challenge(std::vector<Challenge>{{cy, 1.5, 0.1}}, events), std::invalid_argument);
  EXPECT_THROW(world.challenge(std::vector<Challenge>{{cy, NAN, 0.1}}, events), std::invalid_argument);
  EXPECT_THROW(world.challenge(std::vector<Challenge>{{cy, 0.6, 0.1}, {1, 0.6, 0.1}}, events), std::invalid_argument);
  EXPECT_THROW(world.challenge(std::vector<Challenge>{{9, 0.1, 0.1}}, events), std::invalid_argument);
  EXPECT_TRUE(events.empty());
  EXPECT_EQ(world.holder(), ann);
}

}  // namespace
}  // namespace quantum

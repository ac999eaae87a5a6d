// Landings (Field::landings): on a court where the ball's coming down decides a rally, every
// audible touch of the floor is a fate, a decision and an event of its own, with the area it is
// in. The court is tests/sports/court: two box areas either side of a net, as in volleyball.
#include <gtest/gtest.h>

#include <boost/math/distributions/chi_squared.hpp>
#include <iostream>
#include <map>

#include "field_loader.h"
#include "test_scenes.h"

namespace quantum {
namespace {

constexpr float kDt = 1.0f / 60;

Field court() { return lua::load_field(QUANTUM_SOURCE_DIR "/tests/sports/court"); }

int area(const Field& f, const std::string& name) {
  for (size_t k = 0; k < f.areas.size(); ++k)
    if (f.areas[k].name == name) return int(k);
  ADD_FAILURE() << "no area " << name;
  return -1;
}

// Both players far from the ball's way, in the hall's corners.
std::vector<BodyInput> aside() { return {{{-9, -6}, {0, 0}}, {{9, 6}, {0, 0}}}; }

// A spread of hits from (-2, 0) at 2 m over the net and back: some come down in Blue's court
// short of the net, some meet the net, most land in Red's court, some beyond its lines.
Cloud spread(int n) {
  Cloud c;
  for (int i = 0; i < n; ++i) {
    const float across = float(i % 15) / 14, along = float(i / 15) / float((n - 1) / 15);
    c.push(Vec3{-2, 0, 2}, Vec3{1 + 8 * along, -2.5f + 5 * across, 4}, 1, 1);
  }
  return c;
}

// Steps `world` until one of the events that end a flight, and returns it (a Drop when none came).
Event first_ending(World& world) {
  std::vector<Event> events;
  for (int s = 0; s < 600; ++s) {
    events.clear();
    world.step(kDt, aside(), events);
    for (const Event& e : events)
      if (e.type == EventType::Landing || e.type == EventType::Out || e.type == EventType::Catch) return e;
  }
  return {0, EventType::Drop, -1, 0, 0, 0, {}, {}};
}

TEST(Landing, TheBallComingDownLandsInTheAreaItIsIn) {
  const Field f = court();
  const int red = area(f, "Red court");
  struct Case {
    Vec3 velocity;
    int area;
    float x;  // where it comes down: x0 + vx t, with t the time to fall from 2 m to the ball's radius
  };
  const float t = (4 + std::sqrt(16 + 2 * 9.81f * 1.9f)) / 9.81f;
  for (const Case& c : {Case{{5, 0, 4}, red, -2 + 5 * t}, Case{{9, 0, 4}, -1, -2 + 9 * t}}) {
    World world(f, WorldConfig{.particles = 1});
    world.place_bodies(aside());
    world.set_cloud(test::one_ball({-2, 0, 2}, c.velocity));
    const FateReport report = world.predict(3.0f);
    ASSERT_EQ(report.groups.size(), 1u);
    EXPECT_EQ(report.groups[0].fate.kind, FateKind::Landing);
    EXPECT_EQ(report.groups[0].fate.target, c.area);
    EXPECT_EQ(describe(report.groups[0].fate, f), c.area >= 0 ? "lands in Red court" : "lands outside every area");
    const Event e = first_ending(world);
    EXPECT_EQ(e.type, EventType::Landing);
    EXPECT_EQ(e.actor, c.area);
    EXPECT_NEAR(e.at.x, c.x, c.velocity.x * kDt) << "within a step's travel of where it comes down";
    EXPECT_EQ(actor_of(e, f).name, c.area >= 0 ? "Red court" : "");
    EXPECT_TRUE(world.live()) << "the ball bounces on: the rules say what a landing ends";
  }
  // The same court without landings: the floor is a wall the ball bounces off, as in basketball.
  Field plain = f;
  plain.landings = false;
  World world(plain, WorldConfig{.particles = 1});
  world.place_bodies(aside());
  world.set_cloud(test::one_ball({-2, 0, 2}, {5, 0, 4}));
  EXPECT_NE(world.predict(3.0f).groups[0].fate.kind, FateKind::Landing);
  std::vector<Event> events;
  for (int s = 0; s < 90 && events.empty(); ++s) world.step(kDt, aside(), events);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0].type, EventType::Bounce);
  EXPECT_EQ(actor_of(events[0], plain).name, "floor");
}

// Each particle of a spread, flown alone through the step, lands where the prediction said it
// would, net bounces and all: the step and the prediction share one tracer.
TEST(Landing, LandingsArePredictedAndSteppedAlike) {
  const Field f = court();
  const Cloud all = spread(300);
  World whole(f, WorldConfig{.particles = uint32_t(all.size())});
  whole.place_bodies(aside());
  whole.set_cloud(all);
  const FateReport report = whole.predict(5.0f);
  std::map<std::string, int> seen;
  for (size_t i = 0; i < all.size(); ++i) {
    Cloud one;
    one.push_from(all, i);
    World world(f, WorldConfig{.particles = 1});
    world.place_bodies(aside());
    world.set_cloud(one);
    const Fate& fate = report.groups[report.group_of[i]].fate;
    const Event e = first_ending(world);
    ASSERT_EQ(fate.kind, FateKind::Landing) << "particle " << i << ": " << describe(fate, f);
    ASSERT_EQ(e.type, EventType::Landing) << "particle " << i;
    ASSERT_EQ(e.actor, fate.target) << "particle " << i << " predicted " << describe(fate, f);
    ++seen[describe(fate, f)];
  }
  for (const auto& [what, n] : seen) std::cout << what << ": " << n << '\n';
  EXPECT_GE(seen["lands in Blue court"], 10);
  EXPECT_GE(seen["lands in Red court"], 100);
  EXPECT_GE(seen["lands outside every area"], 10);
  EXPECT_GE(seen["lands in Blue court via net"] + seen["lands outside every area via net"], 5) << "some meet the net";
}

// Realized landings follow the tweaked probabilities: Red's court three times likelier, outside
// half as likely, over 2,000 seeded worlds; chi-square goodness of fit, rejected only at p < 0.001.
TEST(Landing, RealizedLandingsFollowTheTweakedProbabilities) {
  const Field f = court();
  const int red = area(f, "Red court");
  const Cloud all = spread(300);
  WorldConfig config;
  config.particles = uint32_t(all.size());
  World scene(f, config);
  scene.place_bodies(aside());
  scene.set_cloud(all);
  FateReport report = scene.predict(5.0f);
  test::tweak_by(scene, report, [&](const Fate& fate) {
    return fate.kind != FateKind::Landing ? 1 : fate.target == red ? 3 : fate.target < 0 ? 0.5 : 1;
  });
  auto where = [&](int a) { return a < 0 ? std::string("outside") : f.areas[size_t(a)].name; };
  std::map<std::string, double> expected;
  for (const FateGroup& g : report.groups) {
    ASSERT_EQ(g.fate.kind, FateKind::Landing) << describe(g.fate, f);
    expected[where(g.fate.target)] += g.tweaked_mass;
  }
  const int kWorlds = 2000;
  std::map<std::string, double> seen;
  for (int seed = 0; seed < kWorlds; ++seed) {
    const std::unique_ptr<World> world = test::scene_world(f, config, uint64_t(seed) + 1, aside(), scene.cloud(), 0,
                                                                 scene.contact_factors());
    const Event e = first_ending(*world);
    ASSERT_EQ(e.type, EventType::Landing) << "seed " << seed;
    seen[where(e.actor)] += 1;
  }
  double chi2 = 0;
  for (const auto& [what, p] : expected) {
    const double e = p * kWorlds;
    ASSERT_GE(e, 5) << what;
    chi2 += (seen[what] - e) * (seen[what] - e) / e;
    std::cout << what << ": tweaked " << p << ", seen " << seen[what] / kWorlds << '\n';
  }
  ASSERT_EQ(expected.size(), 3u);
  const double p_value = 1 - boost::math::cdf(boost::math::chi_squared(double(expected.size() - 1)), chi2);
  std::cout << "chi2 = " << chi2 << " with " << expected.size() - 1 << " degrees of freedom, p = " << p_value << '\n';
  EXPECT_GT(p_value, 0.001);
}

TEST(Landing, OnlyAFieldWithHeightHasLandingsAndABoxHasItsCornersInOrder) {
  Field flat = test::airhockey();
  flat.landings = true;
  EXPECT_THROW(World(flat, WorldConfig{}), FieldError);
  Field f = court();
  std::swap(f.areas[0].a, f.areas[0].b);
  try {
    World world(f, WorldConfig{});
    ADD_FAILURE() << "a box with its corners swapped was taken";
  } catch (const FieldError& e) {
    EXPECT_EQ(e.place, "areas[1] (Blue court).box");
  }
}

}  // namespace
}  // namespace quantum

// Holding, throwing and catching in the core, on the handball hall (rules/handball/field.lua):
// the ball goes where its holder goes, a throw scatters as its spread says, catches are drawn
// as exactly as hits, weights stay normalised, and friction's flight is predicted exactly.
#include <gtest/gtest.h>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>

#include <cmath>
#include <iostream>
#include <map>

#include "test_scenes.h"

namespace quantum {
namespace {

constexpr float kDt = 1.0f / 60;

Field hall() { return test::quiet("handball"); }

int body(const Field& f, const std::string& name) { return test::body_named(f, name); }

// Everyone at rest in a far corner but the players placed.
std::vector<BodyInput> parked(const Field& f, std::initializer_list<std::pair<const char*, Vec2>> placed) {
  std::vector<BodyInput> in;
  for (size_t k = 0; k < f.bodies.size(); ++k) in.push_back({{-8.0f + 1.2f * float(k), -4.6f}, {0, 0}});
  for (const auto& [name, at] : placed) in[size_t(body(f, name))] = {at, {0, 0}};
  return in;
}

// Two-sided p of a normal z score.
double two_sided(double z) { return 2 * boost::math::cdf(boost::math::complement(boost::math::normal(), std::abs(z))); }

// Two-sided p of a sample variance s2 of n draws against the true variance (chi-square with
// n - 1 degrees of freedom).
double variance_p(double s2, double variance, size_t n) {
  const boost::math::chi_squared chi(double(n - 1));
  const double x = double(n - 1) * s2 / variance;
  return 2 * std::min(boost::math::cdf(chi, x), boost::math::cdf(boost::math::complement(chi, x)));
}

TEST(Possession, TheBallGoesWhereItsHolderGoesUntilTheThrow) {
  const Field f = hall();
  World world(f, WorldConfig{});
  const int ben = body(f, "Ben");
  std::vector<BodyInput> in = parked(f, {{"Ben", {-3, 2}}});
  world.place_bodies(in);
  world.give(ben);
  EXPECT_EQ(world.holder(), ben);
  EXPECT_TRUE(world.in_play());
  EXPECT_FALSE(world.live());  // no cloud to step while held
  EXPECT_EQ(world.cloud().size(), 0u);
  // Ben runs 4 m up the hall with it; nothing happens to a held ball.
  std::vector<Event> events;
  for (int s = 0; s < 120; ++s) {
    in[size_t(ben)] = {{-3.0f + 2.0f * kDt * float(s + 1), 2}, {2, 0}};
    world.step(kDt, in, events);
  }
  EXPECT_TRUE(events.empty());
  EXPECT_EQ(world.holder(), ben);
  // The throw leaves from where Ben is now, an arm's length (his reach) and a ball's radius ahead.
  world.release(ben, {0, 8}, ThrowSpread{}, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, EventType::Throw);
  EXPECT_EQ(events[0].actor, ben);
  EXPECT_NEAR(events[0].at.x, 1.0f, 1e-4);
  EXPECT_NEAR(events[0].at.y, 2.0f + f.bodies[size_t(ben)].radius + f.ball_radius, 1e-3);
  EXPECT_EQ(world.holder(), -1);
  EXPECT_TRUE(world.live());
  EXPECT_EQ(world.last_touch(), ben);
  // Only the holder throws.
  EXPECT_THROW(world.release(ben, {0, 8}, ThrowSpread{}, events), std::invalid_argument);
}

TEST(Possession, OnlyABodyThatCatchesCanBeGivenTheBall) {
  Field f = hall();
  f.bodies[0].catches = false;
  World world(f, WorldConfig{});
  EXPECT_THROW(world.give(0), std::invalid_argument);
  EXPECT_THROW(world.give(int(f.bodies.size())), std::invalid_argument);
  world.give(1);
  std::vector<Event> events;
  EXPECT_THROW(world.release(1, {0, 0}, ThrowSpread{}, events), std::invalid_argument);
  EXPECT_THROW(world.release(1, {NAN, 1}, ThrowSpread{}, events), std::invalid_argument);
  EXPECT_THROW(world.release(1, {1, 0}, ThrowSpread{-0.1f, 0.1f}, events), std::invalid_argument);
  EXPECT_EQ(world.holder(), 1);  // a refused throw leaves the ball in hand
}

// The released particles' directions and speeds are normal around the throw's with the spread's
// standard deviations: mean (z test) and variance (chi-square) of 20,000 particles, each
// rejected only at p < 0.001.
TEST(Throw, ItsCloudScattersAsItsSpreadSays) {
  const Field f = hall();
  for (const ThrowSpread spread : {ThrowSpread{0.05f, 0.08f}, ThrowSpread{0.2f, 0.02f}}) {
    WorldConfig config;
    config.particles = 20000;
    config.seed = 7;
    World world(f, config);
    const int ben = body(f, "Ben");
    world.place_bodies(parked(f, {{"Ben", {-3, 0}}}));
    world.give(ben);
    std::vector<Event> events;
    const float speed = 10, heading = 0.3f;
    world.release(ben, {speed * std::cos(heading), speed * std::sin(heading)}, spread, events);
    const Cloud& c = world.cloud();
    ASSERT_EQ(c.size(), config.particles);
    double sum_a = 0, sum_a2 = 0, sum_s = 0, sum_s2 = 0;
    for (size_t i = 0; i < c.size(); ++i) {
      const double a = std::atan2(c.vy[i], c.vx[i]) - heading, s = std::hypot(c.vx[i], c.vy[i]) / speed - 1;
      sum_a += a, sum_a2 += a * a, sum_s += s, sum_s2 += s * s;
      EXPECT_NEAR(c.weight(i), 1.0 / double(c.size()), 1e-12);
    }
    const double n = double(c.size());
    const double mean_a = sum_a / n, mean_s = sum_s / n;
    const double var_a = (sum_a2 - n * mean_a * mean_a) / (n - 1), var_s = (sum_s2 - n * mean_s * mean_s) / (n - 1);
    const double sd_a = spread.direction, sd_s = spread.speed;
    EXPECT_GT(two_sided(mean_a / (sd_a / std::sqrt(n))), 0.001) << "mean direction " << mean_a;
    EXPECT_GT(two_sided(mean_s / (sd_s / std::sqrt(n))), 0.001) << "mean speed " << mean_s;
    EXPECT_GT(variance_p(var_a, sd_a * sd_a, c.size()), 0.001) << "direction sd " << std::sqrt(var_a);
    EXPECT_GT(variance_p(var_s, sd_s * sd_s, c.size()), 0.001) << "speed sd " << std::sqrt(var_s);
    EXPECT_NEAR(test::weight_sum(c), 1.0, 1e-9);
  }
}

// Exactness of catches: Ben throws to Clara with Ida half in the way and Hugo beyond, Brownian
// motion off. The fates are tweaked as handball's factors would (pass 6, intercept 4, out 0.5);
// 4,000 seeded worlds then step until the flight ends. Realized frequencies against tweaked
// probabilities: chi-square goodness of fit, rejected only at p < 0.001.
TEST(Catch, RealizedCatchesFollowTheTweakedProbabilities) {
  const Field f = hall();
  const int ben = body(f, "Ben");
  const std::vector<BodyInput> in =
      parked(f, {{"Ben", {-4, 2}}, {"Ida", {-1.5f, 2.7f}}, {"Clara", {2, 2.3f}}, {"Jonas", {5, 1.6f}}});
  WorldConfig config;
  config.particles = 400;
  World scene(f, config);
  scene.place_bodies(in);
  scene.give(ben);
  std::vector<Event> thrown;
  scene.release(ben, {9, 0}, ThrowSpread{0.08f, 0.1f}, thrown);
  FateReport report = scene.predict(3.0f);
  test::tweak_by(scene, report, [](const Fate& fate) {
    return fate.kind == FateKind::Pass ? 6 : fate.kind == FateKind::Intercept ? 4 : fate.kind == FateKind::Out ? 0.5 : 1;
  });
  EXPECT_NEAR(test::weight_sum(scene.cloud()), 1.0, 1e-9);
  EXPECT_NEAR(test::tweaked_sum(scene.cloud()), 1.0, 1e-9);

  auto name = [&](int k) { return f.bodies[size_t(k)].name; };
  std::map<std::string, double> expected, newtonian;
  for (const FateGroup& g : report.groups) {
    std::string what = g.fate.kind == FateKind::Out ? "out" : g.fate.kind == FateKind::Field ? "none" : "goal";
    if (at_body(g.fate.kind)) what = to_string(g.fate.kind) + std::string(" by ") + name(g.fate.target);
    expected[what] += g.tweaked_mass, newtonian[what] += g.mass;
  }
  ASSERT_GE(expected.size(), 3u);
  EXPECT_GT(expected["pass by Clara"], newtonian["pass by Clara"]);  // the factors moved it

  const int kWorlds = 4000;
  std::map<std::string, double> seen;
  for (int seed = 0; seed < kWorlds; ++seed) {
    const std::unique_ptr<World> scene_of_seed = test::scene_world(f, config, uint64_t(seed) + 1, in, scene.cloud(), ben,
                                                                    scene.contact_factors());
    World& world = *scene_of_seed;
    std::vector<Event> events;
    for (int s = 0; s < 180 && events.empty(); ++s) world.step(kDt, in, events);
    std::string outcome = "none";
    if (!events.empty()) {
      const Event& e = events.back();
      if (e.type == EventType::Catch) {
        outcome = (f.bodies[size_t(e.actor)].team == f.bodies[size_t(ben)].team ? "pass by " : "intercept by ") + name(e.actor);
        EXPECT_EQ(world.holder(), e.actor);
        EXPECT_EQ(world.cloud().size(), 0u);  // a caught ball is held, not flown
      } else {
        outcome = e.type == EventType::Out ? "out" : "goal";
      }
    }
    seen[outcome] += 1;
  }
  double chi2 = 0;
  int cells = 0;
  for (const auto& [what, p] : expected) {
    const double e = p * kWorlds;
    ASSERT_GE(e, 5) << what << ": too rare for the chi-square approximation; change the scene";
    chi2 += (seen[what] - e) * (seen[what] - e) / e;
    ++cells;
    std::cout << what << ": Newtonian " << newtonian[what] << ", tweaked " << p << ", seen " << seen[what] / kWorlds << '\n';
  }
  for (const auto& [what, n] : seen) EXPECT_TRUE(expected.count(what)) << "unpredicted outcome " << what << " x" << n;
  const double p_value = 1 - boost::math::cdf(boost::math::chi_squared(cells - 1), chi2);
  std::cout << "chi2 = " << chi2 << " with " << cells - 1 << " degrees of freedom, p = " << p_value << '\n';
  EXPECT_GT(p_value, 0.001);
}

// With friction k a ball launched at v stops after v/k metres: prediction and stepping agree on
// whether it reaches a catcher just short of that or stops just before one just beyond it. The
// throw that reaches Clara arrives loose (well below kLooseSpeed): a pass when it leaves the hand,
// it is picked up where it rolls to her.
TEST(Friction, PredictionKnowsWhereAThrowStops) {
  Field f = hall();
  ASSERT_GT(f.friction, 0);
  const int ben = body(f, "Ben"), clara = body(f, "Clara");
  const float v = 3, reach = f.bodies[size_t(clara)].radius + f.ball_radius;
  const float stops = v / f.friction;  // metres from the release point
  for (const float margin : {-0.1f, 0.1f}) {
    const float gap = stops + margin;  // release point to Clara's reach
    std::vector<BodyInput> in = parked(f, {{"Ben", {-8, 0}}});
    World world(f, WorldConfig{});
    world.place_bodies(in);
    world.give(ben);
    std::vector<Event> events;
    world.release(ben, {v, 0}, ThrowSpread{0, 0}, events);
    const float from = events[0].at.x;
    in[size_t(clara)] = {{from + gap + reach, 0}, {0, 0}};
    world.place_bodies(in);
    const FateReport report = world.predict(20.0f);
    ASSERT_EQ(report.groups.size(), 1u);
    const bool reaches = margin < 0;
    EXPECT_EQ(report.groups[0].fate.kind, reaches ? FateKind::Pass : FateKind::Field) << "margin " << margin;
    events.clear();
    for (int s = 0; s < 60 * 20 && events.empty(); ++s) world.step(kDt, in, events);
    EXPECT_EQ(!events.empty() && events[0].type == EventType::Pickup, reaches) << "margin " << margin;
    if (!reaches) {
      EXPECT_NEAR(world.cloud().x[0], from + stops, 0.02);
    }
  }
}

}  // namespace
}  // namespace quantum

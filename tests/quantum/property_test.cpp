// The properties the product stands on, checked over whole matches rather than single rules:
// weights stay normalized, no particle rests inside anything, runs repeat exactly, realized
// outcomes follow the tweaked probabilities, and what survives an event agrees with it.
#include <gtest/gtest.h>

#include <sstream>

#include <boost/math/distributions/chi_squared.hpp>
#include <map>

#include "simulate.h"
#include "quantum/noise.h"
#include "scenes.h"
#include "test_scenes.h"

namespace quantum {
namespace {

constexpr float kDt = 1.0f / 60;

// Runs `seconds` of scripted play, calling check(world, events) after every operation.
template <class Check>
void play(World& world, double seconds, Check check) {
  std::vector<Event> events;
  world.drop(0, events);
  check(world, events);
  for (int s = 0; s < int(seconds / kDt); ++s) {
    events.clear();
    if (!world.live()) {
      world.drop(int(s % world.field().spots.size()), events);
      check(world, events);
      events.clear();
    }
    world.step(kDt, tools::scripted_mallets(world.field(), world.time() + kDt), events);
    check(world, events);
    if (world.live() && s % 20 == 0) {
      FateReport r = world.predict();
      test::tweak_by(world, r, [](const Fate& fate) { return factor_by_kind(fate.kind, KindFactors{}); });
      check(world, events);
    }
  }
}

TEST(Property, WeightsSumToOneAfterEveryOperation) {
  WorldConfig config;
  config.particles = 2000;
  World world(test::airhockey(), config);
  int checks = 0;
  play(world, 60, [&](const World& w, const std::vector<Event>&) {
    if (!w.live()) return;
    ASSERT_NEAR(test::weight_sum(w.cloud()), 1.0, 1e-9) << "t = " << w.time();
    ASSERT_NEAR(test::tweaked_sum(w.cloud()), 1.0, 1e-9) << "t = " << w.time();
    for (size_t i = 0; i < w.cloud().size(); ++i) ASSERT_GE(w.cloud().w[i], 0);
    ++checks;
  });
  EXPECT_GT(checks, 3000);
}

TEST(Property, NoParticleEndsAStepInsideAWallOrABody) {
  WorldConfig config;
  config.particles = 3000;
  World world(test::airhockey(), config);
  const Field& f = world.field();
  const float tolerance = 1e-5f;
  size_t checked = 0;
  play(world, 60, [&](const World& w, const std::vector<Event>&) {
    const Cloud& c = w.cloud();
    for (size_t i = 0; i < c.size(); ++i) {
      const Vec2 p{c.x[i], c.y[i]};
      for (const Segment& s : f.segments)
        ASSERT_GE(test::segment_distance(p, s.a, s.b), f.ball_radius - tolerance)
            << "particle " << i << " at (" << p.x << ", " << p.y << ") inside " << f.wall_names[s.wall] << ", t = " << w.time();
      for (size_t k = 0; k < f.bodies.size(); ++k) {
        const Vec2 b = w.body_positions()[k];
        ASSERT_GE(std::hypot(p.x - b.x, p.y - b.y), f.bodies[k].radius + f.ball_radius - tolerance)
            << "particle " << i << " inside " << f.bodies[k].name << ", t = " << w.time();
      }
      ++checked;
    }
  });
  EXPECT_GT(checked, size_t(5'000'000));
}

std::string event_log(uint64_t seed) {
  WorldConfig config;
  config.particles = 1500;
  config.seed = seed;
  World world(test::airhockey(), config);
  std::ostringstream log;
  play(world, 90, [&](const World& w, const std::vector<Event>& events) {
    for (const Event& e : events) tools::write_event(log, e, w.field());
  });
  return log.str();
}

TEST(Property, OneSeedGivesByteIdenticalEventLogs) {
  const std::string a = event_log(42), b = event_log(42), c = event_log(43);
  EXPECT_GT(std::count(a.begin(), a.end(), '\n'), 20);
  EXPECT_NE(a.find("\"type\":\"hit\""), std::string::npos);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);  // the seed matters
}

// Exactness: a fan of shots toward Red's end, with Red's mallet partly in the way, Brownian
// motion off. Fates are predicted, tweaked with the paper's factors, and then 20,000 seeded
// matches are stepped until the ball's flight ends (a hit, a goal, out, or 3 s). Each outcome is
// told with the first wall the ball was heard bouncing off, and every bounce is a decision of
// its own along the way. The realized frequencies must match the tweaked probabilities of the
// predicted fates (end and first wall of the path): chi-square goodness of fit, rejected only
// at p < 0.001.
TEST(Property, RealizedOutcomesFollowTheTweakedProbabilities) {
  Field f = test::quiet_airhockey();
  f.bodies[1].start = {0.8f, 0.12f};
  WorldConfig config;
  config.particles = 400;
  World scene(f, config);
  scene.set_cloud(test::fan(0.0f, 0.0f, 2.5f, -0.9f, 0.9f, 400));
  FateReport report = scene.predict(3.0f);
  test::tweak_by(scene, report, [](const Fate& fate) { return factor_by_kind(fate.kind, KindFactors{}); });

  // Outcome categories: which target ends the ball's flight (or none within 3 s), and the first
  // wall on the way. At 2.5 m/s every wall contact of this fan is well above audible_bounce.
  auto via = [&](int wall) { return wall < 0 ? std::string() : " via " + f.wall_names[wall]; };
  auto category = [&](const Fate& fate) -> std::string {
    const std::string first = via(fate.path_len > 0 ? fate.path[0] : -1);
    switch (fate.kind) {
      case FateKind::Body:
      case FateKind::Catch:
      case FateKind::Pass:
      case FateKind::Intercept:
      case FateKind::Pickup:
      case FateKind::Tackle:
      case FateKind::Hit: return "hit " + f.bodies[fate.target].name + first;
      case FateKind::Goal:
      case FateKind::OwnGoal: return "goal " + f.goals[fate.target].name + first;
      case FateKind::Out: return "out" + first;
      case FateKind::Field: return "none" + first;
      case FateKind::Landing: return "landing" + first;  // none on a flat table
    }
    return "";
  };
  std::map<std::string, double> expected;
  std::map<std::string, double> newtonian;
  for (const FateGroup& g : report.groups) expected[category(g.fate)] += g.tweaked_mass, newtonian[category(g.fate)] += g.mass;
  ASSERT_GE(expected.size(), 3u);
  // The factors really moved the distribution: mallet and goal gain, "none" loses.
  EXPECT_GT(expected["hit Red's mallet"], newtonian["hit Red's mallet"] + 0.02);

  const int kMatches = 20000;
  std::map<std::string, double> seen;
  for (int seed = 0; seed < kMatches; ++seed) {
    WorldConfig c = config;
    c.seed = uint64_t(seed) + 1;
    World world(f, c);
    world.set_cloud(scene.cloud());
    world.set_contact_factors(scene.contact_factors());
    std::vector<Event> events;
    const std::vector<BodyInput> in = test::resting(f);
    auto ended = [&] { return !events.empty() && events.back().type != EventType::Bounce; };
    for (int s = 0; s < 180 && !ended(); ++s) world.step(kDt, in, events);
    const std::string first = via(!events.empty() && events[0].type == EventType::Bounce ? events[0].actor : -1);
    std::string outcome = "none";
    if (ended()) {
      const Event& e = events.back();
      if (e.type == EventType::Hit) outcome = "hit " + f.bodies[e.actor].name;
      else if (e.type == EventType::Out) outcome = "out";
      else outcome = "goal " + f.goals[e.actor].name;
    }
    seen[outcome + first] += 1;
  }
  double chi2 = 0;
  int cells = 0;
  for (const auto& [name, p] : expected) {
    const double e = p * kMatches;
    ASSERT_GE(e, 5) << name << ": too rare for the chi-square approximation; change the scene";
    chi2 += (seen[name] - e) * (seen[name] - e) / e;
    ++cells;
    std::cout << name << ": expected " << e << ", seen " << seen[name] << '\n';
  }
  for (const auto& [name, n] : seen) EXPECT_TRUE(expected.count(name)) << "unpredicted outcome " << name << " x" << n;
  const double p_value = 1 - boost::math::cdf(boost::math::chi_squared(cells - 1), chi2);
  std::cout << "chi2 = " << chi2 << " with " << cells - 1 << " degrees of freedom, p = " << p_value << '\n';
  EXPECT_GT(p_value, 0.001);
}

// Plausibility: after every realized hit, every surviving particle touched that body within the
// purgatory window: it is within reach of the body, give or take what both moved since. After a
// realized bounce every survivor is within one step's flight of that wall.
// After a goal or out nothing survives; after a drop everything is at the spot.
TEST(Property, SurvivorsAreConsistentWithEveryRealizedEvent) {
  WorldConfig config;
  config.particles = 2000;
  World world(test::airhockey(), config);
  const Field& f = world.field();
  int hits = 0, bounces = 0;
  play(world, 120, [&](const World& w, const std::vector<Event>& events) {
    for (const Event& e : events) {
      const Cloud& c = w.cloud();
      if (e.type == EventType::Drop) {
        ASSERT_EQ(c.size(), 1u);
        EXPECT_EQ(c.x[0], f.spots[e.actor].at.x);
      } else if (e.type == EventType::Hit) {
        ++hits;
        const Vec2 b = w.body_positions()[e.actor];
        const float window = float(config.purgatory_frames) * kDt;
        const float body_speed = std::hypot(w.body_velocities()[e.actor].x, w.body_velocities()[e.actor].y);
        for (size_t i = 0; i < c.size(); ++i) {
          const float speed = std::hypot(c.vx[i], c.vy[i]);
          const float reach = f.bodies[e.actor].radius + f.ball_radius + window * (speed + body_speed) + 0.02f;
          ASSERT_LE(std::hypot(c.x[i] - b.x, c.y[i] - b.y), reach) << "a survivor of " << f.bodies[e.actor].name
                                                                     << "'s hit never came near it, t = " << e.t;
        }
        EXPECT_EQ(w.last_touch(), e.actor);
      } else if (e.type == EventType::Bounce) {
        ++bounces;
        for (size_t i = 0; i < c.size(); ++i) {
          float nearest = 1e9f;
          for (const Segment& s : f.segments)
            if (s.wall == e.actor) nearest = std::min(nearest, test::segment_distance({c.x[i], c.y[i]}, s.a, s.b));
          // This step's flight (faster before the bounce) and its Brownian drift.
          const float reach = f.ball_radius + kDt * std::hypot(c.vx[i], c.vy[i]) / f.wall_restitution +
                              std::sqrt(2.0f) * noise_amplitude(f.brownian, kDt) + 1e-4f;
          ASSERT_LE(nearest, reach) << "a survivor of a bounce off " << f.wall_names[e.actor] << " is not at it, t = " << e.t;
        }
      } else {
        EXPECT_TRUE(c.empty());
        EXPECT_FALSE(w.live());
      }
    }
  });
  EXPECT_GT(hits, 10);
  EXPECT_GT(bounces, 10);
}

}  // namespace
}  // namespace quantum

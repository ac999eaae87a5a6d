// Differential test: the fast core and the Box2D reference (one rigid body per particle) move a
// shared scene of 10,000 particles; their fate distributions, and the walls they are first heard
// bouncing off, must agree within a total variation distance of 0.05.
#include <gtest/gtest.h>

#include <map>

#include "box2d_backend.h"
#include "test_scenes.h"

namespace quantum {
namespace {

constexpr float kDt = 1.0f / 60;
constexpr int kParticles = 10000;

// Shots from a spread of points in Blue's half at 1.5-3 m/s in every direction (Box2D's
// solver stops bounces below its restitution threshold; both sides use zero).
Cloud scene() {
  Cloud c;
  uint32_t h = 12345;
  auto next = [&h]() {
    h = h * 1664525u + 1013904223u;
    return float(h >> 8) / float(1 << 24);
  };
  for (int i = 0; i < kParticles; ++i) {
    const float x = -0.6f + 0.4f * next(), y = -0.3f + 0.6f * next();
    const float a = 6.2831853f * next(), speed = 1.5f + 1.5f * next();
    c.push(x, y, speed * std::cos(a), speed * std::sin(a), 1.0 / kParticles, 1.0 / kParticles);
  }
  return c;
}

struct Stepped {
  std::vector<double> ends;         // the first body, goal or out each particle reaches; last: none
  std::vector<double> first_walls;  // the first wall each bounces off audibly; last: none
};

// What each particle reaches within 3 s, stepping the backend directly so no decision removes
// anything.
Stepped fates_by_stepping(Backend& backend, const Field& f) {
  Cloud c = scene();
  const int nb = int(f.bodies.size()), ng = int(f.goals.size()), nw = int(f.wall_names.size());
  std::vector<BodyMotion> bodies;
  for (const BodySpec& b : f.bodies) bodies.push_back({b.start, b.start, {0, 0}, b.radius});
  std::vector<int> end(c.size(), -1), wall(c.size(), -1);
  std::vector<Contact> contacts;
  for (int s = 0; s < 180; ++s) {
    contacts.clear();
    const StepContext ctx{kDt, bodies.data(), nb, 0, 0.0f};
    backend.advance(c, ctx, contacts);
    for (const Contact& k : contacts) {
      if (k.target.kind == TargetKind::Crushed || end[k.particle] >= 0) continue;
      const int index = k.target.index;
      if (k.target.kind == TargetKind::Wall) {
        if (wall[k.particle] < 0) wall[k.particle] = index;
      } else {
        end[k.particle] = k.target.kind == TargetKind::Body ? index : k.target.kind == TargetKind::Goal ? nb + index : nb + ng;
      }
    }
  }
  Stepped out{std::vector<double>(nb + ng + 2, 0), std::vector<double>(nw + 1, 0)};
  for (size_t i = 0; i < c.size(); ++i) {
    out.ends[end[i] < 0 ? nb + ng + 1 : end[i]] += 1.0 / kParticles;
    out.first_walls[wall[i] < 0 ? nw : wall[i]] += 1.0 / kParticles;
  }
  return out;
}

double total_variation(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (size_t k = 0; k < a.size(); ++k) d += std::fabs(a[k] - b[k]);
  return d / 2;
}

TEST(Reference, FastCoreAndBox2DAgreeOnFates) {
  const Field f = test::quiet_airhockey();
  const auto fast = make_fast_backend(f);
  const auto box2d = make_box2d_backend(f);
  const Stepped fast_run = fates_by_stepping(*fast, f), box2d_run = fates_by_stepping(*box2d, f);
  const std::vector<double>&a = fast_run.ends, &b = box2d_run.ends;

  // The fast core's own prediction of the same scene, in the same categories.
  World world(f, WorldConfig{.particles = kParticles});
  world.set_cloud(scene());
  const FateReport r = world.predict(3.0f);
  const int nb = int(f.bodies.size()), ng = int(f.goals.size());
  std::vector<double> predicted(nb + ng + 2, 0);
  for (const FateGroup& g : r.groups) {
    const int k = g.fate.kind == FateKind::Body ? g.fate.target
                  : g.fate.kind == FateKind::Goal || g.fate.kind == FateKind::OwnGoal ? nb + g.fate.target
                  : g.fate.kind == FateKind::Out ? nb + ng
                                                 : nb + ng + 1;
    predicted[k] += g.mass;
  }
  for (size_t k = 0; k < a.size(); ++k)
    std::cout << "category " << k << ": fast " << a[k] << ", predicted " << predicted[k] << ", box2d " << b[k] << '\n';
  // Every category is populated, so agreement is not agreement on nothing.
  for (int k = 0; k < nb + ng; ++k) EXPECT_GT(b[k], 0.02) << "category " << k;
  EXPECT_LT(total_variation(a, b), 0.05);
  EXPECT_LT(total_variation(predicted, b), 0.05);
  // Stepping and predicting without noise are the same physics.
  EXPECT_LT(total_variation(a, predicted), 0.01);
  // Both report the same audible bounces.
  for (size_t k = 0; k < fast_run.first_walls.size(); ++k)
    std::cout << "first bounce " << k << ": fast " << fast_run.first_walls[k] << ", box2d " << box2d_run.first_walls[k] << '\n';
  for (size_t k = 0; k + 1 < box2d_run.first_walls.size(); ++k) EXPECT_GT(box2d_run.first_walls[k], 0.02) << "wall " << k;
  EXPECT_LT(total_variation(fast_run.first_walls, box2d_run.first_walls), 0.05);
}

TEST(Reference, Box2DBackendPlaysAMatch) {
  const Field f = test::airhockey();
  WorldConfig config;
  config.particles = 300;
  World world(f, config, make_box2d_backend(f));
  std::vector<Event> events;
  world.drop(0, events);
  for (int s = 0; s < 300; ++s) world.step(kDt, test::resting(f), events);
  EXPECT_EQ(world.cloud().size(), 300u);
  EXPECT_NEAR(test::weight_sum(world.cloud()), 1.0, 1e-9);
}

}  // namespace
}  // namespace quantum

// Small fields and scenes the core's tests share.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <boost/math/distributions/chi_squared.hpp>
#include <iostream>
#include <map>

#include "field_loader.h"
#include "quantum/world.h"

namespace quantum::test {

// The field of a sport with Brownian motion off: trajectories are exactly what prediction says.
inline Field quiet(const std::string& sport) {
  Field f = lua::load_field(QUANTUM_SOURCE_DIR "/rules/" + sport);
  f.brownian = 0;
  return f;
}

// The index of the body of that name (a test failure when there is none).
inline int body_named(const Field& f, const std::string& name) {
  for (size_t k = 0; k < f.bodies.size(); ++k)
    if (f.bodies[k].name == name) return int(k);
  ADD_FAILURE() << "no player " << name;
  return 0;
}

// One particle at p moving at v: a ball with height, exactly where a test puts it.
inline Cloud one_ball(Vec3 p, Vec3 v) {
  Cloud c;
  c.push(p, v, 1, 1);
  return c;
}

// Every player of the basketball half court (or a field of its size) parked in its far corner,
// out of the way, unless placed.
inline std::vector<BodyInput> parked_in_corner(const Field& f, const std::map<std::string, Vec2>& placed = {}) {
  std::vector<BodyInput> in;
  for (size_t k = 0; k < f.bodies.size(); ++k) {
    const auto it = placed.find(f.bodies[k].name);
    in.push_back({it != placed.end() ? it->second : Vec2{-7.0f + 0.2f * float(k), 13.5f}, {0, 0}});
  }
  return in;
}

// A world of seed `seed` set up as a scene: the bodies placed, the ball replaced by `cloud`,
// `last_touch` the last to touch it, the contacts weighed by `contact_factors` (none: 1). For
// statistical tests that replay one scene many times.
inline std::unique_ptr<World> scene_world(const Field& f, WorldConfig config, uint64_t seed,
                                          const std::vector<BodyInput>& bodies, const Cloud& cloud, int last_touch,
                                          const std::vector<double>& contact_factors = {}) {
  config.seed = seed;
  auto world = std::make_unique<World>(f, config);
  world->place_bodies(bodies);
  world->set_cloud(cloud);
  world->set_last_touch(last_touch);
  if (!contact_factors.empty()) world->set_contact_factors(contact_factors);
  return world;
}

// Tweaks the scene's fates and weighs its contacts with factor_of(fate) alike: with the bodies
// where prediction has them, a particle meets what it was predicted to and weighs what its fate
// did, so the realized outcomes follow the tweaked fates.
template <class FactorOf>
void tweak_by(World& world, FateReport& report, FactorOf factor_of) {
  std::vector<double> factors;
  for (const FateGroup& g : report.groups) factors.push_back(factor_of(g.fate));
  world.tweak(report, factors);
  std::vector<Fate> contacts;
  world.contact_fates(contacts);
  factors.clear();
  for (const Fate& c : contacts) factors.push_back(factor_of(c));
  world.set_contact_factors(factors);
}

inline Field airhockey() { return lua::load_field(QUANTUM_SOURCE_DIR "/rules/airhockey"); }

// The air hockey table with Brownian motion off: trajectories are exactly what prediction says.
inline Field quiet_airhockey() {
  Field f = airhockey();
  f.brownian = 0;
  return f;
}

inline Cloud single(float x, float y, float vx, float vy) {
  Cloud c;
  c.push(x, y, vx, vy, 1, 1);
  return c;
}

// n particles at one point, fanned over [a0, a1] radians at one speed.
inline Cloud fan(float x, float y, float speed, float a0, float a1, int n) {
  Cloud c;
  for (int i = 0; i < n; ++i) {
    const float a = a0 + (a1 - a0) * (float(i) + 0.5f) / float(n);
    c.push(x, y, speed * std::cos(a), speed * std::sin(a), 1.0 / n, 1.0 / n);
  }
  return c;
}

// Every body held at its start position.
inline std::vector<BodyInput> resting(const Field& f) {
  std::vector<BodyInput> in;
  for (const BodySpec& b : f.bodies) in.push_back({b.start, {0, 0}});
  return in;
}

// Body k starts at `from` and moves at `velocity` until something is realized (at most half a
// second). Returns the events and leaves the last input in `in`.
inline std::vector<Event> strike(World& world, int k, Vec2 from, Vec2 velocity, std::vector<BodyInput>& in) {
  constexpr float kDt = 1.0f / 60;
  in = resting(world.field());
  std::vector<Event> events;
  Vec2 at = from;
  for (int s = 0; s < 30 && events.empty(); ++s) {
    at.x += velocity.x * kDt, at.y += velocity.y * kDt;
    in[k] = {at, velocity};
    world.step(kDt, in, events);
  }
  return events;
}

inline double weight_sum(const Cloud& c) {
  double s = 0;
  for (size_t i = 0; i < c.size(); ++i) s += c.weight(i);
  return s;
}

inline double tweaked_sum(const Cloud& c) {
  double s = 0;
  for (size_t i = 0; i < c.size(); ++i) s += c.tweaked(i);
  return s;
}

// Pearson's chi-square goodness of fit of `seen` counts out of `n` draws to `expected` shares
// (each expected count at least 5); prints both and returns the p-value.
inline double fit_p(const std::map<std::string, double>& expected, std::map<std::string, double> seen, int n) {
  double chi2 = 0;
  for (const auto& [what, share] : expected) {
    const double e = share * n;
    EXPECT_GE(e, 5) << what << ": too rare for the chi-square test";
    chi2 += (seen[what] - e) * (seen[what] - e) / e;
    std::cout << what << ": expected " << share << ", seen " << seen[what] / n << '\n';
  }
  const double dof = double(expected.size() - 1);
  const double p = 1 - boost::math::cdf(boost::math::chi_squared(dof), chi2);
  std::cout << "chi2 = " << chi2 << " with " << dof << " degrees of freedom, p = " << p << '\n';
  return p;
}

// Distance from p to segment a-b.
inline float segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const float ex = b.x - a.x, ey = b.y - a.y;
  float t = ((p.x - a.x) * ex + (p.y - a.y) * ey) / (ex * ex + ey * ey);
  t = std::fmax(0.0f, std::fmin(1.0f, t));
  return std::hypot(p.x - a.x - t * ex, p.y - a.y - t * ey);
}

}  // namespace quantum::test

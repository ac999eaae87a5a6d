// The contact search: the batched search (prediction and the step) against the scalar one, and
// the end points' cheap pre-pass against the exact test it stands in front of.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "field_loader.h"
#include "quantum/contact.h"
#include "../shipped_sports.h"

namespace quantum {
namespace {

// A point moving along a line that passes the circle's centre at `miss` times its radius, from
// up to 300 radii away: the pre-pass must take every one the exact test takes, down to grazing
// paths a millionth of the radius either side of touching, at speeds from 1 cm/s to 100 m/s.
TEST(Contact, TheEndPointPrePassNeverLeavesOutAContactTheExactTestFinds) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> angle(0, 6.2831853f), unit(0, 1), decades(-2, 2);
  int met = 0, marked_leaving = 0, leaving = 0;
  for (int draw = 0; draw < 400000; ++draw) {
    const float rr = 0.005f + 0.5f * unit(rng), speed = std::pow(10.0f, decades(rng));
    const float heading = angle(rng), distance = rr * std::pow(10.0f, 2.5f * unit(rng));
    // Grazing lines for half the draws; any line for the rest.
    const float miss = draw % 2 ? 1 + (unit(rng) - 0.5f) * 2e-6f * std::pow(10.0f, 4 * unit(rng)) : 3 * unit(rng);
    const float hx = std::cos(heading), hy = std::sin(heading), side = draw % 4 < 2 ? 1.0f : -1.0f;
    // Start `distance` from the centre, back along the heading and offset sideways by miss * rr.
    const float back = std::sqrt(std::max(distance * distance - miss * miss * rr * rr, 0.0f));
    const float qx = -hx * back - side * hy * miss * rr, qy = -hy * back + side * hx * miss * rr;
    const float wx = hx * speed, wy = hy * speed;
    const bool exact = detail::circle_time(qx, qy, wx, wy, rr, detail::kInf) < detail::kInf;
    met += exact;
    ASSERT_TRUE(detail::circle_may_meet(qx, qy, wx, wy, rr) || !exact)
        << "left out: q (" << qx << ", " << qy << ") w (" << wx << ", " << wy << ") rr " << rr;
    // The same line the other way, leaving the circle from outside it: never a contact, and the
    // pre-pass must not send it to the exact test either.
    if (qx * qx + qy * qy > rr * rr * 1.01f) {
      ++leaving;
      marked_leaving += detail::circle_may_meet(qx, qy, -wx, -wy, rr);
    }
  }
  EXPECT_GT(met, 100000);  // the draws did meet the circle, grazing ones among them
  EXPECT_LT(marked_leaving, leaving / 1000);
}

// Whether m, moved on for dt, touches one of the field's end points rather than a wall's side.
bool touches_an_end_point(const detail::Geometry& g, const detail::Mover& m, float dt) {
  for (size_t k = 0; k < g.cap_x.size(); ++k)
    if (std::hypot(m.x + m.ux * dt - g.cap_x[k], m.y + m.uy * dt - g.cap_y[k]) < g.r * 1.001f) return true;
  return false;
}

// Random particles on every shipped field, the bodies moving: the batched search (every primitive
// over all of them, end points and bodies through the pre-pass, their normals on the marked paths) finds for
// each the contact the scalar search finds (the primitives near it, through the grid). The two
// compute the same formulas, but the compiler may fuse multiply-adds differently in a vectorized
// loop: a path grazing an end point or a body (the square root of a discriminant near zero) can
// then meet it a little earlier or later, or only in one of them. Those are allowed, one in ten
// thousand paths; any other difference is not.
TEST(Contact, TheBatchedSearchFindsWhatTheScalarSearchFinds) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0, 1), angle(0, 6.2831853f);
  int paths = 0, grazing = 0, at_end_points = 0, at_bodies = 0;
  for (const std::string sport : quantum::test::kShippedSports) {
    SCOPED_TRACE(sport);
    const Field f = lua::load_field(QUANTUM_SOURCE_DIR "/rules/" + sport);
    const detail::Geometry g(f);
    std::vector<detail::BodyPath> bodies;
    for (const BodySpec& body : f.bodies) {
      const float a = angle(rng), v = 3 * unit(rng), vx = v * std::cos(a), vy = v * std::sin(a);
      bodies.push_back({body.start.x, body.start.y, vx, vy, 0.25f, vx, vy, body.radius});
    }
    const int nb = int(bodies.size());
    constexpr size_t kBatch = 1024;
    detail::MoverBatch batch;
    batch.resize(kBatch);
    std::vector<detail::Mover> movers(kBatch);
    for (int round = 0; round < 40; ++round) {
      for (size_t i = 0; i < kBatch; ++i) {
        const float a = angle(rng), v = 0.01f + 8 * unit(rng) * unit(rng), vx = v * std::cos(a), vy = v * std::sin(a);
        movers[i] = {f.bounds_min.x + (f.bounds_max.x - f.bounds_min.x) * unit(rng),
                     f.bounds_min.y + (f.bounds_max.y - f.bounds_min.y) * unit(rng), vx, vy, vx, vy};
        batch.set(i, movers[i], 0);
      }
      detail::batch_next_hits(g, bodies.data(), nb, batch, kBatch, 3.0f);
      for (size_t i = 0; i < kBatch; ++i) {
        ++paths;
        const detail::Mover& m = movers[i];
        const detail::Hit hit = detail::next_hit(g, bodies.data(), nb, m, 0, 3.0f, true);
        const detail::HitKind kind = detail::code_kind(batch.code[i]);
        const int index = detail::code_index(batch.code[i]);
        const bool same = kind == hit.kind && (kind == detail::HitKind::None || index == hit.index);
        if (!same || (kind != detail::HitKind::None && std::fabs(batch.when[i] - hit.dt) > 1e-5f * (1 + hit.dt))) {
          ++grazing;
          std::cout << sport << ": (" << m.x << ", " << m.y << ") moving (" << m.ux << ", " << m.uy << "): batch "
                    << int(kind) << "/" << index << " at " << batch.when[i] << ", scalar " << int(hit.kind) << "/"
                    << hit.index << " at " << hit.dt << "\n";
          continue;
        }
        if (kind == detail::HitKind::None) continue;
        // The normal belongs to the contact found: its direction from the point or the body's
        // centre to the ball's at the contact time.
        const float reach = kind == detail::HitKind::Body ? bodies[size_t(index)].radius + g.r : g.r;
        const float slack = 1e-4f + 2 * std::hypot(m.ux, m.uy) * std::fabs(batch.when[i] - hit.dt) / reach;
        ASSERT_NEAR(batch.nx[i], hit.nx, slack) << "kind " << int(kind) << " at " << hit.dt;
        ASSERT_NEAR(batch.ny[i], hit.ny, slack) << "kind " << int(kind) << " at " << hit.dt;
        at_end_points += kind == detail::HitKind::Wall && touches_an_end_point(g, m, batch.when[i]);
        at_bodies += kind == detail::HitKind::Body;
      }
    }
  }
  EXPECT_LE(grazing, paths / 10000);
  // The draws did end at end points and at bodies, whose normals only the marked paths work out.
  EXPECT_GT(at_end_points, 50);
  EXPECT_GT(at_bodies, 500);
}

}  // namespace
}  // namespace quantum

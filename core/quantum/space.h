// The two kinds of field a ball is traced on, behind one interface: Flat (the ball slides on a
// table or flies at chest height) and Tall (a field with gravity, where the ball has height).
// The step's tracer (step_tracer.h) and the fate prediction (fate.cpp) are written once over a
// space, so a new kind of contact is written once and means the same on both; what differs
// between the two is said here. Internal to core/quantum.
#pragma once

#include "height.h"
#include "quantum/cloud.h"
#include "quantum/contact.h"

namespace quantum::detail {

struct Flat {
  static constexpr bool kHeight = false;
  using Mover = detail::Mover;
  using Batch = MoverBatch;
  using Hit = detail::Hit;

  const Geometry& g;

  // The earliest contact of each of the batch's first n particles, each from its own b.t up to t1.
  void search(const BodyPath* bodies, int n_bodies, Batch& b, size_t n, float t1) const {
    batch_next_hits(g, bodies, n_bodies, b, n, t1);
  }
  // The same for one particle from t0: the scalar search, which finds what the batch search does.
  Hit next_hit(const BodyPath* bodies, int n_bodies, const Mover& m, float t0, float t1) const {
    return detail::next_hit(g, bodies, n_bodies, m, t0, t1, true);
  }
  Hit hit(const Batch& b, size_t j) const {
    const HitKind kind = code_kind(b.code[j]);
    return {b.when[j], kind, kind == HitKind::None ? -1 : code_index(b.code[j]), b.nx[j], b.ny[j]};
  }
  static Mover mover(const Batch& b, size_t j) { return {b.x[j], b.y[j], b.ux[j], b.uy[j], b.vx[j], b.vy[j]}; }
  // Particle i of a cloud, moving with its own velocity (no drift).
  static Mover ball(const Cloud& c, size_t i) { return {c.x[i], c.y[i], c.vx[i], c.vy[i], c.vx[i], c.vy[i]}; }
  static Vec3 where(const Mover& m) { return {m.x, m.y, 0}; }
  static Mover shadow(const Mover& m) { return m; }  // the ball seen from above
  // The length of path, at m's start speed, that dt of flight time covers: dt itself (friction is
  // in the flight time already).
  static float span(const Mover&, float dt) { return dt; }
  // Free flight for dt seconds: a straight line.
  Mover advanced(const Mover& m, float dt) const { return {m.x + m.ux * dt, m.y + m.uy * dt, m.ux, m.uy, m.vx, m.vy}; }
  void resolve(const BodyPath* bodies, const Hit& h, float t, Mover& m) const {
    detail::resolve(g, bodies, h.kind, h.index, h.nx, h.ny, t, m);
  }
  // The ball's own speed into the surface it met (for whether a bounce is heard).
  static float impact_speed(const Hit& h, const Mover& m) { return -(m.vx * h.nx + m.vy * h.ny); }
};

struct Tall {
  static constexpr bool kHeight = true;
  using Mover = Mover3;
  using Batch = Mover3Batch;
  using Hit = Hit3;

  const Geometry& g;
  const Sky& sky;

  // Bodies are met only when some are given: a particle that met one already finishes its step
  // against everything else.
  void search(const BodyPath* bodies, int n_bodies, Batch& b, size_t n, float t1) const {
    batch_next_hits3(g, sky, bodies, n_bodies, b, n, t1, n_bodies > 0);
  }
  Hit next_hit(const BodyPath* bodies, int n_bodies, const Mover& m, float t0, float t1) const {
    return landed(next_hit3(g, sky, bodies, n_bodies, m, t0, t1, true), m.x, m.y, m.ux, m.uy);
  }
  Hit hit(const Batch& b, size_t j) const { return landed(b.hit(j), b.x[j], b.y[j], b.ux[j], b.uy[j]); }
  // A touch of the floor on a field of landings is a Landing at the area where the ball's centre
  // comes down (seen from above its flight is a straight line, so that is exact); it bounces as
  // the floor does.
  Hit landed(Hit h, float x, float y, float ux, float uy) const {
    if (sky.landings && h.kind == HitKind::Wall && h.surface == Surface::Floor)
      h.kind = HitKind::Landing, h.index = sky.landing_at(x + ux * h.dt, y + uy * h.dt);
    return h;
  }
  static Mover mover(const Batch& b, size_t j) { return b.mover(j); }
  static Mover ball(const Cloud& c, size_t i) {
    return {c.x[i], c.y[i], c.z[i], c.vx[i], c.vy[i], c.vx[i], c.vy[i], c.vz[i]};
  }
  static Vec3 where(const Mover& m) { return {m.x, m.y, m.z}; }
  static detail::Mover shadow(const Mover& m) { return m.flat(); }
  // The length of path, at m's start speed, that dt seconds cover: dt, or less for a ball rolling
  // on a floor with friction.
  float span(const Mover& m, float dt) const { return sky.gravity_on(m) == 0 ? sky.rolled(dt) : dt; }
  // Free flight for dt seconds: a parabola, or a roll on the floor.
  Mover advanced(const Mover& m, float dt) const { return detail::advanced(sky, m, dt); }
  void resolve(const BodyPath* bodies, const Hit& h, float t, Mover& m) const { detail::resolve(g, sky, bodies, h, t, m); }
  static float impact_speed(const Hit& h, const Mover& m) { return detail::impact_speed(h, m); }
};

}  // namespace quantum::detail

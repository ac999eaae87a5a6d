// Contacts of a ball with height (fields with gravity): it flies in parabolas, bounces off the
// floor, a ceiling, backboards and hoop rims, scores by coming down through a hoop, and meets
// players as vertical cylinders up to their reach. Shared by the step and by fate prediction, so
// a prediction without noise follows exactly the path the step takes. Internal to core/quantum.
//
// The horizontal motion of a flying ball is still a straight line, so walls, goal lines, the
// bounds and the sides of bodies are the flat search's (contact.h), run on the ball's shadow;
// only what depends on height is solved here. The search runs over batches of particles
// (batch_next_hits3), written for the vectorizer; one particle is a batch of one.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "quantum/contact.h"

namespace quantum::detail {

// The ball's centre sits on the floor from this height down, and stops bouncing below this
// upward speed (a bounce 2 mm high): a ball at rest on the floor rolls, and gravity is held by
// the floor.
constexpr float kGroundSkin = 1e-4f;
constexpr float kRestingBounce = 0.2f;

struct Mover3 {
  float x, y, z;
  float ux, uy;      // horizontal velocity along the path: the ball's own plus the Brownian drift
  float vx, vy, vz;  // the ball's own velocity

  Mover flat() const { return {x, y, ux, uy, vx, vy}; }
};

// What depends on height, rearranged for the search.
struct Sky {
  explicit Sky(const Field& field);

  float g = 0, e_floor = 0, r = 0;
  // The floor's rolling friction (Field::friction), 1/s. A rolling ball's speed falls as
  // e^(-roll t), so its path is still a straight line, covered by rolled(t) at its start speed in
  // t seconds: a rolling particle is searched over that length and its contact time read back by
  // roll_time. A flying ball is not slowed.
  float roll = 0;
  float rolled(float t) const { return roll > 0 ? -std::expm1(-roll * t) / roll : t; }
  float roll_time(float span) const { return roll > 0 ? -std::log1p(-roll * span) / roll : span; }
  float ceiling = kInf;  // the highest the ball's centre gets
  int floor_wall = -1, ceiling_wall = -1;
  // Hoops: centre, ring radius, half the rod's thickness, restitution; their goal and rim wall.
  std::vector<float> hx, hy, hz, hring, htube, he, hhop;
  std::vector<int> hgoal, hwall;
  // Boards: the floor line (as a wall segment), height range, restitution, wall.
  std::vector<SegmentParams> board;
  std::vector<float> bbottom, btop, be;
  std::vector<int> bwall;
  // A box around every hoop and board, grown by the ball's radius: only a particle whose step
  // comes near it needs their search.
  float ox0 = 1, oy0 = 1, oz0 = 1, ox1 = 0, oy1 = 0, oz1 = 0;

  // A field of landings (Field::landings): where the floor is touched matters, by its areas.
  bool landings = false;
  std::vector<Area> areas;
  // A landing's index at (x, y): the first area there + 1, 0 outside every area.
  int landing_at(float x, float y) const;

  bool grounded(const Mover3& m) const { return m.vz == 0 && m.z <= r + kGroundSkin; }
  float gravity_on(const Mover3& m) const { return grounded(m) ? 0.0f : g; }
};

// What a contact is with, beyond its HitKind: walls are segments, the floor, the ceiling, a rim
// or a board; a body is met on its side or its top.
enum class Surface : uint8_t { Segment, Floor, Ceiling, Rim, Board, Side, Top };

struct Hit3 {
  float dt;  // from the search's start
  HitKind kind;
  int index;  // wall id, body, goal or wormhole mouth
  Surface surface;
  int item;  // the hoop or board
  float nx, ny, nz;
};

// The rim search's state per particle (height.cpp): two stretches of the arc level with the rod.
struct RingScratch {
  std::vector<float> hi0, lo1, hi1, fast0, fast1, bend0, bend1, at, found, limit;
  // Unsigned: the sanitizers' overflow check on a signed counter kept the probe loop scalar.
  std::vector<uint32_t> stage, steps;
  // The particles still searching, gathered: where they are from the hoop, how they move.
  std::vector<float> qx, qy, qz, ux, uy, vz, g, hit;
  std::vector<int32_t> lane;
  void resize(size_t n);
};

// Particles with height in structure-of-arrays form, searched together (as MoverBatch).
struct Mover3Batch {
  std::vector<float> x, y, z, ux, uy, vx, vy, vz, t;  // each particle at its own time t
  std::vector<float> when, nx, ny, nz;                // the search's answer: time from t, normal
  // Also the answer, all 32 bits wide: the vectorizer gives up on loops that mix widths.
  std::vector<int32_t> code;     // hit_code(kind, index), or -1 for none
  std::vector<int32_t> surface;  // Surface
  std::vector<int32_t> item;     // the hoop or board
  std::vector<float> g, span, clear;  // the search's scratch
  std::vector<int32_t> near;
  RingScratch ring;
  void resize(size_t n);
  void set(size_t j, const Mover3& m, float at) {
    x[j] = m.x, y[j] = m.y, z[j] = m.z, ux[j] = m.ux, uy[j] = m.uy, vx[j] = m.vx, vy[j] = m.vy, vz[j] = m.vz;
    t[j] = at;
  }
  Mover3 mover(size_t j) const { return {x[j], y[j], z[j], ux[j], uy[j], vx[j], vy[j], vz[j]}; }
  Hit3 hit(size_t j) const {
    const HitKind kind = code_kind(code[j]);
    return {when[j], kind, kind == HitKind::None ? -1 : code_index(code[j]), Surface(surface[j]), item[j],
            nx[j], ny[j], nz[j]};
  }
};

// The columns the search with height reads and answers beyond the flat search's (Paths): taken
// once per search, and handed on to the rim search.
struct Paths3 : Paths {
  const float *__restrict z, *__restrict vz;
  float *__restrict nz, *__restrict g, *__restrict span;  // g and span: the search's scratch
  int32_t *__restrict surface, *__restrict item, *__restrict near;

  explicit Paths3(Mover3Batch& b)
      : Paths(b), z(b.z.data()), vz(b.vz.data()), nz(b.nz.data()), g(b.g.data()), span(b.span.data()),
        surface(b.surface.data()), item(b.item.data()), near(b.near.data()) {}
};

// next_hit3 for particles [0, n) of the batch, each from its own b.t up to t1. next_hit3 is this
// search on a batch of one, so both find the same contact to the bit.
void batch_next_hits3(const Geometry& g, const Sky& sky, const BodyPath* bodies, int n_bodies, Mover3Batch& b,
                      size_t n, float t1, bool with_bodies);

// m moved on by dt seconds of free flight (or of rolling, slowed by the floor).
Mover3 advanced(const Sky& sky, const Mover3& m, float dt);

// Earliest contact of m (at time t0) in (t0, t1]; bodies skipped when `with_bodies` is false.
Hit3 next_hit3(const Geometry& g, const Sky& sky, const BodyPath* bodies, int n_bodies, const Mover3& m, float t0,
               float t1, bool with_bodies);

// Applies a contact found by the search to m, already moved to the contact time t: the floor, the
// ceiling, a board, a rim or a body's top here, the rest by the flat field's resolve (contact.h).
void resolve(const Geometry& g, const Sky& sky, const BodyPath* bodies, const Hit3& hit, float t, Mover3& m);

// The ball's speed into the surface it met (for whether a bounce is heard).
float impact_speed(const Hit3& hit, const Mover3& m);

}  // namespace quantum::detail

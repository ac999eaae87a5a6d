// Swept contacts of particles against walls, goal lines, the field's bounds and moving bodies.
// Shared by the step and by fate prediction, so a prediction without noise follows exactly the
// path the step would take. Internal to core/quantum and its backends.
//
// Each primitive test is one branch-free inline function. The scalar search (next_hit) calls it
// for the few primitives near one particle; the batch search (batch_next_hits) calls it for
// every primitive over many particles at once, which the compiler vectorizes. Same functions,
// same arithmetic: both searches find the same contact.
#pragma once

#include <algorithm>
#include <bit>
#include <cstring>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "quantum/backend.h"
#include "quantum/field.h"
#include "quantum/independent_loop.h"

namespace quantum::detail {

// Distances below this count as touching: a few float ulps at field scale.
constexpr float kTolerance = 1e-5f;
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Box {
  float x0 = 1, y0 = 1, x1 = 0, y1 = 0;  // empty by default
  bool contains(float x, float y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

// The field rearranged for the contact search: structure of arrays throughout.
struct Geometry {
  explicit Geometry(const Field& field);

  float r, e_wall, e_body, audible_bounce;
  std::vector<float> ax, ay, tx, ty, nx, ny, len;  // segments: start, unit tangent, left normal
  std::vector<int> wall;
  std::vector<float> sx0, sy0, sx1, sy1;           // segment bounding boxes
  std::vector<float> cap_x, cap_y;                 // segment end points: round caps a ball can hit
  std::vector<int> cap_wall;                       // the wall each end point belongs to
  std::vector<float> gax, gay, gtx, gty, gnx, gny, glen;  // goal lines; normal points into the goal
  std::vector<float> gx0, gy0, gx1, gy1;
  std::vector<int> goal_id;  // the field's goal each line is (hoops are goals without a line)
  Box bounds;
  // No wall, goal line or bound within reach of a ball centre inside this box: a particle that
  // starts and ends a step inside it needs no contact search.
  Box safe;
  // Wormhole mouths: 2k and 2k + 1 are the two ends of wormhole k (set at run time).
  std::vector<float> mx, my, mr;
  void set_wormholes(const std::vector<Wormhole>& wormholes);

  // A uniform grid over the bounds. Each cell lists the segments, end points and goal lines
  // that a ball starting in the cell can reach within `grid_reach` of travel: a step's path is a
  // few centimetres, so its contact search tests one or two primitives instead of all of them.
  struct Candidates {
    const uint16_t *segments, *caps, *goals;
    uint16_t n_segments, n_caps, n_goals;
    bool near_bounds;
  };
  Candidates candidates(float x, float y, float travel_squared) const;
  float cell = 0, inv_cell = 0, grid_reach = 0;
  int cols = 0, rows = 0;
  std::vector<uint32_t> cell_start;  // per cell: offsets into cell_items, 3 lists per cell
  std::vector<uint16_t> cell_items;
  std::vector<uint8_t> cell_near_bounds;
  std::vector<uint16_t> all_items;   // 0, 1, 2, ... for searches the grid cannot serve
  // What the grid holds, in bytes: at most limits::kMaxGridBytes whatever the bounds.
  size_t grid_bytes() const;

 private:
  void use_cells_of(float size);
  void build_grid(const Field& field);
};

// A body's motion over the traced interval: linear until `stop`, then at rest.
struct BodyPath {
  float x, y;    // position at t = 0
  float ux, uy;  // sweep velocity until `stop`
  float stop;
  float vx, vy;  // velocity given to the ball on contact while moving
  float radius;
  float top = kInf;  // fields with height: how high the body reaches
  bool passes = false;  // the ball passes through it (BodyMotion::passes): searches skip it
};

[[gnu::always_inline]] inline float body_x(const BodyPath& b, float t) { return b.x + b.ux * std::min(t, b.stop); }
[[gnu::always_inline]] inline float body_y(const BodyPath& b, float t) { return b.y + b.uy * std::min(t, b.stop); }
inline Vec2 body_position(const BodyPath& b, float t) { return {body_x(b, t), body_y(b, t)}; }

struct Mover {
  float x, y;
  float ux, uy;  // velocity along the path: the ball's own plus this step's Brownian drift
  float vx, vy;  // the ball's own velocity
};

// --- Primitive tests. Each returns the time from now to the contact within `span`, or kInf.

// A segment (start a, unit tangent t, left normal n, length len): the ball's centre reaching one
// of its two offset lines at distance r. Sets the normal toward the ball.
struct SegmentParams {
  float ax, ay, tx, ty, nx, ny, len;
};
inline SegmentParams segment(const Geometry& g, size_t k) {
  return {g.ax[k], g.ay[k], g.tx[k], g.ty[k], g.nx[k], g.ny[k], g.len[k]};
}
[[gnu::always_inline]] inline float wall_time(const SegmentParams& s, float r, float x, float y, float ux, float uy, float span, float& hnx,
                       float& hny) {
  const float d0 = (x - s.ax) * s.nx + (y - s.ay) * s.ny;
  const float side = d0 >= 0 ? 1.0f : -1.0f;
  const float approach = -side * (ux * s.nx + uy * s.ny);
  const float dt = std::max(0.0f, (side * d0 - r) / approach);
  const float along = (x + ux * dt - s.ax) * s.tx + (y + uy * dt - s.ay) * s.ty;
  hnx = side * s.nx, hny = side * s.ny;
  return approach > 0 && dt <= span && along >= 0 && along <= s.len ? dt : kInf;
}

// A point at (qx, qy) relative to a circle's centre entering the circle of radius rr while
// moving with (wx, wy); 0 when it is inside already.
[[gnu::always_inline]] inline float circle_time(float qx, float qy, float wx, float wy, float rr, float span) {
  const float c = qx * qx + qy * qy - rr * rr;
  const float b = qx * wx + qy * wy;
  const float ww = wx * wx + wy * wy;
  const float disc = b * b - ww * c;
  const bool inside = c < -2 * rr * kTolerance;
  const float dt = inside ? 0.0f : std::max(0.0f, (-b - std::sqrt(std::max(disc, 0.0f))) / ww);
  return (inside || (b < 0 && disc >= 0)) && dt <= span ? dt : kInf;
}

// A superset of the cases circle_time finds a contact in, without its square root and division:
// the point inside already, or closing on the circle (b < 0) along a line that passes within
// reach of its centre (disc >= 0). The slack is far above what rounding b and disc can change
// (a few ulps of |q||w| and of |w|^2 (|q|^2 + rr^2)), so a contact the exact test finds is never
// left out, whichever way the compiler contracts the two.
[[gnu::always_inline]] inline bool circle_may_meet(float qx, float qy, float wx, float wy, float rr) {
  const float qq = qx * qx + qy * qy, ww = wx * wx + wy * wy;
  const float c = qq - rr * rr, b = qx * wx + qy * wy;
  const float disc = b * b - ww * c;
  constexpr float kSlack = 1e-5f;
  const bool closing = (b < 0) | (b * b < kSlack * kSlack * qq * ww);
  return (c < 0) | (closing & (disc >= -kSlack * ww * (qq + rr * rr)));
}

// The ball's centre crossing a goal line into the goal (n points into the goal).
inline SegmentParams goal_line(const Geometry& g, size_t k) {
  return {g.gax[k], g.gay[k], g.gtx[k], g.gty[k], g.gnx[k], g.gny[k], g.glen[k]};
}
[[gnu::always_inline]] inline float goal_time(const SegmentParams& s, float x, float y, float ux, float uy, float span) {
  const float d0 = (x - s.ax) * s.nx + (y - s.ay) * s.ny;
  const float approach = ux * s.nx + uy * s.ny;
  const float dt = std::max(0.0f, -d0 / approach);
  const float along = (x + ux * dt - s.ax) * s.tx + (y + uy * dt - s.ay) * s.ty;
  return d0 <= kTolerance && approach > 0 && dt <= span && along >= 0 && along <= s.len ? dt : kInf;
}

// The ball's centre entering a wormhole mouth (centre at -q, radius rr) from outside: a ball
// inside one, just arrived through it, is not entering it.
[[gnu::always_inline]] inline float mouth_time(float qx, float qy, float wx, float wy, float rr, float span) {
  const float c = qx * qx + qy * qy - rr * rr;
  const float b = qx * wx + qy * wy, ww = wx * wx + wy * wy;
  const float disc = b * b - ww * c;
  const float dt = std::max(0.0f, (-b - std::sqrt(std::max(disc, 0.0f))) / ww);
  return c > 0 && b < 0 && disc >= 0 && dt <= span ? dt : kInf;
}

// The ball's centre leaving the bounds.
[[gnu::always_inline]] inline float bounds_time(const Box& bounds, float x, float y, float ux, float uy, float span) {
  const float tx = ux > 0 ? (bounds.x1 - x) / ux : ux < 0 ? (bounds.x0 - x) / ux : kInf;
  const float ty = uy > 0 ? (bounds.y1 - y) / uy : uy < 0 ? (bounds.y0 - y) / uy : kInf;
  const float dt = std::max(0.0f, std::min(tx, ty));
  return dt <= span ? dt : kInf;
}

// Body b, which moves until its stop and then rests, met by a ball at time t0.
[[gnu::always_inline]] inline float body_time(const BodyPath& b, float r, float x, float y, float ux, float uy, float t0, float t1) {
  const float rr = b.radius + r;
  // While the body moves...
  const float moving = std::max(0.0f, std::min(t1, b.stop) - t0);
  const float d1 = circle_time(x - body_x(b, t0), y - body_y(b, t0), ux - b.ux, uy - b.uy, rr, moving);
  // ...and once it rests.
  const float ts = std::max(t0, b.stop);
  const float d2 = circle_time(x + ux * (ts - t0) - body_x(b, ts), y + uy * (ts - t0) - body_y(b, ts), ux, uy, rr,
                               std::max(0.0f, t1 - ts));
  const float first = t0 < b.stop ? d1 : kInf;
  const float second = t1 > b.stop ? (ts - t0) + d2 : kInf;
  return std::min(first, second);
}

// A superset of the cases body_time finds a contact in (circle_may_meet for its two phases).
[[gnu::always_inline]] inline bool body_may_meet(const BodyPath& b, float r, float x, float y, float ux, float uy,
                                                 float t0) {
  const float rr = b.radius + r, ts = std::max(t0, b.stop);
  const bool moving = circle_may_meet(x - body_x(b, t0), y - body_y(b, t0), ux - b.ux, uy - b.uy, rr);
  const bool held = circle_may_meet(x + ux * (ts - t0) - body_x(b, ts), y + uy * (ts - t0) - body_y(b, ts), ux, uy, rr);
  return moving | held;  // both evaluated: no branch in the vectorized loops that call this
}

// --- Searches.

// Landing: an audible touch of the floor on a field of landings (index: the area + 1, 0 for none).
enum class HitKind : uint8_t { None, Wall, Body, Goal, Out, Crushed, Wormhole, Landing };

struct Hit {
  float dt;  // from the search's start
  HitKind kind;
  int index;  // wall id, body, goal or wormhole mouth
  float nx, ny;
};

// Earliest contact of m (at time t0) in (t0, t1]; bodies skipped when `with_bodies` is false.
Hit next_hit(const Geometry& g, const BodyPath* bodies, int n_bodies, const Mover& m, float t0, float t1,
             bool with_bodies);

// Particles in structure-of-arrays form, searched together.
struct MoverBatch {
  std::vector<float> x, y, ux, uy, vx, vy, t;
  std::vector<float> when, nx, ny;    // the search's answer: time from t, normal
  std::vector<int32_t> code;          // kind << 16 | index, or -1 for none
  std::vector<uint8_t> maybe;         // scratch: particles an end point may meet...
  std::vector<int16_t> marked;        // ...and their indices
  void resize(size_t n);
  void set(size_t j, const Mover& m, float at) {
    x[j] = m.x, y[j] = m.y, ux[j] = m.ux, uy[j] = m.uy, vx[j] = m.vx, vy[j] = m.vy, t[j] = at;
  }
};
constexpr int32_t hit_code(HitKind kind, int index) { return int32_t(kind) << 16 | index; }

// What every batched search reads and answers, flat or with height (Mover3Batch has these
// columns too): each particle's path from its own time t, and its nearest contact so far. Taken
// once per search and handed by value to its passes, so the vectorized loops read plain local
// pointers (a copy whose address never escapes is split into registers).
struct Paths {
  const float *__restrict x, *__restrict y, *__restrict ux, *__restrict uy, *__restrict t;
  float *__restrict when, *__restrict nx, *__restrict ny;
  int32_t* __restrict code;

  template <class Batch>
  explicit Paths(Batch& b)
      : x(b.x.data()), y(b.y.data()), ux(b.ux.data()), uy(b.uy.data()), t(b.t.data()), when(b.when.data()),
        nx(b.nx.data()), ny(b.ny.data()), code(b.code.data()) {}
};
inline HitKind code_kind(int32_t code) { return code < 0 ? HitKind::None : HitKind(code >> 16); }
inline int code_index(int32_t code) { return code & 0xFFFF; }

// next_hit for particles [0, n) of the batch, each from its own b.t up to t1.
void batch_next_hits(const Geometry& g, const BodyPath* bodies, int n_bodies, MoverBatch& b, size_t n, float t1);

// A resolved contact leaves the ball this far outside the surface, so rounding never puts it
// back inside.
constexpr float kSkin = 2e-6f;

// A bounce off a vertical surface of restitution e (a wall, a backboard), normal (nx, ny) toward
// the ball: the drift and the ball's own velocity are reflected alike, on a flat field or with
// height (M is a Mover or a Mover3).
template <class M>
[[gnu::always_inline]] inline void reflect_off(M& m, float nx, float ny, float e) {
  const float un = m.ux * nx + m.uy * ny, vn = m.vx * nx + m.vy * ny;
  if (un < 0) m.ux -= (1 + e) * un * nx, m.uy -= (1 + e) * un * ny;
  if (vn < 0) m.vx -= (1 + e) * vn * nx, m.vy -= (1 + e) * vn * ny;
  m.x += kSkin * nx, m.y += kSkin * ny;
}

// Applies a contact found by a search to m, already moved to the contact time t: a wall, a
// wormhole mouth or a body's side. Each acts on the ball's horizontal motion only, so this is the
// one resolve of them on a flat field and with height (M is a Mover or a Mover3; height.h's
// resolve adds the floor, the ceiling, boards, rims and bodies' tops, and hands the rest here).
// Inline: the prediction resolves every particle's every contact, most of them walls.
template <class M>
inline void resolve(const Geometry& g, const BodyPath* bodies, HitKind kind, int index, float nx, float ny, float t,
                    M& m) {
  if (kind == HitKind::Wall) {
    reflect_off(m, nx, ny, g.e_wall);
  } else if (kind == HitKind::Wormhole) {
    // Out of the other mouth at the same offset, a hair inside it so it is not entering it.
    const int to = index ^ 1;
    const float s = 1 - 1e-4f;
    m.x = g.mx[size_t(to)] + (m.x - g.mx[size_t(index)]) * s;
    m.y = g.my[size_t(to)] + (m.y - g.my[size_t(index)]) * s;
  } else if (kind == HitKind::Body) {
    // A mallet is far heavier than a puck: the ball takes the body's velocity along the normal.
    const BodyPath& b = bodies[index];
    const bool moving = t < b.stop;
    const float bvx = moving ? b.vx : 0, bvy = moving ? b.vy : 0;
    const float rn = (m.vx - bvx) * nx + (m.vy - bvy) * ny;
    if (rn < 0) m.vx -= (1 + g.e_body) * rn * nx, m.vy -= (1 + g.e_body) * rn * ny;
    m.ux = m.vx, m.uy = m.vy;  // the rest of this step's Brownian drift is spent in the contact
    const float reach = b.radius + g.r + kSkin;
    m.x = body_x(b, t) + nx * reach, m.y = body_y(b, t) + ny * reach;
  }
}

struct Outcome {
  HitKind kind;  // None, Body, Goal, Out, Crushed, or the first audible Wall or Landing
  int index;
};

// The step loops' shared passes over one block of m particles (start ox, oy; end x, y from
// `base`), written for the vectorizer. Flags every particle whose step can reach a wormhole mouth.
[[gnu::always_inline]] inline void flag_near_mouths(const Geometry& g, const float* __restrict ox, const float* __restrict oy,
                                                   const float* __restrict x, const float* __restrict y, int base, int m,
                                                   uint8_t* __restrict flag) {
  // The block's ends by pointer: under UBSan, the overflow check on `base + j` was a second exit
  // from the loop, and clang's vectorizer refused it.
  const float* __restrict end_x = x + base;
  const float* __restrict end_y = y + base;
  for (size_t k = 0; k < g.mx.size(); ++k) {
    const float cx = g.mx[k], cy = g.my[k], reach = g.mr[k] + 1e-3f;
    QUANTUM_INDEPENDENT_ITERATIONS
    for (int j = 0; j < m; ++j) {
      const float travel = std::fabs(end_x[j] - ox[j]) + std::fabs(end_y[j] - oy[j]);
      const float qx = ox[j] - cx, qy = oy[j] - cy, around = reach + travel;
      flag[j] |= uint8_t(qx * qx + qy * qy < around * around);
    }
  }
}

// A body over one step, for the step loops' vectorized near-test.
struct BodySweep {
  float x, y;    // the body at the start of the step
  float dx, dy;  // its displacement over the step
  float reach2;  // squared contact distance, plus a millimetre
  float touch2;  // squared distance below which a particle overlaps the body
};
inline BodySweep body_sweep(const BodyMotion& b, float r) {
  const float reach = b.radius + r + 1e-3f, touch = b.radius + r - kTolerance;
  return {b.from.x, b.from.y, b.to.x - b.from.x, b.to.y - b.from.y, reach * reach, touch * touch};
}

// Whether a particle stepping from (x0, y0) to (x1, y1) comes within reach of the body, both
// moving linearly: the closest approach, exact up to a millimetre, so only particles that really
// touch a body take the slow path. A separating pair (a shot just leaving the hand or the mallet)
// can only touch if it overlaps already.
[[gnu::always_inline]] inline bool sweeps_touch(const BodySweep& c, float x0, float y0, float x1, float y1) {
  const float qx = x0 - c.x, qy = y0 - c.y;
  const float wx = (x1 - x0) - c.dx, wy = (y1 - y0) - c.dy;
  const float qq = qx * qx + qy * qy, ww = wx * wx + wy * wy, qw = qx * wx + qy * wy;
  // min over t in [0, 1] of |q + t w|^2 < R^2, without a division: at t = 0 when separating,
  // at t = 1 when still closing at the end, else (qq - R^2) ww < qw^2.
  const bool separating = qw >= 0, closing_at_end = -qw >= ww;
  return (separating & (qq < c.touch2)) | (!separating & closing_at_end & (qq + 2 * qw + ww < c.reach2)) |
         (!separating & !closing_at_end & ((qq - c.reach2) * ww < qw * qw));
}

// The flagged particles of a block, eight flags at a time: most words are all zero, and a
// branch per particle would mispredict constantly. `flag` has room for m rounded up to 8.
inline int collect_flagged(uint8_t* flag, int m, int16_t* slow) {
  std::fill(flag + m, flag + ((m + 7) & ~7), uint8_t(0));
  int flagged = 0;
  for (int w = 0; w < m; w += 8) {
    uint64_t word;
    std::memcpy(&word, flag + w, 8);
    for (word &= 0x0101010101010101ull; word; word &= word - 1) slow[flagged++] = int16_t(w + std::countr_zero(word) / 8);
  }
  return flagged;
}

// What a backend reports for a particle's outcome.
inline Target target_of(Outcome out) {
  switch (out.kind) {
    case HitKind::Body: return {TargetKind::Body, uint16_t(out.index)};
    case HitKind::Goal: return {TargetKind::Goal, uint16_t(out.index)};
    case HitKind::Out: return {TargetKind::Out, 0};
    case HitKind::Wall: return {TargetKind::Wall, uint16_t(out.index)};
    case HitKind::Landing: return {TargetKind::Landing, uint16_t(out.index)};
    default: return {TargetKind::Crushed, 0};
  }
}

// Pushes m out of walls it overlaps. Bodies are at their positions at time t. With
// `push_from_bodies` a particle inside a body is moved to its surface; otherwise it is reported
// as a contact with that body. Crushed: stuck inside walls (or between a body and a wall).
Outcome settle(const Geometry& g, const BodyPath* bodies, int n_bodies, float t, Mover& m, bool push_from_bodies);

}  // namespace quantum::detail

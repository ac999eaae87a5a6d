// Contacts of a ball with height (fields with gravity): it flies in parabolas, bounces off the
// floor, a ceiling, backboards and hoop rims, scores by coming down through a hoop, and meets
// players as vertical cylinders up to their reach. Shared by the step and by fate prediction, so
// a prediction without noise follows exactly the path the step takes. Internal to core/quantum.
//
// The horizontal motion of a flying ball is still a straight line, so walls, goal lines, the
// bounds and the sides of bodies are the flat search's (contact.h), run on the ball's shadow;
// only what depends on height is solved here. Scalar code: in a match few particles are near
// anything at once, and the vectorized part of the step (height_backend.cpp) sorts them out.
#pragma once

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

// m moved on by dt seconds of free flight.
Mover3 advanced(const Sky& sky, const Mover3& m, float dt);

// Earliest contact of m (at time t0) in (t0, t1]; bodies skipped when `with_bodies` is false.
Hit3 next_hit3(const Geometry& g, const Sky& sky, const BodyPath* bodies, int n_bodies, const Mover3& m, float t0,
               float t1, bool with_bodies);

// Applies a contact found by the search to m, already moved to the contact time t.
void resolve3(const Geometry& g, const Sky& sky, const BodyPath* bodies, const Hit3& hit, float t, Mover3& m);

// The ball's speed into the surface it met (for whether a bounce is heard).
float impact_speed(const Hit3& hit, const Mover3& m);

// One particle through a step of dt (or a catch-up with no bodies): contact by contact, as
// StepTracer does on a flat field. The Outcome is the first body, goal or out it met, else the
// first surface it bounced off audibly, else None; Crushed when it rattled to a stop.
Outcome trace_step3(const Geometry& g, const Sky& sky, const BodyPath* bodies, int n_bodies, float dt, Mover3& m);

}  // namespace quantum::detail

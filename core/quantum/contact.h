// Swept contacts of one particle against walls, goal lines, the field's bounds and moving bodies.
// Shared by the step's slow path and by fate prediction, so a prediction without noise follows
// exactly the path the step would take. Internal to core/quantum and its backends.
#pragma once

#include <cstdint>
#include <vector>

#include "quantum/field.h"

namespace quantum::detail {

// Distances below this count as touching: a few float ulps at field scale.
constexpr float kTolerance = 1e-5f;

struct Box {
  float x0 = 1, y0 = 1, x1 = 0, y1 = 0;  // empty by default
  bool contains(float x, float y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

// The field rearranged for the contact search: segments and goal lines as structure of arrays so
// the search over them vectorizes.
struct Geometry {
  explicit Geometry(const Field& field);
  void build_grid(const Field& field);

  float r, e_wall, e_body;
  std::vector<float> ax, ay, tx, ty, nx, ny, len;  // segments: start, unit tangent, left normal
  std::vector<int> wall;
  std::vector<float> sx0, sy0, sx1, sy1;           // segment bounding boxes
  std::vector<float> vx, vy;                       // segment end points (round caps)
  std::vector<int> vwall;                          // the wall each end point belongs to
  std::vector<float> gax, gay, gtx, gty, gnx, gny, glen;  // goal lines; normal points into the goal
  std::vector<float> gx0, gy0, gx1, gy1;
  Box bounds;

  // A uniform grid over the bounds. Each cell lists the segments, end points and goal lines
  // that a ball starting in the cell can reach within `grid_reach` of travel: a step's path is a
  // few centimetres, so its contact search tests one or two primitives instead of all of them.
  struct Candidates {
    const uint16_t *segments, *points, *goals;
    uint16_t n_segments, n_points, n_goals;
    bool near_bounds;
  };
  Candidates candidates(float x, float y, float travel_squared) const;
  float cell = 0, inv_cell = 0, grid_reach = 0;
  int cols = 0, rows = 0;
  std::vector<uint32_t> cell_start;    // per cell: offsets into cell_items, 3 lists per cell
  std::vector<uint16_t> cell_items;
  std::vector<uint8_t> cell_near_bounds;
  std::vector<uint16_t> all_items;     // 0, 1, 2, ... for searches the grid cannot serve

  // No wall, goal line or bound within reach of a ball centre inside this box: a particle that
  // starts and ends a step inside it needs no contact search.
  Box safe;
};

// A body's motion over the traced interval: linear until `stop`, then at rest.
struct BodyPath {
  float x, y;    // position at t = 0
  float ux, uy;  // sweep velocity until `stop`
  float stop;
  float vx, vy;  // velocity given to the ball on contact while moving
  float radius;
};

struct Mover {
  float x, y;
  float ux, uy;  // velocity along the path: the ball's own plus this step's Brownian drift
  float vx, vy;  // the ball's own velocity
};

enum class HitKind : uint8_t { None, Wall, Body, Goal, Out, Crushed };

struct Hit {
  float t;
  HitKind kind;
  int index;  // wall id, body or goal
  float nx, ny;
};

Hit next_hit(const Geometry& g, const BodyPath* bodies, int n_bodies, const Mover& m, float t0, float t1,
             bool with_bodies);

// Applies a contact found by next_hit to m (already moved to the contact time t).
void resolve(const Geometry& g, const BodyPath* bodies, const Hit& hit, float t, Mover& m);

struct Outcome {
  HitKind kind;  // None, Body, Goal, Out or Crushed
  int index;
};

// Moves m through one step of length dt and reports the first body, goal or out it met.
// After a body contact the particle finishes the step against walls only: it now belongs to
// that body's purgatory and its state must stay a valid ball state.
Outcome trace_step(const Geometry& g, const BodyPath* bodies, int n_bodies, Mover& m, float dt);

// Pushes m out of walls it overlaps. Bodies are at their positions at time t. With
// `push_from_bodies` a particle inside a body is moved to its surface; otherwise it is reported
// as a contact with that body. Crushed: stuck inside walls (or between a body and a wall).
Outcome settle(const Geometry& g, const BodyPath* bodies, int n_bodies, float t, Mover& m, bool push_from_bodies);

Vec2 body_position(const BodyPath& b, float t);

}  // namespace quantum::detail

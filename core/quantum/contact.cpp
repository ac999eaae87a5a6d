#include "quantum/contact.h"

#include "quantum/limits.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_set>

namespace quantum::detail {
namespace {

float dot(float ax, float ay, float bx, float by) { return ax * bx + ay * by; }
// std::hypot guards against overflow at a large cost; field coordinates never come near it.
float norm(float x, float y) { return std::sqrt(x * x + y * y); }

// Whether the segment p-q passes through box b (Liang-Barsky clipping).
bool segment_touches_box(Vec2 p, Vec2 q, const Box& b) {
  float t0 = 0, t1 = 1;
  const float dx = q.x - p.x, dy = q.y - p.y;
  const float pp[4] = {-dx, dx, -dy, dy};
  const float qq[4] = {p.x - b.x0, b.x1 - p.x, p.y - b.y0, b.y1 - p.y};
  for (int k = 0; k < 4; ++k) {
    if (pp[k] == 0) {
      if (qq[k] < 0) return false;
      continue;
    }
    const float t = qq[k] / pp[k];
    if (pp[k] < 0) t0 = std::max(t0, t);
    else t1 = std::min(t1, t);
    if (t0 > t1) return false;
  }
  return true;
}

Box grown(const Box& b, float m) { return {b.x0 - m, b.y0 - m, b.x1 + m, b.y1 + m}; }

// A point's coordinates as one key, equal where they compare equal: -0 becomes +0 (NaN never
// gets here: finish_field refuses it). Thousands of wall pieces find their shared ends at once.
uint64_t point_key(Vec2 p) {
  return uint64_t(std::bit_cast<uint32_t>(p.x + 0.0f)) << 32 | std::bit_cast<uint32_t>(p.y + 0.0f);
}

bool box_is_clear(const Field& f, const Box& box, float r) {
  constexpr float kMargin = 1e-3f;
  const Box bounds{f.bounds_min.x, f.bounds_min.y, f.bounds_max.x, f.bounds_max.y};
  if (box.x0 < bounds.x0 + kMargin || box.y0 < bounds.y0 + kMargin || box.x1 > bounds.x1 - kMargin ||
      box.y1 > bounds.y1 - kMargin)
    return false;
  const Box near_walls = grown(box, r + kMargin);
  for (const Segment& s : f.segments)
    if (segment_touches_box(s.a, s.b, near_walls)) return false;
  const Box near_goals = grown(box, kMargin);
  for (const Goal& gl : f.goals)
    if (!gl.hoop() && segment_touches_box(gl.a, gl.b, near_goals)) return false;
  return true;
}

// Grows a box from `centre` one millimetre per side at a time while it stays clear: close to the
// largest empty axis-aligned box, which is all the fast path needs. Rounds in which every side
// still growing grows are taken in bulk (doubling while the box after them is clear, which makes
// every box before it clear), so a hall costs tens of tests instead of tens of thousands; the
// coordinates are stepped a millimetre at a time all the same, so the box is the one a round at a
// time gives.
Box largest_clear_box(const Field& f, Vec2 centre, float r) {
  Box box{centre.x, centre.y, centre.x, centre.y};
  if (!box_is_clear(f, box, r)) return Box{};
  constexpr float kGrowth = 1e-3f;
  bool grow[4] = {true, true, true, true};
  auto grown_by = [&](Box b, int side, int rounds) {
    for (int k = 0; k < rounds; ++k) {
      if (side == 0) b.x0 -= kGrowth;
      if (side == 1) b.x1 += kGrowth;
      if (side == 2) b.y0 -= kGrowth;
      if (side == 3) b.y1 += kGrowth;
    }
    return b;
  };
  int rounds = 1;
  while (grow[0] || grow[1] || grow[2] || grow[3]) {
    Box bulk = box;
    for (int side = 0; side < 4; ++side)
      if (grow[side]) bulk = grown_by(bulk, side, rounds);
    if (box_is_clear(f, bulk, r)) {
      box = bulk;
      rounds *= 2;
      continue;
    }
    if (rounds > 1) {
      rounds /= 2;
      continue;
    }
    for (int side = 0; side < 4; ++side) {  // one round, side by side: some side stops here
      if (!grow[side]) continue;
      const Box next = grown_by(box, side, 1);
      if (box_is_clear(f, next, r)) box = next;
      else grow[side] = false;
    }
  }
  return box;
}

}  // namespace

Geometry::Geometry(const Field& f)
    : r(f.ball_radius), e_wall(f.wall_restitution), e_body(f.body_restitution), audible_bounce(f.audible_bounce) {
  std::unordered_set<uint64_t> end_points;  // a point two pieces share is one cap
  for (const Segment& s : f.segments) {
    const float dx = s.b.x - s.a.x, dy = s.b.y - s.a.y, l = norm(dx, dy);
    ax.push_back(s.a.x), ay.push_back(s.a.y);
    tx.push_back(dx / l), ty.push_back(dy / l);
    nx.push_back(-dy / l), ny.push_back(dx / l);
    len.push_back(l);
    wall.push_back(s.wall);
    sx0.push_back(std::min(s.a.x, s.b.x)), sx1.push_back(std::max(s.a.x, s.b.x));
    sy0.push_back(std::min(s.a.y, s.b.y)), sy1.push_back(std::max(s.a.y, s.b.y));
    for (Vec2 p : {s.a, s.b})
      if (end_points.insert(point_key(p)).second) cap_x.push_back(p.x), cap_y.push_back(p.y), cap_wall.push_back(s.wall);
  }
  Vec2 centre{0, 0};
  for (const Spot& s : f.spots) centre.x += s.at.x / f.spots.size(), centre.y += s.at.y / f.spots.size();
  for (size_t id = 0; id < f.goals.size(); ++id) {
    const Goal& gl = f.goals[id];
    if (gl.hoop()) continue;
    goal_id.push_back(int(id));
    const float dx = gl.b.x - gl.a.x, dy = gl.b.y - gl.a.y, l = norm(dx, dy);
    float gnx_ = -dy / l, gny_ = dx / l;
    // The goal's inside is the side away from the respawn spots.
    if (dot(centre.x - gl.a.x, centre.y - gl.a.y, gnx_, gny_) > 0) gnx_ = -gnx_, gny_ = -gny_;
    gax.push_back(gl.a.x), gay.push_back(gl.a.y);
    gtx.push_back(dx / l), gty.push_back(dy / l);
    gnx.push_back(gnx_), gny.push_back(gny_);
    glen.push_back(l);
    gx0.push_back(std::min(gl.a.x, gl.b.x)), gx1.push_back(std::max(gl.a.x, gl.b.x));
    gy0.push_back(std::min(gl.a.y, gl.b.y)), gy1.push_back(std::max(gl.a.y, gl.b.y));
  }
  bounds = Box{f.bounds_min.x, f.bounds_min.y, f.bounds_max.x, f.bounds_max.y};
  const Vec2 middle{(bounds.x0 + bounds.x1) / 2, (bounds.y0 + bounds.y1) / 2};
  safe = largest_clear_box(f, middle, r);
  if (safe.x0 > safe.x1) safe = largest_clear_box(f, centre, r);
  build_grid(f);
}

namespace {

// A step's path is a few centimetres: in 5 cm cells its contact search tests one or two primitives.
constexpr float kFinestCell = 0.05f;

// The cells an item's box grown by `reach` overlaps, and one more on each side for rounding.
struct CellRange {
  int c0, c1, r0, r1;
  size_t count() const { return c1 < c0 || r1 < r0 ? 0 : size_t(c1 - c0 + 1) * size_t(r1 - r0 + 1); }
};

CellRange cells_near(const Geometry& g, float x0, float y0, float x1, float y1, float reach) {
  return {std::max(0, int(std::floor((x0 - reach - g.bounds.x0) * g.inv_cell)) - 1),
          std::min(g.cols - 1, int(std::floor((x1 + reach - g.bounds.x0) * g.inv_cell)) + 1),
          std::max(0, int(std::floor((y0 - reach - g.bounds.y0) * g.inv_cell)) - 1),
          std::min(g.rows - 1, int(std::floor((y1 + reach - g.bounds.y0) * g.inv_cell)) + 1)};
}

// Calls visit(list, item, cells, touches) for every segment (list 0), end point (1) and goal line
// (2): the cells its reach covers, and whether it reaches a ball starting in a given cell's box.
template <class Visit>
void for_each_item(const Geometry& g, const Field& f, Visit&& visit) {
  // Conservative: a square grown by the reach stands in for the rounded one.
  const float wall_reach = g.r + g.grid_reach + 1e-3f, goal_reach = g.grid_reach + 1e-3f;
  for (size_t k = 0; k < g.ax.size(); ++k)
    visit(0, k, cells_near(g, g.sx0[k], g.sy0[k], g.sx1[k], g.sy1[k], wall_reach), [&](const Box& b) {
      return segment_touches_box(f.segments[k].a, f.segments[k].b, grown(b, wall_reach));
    });
  for (size_t k = 0; k < g.cap_x.size(); ++k)
    visit(1, k, cells_near(g, g.cap_x[k], g.cap_y[k], g.cap_x[k], g.cap_y[k], wall_reach),
          [&](const Box& b) { return grown(b, wall_reach).contains(g.cap_x[k], g.cap_y[k]); });
  for (size_t k = 0; k < g.gax.size(); ++k)
    visit(2, k, cells_near(g, g.gx0[k], g.gy0[k], g.gx1[k], g.gy1[k], goal_reach), [&](const Box& b) {
      const Goal& gl = f.goals[size_t(g.goal_id[k])];
      return segment_touches_box(gl.a, gl.b, grown(b, goal_reach));
    });
}

// What building the grid takes at its peak: per cell three list offsets and as many fill
// cursors (uint32_t) and a near-bounds flag, and an entry (uint16_t) for every cell an item's
// reach covers, whether or not it is listed there. Building visits those cells, so this bounds
// its time as well.
size_t grid_bytes_at_most(const Geometry& g, const Field& f) {
  size_t visits = 0;
  for_each_item(g, f, [&](int, size_t, const CellRange& cells, auto&&) { visits += cells.count(); });
  const size_t cells = size_t(g.cols) * size_t(g.rows);
  return (3 * cells + 1) * sizeof(uint32_t) * 2 + cells * sizeof(uint8_t) + (visits + g.all_items.size()) * sizeof(uint16_t);
}

}  // namespace

void Geometry::use_cells_of(float size) {
  cell = size;
  inv_cell = 1 / cell;
  grid_reach = cell;
  cols = std::max(1, int(std::ceil((bounds.x1 - bounds.x0) / cell)));
  rows = std::max(1, int(std::ceil((bounds.y1 - bounds.y0) / cell)));
}

size_t Geometry::grid_bytes() const {
  return cell_start.size() * sizeof(uint32_t) + (cell_items.size() + all_items.size()) * sizeof(uint16_t) +
         cell_near_bounds.size() * sizeof(uint8_t);
}

void Geometry::build_grid(const Field& f) {
  const size_t most = std::max({ax.size(), cap_x.size(), gax.size(), size_t(1)});
  for (size_t k = 0; k < most; ++k) all_items.push_back(uint16_t(k));
  // Large bounds, or long walls reaching across many cells, make the cells coarser until the
  // grid fits: a contact search then tests more primitives, but memory stays bounded.
  use_cells_of(kFinestCell);
  while (grid_bytes_at_most(*this, f) > limits::kMaxGridBytes) use_cells_of(2 * cell);
  auto cell_box = [&](int col, int row) {
    return Box{bounds.x0 + col * cell, bounds.y0 + row * cell, bounds.x0 + (col + 1) * cell, bounds.y0 + (row + 1) * cell};
  };
  // Each item visits only the cells its reach covers, not the whole grid: a hall's 320,000 cells
  // made building a World cost 11 ms. Two passes over the same visits: count each cell's lists,
  // then fill them in item order.
  auto visit_all = [&](auto&& add) {
    for_each_item(*this, f, [&](int list, size_t k, const CellRange& cells, auto&& touches) {
      for (int row = cells.r0; row <= cells.r1; ++row)
        for (int col = cells.c0; col <= cells.c1; ++col)
          if (touches(cell_box(col, row))) add(3 * (size_t(row) * size_t(cols) + size_t(col)) + size_t(list), k);
    });
  };
  // Counted two places on, each list's start lands one place on, and serves as the fill's cursor
  // until it ends where the next list starts: no copy of a hall's 4 MB of starts to fill from.
  const size_t cells = size_t(rows) * size_t(cols);
  cell_start.assign(3 * cells + 2, 0);
  visit_all([&](size_t list, size_t) { ++cell_start[list + 2]; });
  std::partial_sum(cell_start.begin(), cell_start.end(), cell_start.begin());
  cell_items.resize(cell_start.back());
  visit_all([&](size_t list, size_t k) { cell_items[cell_start[list + 1]++] = uint16_t(k); });
  cell_start.pop_back();
  const float goal_reach = grid_reach + 1e-3f;
  cell_near_bounds.resize(cells);
  for (int row = 0; row < rows; ++row)
    for (int col = 0; col < cols; ++col) {
      const Box goal_zone = grown(cell_box(col, row), goal_reach);
      cell_near_bounds[size_t(row) * size_t(cols) + size_t(col)] =
          goal_zone.x0 < bounds.x0 || goal_zone.y0 < bounds.y0 || goal_zone.x1 > bounds.x1 || goal_zone.y1 > bounds.y1;
    }
}

Geometry::Candidates Geometry::candidates(float x, float y, float travel2) const {
  const int col = int(std::floor((x - bounds.x0) * inv_cell)), row = int(std::floor((y - bounds.y0) * inv_cell));
  if (travel2 > grid_reach * grid_reach || col < 0 || row < 0 || col >= cols || row >= rows)
    return {all_items.data(), all_items.data(), all_items.data(), uint16_t(ax.size()), uint16_t(cap_x.size()),
            uint16_t(gax.size()), true};
  const uint32_t* at = &cell_start[3 * size_t(row * cols + col)];
  // Pointers, not references: a list may end the items, or there may be none (a field without walls).
  const uint16_t* items = cell_items.data();
  return {items + at[0], items + at[1], items + at[2], uint16_t(at[1] - at[0]),
          uint16_t(at[2] - at[1]), uint16_t(at[3] - at[2]), cell_near_bounds[row * cols + col] != 0};
}

void Geometry::set_wormholes(const std::vector<Wormhole>& wormholes) {
  mx.clear(), my.clear(), mr.clear();
  for (const Wormhole& w : wormholes)
    for (Vec2 p : {w.a, w.b}) mx.push_back(p.x), my.push_back(p.y), mr.push_back(w.radius);
}

void MoverBatch::resize(size_t n) {
  // A little more than asked: arrays of a prediction chunk's power-of-two length lie a multiple
  // of 4 KiB apart, so one particle's x, y, ux, ... fall in one L1 set and evict each other. 96
  // bytes more staggers them (at chunks of 1,024 the 1M fate report measured about 5 % faster).
  for (auto* v : {&x, &y, &ux, &uy, &vx, &vy, &t, &when, &nx, &ny}) v->resize(n + 24);
  code.resize(n);
  maybe.resize(n + 8);  // collect_flagged reads whole words of eight
  marked.resize(n);
}

Hit next_hit(const Geometry& g, const BodyPath* bodies, int n_bodies, const Mover& m, float t0, float t1,
             bool with_bodies) {
  Hit best{kInf, HitKind::None, -1, 0, 0};
  const float span = t1 - t0;
  const float r = g.r;
  // Only what the path's box (grown by the ball's radius) reaches can be hit: a step moves a few
  // centimetres, so this rejects almost every primitive with four compares.
  const float ex = m.x + m.ux * span, ey = m.y + m.uy * span;
  const float bx0 = std::min(m.x, ex) - r, bx1 = std::max(m.x, ex) + r;
  const float by0 = std::min(m.y, ey) - r, by1 = std::max(m.y, ey) + r;
  const Geometry::Candidates near = g.candidates(m.x, m.y, (m.ux * m.ux + m.uy * m.uy) * span * span);

  // Walls: the ball's centre against each segment's two offset lines...
  for (uint16_t q = 0; q < near.n_segments; ++q) {
    const size_t k = near.segments[q];
    if (g.sx1[k] < bx0 || g.sx0[k] > bx1 || g.sy1[k] < by0 || g.sy0[k] > by1) continue;
    float hnx, hny;
    const float dt = wall_time(segment(g, k), r, m.x, m.y, m.ux, m.uy, span, hnx, hny);
    if (dt < best.dt) best = {dt, HitKind::Wall, g.wall[k], hnx, hny};
  }
  // ...and against the round caps at the segment ends (goal posts, convex corners).
  for (uint16_t q = 0; q < near.n_caps; ++q) {
    const size_t k = near.caps[q];
    if (g.cap_x[k] < bx0 || g.cap_x[k] > bx1 || g.cap_y[k] < by0 || g.cap_y[k] > by1) continue;
    const float qx = m.x - g.cap_x[k], qy = m.y - g.cap_y[k];
    const float dt = circle_time(qx, qy, m.ux, m.uy, r, span);
    if (!(dt < best.dt)) continue;
    const float hx = qx + m.ux * dt, hy = qy + m.uy * dt, l = norm(hx, hy);
    if (l > 0) best = {dt, HitKind::Wall, g.cap_wall[k], hx / l, hy / l};
  }
  for (uint16_t q = 0; q < near.n_goals; ++q) {
    const size_t k = near.goals[q];
    if (g.gx1[k] < bx0 || g.gx0[k] > bx1 || g.gy1[k] < by0 || g.gy0[k] > by1) continue;
    const float dt = goal_time(goal_line(g, k), m.x, m.y, m.ux, m.uy, span);
    if (dt < best.dt) best = {dt, HitKind::Goal, g.goal_id[k], g.gnx[k], g.gny[k]};
  }
  if (near.near_bounds) {
    const float dt = bounds_time(g.bounds, m.x, m.y, m.ux, m.uy, span);
    if (dt < best.dt) best = {dt, HitKind::Out, 0, 0, 0};
  }
  for (size_t k = 0; k < g.mx.size(); ++k) {
    const float dt = mouth_time(m.x - g.mx[k], m.y - g.my[k], m.ux, m.uy, g.mr[k], span);
    if (dt < best.dt) best = {dt, HitKind::Wormhole, int(k), 0, 0};
  }
  if (!with_bodies) return best;
  for (int k = 0; k < n_bodies; ++k) {
    const BodyPath& b = bodies[k];
    if (b.passes) continue;
    // Cull by the box the body sweeps over the interval, grown by its radius.
    const float cx0 = body_x(b, t0), cx1 = body_x(b, t1), cy0 = body_y(b, t0), cy1 = body_y(b, t1);
    if (std::max(cx0, cx1) + b.radius < bx0 || std::min(cx0, cx1) - b.radius > bx1 ||
        std::max(cy0, cy1) + b.radius < by0 || std::min(cy0, cy1) - b.radius > by1)
      continue;
    const float dt = body_time(b, r, m.x, m.y, m.ux, m.uy, t0, t1);
    if (!(dt < best.dt)) continue;
    float hx = m.x + m.ux * dt - body_x(b, t0 + dt), hy = m.y + m.uy * dt - body_y(b, t0 + dt);
    float l = norm(hx, hy);
    if (l <= 0) hx = 1, hy = 0, l = 1;  // dead centre: any direction is as good
    best = {dt, HitKind::Body, k, hx / l, hy / l};
  }
  return best;
}

namespace {

// A particle's nearest contact so far (w, k, ax, ay) becomes (dt, c, nx, ny) if that comes sooner.
[[gnu::always_inline]] inline void take_sooner(float dt, int32_t c, float nx, float ny, float& w, int32_t& k, float& ax,
                                               float& ay) {
  const bool sooner = dt < w;
  w = sooner ? dt : w, k = sooner ? c : k, ax = sooner ? nx : ax, ay = sooner ? ny : ay;
}

// Particle i's contact becomes (dt, c, nx, ny) if that comes sooner. Every load comes before any
// store: clang's vectorizer gives up on a loop that loads one array after storing to another.
[[gnu::always_inline]] inline void keep_sooner(const Paths& p, size_t i, float dt, int32_t c, float nx, float ny) {
  float w = p.when[i], ax = p.nx[i], ay = p.ny[i];
  int32_t k = p.code[i];
  take_sooner(dt, c, nx, ny, w, k, ax, ay);
  p.when[i] = w, p.code[i] = k, p.nx[i] = ax, p.ny[i] = ay;
}

// The walls k0 .. k0 + B - 1 against every particle, in one pass: each particle's nearest
// contact so far stays in registers across the B tests instead of being loaded and stored per
// wall, which was most of the wall loops' time. The same tests in the same order as one wall
// at a time, so the same contact wins.
template <size_t B>
void walls_block(const Geometry& g, size_t k0, const Paths p, size_t n, float t1) {
  SegmentParams s[B];
  int32_t c[B];
  for (size_t j = 0; j < B; ++j) s[j] = segment(g, k0 + j), c[j] = hit_code(HitKind::Wall, g.wall[k0 + j]);
  const float r = g.r;
  QUANTUM_INDEPENDENT_ITERATIONS
  for (size_t i = 0; i < n; ++i) {
    float w = p.when[i], ax = p.nx[i], ay = p.ny[i];
    int32_t k = p.code[i];
#pragma GCC unroll 4  // unrolled before the vectorizer sees the particle loop, which it otherwise leaves
    for (size_t j = 0; j < B; ++j) {
      float nx, ny;
      const float dt = wall_time(s[j], r, p.x[i], p.y[i], p.ux[i], p.uy[i], t1 - p.t[i], nx, ny);
      take_sooner(dt, c[j], nx, ny, w, k, ax, ay);
    }
    p.when[i] = w, p.code[i] = k, p.nx[i] = ax, p.ny[i] = ay;
  }
}

}  // namespace

void batch_next_hits(const Geometry& g, const BodyPath* bodies, int n_bodies, MoverBatch& b, size_t n, float t1) {
  // Hand-written for the compiler's vectorizer: each loop runs one primitive over all particles,
  // and the primitive tests are the branch-free functions next_hit uses too.
  const Paths p(b);
  for (size_t i = 0; i < n; ++i) p.when[i] = kInf, p.code[i] = -1, p.nx[i] = 0, p.ny[i] = 0;
  const float r = g.r;
  size_t k = 0;
  for (; k + 4 <= g.ax.size(); k += 4) walls_block<4>(g, k, p, n, t1);
  for (; k + 2 <= g.ax.size(); k += 2) walls_block<2>(g, k, p, n, t1);
  for (; k < g.ax.size(); ++k) walls_block<1>(g, k, p, n, t1);
  // End points: a path passes near a given one rarely (a corner or a post a few centimetres
  // wide, seen from across the field). A vectorized pass without a square root or a division
  // marks the particles whose line comes within reach of the point, or that overlap it; only
  // those take the exact test.
  uint8_t* __restrict maybe = b.maybe.data();
  int16_t* __restrict marked = b.marked.data();
  for (size_t k = 0; k < g.cap_x.size(); ++k) {
    const int32_t c = hit_code(HitKind::Wall, g.cap_wall[k]);
    const float px = g.cap_x[k], py = g.cap_y[k];
    QUANTUM_INDEPENDENT_ITERATIONS
    for (size_t i = 0; i < n; ++i)
      maybe[i] = uint8_t(circle_may_meet(p.x[i] - px, p.y[i] - py, p.ux[i], p.uy[i], r));
    const int m = collect_flagged(maybe, int(n), marked);
    for (int j = 0; j < m; ++j) {
      const size_t i = size_t(marked[j]);
      const float qx = p.x[i] - px, qy = p.y[i] - py;
      const float dt = circle_time(qx, qy, p.ux[i], p.uy[i], r, t1 - p.t[i]);
      const float hx = qx + p.ux[i] * dt, hy = qy + p.uy[i] * dt, ll = hx * hx + hy * hy;
      if (!(dt < p.when[i] && ll > 0)) continue;
      // The normal (a square root and two divisions) only for a nearer contact among the few
      // marked paths, never in the vectorized loops for every candidate: in a match's frame that
      // was a third of its time (docs/PERFORMANCE.md).
      const float l = std::sqrt(ll);
      p.when[i] = dt, p.code[i] = c, p.nx[i] = hx / l, p.ny[i] = hy / l;
    }
  }
  for (size_t k = 0; k < g.gax.size(); ++k) {
    const int32_t c = hit_code(HitKind::Goal, g.goal_id[k]);
    const SegmentParams s = goal_line(g, k);
    QUANTUM_INDEPENDENT_ITERATIONS
    for (size_t i = 0; i < n; ++i) {
      const float dt = goal_time(s, p.x[i], p.y[i], p.ux[i], p.uy[i], t1 - p.t[i]);
      keep_sooner(p, i, dt, c, s.nx, s.ny);
    }
  }
  {
    const int32_t c = hit_code(HitKind::Out, 0);
    const Box bounds = g.bounds;
    QUANTUM_INDEPENDENT_ITERATIONS
    for (size_t i = 0; i < n; ++i) {
      const float dt = bounds_time(bounds, p.x[i], p.y[i], p.ux[i], p.uy[i], t1 - p.t[i]);
      keep_sooner(p, i, dt, c, 0, 0);
    }
  }
  for (size_t k = 0; k < g.mx.size(); ++k) {
    const int32_t c = hit_code(HitKind::Wormhole, int(k));
    const float px = g.mx[k], py = g.my[k], pr = g.mr[k];
    QUANTUM_INDEPENDENT_ITERATIONS
    for (size_t i = 0; i < n; ++i) {
      const float dt = mouth_time(p.x[i] - px, p.y[i] - py, p.ux[i], p.uy[i], pr, t1 - p.t[i]);
      keep_sooner(p, i, dt, c, 0, 0);
    }
  }
  for (int k = 0; k < n_bodies; ++k) {
    const BodyPath body = bodies[k];
    if (body.passes) continue;
    const int32_t c = hit_code(HitKind::Body, k);
    // As for end points: the pre-pass marks the paths that can come within reach of the body
    // while it moves or once it rests, and only those take body_time's two exact tests.
    QUANTUM_INDEPENDENT_ITERATIONS
    for (size_t i = 0; i < n; ++i) maybe[i] = uint8_t(body_may_meet(body, r, p.x[i], p.y[i], p.ux[i], p.uy[i], p.t[i]));
    const int m = collect_flagged(maybe, int(n), marked);
    for (int j = 0; j < m; ++j) {
      const size_t i = size_t(marked[j]);
      const float dt = body_time(body, r, p.x[i], p.y[i], p.ux[i], p.uy[i], p.t[i], t1);
      if (!(dt < p.when[i])) continue;
      const float hx = p.x[i] + p.ux[i] * dt - body_x(body, p.t[i] + dt), hy = p.y[i] + p.uy[i] * dt - body_y(body, p.t[i] + dt);
      const float l = norm(hx, hy);
      const bool centre = !(l > 0);  // dead centre: any direction is as good
      p.when[i] = dt, p.code[i] = c, p.nx[i] = centre ? 1.0f : hx / l, p.ny[i] = centre ? 0.0f : hy / l;
    }
  }
}

Outcome settle(const Geometry& g, const BodyPath* bodies, int n_bodies, float t, Mover& m, bool push_from_bodies) {
  const float r = g.r;
  for (int pass = 0; pass < 4; ++pass) {
    bool moved = false;
    if (push_from_bodies) {
      for (int k = 0; k < n_bodies; ++k) {
        if (bodies[k].passes) continue;
        const Vec2 c = body_position(bodies[k], t);
        const float hx = m.x - c.x, hy = m.y - c.y, l = norm(hx, hy), reach = bodies[k].radius + r;
        if (l >= reach - kTolerance) continue;
        const float nx = l > 0 ? hx / l : 1, ny = l > 0 ? hy / l : 0;
        m.x = c.x + nx * (reach + kSkin), m.y = c.y + ny * (reach + kSkin);
        moved = true;
      }
    }
    for (size_t k = 0; k < g.ax.size(); ++k) {
      const float px = m.x - g.ax[k], py = m.y - g.ay[k];
      const float along = std::clamp(dot(px, py, g.tx[k], g.ty[k]), 0.0f, g.len[k]);
      const float hx = px - along * g.tx[k], hy = py - along * g.ty[k], l = norm(hx, hy);
      if (l >= r - kTolerance) continue;
      const float nx = l > 0 ? hx / l : g.nx[k], ny = l > 0 ? hy / l : g.ny[k];
      m.x += nx * (r + kSkin - l), m.y += ny * (r + kSkin - l);
      const float vn = dot(m.vx, m.vy, nx, ny);
      if (vn < 0) m.vx -= vn * nx, m.vy -= vn * ny;
      m.ux = m.vx, m.uy = m.vy;
      moved = true;
    }
    if (!moved) {
      for (int k = 0; k < n_bodies; ++k) {
        if (bodies[k].passes) continue;
        const Vec2 c = body_position(bodies[k], t);
        if (norm(m.x - c.x, m.y - c.y) < bodies[k].radius + r - kTolerance)
          return push_from_bodies ? Outcome{HitKind::Crushed, k} : Outcome{HitKind::Body, k};
      }
      if (!g.bounds.contains(m.x, m.y)) return {HitKind::Out, 0};
      return {HitKind::None, -1};
    }
  }
  return {HitKind::Crushed, -1};
}

}  // namespace quantum::detail

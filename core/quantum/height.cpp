#include "height.h"

#include <algorithm>
#include <cmath>

namespace quantum::detail {
namespace {

// The ring search stops this close to the rod: a thousandth of a millimetre, below the skin a
// bounce leaves, so a ball that just bounced off the rod is not touching it. The step and the
// prediction reach the rod from different starts: the tighter this, the closer their contacts.
constexpr float kRingTolerance = 1e-6f;
constexpr uint32_t kMaxRingSteps = 400;

[[gnu::always_inline]] inline float hypot2(float x, float y) { return std::sqrt(x * x + y * y); }

// The later time at which height z0 + vz t - g t^2 / 2 equals `level` (the ball coming down
// through it), if it is still to come; kInf otherwise. Without gravity, the linear crossing.
// Branch-free, for the batched search.
[[gnu::always_inline]] inline float descent_time(float z0, float vz, float g, float level) {
  const float linear = ((vz < 0) & (z0 >= level)) ? (z0 - level) / -vz : kInf;
  const float disc = vz * vz + 2 * g * (z0 - level);
  const float t = (vz + std::sqrt(std::max(disc, 0.0f))) / g;
  const float falling = ((disc >= 0) & (t >= 0)) ? t : kInf;
  return g > 0 ? falling : linear;
}

// The earlier time at which the height rises to `level`, kInf when it never does.
[[gnu::always_inline]] inline float ascent_time(float z0, float vz, float g, float level) {
  const float disc = vz * vz - 2 * g * (level - z0);
  const float rising = std::max(0.0f, (vz - std::sqrt(std::max(disc, 0.0f))) / g), linear = (level - z0) / vz;
  const bool gravity = g > 0;
  const bool rises = (vz > 0) & gravity & (disc >= 0), climbs = (vz > 0) & !gravity & (z0 <= level);
  return rises ? rising : climbs ? linear : kInf;
}

// A hoop as the rim search sees it.
struct Ring {
  float x, y, z;  // centre
  float radius;   // of the ring line
  float reach;    // the rod's half thickness plus the ball's radius
};

// The rod is a torus: its contact with a parabola has no closed form, so the search advances by
// the largest step that cannot pass a contact (conservative advancement). Two bounds give such a
// step, and it takes the longer: the gap closes no faster than the ball's speed (`fast`); and the
// gap's rate of change falls no faster than gravity plus the horizontal speed bent around the
// hoop's axis (`bend`: the distance from a ring curves down only along the ring, by at most
// 1/rho). The second makes a ball moving away from the rod, or past it, take a few long steps,
// and one closing in converge as Newton's method would. Returns the next time to look at, or t
// itself at a contact.
[[gnu::always_inline]] inline float ring_probe(const Ring& h, float qx, float qy, float z, float ux, float uy, float vz,
                                               float g, float t, float fast, float bend, bool& touching) {
  const float px = qx + ux * t, py = qy + uy * t, pz = z + vz * t - 0.5f * g * t * t - h.z, rho = hypot2(px, py);
  const float radial = rho - h.radius, gap = hypot2(radial, pz) - h.reach;
  // How fast the gap grows: the velocity along the direction from the rod to the ball.
  const float nx = rho > 0 ? radial * px / rho : 0, ny = rho > 0 ? radial * py / rho : 0;
  const float rate = (nx * ux + ny * uy + pz * (vz - g * t)) / (gap + h.reach);
  // The later root of gap + rate dt - bend dt^2 / 2, in the form that keeps its digits.
  const float root = std::sqrt(rate * rate + 2 * bend * gap);
  const float step = std::max(gap / fast, rate >= 0 ? (rate + root) / bend : 2 * gap / (root - rate));
  const bool close = gap < kRingTolerance;
  touching = close & ((t > 0) | (rate < 0));
  // Close but moving away: it has just bounced off the rod.
  return touching ? t : close ? t + 2 * kRingTolerance / fast + 1e-6f : t + step;
}

// When each particle i with near[i] first touches hoop h's rod before limit[i] (kInf if never),
// into found[i]. The search runs only while the ball is level with the rod (one or two stretches
// of the arc) and passes within reach of it horizontally; the particles still searching probe
// together, round by round.
void ring_times(const Ring& hoop, const Paths3 p, RingScratch& w, size_t n, const float* limit) {
  const Ring h = hoop;  // a local: stores to the float arrays might otherwise alias it
  float* __restrict hi0 = w.hi0.data();
  float* __restrict lo1 = w.lo1.data();
  float* __restrict hi1 = w.hi1.data();
  float* __restrict fast0 = w.fast0.data();
  float* __restrict fast1 = w.fast1.data();
  float* __restrict bend0 = w.bend0.data();
  float* __restrict bend1 = w.bend1.data();
  float* __restrict at = w.at.data();
  float* __restrict found = w.found.data();
  uint32_t* __restrict stage = w.stage.data();
  uint32_t* __restrict steps = w.steps.data();
  auto distance = [&](size_t i, float t) __attribute__((always_inline)) {
    return hypot2(p.x[i] - h.x + p.ux[i] * t, p.y[i] - h.y + p.uy[i] * t);
  };
  // A stretch [lo, hi] of the arc, clamped to [0, limit]: whether it can meet the rod, how fast
  // the ball goes in it at most, and how its gap may bend.
  int32_t any = 0;
  auto stretch = [&](size_t i, float& lo, float& hi, float& fast, float& bend) __attribute__((always_inline)) {
    const float g = p.g[i], uu = p.ux[i] * p.ux[i] + p.uy[i] * p.uy[i];
    lo = std::max(lo, 0.0f), hi = std::min(hi, limit[i]);
    // Horizontally: never within reach of the ring line, or all the time well inside the ring.
    const float qx = p.x[i] - h.x, qy = p.y[i] - h.y;
    const float closest = uu > 0 ? std::clamp(-(qx * p.ux[i] + qy * p.uy[i]) / uu, lo, hi) : lo;
    const float nearest = distance(i, closest);
    const float w0 = p.vz[i] - g * lo, w1 = p.vz[i] - g * hi;
    fast = std::sqrt(uu + std::max(w0 * w0, w1 * w1));
    bend = g + uu / std::max(nearest, 1e-3f);
    return (lo <= hi) & !(nearest > h.radius + h.reach) &
           !(std::max(distance(i, lo), distance(i, hi)) < h.radius - h.reach) & (fast > 0);
  };
  QUANTUM_INDEPENDENT_ITERATIONS
  for (size_t i = 0; i < n; ++i) {
    const float g = p.g[i], v = p.vz[i];
    // Level with the rod: the arc above its bottom, less the time above its top.
    const float low = v * v + 2 * g * (p.z[i] - (h.z - h.reach)), high = v * v + 2 * g * (p.z[i] - (h.z + h.reach));
    const float rl = std::sqrt(std::max(low, 0.0f)), rh = std::sqrt(std::max(high, 0.0f));
    const float a0 = (v - rl) / g, a1 = (v + rl) / g, b0 = (v - rh) / g, b1 = (v + rh) / g;
    const bool split = high >= 0;
    float l0 = a0, h0 = split ? b0 : a1, l1 = b1, h1 = a1;
    float f0, f1, e0, e1;
    // A ball on the floor never reaches a ring.
    const bool level = (p.near[i] != 0) & (g > 0) & (low >= 0);
    const bool first = level & stretch(i, l0, h0, f0, e0), second = level & split & stretch(i, l1, h1, f1, e1);
    hi0[i] = h0, lo1[i] = second ? l1 : kInf, hi1[i] = h1, fast0[i] = f0, fast1[i] = f1, bend0[i] = e0, bend1[i] = e1;
    stage[i] = first ? 0 : second ? 1 : 2;
    at[i] = first ? l0 : l1;
    steps[i] = 0, found[i] = kInf;
    any |= int32_t(first | second);
  }
  if (!any) return;
  // The searching particles, gathered to the front with what their probes read: most particles
  // of a batch never come level with the rod, and most that do finish within a few probes.
  float* __restrict qx = w.qx.data();
  float* __restrict qy = w.qy.data();
  float* __restrict qz = w.qz.data();
  float* __restrict wx = w.ux.data();
  float* __restrict wy = w.uy.data();
  float* __restrict wz = w.vz.data();
  float* __restrict wg = w.g.data();
  float* __restrict hit = w.hit.data();
  int32_t* __restrict lane = w.lane.data();
  size_t m = 0;
  for (size_t i = 0; i < n; ++i) {
    // Slot m is at or before i: what it overwrites has been read.
    lane[m] = int32_t(i), qx[m] = p.x[i] - h.x, qy[m] = p.y[i] - h.y, qz[m] = p.z[i], wx[m] = p.ux[i], wy[m] = p.uy[i];
    wz[m] = p.vz[i], wg[m] = p.g[i];
    hi0[m] = hi0[i], lo1[m] = lo1[i], hi1[m] = hi1[i], fast0[m] = fast0[i], fast1[m] = fast1[i];
    bend0[m] = bend0[i], bend1[m] = bend1[i], at[m] = at[i], stage[m] = stage[i], steps[m] = 0;
    m += stage[i] < 2;
  }
  while (m > 0) {
    // One probe for every particle still searching...
    QUANTUM_INDEPENDENT_ITERATIONS
    for (size_t j = 0; j < m; ++j) {
      // Every load before any store, for clang's vectorizer (keep_sooner in contact.cpp).
      const uint32_t was_stage = stage[j], was_steps = steps[j];
      const float was_at = at[j];
      const bool in_first = was_stage == 0;
      const float fast = in_first ? fast0[j] : fast1[j], bend = in_first ? bend0[j] : bend1[j];
      const float hi = in_first ? hi0[j] : hi1[j];
      bool touching;
      const float next = ring_probe(h, qx[j], qy[j], qz[j], wx[j], wy[j], wz[j], wg[j], was_at, fast, bend, touching);
      const bool done = (!touching) & ((next > hi) | (was_steps + 1 >= kMaxRingSteps));
      const bool move_on = done & in_first & (lo1[j] <= hi1[j]);
      hit[j] = touching ? was_at : kInf;
      at[j] = move_on ? lo1[j] : next;
      steps[j] = move_on ? 0 : was_steps + 1;
      stage[j] = (touching | (done & !move_on)) ? 2 : was_stage + uint32_t(move_on);
    }
    // ...then the finished ones answer and leave.
    size_t kept = 0;
    for (size_t j = 0; j < m; ++j) {
      if (stage[j] == 2) {
        found[lane[j]] = hit[j];
        continue;
      }
      lane[kept] = lane[j], qx[kept] = qx[j], qy[kept] = qy[j], qz[kept] = qz[j], wx[kept] = wx[j], wy[kept] = wy[j];
      wz[kept] = wz[j], wg[kept] = wg[j], hi0[kept] = hi0[j], lo1[kept] = lo1[j], hi1[kept] = hi1[j];
      fast0[kept] = fast0[j], fast1[kept] = fast1[j], bend0[kept] = bend0[j], bend1[kept] = bend1[j];
      at[kept] = at[j], stage[kept] = stage[j], steps[kept] = steps[j];
      ++kept;
    }
    m = kept;
  }
}

}  // namespace

Sky::Sky(const Field& f)
    : g(f.gravity), e_floor(f.floor_restitution), r(f.ball_radius), roll(f.friction), floor_wall(f.floor_wall),
      ceiling_wall(f.ceiling_wall), landings(f.landings), areas(f.landings ? f.areas : std::vector<Area>{}) {
  if (f.ceiling > 0) ceiling = f.ceiling - r;
  auto cover = [&](float x0, float y0, float z0, float x1, float y1, float z1) {
    const bool first = ox0 > ox1;
    ox0 = first ? x0 : std::min(ox0, x0), oy0 = first ? y0 : std::min(oy0, y0), oz0 = first ? z0 : std::min(oz0, z0);
    ox1 = first ? x1 : std::max(ox1, x1), oy1 = first ? y1 : std::max(oy1, y1), oz1 = first ? z1 : std::max(oz1, z1);
  };
  for (size_t k = 0; k < f.goals.size(); ++k) {
    const Goal& gl = f.goals[k];
    if (!gl.hoop()) continue;
    hx.push_back(gl.a.x), hy.push_back(gl.a.y), hz.push_back(gl.rim_height);
    hring.push_back(gl.rim_radius), htube.push_back(gl.rim_thickness / 2), he.push_back(gl.rim_restitution);
    hgoal.push_back(int(k)), hwall.push_back(gl.rim_wall);
    // A ball never comes to rest on a rim: it would bounce ever lower, infinitely often (the
    // floor has kRestingBounce for that). A slow contact sends it off the rod at least this fast,
    // enough to clear the rod's curve under gravity (v^2 > g (rod + ball radius)), so it falls
    // off to one side or the other within a few hops, as a real ball rolls off.
    hhop.push_back(1.1f * std::sqrt(f.gravity * (gl.rim_thickness / 2 + r)));
    const float out = gl.rim_radius + gl.rim_thickness / 2 + r, up = gl.rim_thickness / 2 + r;
    cover(gl.a.x - out, gl.a.y - out, gl.rim_height - up, gl.a.x + out, gl.a.y + out, gl.rim_height + up);
  }
  for (const Board& b : f.boards) {
    const float dx = b.b.x - b.a.x, dy = b.b.y - b.a.y, l = hypot2(dx, dy);
    board.push_back({b.a.x, b.a.y, dx / l, dy / l, -dy / l, dx / l, l});
    bbottom.push_back(b.bottom), btop.push_back(b.top), be.push_back(b.restitution), bwall.push_back(b.wall);
    cover(std::min(b.a.x, b.b.x) - r, std::min(b.a.y, b.b.y) - r, b.bottom - r, std::max(b.a.x, b.b.x) + r,
          std::max(b.a.y, b.b.y) + r, b.top + r);
  }
}

int Sky::landing_at(float x, float y) const {
  for (size_t k = 0; k < areas.size(); ++k)
    if (areas[k].contains({x, y})) return int(k) + 1;
  return 0;
}

Mover3 advanced(const Sky& sky, const Mover3& m, float dt) {
  const float g = sky.gravity_on(m);
  Mover3 out = m;
  if (sky.roll > 0 && g == 0) {
    const float span = sky.rolled(dt), slow = std::exp(-sky.roll * dt);
    out.x += m.ux * span, out.y += m.uy * span;
    out.ux *= slow, out.uy *= slow, out.vx *= slow, out.vy *= slow;
    return out;
  }
  out.x += m.ux * dt, out.y += m.uy * dt;
  out.z += m.vz * dt - 0.5f * g * dt * dt;
  out.vz -= g * dt;
  return out;
}

void RingScratch::resize(size_t n) {
  for (auto* v : {&hi0, &lo1, &hi1, &fast0, &fast1, &bend0, &bend1, &at, &found, &limit, &qx, &qy, &qz, &ux,
                  &uy, &vz, &g, &hit})
    v->resize(n);
  stage.resize(n), steps.resize(n), lane.resize(n);
}

void Mover3Batch::resize(size_t n) {
  ring.resize(n);
  for (auto* v : {&x, &y, &z, &ux, &uy, &vx, &vy, &vz, &t, &when, &nx, &ny, &nz, &g, &span, &clear}) v->resize(n);
  code.resize(n), surface.resize(n), item.resize(n), near.resize(n);
}

namespace {

// batch_next_hits3 in the units of each particle's path: seconds for a flying particle, the
// length rolled() at its start speed for a rolling one. A rolling particle meets a moving body
// as if the body's clock ran at the ball's pace: within a step (1/60 s at friction 1/s) the two
// differ by under 0.2 ms; over a prediction's horizon the body's predicted sweep, itself an
// extrapolation, is met a little early, as on a flat field with friction.
void search3(const Geometry& geo, const Sky& s, const BodyPath* bodies, int n_bodies, Mover3Batch& b, size_t n,
             float t1, bool with_bodies) {
  // Hand-written for the compiler's vectorizer, as batch_next_hits: each loop runs one kind of
  // surface over all particles, branch-free. Only the rim search and the walls (rare: a path
  // leaving the safe box) run one particle at a time, each for the particles that need them.
  const Paths3 p(b);
  const float r = s.r, gravity = s.g, ground = s.r + kGroundSkin, ceiling = s.ceiling;
  const int32_t floor_code = hit_code(HitKind::Wall, s.floor_wall), ceiling_code = hit_code(HitKind::Wall, s.ceiling_wall);
  auto set = [&](size_t i, bool better, float dt, int32_t c, Surface f, int k, float nx, float ny, float nz) {
    p.when[i] = better ? dt : p.when[i], p.code[i] = better ? c : p.code[i];
    p.surface[i] = better ? int32_t(f) : p.surface[i], p.item[i] = better ? k : p.item[i];
    p.nx[i] = better ? nx : p.nx[i], p.ny[i] = better ? ny : p.ny[i], p.nz[i] = better ? nz : p.nz[i];
  };
  // The floor and the ceiling first, in closed form: nothing after the ball meets them counts, so
  // every other search looks only that far (a long prediction's flight ends at the next bounce).
  QUANTUM_INDEPENDENT_ITERATIONS
  for (size_t i = 0; i < n; ++i) {
    // A ball resting on the floor rolls: the floor holds gravity.
    const float g = ((p.vz[i] == 0) & (p.z[i] <= ground)) ? 0.0f : gravity;
    p.g[i] = g;
    p.when[i] = kInf, p.code[i] = -1, p.surface[i] = int32_t(Surface::Segment), p.item[i] = -1;
    p.nx[i] = 0, p.ny[i] = 0, p.nz[i] = 0;
    const float left = t1 - p.t[i];
    const float down = ((p.z[i] <= r) & (p.vz[i] < 0)) ? 0.0f : descent_time(p.z[i], p.vz[i], g, r);
    set(i, (g > 0) & (down <= left), down, floor_code, Surface::Floor, -1, 0, 0, 1);
    p.span[i] = std::min(left, p.when[i]);
  }
  if (ceiling < kInf) {
    for (size_t i = 0; i < n; ++i) {
      const float left = t1 - p.t[i], up = ascent_time(p.z[i], p.vz[i], p.g[i], ceiling);
      set(i, (up <= left) & (up < p.when[i]), up, ceiling_code, Surface::Ceiling, -1, 0, 0, -1);
      p.span[i] = std::min(left, p.when[i]);
    }
  }
  if (s.roll > 0) {
    for (size_t i = 0; i < n; ++i)
      if (p.g[i] == 0) p.span[i] = s.rolled(t1 - p.t[i]);
  }
  // Walls, goal lines, the bounds and wormholes: only where the path leaves the safe box. A court
  // with lines only (no walls, no goal lines) has just its bounds to search, for every particle
  // at once.
  const Box safe = geo.safe, bounds = geo.bounds;
  const bool mouths = !geo.mx.empty();
  if (geo.ax.empty() && geo.cap_x.empty() && geo.gax.empty() && !mouths) {
    const int32_t out = hit_code(HitKind::Out, 0);
    QUANTUM_INDEPENDENT_ITERATIONS
    for (size_t i = 0; i < n; ++i) {
      const float dt = bounds_time(bounds, p.x[i], p.y[i], p.ux[i], p.uy[i], p.span[i]);
      set(i, dt < p.when[i], dt, out, Surface::Segment, -1, 0, 0, 0);
    }
  } else {
    for (size_t i = 0; i < n; ++i) {
      const float ex = p.x[i] + p.ux[i] * p.span[i], ey = p.y[i] + p.uy[i] * p.span[i];
      if (!mouths && safe.contains(p.x[i], p.y[i]) && safe.contains(ex, ey)) continue;
      const Hit flat = next_hit(geo, nullptr, 0, {p.x[i], p.y[i], p.ux[i], p.uy[i], b.vx[i], b.vy[i]}, p.t[i], p.t[i] + p.span[i], false);
      set(i, flat.dt < p.when[i], flat.dt, hit_code(flat.kind, flat.index), Surface::Segment, -1, flat.nx, flat.ny, 0);
    }
  }

  // Hoops and boards, for paths whose box comes near theirs.
  if (s.ox0 <= s.ox1) {
    const float ox0 = s.ox0, oy0 = s.oy0, oz0 = s.oz0, ox1 = s.ox1, oy1 = s.oy1, oz1 = s.oz1;
    int32_t any_near = 0;
    QUANTUM_INDEPENDENT_ITERATIONS
    for (size_t i = 0; i < n; ++i) {
      const float g = p.g[i], d = p.span[i], ex = p.x[i] + p.ux[i] * d, ey = p.y[i] + p.uy[i] * d;
      const float end = p.z[i] + p.vz[i] * d - 0.5f * g * d * d;
      const float peak = ((g > 0) & (p.vz[i] > 0) & (p.vz[i] < g * d)) ? p.z[i] + p.vz[i] * p.vz[i] / (2 * g) : std::max(p.z[i], end);
      p.near[i] = int32_t((std::max(p.x[i], ex) >= ox0) & (std::min(p.x[i], ex) <= ox1) & (std::max(p.y[i], ey) >= oy0) &
                        (std::min(p.y[i], ey) <= oy1) & (peak >= oz0) & (std::min(p.z[i], end) <= oz1));
      any_near |= p.near[i];
    }
    if (!any_near) goto bodies;
    for (size_t k = 0; k < s.board.size(); ++k) {
      const SegmentParams board = s.board[k];
      const float bottom = s.bbottom[k], top = s.btop[k];
      const int32_t c = hit_code(HitKind::Wall, s.bwall[k]);
      QUANTUM_INDEPENDENT_ITERATIONS
      for (size_t i = 0; i < n; ++i) {
        // Beside a board's edge (within a ball's radius of its plane, over, under or past it) the
        // ball flies on: edges are not modelled, and a ball there must not hit the face from inside.
        const bool beside = std::fabs((p.x[i] - board.ax) * board.nx + (p.y[i] - board.ay) * board.ny) < r - kTolerance;
        float nx, ny;
        const float dt = wall_time(board, r, p.x[i], p.y[i], p.ux[i], p.uy[i], p.span[i], nx, ny);
        const float h = p.z[i] + p.vz[i] * dt - 0.5f * p.g[i] * dt * dt;
        set(i, p.near[i] & !beside & (dt < p.when[i]) & (h >= bottom) & (h <= top), dt, c, Surface::Board, int(k), nx, ny, 0);
      }
    }
    for (size_t k = 0; k < s.hx.size(); ++k) {
      const float cx = s.hx[k], cy = s.hy[k], cz = s.hz[k], ring = s.hring[k];
      const int32_t rim = hit_code(HitKind::Wall, s.hwall[k]), basket = hit_code(HitKind::Goal, s.hgoal[k]);
      float* __restrict limit = b.ring.limit.data();
      for (size_t i = 0; i < n; ++i) limit[i] = std::min(p.span[i], p.when[i]);
      ring_times({cx, cy, cz, ring, s.htube[k] + r}, p, b.ring, n, limit);
      const float* __restrict found = b.ring.found.data();
      QUANTUM_INDEPENDENT_ITERATIONS
      for (size_t i = 0; i < n; ++i) {
        const float dt = found[i];
        const float px = p.x[i] + p.ux[i] * dt - cx, py = p.y[i] + p.uy[i] * dt - cy;
        const float pz = p.z[i] + p.vz[i] * dt - 0.5f * p.g[i] * dt * dt - cz, rho = hypot2(px, py);
        const float nx = rho > 0 ? px - ring * px / rho : 0, ny = rho > 0 ? py - ring * py / rho : 0;
        const float l = std::sqrt(nx * nx + ny * ny + pz * pz);
        const bool flat = !(l > 0);
        set(i, dt < p.when[i], dt, rim, Surface::Rim, int(k), flat ? 0.0f : nx / l, flat ? 0.0f : ny / l, flat ? 1.0f : pz / l);
      }
      // Through the ring from above: a basket.
      QUANTUM_INDEPENDENT_ITERATIONS
      for (size_t i = 0; i < n; ++i) {
        const float down = descent_time(p.z[i], p.vz[i], p.g[i], cz);
        const float hx = p.x[i] + p.ux[i] * down - cx, hy = p.y[i] + p.uy[i] * down - cy;
        set(i, p.near[i] & (p.g[i] > 0) & (down <= p.span[i]) & (down < p.when[i]) & (hypot2(hx, hy) < ring), down, basket,
            Surface::Segment, int(k), 0, 0, -1);
      }
    }
  }

bodies:
  if (!with_bodies) return;
  for (int k = 0; k < n_bodies; ++k) {
    const BodyPath body = bodies[k];
    if (body.passes) continue;
    const float reach = body.radius + r, over = body.top + r;
    const int32_t c = hit_code(HitKind::Body, k);
    // Cull by the box the body sweeps, grown by its radius, as the flat search does; a body clear
    // of every path is not searched at all.
    float* __restrict clear = b.clear.data();
    int32_t any_close = 0;
    QUANTUM_INDEPENDENT_ITERATIONS
    for (size_t i = 0; i < n; ++i) {
      const float t0 = p.t[i], d = p.span[i], ex = p.x[i] + p.ux[i] * d, ey = p.y[i] + p.uy[i] * d;
      const float cx0 = body_x(body, t0), cx1 = body_x(body, t0 + d), cy0 = body_y(body, t0), cy1 = body_y(body, t0 + d);
      clear[i] = float((std::max(cx0, cx1) + body.radius < std::min(p.x[i], ex) - r) |
                         (std::min(cx0, cx1) - body.radius > std::max(p.x[i], ex) + r) |
                         (std::max(cy0, cy1) + body.radius < std::min(p.y[i], ey) - r) |
                         (std::min(cy0, cy1) - body.radius > std::max(p.y[i], ey) + r));
      any_close |= int32_t(clear[i] == 0);
    }
    if (!any_close) continue;
    QUANTUM_INDEPENDENT_ITERATIONS
    for (size_t i = 0; i < n; ++i) {
      const float t0 = p.t[i], d = p.span[i], g = p.g[i];
      // The side, below the body's reach...
      const float side = body_time(body, r, p.x[i], p.y[i], p.ux[i], p.uy[i], t0, t0 + d);
      float hx = p.x[i] + p.ux[i] * side - body_x(body, t0 + side), hy = p.y[i] + p.uy[i] * side - body_y(body, t0 + side);
      const float l = hypot2(hx, hy);
      const bool centred = !(l > 0);  // dead centre: any direction is as good
      hx = centred ? 1.0f : hx / l, hy = centred ? 0.0f : hy / l;
      const float h = p.z[i] + p.vz[i] * side - 0.5f * g * side * side;
      set(i, (clear[i] == 0.0f) & (side < p.when[i]) & (h <= over), side, c, Surface::Side, -1, hx, hy, 0);
      // ...or the top, coming down onto the hands.
      const float top = descent_time(p.z[i], p.vz[i], g, over);
      const float tx = p.x[i] + p.ux[i] * top - body_x(body, t0 + top), ty = p.y[i] + p.uy[i] * top - body_y(body, t0 + top);
      set(i, (clear[i] == 0.0f) & (p.z[i] > over) & (top <= d) & (top < p.when[i]) & (hypot2(tx, ty) < reach), top, c, Surface::Top, -1,
          0, 0, 1);
    }
  }
}

}  // namespace

void batch_next_hits3(const Geometry& geo, const Sky& s, const BodyPath* bodies, int n_bodies, Mover3Batch& b,
                      size_t n, float t1, bool with_bodies) {
  search3(geo, s, bodies, n_bodies, b, n, t1, with_bodies);
  if (!(s.roll > 0)) return;
  // A rolling particle's contact, read back from the length rolled to seconds; rounding never
  // takes it past the search's end.
  for (size_t i = 0; i < n; ++i)
    if (b.g[i] == 0 && b.when[i] < kInf) b.when[i] = std::min(s.roll_time(b.when[i]), t1 - b.t[i]);
}

Hit3 next_hit3(const Geometry& geo, const Sky& sky, const BodyPath* bodies, int n_bodies, const Mover3& m, float t0,
               float t1, bool with_bodies) {
  // One particle is a batch of one: the step, the prediction and a picture's path search alike.
  thread_local Mover3Batch one = [] {
    Mover3Batch b;
    b.resize(1);
    return b;
  }();
  one.set(0, m, t0);
  batch_next_hits3(geo, sky, bodies, n_bodies, one, 1, t1, with_bodies);
  return one.hit(0);
}

void resolve(const Geometry& geo, const Sky& s, const BodyPath* bodies, const Hit3& hit, float t, Mover3& m) {
  switch (hit.surface) {
    case Surface::Floor:
    case Surface::Ceiling: {
      const float up = hit.surface == Surface::Floor ? 1.0f : -1.0f;
      if (m.vz * up < 0) m.vz = -s.e_floor * m.vz;
      if (hit.surface == Surface::Floor && m.vz < kRestingBounce) {
        m.vz = 0, m.z = s.r;  // on the floor: it rolls
      } else {
        m.z = hit.surface == Surface::Floor ? s.r + kSkin : s.ceiling - kSkin;
      }
      break;
    }
    case Surface::Board: reflect_off(m, hit.nx, hit.ny, s.be[size_t(hit.item)]); break;
    case Surface::Rim: {
      const float e = s.he[size_t(hit.item)];
      const float vn = m.vx * hit.nx + m.vy * hit.ny + m.vz * hit.nz;
      const float out = std::max(-e * vn, s.hhop[size_t(hit.item)]);
      if (vn < out) m.vx += (out - vn) * hit.nx, m.vy += (out - vn) * hit.ny, m.vz += (out - vn) * hit.nz;
      m.ux = m.vx, m.uy = m.vy;  // the rest of this step's drift is spent in the contact
      m.x += kSkin * hit.nx, m.y += kSkin * hit.ny, m.z += kSkin * hit.nz;
      break;
    }
    case Surface::Top: {
      if (m.vz < 0) m.vz = -geo.e_body * m.vz;
      m.z = bodies[hit.index].top + s.r + kSkin;
      m.ux = m.vx, m.uy = m.vy;
      break;
    }
    case Surface::Segment:
    case Surface::Side: resolve(geo, bodies, hit.kind, hit.index, hit.nx, hit.ny, t, m); break;
  }
}

float impact_speed(const Hit3& hit, const Mover3& m) { return -(m.vx * hit.nx + m.vy * hit.ny + m.vz * hit.nz); }

}  // namespace quantum::detail

#include "height.h"

#include <algorithm>
#include <cmath>

namespace quantum::detail {
namespace {

// A resolved contact leaves the ball this far off the surface, so rounding never puts it back.
constexpr float kSkin = 2e-6f;
// The ring search stops this close to the rod: a thousandth of a millimetre, below the skin a
// bounce leaves, so a ball that just bounced off the rod is not touching it. The step and the
// prediction reach the rod from different starts: the tighter this, the closer their contacts.
constexpr float kRingTolerance = 1e-6f;
constexpr int kMaxRingSteps = 400;
constexpr int kMaxContacts = 8;  // as the flat step: a particle rattling in a corner stops where it is

float hypot2(float x, float y) { return std::sqrt(x * x + y * y); }

// The later time at which height z0 + vz t - g t^2 / 2 equals `level` (the ball coming down
// through it), if it is still to come; kInf otherwise. Without gravity, the linear crossing.
float descent_time(float z0, float vz, float g, float level) {
  if (g <= 0) return vz < 0 && z0 >= level ? (z0 - level) / -vz : kInf;
  const float disc = vz * vz + 2 * g * (z0 - level);
  if (disc < 0) return kInf;
  const float t = (vz + std::sqrt(disc)) / g;
  return t >= 0 ? t : kInf;
}

// The earlier time at which the height rises to `level`, kInf when it never does.
float ascent_time(float z0, float vz, float g, float level) {
  if (vz <= 0) return kInf;
  if (g <= 0) return z0 <= level ? (level - z0) / vz : kInf;
  const float disc = vz * vz - 2 * g * (level - z0);
  if (disc < 0) return kInf;
  return std::max(0.0f, (vz - std::sqrt(disc)) / g);
}

// When the height z0 + vz t - g t^2 / 2 is at least `level`: on [t0, t1] (g > 0); false if never.
bool above(float z0, float vz, float g, float level, float& t0, float& t1) {
  const float disc = vz * vz + 2 * g * (z0 - level);
  if (disc < 0) return false;
  const float root = std::sqrt(disc);
  t0 = (vz - root) / g, t1 = (vz + root) / g;
  return true;
}

// When the ball first touches hoop k's rod within `span`. The rod is a torus: its contact with a
// parabola has no closed form, so the search advances by the largest step that cannot pass a
// contact (conservative advancement). Two bounds give such a step, and it takes the longer: the
// gap closes no faster than the ball's speed; and the gap's rate of change falls no faster than
// gravity plus the horizontal speed bent around the hoop's axis (the distance from a ring curves
// down only along the ring, by at most 1/rho). The second makes a ball moving away from the rod,
// or past it, take a few long steps, and one closing in converge as Newton's method would.
// It runs only while the ball is level with the rod (one or two stretches of the arc) and
// passes within reach of it horizontally.
float ring_time(const Sky& s, size_t k, const Mover3& m, float g, float span) {
  if (!(g > 0)) return kInf;  // a ball on the floor never reaches a ring
  const float reach = s.htube[k] + s.r;
  float a0, a1, b0, b1;
  if (!above(m.z, m.vz, g, s.hz[k] - reach, a0, a1)) return kInf;
  float stretch[2][2];
  int n = 0;
  auto add = [&](float lo, float hi) {
    lo = std::max(lo, 0.0f), hi = std::min(hi, span);
    if (lo <= hi) stretch[n][0] = lo, stretch[n][1] = hi, ++n;
  };
  if (above(m.z, m.vz, g, s.hz[k] + reach, b0, b1)) add(a0, b0), add(b1, a1);
  else add(a0, a1);
  const float qx = m.x - s.hx[k], qy = m.y - s.hy[k], uu = m.ux * m.ux + m.uy * m.uy;
  auto distance = [&](float t) { return hypot2(qx + m.ux * t, qy + m.uy * t); };
  for (int piece = 0; piece < n; ++piece) {
    const float lo = stretch[piece][0], hi = stretch[piece][1];
    // Horizontally: never within reach of the ring line, or all the time well inside the ring.
    const float closest = uu > 0 ? std::clamp(-(qx * m.ux + qy * m.uy) / uu, lo, hi) : lo;
    const float nearest = distance(closest);
    if (nearest > s.hring[k] + reach || std::max(distance(lo), distance(hi)) < s.hring[k] - reach) continue;
    const float fastest = std::sqrt(uu + std::max((m.vz - g * lo) * (m.vz - g * lo), (m.vz - g * hi) * (m.vz - g * hi)));
    if (!(fastest > 0)) continue;
    const float bend = g + uu / std::max(nearest, 1e-3f);
    float t = lo;
    for (int i = 0; i < kMaxRingSteps && t <= hi; ++i) {
      const float z = m.z + m.vz * t - 0.5f * g * t * t;
      const float px = qx + m.ux * t, py = qy + m.uy * t, pz = z - s.hz[k], rho = hypot2(px, py);
      const float radial = rho - s.hring[k], gap = hypot2(radial, pz) - reach;
      // How fast the gap grows: the velocity along the direction from the rod to the ball.
      const float nx = rho > 0 ? radial * px / rho : 0, ny = rho > 0 ? radial * py / rho : 0;
      const float rate = (nx * m.ux + ny * m.uy + pz * (m.vz - g * t)) / (gap + reach);
      if (gap < kRingTolerance) {
        if (t > 0 || rate < 0) return t;
        t += 2 * kRingTolerance / fastest + 1e-6f;  // just bounced off it, moving away
        continue;
      }
      // The later root of gap + rate dt - bend dt^2 / 2, in the form that keeps its digits.
      const float root = std::sqrt(rate * rate + 2 * bend * gap);
      t += std::max(gap / fastest, rate >= 0 ? (rate + root) / bend : 2 * gap / (root - rate));
    }
  }
  return kInf;
}

Hit3 flat_hit(const Hit& h) { return {h.dt, h.kind, h.index, Surface::Segment, -1, h.nx, h.ny, 0}; }

}  // namespace

Sky::Sky(const Field& f)
    : g(f.gravity), e_floor(f.floor_restitution), r(f.ball_radius), floor_wall(f.floor_wall),
      ceiling_wall(f.ceiling_wall) {
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

Mover3 advanced(const Sky& sky, const Mover3& m, float dt) {
  const float g = sky.gravity_on(m);
  Mover3 out = m;
  out.x += m.ux * dt, out.y += m.uy * dt;
  out.z += m.vz * dt - 0.5f * g * dt * dt;
  out.vz -= g * dt;
  return out;
}

Hit3 next_hit3(const Geometry& geo, const Sky& s, const BodyPath* bodies, int n_bodies, const Mover3& m, float t0,
               float t1, bool with_bodies) {
  const float g = s.gravity_on(m), r = s.r;
  auto height_at = [&](float dt) { return m.z + m.vz * dt - 0.5f * g * dt * dt; };
  Hit3 best{kInf, HitKind::None, -1, Surface::Segment, -1, 0, 0, 0};
  // The floor and the ceiling first, in closed form: nothing after the ball meets them counts, so
  // every other search looks only that far (a long prediction's flight ends at the next bounce).
  if (g > 0) {
    const float dt = m.z <= r && m.vz < 0 ? 0.0f : descent_time(m.z, m.vz, g, r);
    if (dt <= t1 - t0) best = {dt, HitKind::Wall, s.floor_wall, Surface::Floor, -1, 0, 0, 1};
  }
  if (s.ceiling < kInf) {
    const float dt = ascent_time(m.z, m.vz, g, s.ceiling);
    if (dt <= t1 - t0 && dt < best.dt) best = {dt, HitKind::Wall, s.ceiling_wall, Surface::Ceiling, -1, 0, 0, -1};
  }
  const float span = std::min(t1 - t0, best.dt);
  const float ex = m.x + m.ux * span, ey = m.y + m.uy * span;
  // Walls, goal lines, the bounds and wormholes: only where the path leaves the safe box.
  if (!geo.mx.empty() || !geo.safe.contains(m.x, m.y) || !geo.safe.contains(ex, ey)) {
    const Hit flat = next_hit(geo, nullptr, 0, m.flat(), t0, t0 + span, false);
    if (flat.dt < best.dt) best = flat_hit(flat);
  }

  // Hoops and boards, when the path's box comes near theirs.
  const float peak = g > 0 && m.vz > 0 && m.vz < g * span ? m.z + m.vz * m.vz / (2 * g) : std::max(m.z, height_at(span));
  const bool near = std::max(m.x, ex) >= s.ox0 && std::min(m.x, ex) <= s.ox1 && std::max(m.y, ey) >= s.oy0 &&
                    std::min(m.y, ey) <= s.oy1 && peak >= s.oz0 && std::min(m.z, height_at(span)) <= s.oz1;
  if (near) {
    for (size_t k = 0; k < s.board.size(); ++k) {
      // Beside a board's edge (within a ball's radius of its plane, over, under or past it) the
      // ball flies on: edges are not modelled, and a ball there must not hit the face from inside.
      const SegmentParams& b = s.board[k];
      if (std::fabs((m.x - b.ax) * b.nx + (m.y - b.ay) * b.ny) < r - kTolerance) continue;
      float nx, ny;
      const float dt = wall_time(s.board[k], r, m.x, m.y, m.ux, m.uy, span, nx, ny);
      if (!(dt < best.dt)) continue;
      const float z = height_at(dt);
      if (z >= s.bbottom[k] && z <= s.btop[k]) best = {dt, HitKind::Wall, s.bwall[k], Surface::Board, int(k), nx, ny, 0};
    }
    for (size_t k = 0; k < s.hx.size(); ++k) {
      const float dt = ring_time(s, k, m, g, std::min(span, best.dt));
      if (dt < best.dt) {
        const float px = m.x + m.ux * dt - s.hx[k], py = m.y + m.uy * dt - s.hy[k], pz = height_at(dt) - s.hz[k];
        const float rho = hypot2(px, py);
        float nx = rho > 0 ? px - s.hring[k] * px / rho : 0, ny = rho > 0 ? py - s.hring[k] * py / rho : 0, nz = pz;
        const float l = std::sqrt(nx * nx + ny * ny + nz * nz);
        if (l > 0) nx /= l, ny /= l, nz /= l;
        else nz = 1;
        best = {dt, HitKind::Wall, s.hwall[k], Surface::Rim, int(k), nx, ny, nz};
      }
      // Through the ring from above: a basket.
      if (g > 0) {
        const float down = descent_time(m.z, m.vz, g, s.hz[k]);
        if (down <= span && down < best.dt &&
            hypot2(m.x + m.ux * down - s.hx[k], m.y + m.uy * down - s.hy[k]) < s.hring[k])
          best = {down, HitKind::Goal, s.hgoal[k], Surface::Segment, int(k), 0, 0, -1};
      }
    }
  }

  if (!with_bodies) return best;
  const float bx0 = std::min(m.x, ex) - r, bx1 = std::max(m.x, ex) + r, by0 = std::min(m.y, ey) - r,
              by1 = std::max(m.y, ey) + r;
  for (int k = 0; k < n_bodies; ++k) {
    const BodyPath& b = bodies[k];
    // Cull by the box the body sweeps, grown by its radius, as the flat search does.
    const float cx0 = body_x(b, t0), cx1 = body_x(b, t0 + span), cy0 = body_y(b, t0), cy1 = body_y(b, t0 + span);
    if (std::max(cx0, cx1) + b.radius < bx0 || std::min(cx0, cx1) - b.radius > bx1 ||
        std::max(cy0, cy1) + b.radius < by0 || std::min(cy0, cy1) - b.radius > by1)
      continue;
    // The side, below the body's reach...
    const float side = body_time(b, r, m.x, m.y, m.ux, m.uy, t0, t0 + span);
    if (side < best.dt && height_at(side) <= b.top + r) {
      float hx = m.x + m.ux * side - body_x(b, t0 + side), hy = m.y + m.uy * side - body_y(b, t0 + side);
      float l = hypot2(hx, hy);
      if (l <= 0) hx = 1, hy = 0, l = 1;  // dead centre: any direction is as good
      best = {side, HitKind::Body, k, Surface::Side, -1, hx / l, hy / l, 0};
    }
    // ...or the top, coming down onto the hands.
    if (m.z > b.top + r) {
      const float top = descent_time(m.z, m.vz, g, b.top + r);
      if (top <= span && top < best.dt &&
          hypot2(m.x + m.ux * top - body_x(b, t0 + top), m.y + m.uy * top - body_y(b, t0 + top)) < b.radius + r)
        best = {top, HitKind::Body, k, Surface::Top, -1, 0, 0, 1};
    }
  }
  return best;
}

void resolve3(const Geometry& geo, const Sky& s, const BodyPath* bodies, const Hit3& hit, float t, Mover3& m) {
  auto reflect_flat = [&](float e) {
    const float un = m.ux * hit.nx + m.uy * hit.ny, vn = m.vx * hit.nx + m.vy * hit.ny;
    if (un < 0) m.ux -= (1 + e) * un * hit.nx, m.uy -= (1 + e) * un * hit.ny;
    if (vn < 0) m.vx -= (1 + e) * vn * hit.nx, m.vy -= (1 + e) * vn * hit.ny;
    m.x += kSkin * hit.nx, m.y += kSkin * hit.ny;
  };
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
    case Surface::Board: reflect_flat(s.be[size_t(hit.item)]); break;
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
    case Surface::Side: {
      Mover flat = m.flat();
      resolve(geo, bodies, hit.kind, hit.index, hit.nx, hit.ny, t, flat);
      m.x = flat.x, m.y = flat.y, m.ux = flat.ux, m.uy = flat.uy, m.vx = flat.vx, m.vy = flat.vy;
      break;
    }
  }
}

float impact_speed(const Hit3& hit, const Mover3& m) { return -(m.vx * hit.nx + m.vy * hit.ny + m.vz * hit.nz); }

Outcome trace_step3(const Geometry& geo, const Sky& sky, const BodyPath* bodies, int n_bodies, float dt, Mover3& m) {
  float t = 0;
  int first_body = -1, first_wall = -1;
  for (int contact = 0;; ++contact) {
    if (contact == kMaxContacts) break;
    const bool with_bodies = first_body < 0 && n_bodies > 0;
    const Hit3 hit = next_hit3(geo, sky, bodies, n_bodies, m, t, dt, with_bodies);
    if (hit.kind == HitKind::None) {
      m = advanced(sky, m, dt - t);
      break;
    }
    m = advanced(sky, m, hit.dt);
    t += hit.dt;
    if (hit.kind == HitKind::Goal || hit.kind == HitKind::Out)
      return first_body >= 0 ? Outcome{HitKind::Body, first_body} : Outcome{hit.kind, hit.index};
    // The ball's own velocity, not the Brownian drift: knowledge blurring into a wall makes no sound.
    if (hit.kind == HitKind::Wall && first_wall < 0 && impact_speed(hit, m) > geo.audible_bounce) first_wall = hit.index;
    resolve3(geo, sky, bodies, hit, t, m);
    if (hit.kind == HitKind::Body) first_body = hit.index;
  }
  if (first_body >= 0) return {HitKind::Body, first_body};
  if (first_wall >= 0) return {HitKind::Wall, first_wall};
  return {HitKind::None, -1};
}

}  // namespace quantum::detail

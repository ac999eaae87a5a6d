// The step loop. Hand-written because it is this project's reason to exist: a structure-of-arrays
// pass that the compiler vectorizes (counter-based noise, no branches, no per-particle objects)
// moves every particle and flags the few whose step comes near a wall, a goal line, a wormhole
// mouth or a body, and on a field with height near the floor, the ceiling, a hoop or a board;
// only those take the exact contact search (step_tracer.h), in batches. See docs/PERFORMANCE.md
// for what it reaches.
//
// Written once over the space (space.h): what only a field with height has (arcs, hoops, boards,
// rolling friction) is `if constexpr (Space::kHeight)`, compiled out of the flat step, so the
// flat loops are what they were on their own and a change to the shared passes is made once.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "quantum/backend.h"
#include "quantum/noise.h"
#include "space.h"
#include "step_tracer.h"

namespace quantum {
namespace {

// Large enough to amortize the per-block checks, small enough for the scratch to stay in L1.
constexpr int kBlock = 256;
// Every near-test of a field with height is grown by this, so rounding in a test never skips a
// contact the search finds.
constexpr float kMargin = 1e-3f;
constexpr int32_t kMaxKey = std::numeric_limits<int32_t>::max(), kMinKey = std::numeric_limits<int32_t>::min();

// Floats as integers of the same order: integer min and max reductions vectorize, float ones do
// not (their NaN rules keep the compiler from reordering them).
inline int32_t order_key(float f) {
  int32_t k;
  std::memcpy(&k, &f, sizeof k);
  return k ^ ((k >> 31) & 0x7FFFFFFF);
}
inline float from_order_key(int32_t k) {
  k ^= (k >> 31) & 0x7FFFFFFF;
  float f;
  std::memcpy(&f, &k, sizeof f);
  return f;
}

struct Box3 {
  float x0, y0, z0, x1, y1, z1;
  bool overlaps(const Box3& o) const {
    return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1 && z0 <= o.z1 && o.z0 <= z1;
  }
};

template <class Space>
class StepBackend final : public Backend {
  using Mover = typename Space::Mover;
  static constexpr bool kHeight = Space::kHeight;

 public:
  // A flat field's sky has no hoops and no boards: their lists stay empty.
  explicit StepBackend(const Field& field) : geometry_(field), sky_(field) {
    const detail::Sky& s = sky_;
    for (size_t k = 0; k < s.hx.size(); ++k) {
      const float reach = s.htube[k] + s.r + kMargin;
      const float outer = s.hring[k] + reach;
      rims_.push_back({s.hx[k], s.hy[k], s.hz[k], std::max(0.0f, s.hring[k] - reach), outer,
                       {s.hx[k] - outer, s.hy[k] - outer, s.hz[k] - reach, s.hx[k] + outer, s.hy[k] + outer,
                        s.hz[k] + reach}});
    }
    for (size_t k = 0; k < s.board.size(); ++k) {
      const detail::SegmentParams& b = s.board[k];
      const float near = s.r + kMargin, z0 = s.bbottom[k] - near, z1 = s.btop[k] + near;
      const float ex = b.ax + b.tx * b.len, ey = b.ay + b.ty * b.len;
      boards_.push_back({b.ax, b.ay, b.tx, b.ty, b.nx, b.ny, b.len, near,
                         {std::min(b.ax, ex) - near, std::min(b.ay, ey) - near, z0, std::max(b.ax, ex) + near,
                          std::max(b.ay, ey) + near, z1}});
    }
  }

  void advance(Cloud& cloud, const StepContext& ctx, std::vector<Contact>& contacts) override {
    const detail::Geometry& g = geometry_;
    const detail::Sky& s = sky_;
    const int nb = ctx.n_bodies;
    paths_.resize(nb);
    near_.resize(nb);
    for (int k = 0; k < nb; ++k) {
      const BodyMotion& b = ctx.bodies[k];
      const float ux = (b.to.x - b.from.x) / ctx.dt, uy = (b.to.y - b.from.y) / ctx.dt;
      paths_[k] = {b.from.x, b.from.y, ux, uy, ctx.dt, b.velocity.x, b.velocity.y, b.radius,
                   kHeight ? b.top : detail::kInf, b.passes};
      // Anything a particle can do within a step stays within its own travel of where it started:
      // beyond this distance of the body's sweep (plus that travel) no bounce can bring it in.
      const float sweep = std::hypot(b.to.x - b.from.x, b.to.y - b.from.y);
      const float reach = b.radius + g.r + kMargin;
      near_[k] = {detail::body_sweep(b, g.r), b.radius + g.r + 1e-3f + sweep,
                  {std::min(b.from.x, b.to.x) - reach, std::min(b.from.y, b.to.y) - reach, -detail::kInf,
                   std::max(b.from.x, b.to.x) + reach, std::max(b.from.y, b.to.y) + reach, b.top + g.r + kMargin}};
    }

    const int n = int(cloud.size());
    float* __restrict x = cloud.x.data();
    float* __restrict y = cloud.y.data();
    float* __restrict z = cloud.z.data();  // with height only: empty on a flat field
    float* __restrict vx = cloud.vx.data();
    float* __restrict vy = cloud.vy.data();
    float* __restrict vz = cloud.vz.data();
    // Everything the loops read is a local: the flags are bytes, which may alias any member, so
    // a member read inside a loop would be reloaded every particle and keep it from vectorizing.
    const float dt = ctx.dt, amp = ctx.noise_amplitude, gravity = s.g, ground = s.r + detail::kGroundSkin;
    const float floor_line = s.r, ceiling_line = s.ceiling, bulge = 0.125f * gravity * dt * dt;
    // A ball rolling on a floor with friction covers less than its speed times dt, and slows.
    const float rolled = s.rolled(dt), slowed = s.roll > 0 ? std::exp(-s.roll * dt) : 1.0f;
    const uint32_t key = ctx.noise_key;
    const detail::Box safe = g.safe;

    tracer_.begin(paths_.data(), nb, dt);
    auto finish = [&](uint32_t i, const Mover& m, detail::Outcome out) {
      x[i] = m.x, y[i] = m.y, vx[i] = m.vx, vy[i] = m.vy;
      if constexpr (kHeight) z[i] = m.z, vz[i] = m.vz;
      if (out.kind != detail::HitKind::None) contacts.push_back({i, detail::target_of(out)});
    };

    // Where each particle of the block started; with height, its start height and upward speed,
    // and the lowest and highest its step reaches.
    alignas(64) float ox[kBlock], oy[kBlock];
    [[maybe_unused]] alignas(64) float oz[kBlock], ovz[kBlock], lo[kBlock], hi[kBlock];
    // Non-zero: needs the contact search.
    alignas(64) uint8_t flag[kBlock];
    int16_t slow[kBlock];
    for (int base = 0; base < n; base += kBlock) {
      const int m = std::min(kBlock, n - base);
      if constexpr (!kHeight) {
        for (int j = 0; j < m; ++j) {
          const int i = base + j;
          float dx, dy;
          noise_offsets(noise_bits(uint32_t(i), key), amp, dx, dy);
          const float x0 = x[i], y0 = y[i];
          const float x1 = x0 + vx[i] * dt + dx, y1 = y0 + vy[i] * dt + dy;
          ox[j] = x0, oy[j] = y0;
          x[i] = x1, y[i] = y1;
          flag[j] = uint8_t((x0 < safe.x0) | (x0 > safe.x1) | (y0 < safe.y0) | (y0 > safe.y1) | (x1 < safe.x0) |
                            (x1 > safe.x1) | (y1 < safe.y0) | (y1 > safe.y1));
        }
        for (int k = 0; k < nb; ++k) {
          const detail::BodySweep c = near_[k].sweep;
          QUANTUM_INDEPENDENT_ITERATIONS
          for (int j = 0; j < m; ++j) {
            const int i = base + j;
            flag[j] |= uint8_t(detail::sweeps_touch(c, ox[j], oy[j], x[i], y[i]));
          }
        }
      } else {
        QUANTUM_INDEPENDENT_ITERATIONS
        for (int j = 0; j < m; ++j) {
          const int i = base + j;
          float dx, dy;
          noise_offsets(noise_bits(uint32_t(i), key), amp, dx, dy);
          const float x0 = x[i], y0 = y[i], z0 = z[i], w0 = vz[i];
          // A ball resting on the floor rolls: the floor holds gravity.
          const bool resting = (w0 == 0) & (z0 <= ground);
          const float fall = resting ? 0.0f : gravity, along = resting ? rolled : dt;
          const float x1 = x0 + vx[i] * along + dx, y1 = y0 + vy[i] * along + dy;
          const float z1 = z0 + w0 * dt - 0.5f * fall * dt * dt;
          ox[j] = x0, oy[j] = y0, oz[j] = z0, ovz[j] = w0;
          x[i] = x1, y[i] = y1, z[i] = z1, vz[i] = w0 - fall * dt;
          // A step's arc bulges above its chord by at most g dt^2 / 8.
          lo[j] = std::min(z0, z1), hi[j] = std::max(z0, z1) + bulge;
          flag[j] = uint8_t((x0 < safe.x0) | (x0 > safe.x1) | (y0 < safe.y0) | (y0 > safe.y1) | (x1 < safe.x0) |
                            (x1 > safe.x1) | (y1 < safe.y0) | (y1 > safe.y1) | ((z1 < floor_line) & !resting) |
                            (hi[j] > ceiling_line));
        }
        flag_near_heights(x, y, z, ox, oy, lo, hi, base, m, nb, flag);
      }
      // Wormhole mouths may lie inside the safe box: a particle whose step can reach one is searched.
      detail::flag_near_mouths(g, ox, oy, x, y, base, m, flag);
      // Friction slows the rolling balls; the tracer slows the ones it traces itself. Its own
      // pass, so a floor without friction costs the loop above no stores.
      if constexpr (kHeight) {
        if (slowed < 1) {
          for (int j = 0; j < m; ++j) {
            const int i = base + j;
            const float keep = ((ovz[j] == 0) & (oz[j] <= ground) & (flag[j] == 0)) ? slowed : 1.0f;
            vx[i] *= keep, vy[i] *= keep;
          }
        }
      }
      const int flagged = detail::collect_flagged(flag, m, slow);
      for (int q = 0; q < flagged; ++q) {
        const int j = slow[q], i = base + j;
        if constexpr (!kHeight) {
          const detail::Mover mv{ox[j], oy[j], (x[i] - ox[j]) / dt, (y[i] - oy[j]) / dt, vx[i], vy[i]};
          tracer_.add(uint32_t(i), mv, near_a_body(mv, dt, nb), finish);
        } else {
          const float along = ((ovz[j] == 0) & (oz[j] <= ground)) ? rolled : dt;
          const detail::Mover3 mv{ox[j], oy[j], oz[j], (x[i] - ox[j]) / along, (y[i] - oy[j]) / along, vx[i], vy[i], ovz[j]};
          tracer_.add(uint32_t(i), mv, true, finish);
        }
      }
    }
    tracer_.finish_all(finish);
  }

  void set_wormholes(const std::vector<Wormhole>& wormholes) override { geometry_.set_wormholes(wormholes); }

 private:
  struct Near {
    detail::BodySweep sweep;
    float around;  // flat: a particle starting further than this plus twice its travel cannot touch it
    Box3 box;      // with height: where a particle may touch the body (above its top, all step, it cannot)
  };
  struct Rim {
    float x, y, z;       // the ring's centre
    float inner, outer;  // distances from the hoop's axis within reach of the rod
    Box3 box;            // around the rod, within reach (its heights: level with the rod)
  };
  struct Pane {
    float ax, ay, tx, ty, nx, ny, len;  // the board's floor line
    float near;                          // within this of the plane a particle may touch it
    Box3 box;                            // around the board, within reach (its heights: level with it)
  };

  // Flags the particles of a block whose step comes near a hoop, a board or a body, below its
  // reach. The box around every path of the block comes first: a hoop, a board or a body outside
  // it is near none of them, and its pass is skipped (a block in flight far from the basket, over
  // everyone's reach, takes none).
  [[gnu::always_inline]] void flag_near_heights(const float* __restrict x, const float* __restrict y,
                                                const float* __restrict z, const float* __restrict ox,
                                                const float* __restrict oy, const float* __restrict lo,
                                                const float* __restrict hi, int base, int m, int nb,
                                                uint8_t* __restrict flag) const {
    int32_t kx0 = kMaxKey, ky0 = kMaxKey, kz0 = kMaxKey, kx1 = kMinKey, ky1 = kMinKey, kz1 = kMinKey;
    for (int j = 0; j < m; ++j) {
      const int i = base + j;
      kx0 = std::min(kx0, order_key(std::min(ox[j], x[i]))), kx1 = std::max(kx1, order_key(std::max(ox[j], x[i])));
      ky0 = std::min(ky0, order_key(std::min(oy[j], y[i]))), ky1 = std::max(ky1, order_key(std::max(oy[j], y[i])));
      kz0 = std::min(kz0, order_key(lo[j])), kz1 = std::max(kz1, order_key(hi[j]));
    }
    const Box3 block{from_order_key(kx0), from_order_key(ky0), from_order_key(kz0),
                     from_order_key(kx1), from_order_key(ky1), from_order_key(kz1)};
    // Hoops: a particle level with the rod (within reach, over the step) whose path passes
    // within reach of the ring line horizontally, or one coming down through the ring. The
    // path is a straight line horizontally, so its distance from the hoop's axis stays within
    // its travel of where it started.
    for (const Rim& c : rims_) {
      if (!block.overlaps(c.box)) continue;
      QUANTUM_INDEPENDENT_ITERATIONS
      for (int j = 0; j < m; ++j) {
        const int i = base + j;
        const float travel = std::fabs(x[i] - ox[j]) + std::fabs(y[i] - oy[j]);
        const float qx = ox[j] - c.x, qy = oy[j] - c.y, d = std::sqrt(qx * qx + qy * qy);
        const bool level = (hi[j] >= c.box.z0) & (lo[j] <= c.box.z1);
        const bool through = (hi[j] >= c.z) & (z[i] < c.z);
        flag[j] |= uint8_t(level & (d - travel < c.outer) & ((d + travel > c.inner) | through));
      }
    }
    // Boards: a particle whose path comes within a ball's radius of the board's plane (or
    // crosses it) beside the board, level with it.
    for (const Pane& c : boards_) {
      if (!block.overlaps(c.box)) continue;
      QUANTUM_INDEPENDENT_ITERATIONS
      for (int j = 0; j < m; ++j) {
        const int i = base + j;
        const float px0 = ox[j] - c.ax, py0 = oy[j] - c.ay, px1 = x[i] - c.ax, py1 = y[i] - c.ay;
        const float d0 = px0 * c.nx + py0 * c.ny, d1 = px1 * c.nx + py1 * c.ny;
        const float a0 = px0 * c.tx + py0 * c.ty, a1 = px1 * c.tx + py1 * c.ty;
        const bool close = (std::min(std::fabs(d0), std::fabs(d1)) < c.near) | (d0 * d1 <= 0);
        const bool beside = (std::max(a0, a1) > -c.near) & (std::min(a0, a1) < c.len + c.near);
        flag[j] |= uint8_t(close & beside & (hi[j] >= c.box.z0) & (lo[j] <= c.box.z1));
      }
    }
    // Bodies: a particle whose path comes within reach of a body's, below its reach.
    for (int k = 0; k < nb; ++k) {
      const Near c = near_[k];
      if (!block.overlaps(c.box)) continue;
      QUANTUM_INDEPENDENT_ITERATIONS
      for (int j = 0; j < m; ++j) {
        const int i = base + j;
        flag[j] |= uint8_t(detail::sweeps_touch(c.sweep, ox[j], oy[j], x[i], y[i]) & (lo[j] < c.box.z1));
      }
    }
  }

  // Whether a flagged particle's bounces could bring it to a body this step, on a flat field: a
  // bounce keeps it within its own travel of where it started, so beyond the body's sweep plus
  // that it cannot. (With height every flagged particle is searched with the bodies.)
  bool near_a_body(const detail::Mover& m, float dt, int nb) const {
    const float travel = 2 * (std::fabs(m.ux) + std::fabs(m.uy)) * dt;
    for (int k = 0; k < nb; ++k) {
      const Near& c = near_[k];
      const float qx = m.x - c.sweep.x, qy = m.y - c.sweep.y, around = c.around + travel;
      if (qx * qx + qy * qy < around * around) return true;
    }
    return false;
  }

  Space space() const {
    if constexpr (kHeight) return Space{geometry_, sky_};
    else return Space{geometry_};
  }

  detail::Geometry geometry_;
  detail::Sky sky_;
  detail::StepTracer<Space> tracer_{space()};
  std::vector<Rim> rims_;
  std::vector<Pane> boards_;
  std::vector<detail::BodyPath> paths_;
  std::vector<Near> near_;
};

}  // namespace

std::unique_ptr<Backend> make_fast_backend(const Field& field) {
  return std::make_unique<StepBackend<detail::Flat>>(field);
}
std::unique_ptr<Backend> make_height_backend(const Field& field) {
  return std::make_unique<StepBackend<detail::Tall>>(field);
}

}  // namespace quantum

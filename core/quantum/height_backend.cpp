// The step on a field with height. Hand-written for the same reason as the flat one
// (fast_backend.cpp): a structure-of-arrays pass the compiler vectorizes moves every particle
// along its arc and flags the few whose step comes near the floor, the ceiling, a hoop, a board,
// a wall or a body; only those take the exact contact search (height.h), one at a time.
#include <algorithm>
#include <cmath>

#include "height.h"
#include "quantum/backend.h"
#include "quantum/noise.h"

namespace quantum {
namespace {

constexpr int kBlock = 256;  // as the flat step: amortizes the per-block checks, scratch stays in L1

class HeightBackend final : public Backend {
 public:
  explicit HeightBackend(const Field& field) : geometry_(field), sky_(field) {}

  void advance(Cloud& cloud, const StepContext& ctx, std::vector<Contact>& contacts) override {
    const detail::Geometry& g = geometry_;
    const detail::Sky& s = sky_;
    const int nb = ctx.n_bodies;
    paths_.resize(nb);
    near_.resize(nb);
    for (int k = 0; k < nb; ++k) {
      const BodyMotion& b = ctx.bodies[k];
      const float ux = (b.to.x - b.from.x) / ctx.dt, uy = (b.to.y - b.from.y) / ctx.dt;
      paths_[k] = {b.from.x, b.from.y, ux, uy, ctx.dt, b.velocity.x, b.velocity.y, b.radius, b.top};
      const float sweep = std::hypot(b.to.x - b.from.x, b.to.y - b.from.y);
      near_[k] = {b.from.x + 0.5f * (b.to.x - b.from.x), b.from.y + 0.5f * (b.to.y - b.from.y),
                  b.radius + g.r + 0.5f * sweep + 1e-3f, b.top + g.r + 1e-3f};
    }

    const int n = int(cloud.size());
    float* __restrict x = cloud.x.data();
    float* __restrict y = cloud.y.data();
    float* __restrict z = cloud.z.data();
    float* __restrict vx = cloud.vx.data();
    float* __restrict vy = cloud.vy.data();
    float* __restrict vz = cloud.vz.data();
    const float dt = ctx.dt, amp = ctx.noise_amplitude, gravity = s.g, ground = s.r + detail::kGroundSkin;
    const float floor_line = s.r, ceiling_line = s.ceiling;
    const uint32_t key = ctx.noise_key;
    const detail::Box safe = g.safe;

    alignas(64) float ox[kBlock], oy[kBlock], oz[kBlock], ovz[kBlock];
    alignas(64) uint8_t flag[kBlock];
    int16_t slow[kBlock];
    for (int base = 0; base < n; base += kBlock) {
      const int m = std::min(kBlock, n - base);
      for (int j = 0; j < m; ++j) {
        const int i = base + j;
        float dx, dy;
        noise_offsets(noise_bits(uint32_t(i), key), amp, dx, dy);
        const float x0 = x[i], y0 = y[i], z0 = z[i], w0 = vz[i];
        // A ball resting on the floor rolls: the floor holds gravity.
        const float fall = (w0 == 0) & (z0 <= ground) ? 0.0f : gravity;
        const float x1 = x0 + vx[i] * dt + dx, y1 = y0 + vy[i] * dt + dy;
        const float z1 = z0 + w0 * dt - 0.5f * fall * dt * dt;
        ox[j] = x0, oy[j] = y0, oz[j] = z0, ovz[j] = w0;
        x[i] = x1, y[i] = y1, z[i] = z1, vz[i] = w0 - fall * dt;
        // A step's arc bulges above its chord by at most g dt^2 / 8: well under the margins below.
        const float lo = std::min(z0, z1), hi = std::max(z0, z1) + 0.125f * gravity * dt * dt;
        const float bx0 = std::min(x0, x1), bx1 = std::max(x0, x1), by0 = std::min(y0, y1), by1 = std::max(y0, y1);
        flag[j] = uint8_t((x0 < safe.x0) | (x0 > safe.x1) | (y0 < safe.y0) | (y0 > safe.y1) | (x1 < safe.x0) |
                          (x1 > safe.x1) | (y1 < safe.y0) | (y1 > safe.y1) | ((z1 < floor_line) & (fall > 0)) |
                          (hi > ceiling_line) |
                          ((bx1 >= s.ox0) & (bx0 <= s.ox1) & (by1 >= s.oy0) & (by0 <= s.oy1) & (hi >= s.oz0) &
                           (lo <= s.oz1)));
      }
      // Bodies: a particle whose step passes within reach of a body's middle position (grown by
      // half its sweep), below its reach, is searched. Conservative like the flat step's test.
      for (int k = 0; k < nb; ++k) {
        const Near c = near_[k];
#pragma GCC ivdep
        for (int j = 0; j < m; ++j) {
          const int i = base + j;
          const float travel = std::fabs(x[i] - ox[j]) + std::fabs(y[i] - oy[j]);
          const float qx = ox[j] - c.x, qy = oy[j] - c.y, around = c.reach + travel;
          flag[j] |= uint8_t((qx * qx + qy * qy < around * around) & (std::min(oz[j], z[i]) < c.top));
        }
      }
      detail::flag_near_mouths(g, ox, oy, x, y, base, m, flag);
      const int flagged = detail::collect_flagged(flag, m, slow);
      for (int q = 0; q < flagged; ++q) {
        const int j = slow[q], i = base + j;
        detail::Mover3 mv{ox[j], oy[j], oz[j], (x[i] - ox[j]) / dt, (y[i] - oy[j]) / dt, vx[i], vy[i], ovz[j]};
        const detail::Outcome out = detail::trace_step3(g, s, paths_.data(), nb, dt, mv);
        x[i] = mv.x, y[i] = mv.y, z[i] = mv.z, vx[i] = mv.vx, vy[i] = mv.vy, vz[i] = mv.vz;
        if (out.kind != detail::HitKind::None) contacts.push_back({uint32_t(i), detail::target_of(out)});
      }
    }
  }

  void set_wormholes(const std::vector<Wormhole>& wormholes) override { geometry_.set_wormholes(wormholes); }

 private:
  struct Near {
    float x, y;   // the body halfway through the step
    float reach;  // a particle closer than this plus its travel may touch it
    float top;    // a particle above this all step cannot
  };


  detail::Geometry geometry_;
  detail::Sky sky_;
  std::vector<detail::BodyPath> paths_;
  std::vector<Near> near_;
};

}  // namespace

std::unique_ptr<Backend> make_height_backend(const Field& field) { return std::make_unique<HeightBackend>(field); }

}  // namespace quantum

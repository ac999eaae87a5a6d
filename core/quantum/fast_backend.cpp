// The step loop. Hand-written because it is this project's reason to exist: a structure-of-arrays
// pass that the compiler vectorizes (counter-based noise, no branches, no per-particle objects),
// followed by an exact swept contact search only for the few particles near a wall, a goal line
// or a body. See docs/PERFORMANCE.md for what it reaches.
#include <algorithm>
#include <cmath>

#include "quantum/backend.h"
#include "quantum/contact.h"
#include "quantum/noise.h"

namespace quantum {
namespace {

// Large enough to amortize the per-block checks, small enough for the scratch to stay in L1.
constexpr int kBlock = 256;

class FastBackend final : public Backend {
 public:
  explicit FastBackend(const Field& field) : geometry_(field) {}

  void advance(Cloud& cloud, const StepContext& ctx, std::vector<Contact>& contacts) override {
    const detail::Geometry& g = geometry_;
    const int nb = ctx.n_bodies;
    paths_.resize(nb);
    near_.resize(nb);
    for (int k = 0; k < nb; ++k) {
      const BodyMotion& b = ctx.bodies[k];
      const float ux = (b.to.x - b.from.x) / ctx.dt, uy = (b.to.y - b.from.y) / ctx.dt;
      paths_[k] = {b.from.x, b.from.y, ux, uy, ctx.dt, b.velocity.x, b.velocity.y, b.radius};
      // A particle ending within this reach of the sweep's midpoint, plus its own travel, may
      // have touched the body.
      const float half_sweep = 0.5f * std::hypot(b.to.x - b.from.x, b.to.y - b.from.y);
      near_[k] = {0.5f * (b.from.x + b.to.x), 0.5f * (b.from.y + b.to.y), b.radius + g.r + half_sweep + 1e-3f};
    }

    const int n = int(cloud.size());
    float* __restrict x = cloud.x.data();
    float* __restrict y = cloud.y.data();
    float* __restrict vx = cloud.vx.data();
    float* __restrict vy = cloud.vy.data();
    const float dt = ctx.dt, amp = ctx.noise_amplitude;
    const uint32_t key = ctx.noise_key;
    const detail::Box s = g.safe;

    alignas(64) float ox[kBlock], oy[kBlock];
    alignas(64) int32_t flag[kBlock];
    for (int base = 0; base < n; base += kBlock) {
      const int m = std::min(kBlock, n - base);
      for (int j = 0; j < m; ++j) {
        const int i = base + j;
        float dx, dy;
        noise_offsets(noise_bits(uint32_t(i), key), amp, dx, dy);
        const float x0 = x[i], y0 = y[i];
        const float x1 = x0 + vx[i] * dt + dx, y1 = y0 + vy[i] * dt + dy;
        ox[j] = x0, oy[j] = y0;
        x[i] = x1, y[i] = y1;
        flag[j] = (x0 < s.x0) | (x0 > s.x1) | (y0 < s.y0) | (y0 > s.y1) | (x1 < s.x0) | (x1 > s.x1) |
                  (y1 < s.y0) | (y1 > s.y1);
      }
      for (int k = 0; k < nb; ++k) {
        const Near c = near_[k];
        for (int j = 0; j < m; ++j) {
          const int i = base + j;
          const float travel = std::fabs(x[i] - ox[j]) + std::fabs(y[i] - oy[j]);
          const float qx = x[i] - c.x, qy = y[i] - c.y, reach = c.reach + travel;
          flag[j] |= int32_t(qx * qx + qy * qy < reach * reach);
        }
      }
      int32_t any = 0;
      for (int j = 0; j < m; ++j) any |= flag[j];
      if (!any) continue;
      for (int j = 0; j < m; ++j) {
        if (!flag[j]) continue;
        const int i = base + j;
        detail::Mover mv{ox[j], oy[j], (x[i] - ox[j]) / dt, (y[i] - oy[j]) / dt, vx[i], vy[i]};
        const detail::Outcome out = detail::trace_step(g, paths_.data(), nb, mv, dt);
        x[i] = mv.x, y[i] = mv.y, vx[i] = mv.vx, vy[i] = mv.vy;
        if (out.kind != detail::HitKind::None) contacts.push_back({uint32_t(i), target_of(out, nb)});
      }
    }
  }

 private:
  struct Near {
    float x, y, reach;
  };

  int32_t target_of(detail::Outcome out, int nb) const {
    switch (out.kind) {
      case detail::HitKind::Body: return out.index;
      case detail::HitKind::Goal: return nb + out.index;
      case detail::HitKind::Out: return nb + int32_t(geometry_.gax.size());
      default: return kCrushed;
    }
  }

  detail::Geometry geometry_;
  std::vector<detail::BodyPath> paths_;
  std::vector<Near> near_;
};

}  // namespace

std::unique_ptr<Backend> make_fast_backend(const Field& field) { return std::make_unique<FastBackend>(field); }

}  // namespace quantum

// The step loop. Hand-written because it is this project's reason to exist: a structure-of-arrays
// pass that the compiler vectorizes (counter-based noise, no branches, no per-particle objects),
// followed by an exact swept contact search only for the few particles near a wall, a goal line
// or a body. See docs/PERFORMANCE.md for what it reaches.
#include <algorithm>
#include <cmath>

#include "quantum/backend.h"
#include "quantum/contact.h"
#include "quantum/noise.h"
#include "step_tracer.h"

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
      paths_[k] = {b.from.x, b.from.y, ux, uy, ctx.dt, b.velocity.x, b.velocity.y, b.radius, detail::kInf, b.passes};
      // Anything a particle can do within a step stays within its own travel of where it started:
      // beyond this distance of the body's sweep (plus that travel) no bounce can bring it in.
      const float sweep = std::hypot(b.to.x - b.from.x, b.to.y - b.from.y);
      near_[k] = {detail::body_sweep(b, g.r), b.radius + g.r + 1e-3f + sweep};
    }

    const int n = int(cloud.size());
    float* __restrict x = cloud.x.data();
    float* __restrict y = cloud.y.data();
    float* __restrict vx = cloud.vx.data();
    float* __restrict vy = cloud.vy.data();
    const float dt = ctx.dt, amp = ctx.noise_amplitude;
    const uint32_t key = ctx.noise_key;
    const detail::Box s = g.safe;

    tracer_.begin(paths_.data(), nb, dt);
    auto finish = [&](uint32_t i, const detail::Mover& m, detail::Outcome out) {
      x[i] = m.x, y[i] = m.y, vx[i] = m.vx, vy[i] = m.vy;
      if (out.kind != detail::HitKind::None) contacts.push_back({i, detail::target_of(out)});
    };

    alignas(64) float ox[kBlock], oy[kBlock];
    // Non-zero: needs the contact search.
    alignas(64) uint8_t flag[kBlock];
    int16_t slow[kBlock];
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
        flag[j] = uint8_t((x0 < s.x0) | (x0 > s.x1) | (y0 < s.y0) | (y0 > s.y1) | (x1 < s.x0) | (x1 > s.x1) |
                          (y1 < s.y0) | (y1 > s.y1));
      }
      for (int k = 0; k < nb; ++k) {
        const detail::BodySweep c = near_[k].sweep;
        QUANTUM_INDEPENDENT_ITERATIONS
        for (int j = 0; j < m; ++j) {
          const int i = base + j;
          flag[j] |= uint8_t(detail::sweeps_touch(c, ox[j], oy[j], x[i], y[i]));
        }
      }
      // Wormhole mouths may lie inside the safe box: a particle whose step can reach one is searched.
      detail::flag_near_mouths(g, ox, oy, x, y, base, m, flag);
      const int flagged = detail::collect_flagged(flag, m, slow);
      for (int q = 0; q < flagged; ++q) {
        const int j = slow[q], i = base + j;
        const detail::Mover mv{ox[j], oy[j], (x[i] - ox[j]) / dt, (y[i] - oy[j]) / dt, vx[i], vy[i]};
        tracer_.add(uint32_t(i), mv, near_a_body(mv, dt, nb), finish);
      }
    }
    tracer_.finish_all(finish);
  }

  void set_wormholes(const std::vector<Wormhole>& wormholes) override { geometry_.set_wormholes(wormholes); }

 private:
  struct Near {
    detail::BodySweep sweep;
    float around;  // a particle starting further than this plus twice its travel cannot touch it
  };

  // Whether a flagged particle's bounces could bring it to a body this step: a bounce keeps it
  // within its own travel of where it started, so beyond the body's sweep plus that it cannot.
  bool near_a_body(const detail::Mover& m, float dt, int nb) const {
    const float travel = 2 * (std::fabs(m.ux) + std::fabs(m.uy)) * dt;
    for (int k = 0; k < nb; ++k) {
      const Near& c = near_[k];
      const float qx = m.x - c.sweep.x, qy = m.y - c.sweep.y, around = c.around + travel;
      if (qx * qx + qy * qy < around * around) return true;
    }
    return false;
  }


  detail::Geometry geometry_;
  detail::StepTracer<detail::Flat> tracer_{detail::Flat{geometry_}};
  std::vector<detail::BodyPath> paths_;
  std::vector<Near> near_;
};

}  // namespace

std::unique_ptr<Backend> make_fast_backend(const Field& field) { return std::make_unique<FastBackend>(field); }

}  // namespace quantum

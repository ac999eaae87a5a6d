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
  explicit FastBackend(const Field& field) : geometry_(field) { walls_.resize(kBatch); }

  void advance(Cloud& cloud, const StepContext& ctx, std::vector<Contact>& contacts) override {
    const detail::Geometry& g = geometry_;
    const int nb = ctx.n_bodies;
    paths_.resize(nb);
    near_.resize(nb);
    for (int k = 0; k < nb; ++k) {
      const BodyMotion& b = ctx.bodies[k];
      const float ux = (b.to.x - b.from.x) / ctx.dt, uy = (b.to.y - b.from.y) / ctx.dt;
      paths_[k] = {b.from.x, b.from.y, ux, uy, ctx.dt, b.velocity.x, b.velocity.y, b.radius};
      const float reach = b.radius + g.r + 1e-3f, touch = b.radius + g.r - detail::kTolerance;
      // Anything a particle can do within a step stays within its own travel of where it started:
      // beyond this distance of the body's sweep (plus that travel) no bounce can bring it in.
      const float sweep = std::hypot(b.to.x - b.from.x, b.to.y - b.from.y);
      near_[k] = {b.from.x, b.from.y, b.to.x - b.from.x, b.to.y - b.from.y, reach * reach, touch * touch,
                  reach + sweep};
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
        flag[j] = (x0 < s.x0) | (x0 > s.x1) | (y0 < s.y0) | (y0 > s.y1) | (x1 < s.x0) | (x1 > s.x1) |
                  (y1 < s.y0) | (y1 > s.y1);
      }
      // Closest approach of the particle to the body over the step, both moving linearly: exact
      // up to a millimetre, so only particles that really touch a body take the slow path. A
      // separating pair (a shot just leaving the mallet) can only touch if it overlaps already.
      for (int k = 0; k < nb; ++k) {
        const Near c = near_[k];
        for (int j = 0; j < m; ++j) {
          const int i = base + j;
          const float qx = ox[j] - c.x, qy = oy[j] - c.y;
          const float wx = (x[i] - ox[j]) - c.dx, wy = (y[i] - oy[j]) - c.dy;
          const float ww = wx * wx + wy * wy;
          const float qw = qx * wx + qy * wy;
          const float t = std::clamp(-qw / std::max(ww, 1e-20f), 0.0f, 1.0f);
          const float cx = qx + t * wx, cy = qy + t * wy;
          flag[j] |= int32_t(cx * cx + cy * cy < (qw >= 0 ? c.touch2 : c.reach2));
          // Bit 1: near enough that a wall bounce might still send it into the body.
          const float around = c.around + 2 * (std::fabs(x[i] - ox[j]) + std::fabs(y[i] - oy[j]));
          flag[j] |= int32_t(qx * qx + qy * qy < around * around) << 1;
        }
      }
      // Branch-free compaction: a data-dependent branch per particle mispredicts constantly.
      int flagged = 0;
      for (int j = 0; j < m; ++j) {
        slow[flagged] = int16_t(j);
        flagged += (flag[j] & 1) != 0;
      }
      for (int q = 0; q < flagged; ++q) {
        const int j = slow[q], i = base + j;
        detail::Mover mv{ox[j], oy[j], (x[i] - ox[j]) / dt, (y[i] - oy[j]) / dt, vx[i], vy[i]};
        if (!(flag[j] & 2)) {
          // Near walls only: traced later with the others, vectorized across particles.
          walls_.x[pending_] = mv.x, walls_.y[pending_] = mv.y, walls_.ux[pending_] = mv.ux, walls_.uy[pending_] = mv.uy;
          walls_.vx[pending_] = mv.vx, walls_.vy[pending_] = mv.vy, walls_.t[pending_] = 0;
          pending_id_[pending_] = uint32_t(i);
          if (++pending_ == kBatch) trace_walls(cloud, dt, nb, contacts);
          continue;
        }
        const detail::Outcome out = detail::trace_step(g, paths_.data(), nb, mv, dt);
        x[i] = mv.x, y[i] = mv.y, vx[i] = mv.vx, vy[i] = mv.vy;
        if (out.kind != detail::HitKind::None) contacts.push_back({uint32_t(i), target_of(out, nb)});
      }
    }
    trace_walls(cloud, dt, nb, contacts);
  }

 private:
  struct Near {
    float x, y;    // body at the start of the step
    float dx, dy;  // its displacement over the step
    float reach2;  // squared contact distance, plus a millimetre
    float touch2;  // squared distance below which a particle overlaps the body
    float around;  // a particle starting further than this plus twice its travel cannot touch it
  };

  // Traces the pending wall-only particles through the rest of the step, all at once: the same
  // contacts trace_step finds for them, one vectorized search per round of bounces.
  void trace_walls(Cloud& cloud, float dt, int nb, std::vector<Contact>& contacts) {
    const detail::Geometry& g = geometry_;
    size_t n = pending_;
    pending_ = 0;
    std::fill(bounces_.begin(), bounces_.begin() + n, 0);
    while (n > 0) {
      detail::batch_next_hits(g, nullptr, 0, walls_, n, dt);
      size_t moving = 0;
      for (size_t j = 0; j < n; ++j) {
        const detail::HitKind kind = detail::code_kind(walls_.code[j]);
        const float t = walls_.t[j], until = kind == detail::HitKind::None ? dt - t : walls_.when[j];
        detail::Mover m{walls_.x[j] + walls_.ux[j] * until, walls_.y[j] + walls_.uy[j] * until, walls_.ux[j],
                        walls_.uy[j], walls_.vx[j], walls_.vy[j]};
        const uint32_t i = pending_id_[j];
        bool done = kind != detail::HitKind::Wall;
        if (kind == detail::HitKind::Goal || kind == detail::HitKind::Out)
          contacts.push_back({i, target_of({kind, detail::code_index(walls_.code[j])}, nb)});
        if (kind == detail::HitKind::Wall) {
          detail::resolve(g, nullptr, kind, 0, walls_.hnx[j], walls_.hny[j], t + until, m);
          if (++bounces_[j] == kMaxBounces) {  // rattling in a corner: stop it where it is
            const detail::Outcome out = detail::settle(g, nullptr, 0, dt, m, false);
            if (out.kind != detail::HitKind::None) contacts.push_back({i, target_of(out, nb)});
            done = true;
          }
        }
        if (done) {
          cloud.x[i] = m.x, cloud.y[i] = m.y, cloud.vx[i] = m.vx, cloud.vy[i] = m.vy;
          continue;
        }
        walls_.x[moving] = m.x, walls_.y[moving] = m.y, walls_.ux[moving] = m.ux, walls_.uy[moving] = m.uy;
        walls_.vx[moving] = m.vx, walls_.vy[moving] = m.vy, walls_.t[moving] = t + until;
        pending_id_[moving] = i, bounces_[moving] = bounces_[j];
        ++moving;
      }
      n = moving;
    }
  }

  int32_t target_of(detail::Outcome out, int nb) const {
    switch (out.kind) {
      case detail::HitKind::Body: return out.index;
      case detail::HitKind::Goal: return nb + out.index;
      case detail::HitKind::Out: return nb + int32_t(geometry_.gax.size());
      default: return kCrushed;
    }
  }

  static constexpr size_t kBatch = 512;
  static constexpr int kMaxBounces = 8;  // as trace_step

  detail::Geometry geometry_;
  std::vector<detail::BodyPath> paths_;
  detail::MoverBatch walls_;
  std::vector<uint32_t> pending_id_ = std::vector<uint32_t>(kBatch);
  std::vector<uint8_t> bounces_ = std::vector<uint8_t>(kBatch);
  size_t pending_ = 0;
  std::vector<Near> near_;
};

}  // namespace

std::unique_ptr<Backend> make_fast_backend(const Field& field) { return std::make_unique<FastBackend>(field); }

}  // namespace quantum

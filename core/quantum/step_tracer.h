// Traces particles through one step, contact by contact, many at a time: the vectorized search
// runs over a queue of particles per round of bounces. Internal to core/quantum.
//
// A particle near a body is searched with the bodies until it meets one; from then on it belongs
// to that body's purgatory and finishes the step against walls only, so its state stays a valid
// ball state. Every particle ends with an Outcome: None, or the first body, goal or out it met,
// Crushed when no valid place is left for it, or else the first wall it bounced off hard enough
// to be heard (Geometry::audible_bounce), so the bounce can be decided and announced.
#pragma once

#include <cstdint>
#include <vector>

#include "quantum/contact.h"

namespace quantum::detail {

class StepTracer {
 public:
  explicit StepTracer(const Geometry& g) : g_(g) {
    for (Queue* q : {&with_bodies_, &walls_only_}) {
      q->batch.resize(kBatch);
      q->id.resize(kBatch);
      q->contacts.resize(kBatch);
      q->first_body.resize(kBatch);
      q->first_wall.resize(kBatch);
    }
  }

  // Starts a step of length dt; bodies move as `bodies` say (none for a walls-only catch-up).
  void begin(const BodyPath* bodies, int n_bodies, float dt) {
    bodies_ = bodies, n_bodies_ = n_bodies, dt_ = dt;
  }

  // Queues particle `id`, at m at the start of the step. finish(id, const Mover&, Outcome) is
  // called for every particle once its step is traced, in no particular order.
  template <class Finish>
  void add(uint32_t id, const Mover& m, bool near_bodies, Finish&& finish) {
    Queue& q = near_bodies && n_bodies_ > 0 ? with_bodies_ : walls_only_;
    while (q.n == kBatch) trace(q, finish);  // a round may keep every particle; each ends within kMaxContacts
    push(q, id, m, 0, 0, -1, -1);
  }

  // Traces everything still queued.
  template <class Finish>
  void finish_all(Finish&& finish) {
    while (with_bodies_.n > 0 || walls_only_.n > 0) trace(with_bodies_.n > 0 ? with_bodies_ : walls_only_, finish);
  }

 private:
  static constexpr size_t kBatch = 512;
  static constexpr int kMaxContacts = 8;  // a particle rattling in a corner stops where it is

  struct Queue {
    MoverBatch batch;
    std::vector<uint32_t> id;
    std::vector<uint8_t> contacts;
    std::vector<int16_t> first_body;  // body met earlier this step, -1 for none
    std::vector<int16_t> first_wall;  // wall bounced off audibly earlier this step, -1 for none
    size_t n = 0;
  };

  void push(Queue& q, uint32_t id, const Mover& m, float t, uint8_t contacts, int16_t first_body, int16_t first_wall) {
    MoverBatch& b = q.batch;
    b.x[q.n] = m.x, b.y[q.n] = m.y, b.ux[q.n] = m.ux, b.uy[q.n] = m.uy, b.vx[q.n] = m.vx, b.vy[q.n] = m.vy;
    b.t[q.n] = t;
    q.id[q.n] = id, q.contacts[q.n] = contacts, q.first_body[q.n] = first_body, q.first_wall[q.n] = first_wall;
    ++q.n;
  }

  // One round for every particle of q: find its next contact, move it there, resolve it.
  template <class Finish>
  void trace(Queue& q, Finish& finish) {
    const bool bodies_on = &q == &with_bodies_;
    MoverBatch& b = q.batch;
    const size_t n = q.n;
    batch_next_hits(g_, bodies_, bodies_on ? n_bodies_ : 0, b, n, dt_);
    size_t kept = 0;
    for (size_t j = 0; j < n; ++j) {
      const HitKind kind = code_kind(b.code[j]);
      const float dt = kind == HitKind::None ? dt_ - b.t[j] : b.when[j], t = b.t[j] + dt;
      Mover m{b.x[j] + b.ux[j] * dt, b.y[j] + b.uy[j] * dt, b.ux[j], b.uy[j], b.vx[j], b.vy[j]};
      const uint32_t id = q.id[j];
      int16_t first_body = q.first_body[j], first_wall = q.first_wall[j];
      if (kind == HitKind::None) {
        done(id, m, first_body, first_wall, false, finish);
        continue;
      }
      if (kind == HitKind::Goal || kind == HitKind::Out) {
        finish(id, m, first_body >= 0 ? Outcome{HitKind::Body, first_body} : Outcome{kind, code_index(b.code[j])});
        continue;
      }
      const int index = code_index(b.code[j]);
      // The ball's own velocity, not the Brownian drift: knowledge blurring into a wall makes no sound.
      const bool audible = kind == HitKind::Wall && -(m.vx * b.hnx[j] + m.vy * b.hny[j]) > g_.audible_bounce;
      if (audible && first_wall < 0) first_wall = int16_t(index);
      resolve(g_, bodies_, kind, index, b.hnx[j], b.hny[j], t, m);
      const uint8_t contacts = uint8_t(q.contacts[j] + 1);
      if (kind == HitKind::Body) first_body = int16_t(index);
      if (contacts == kMaxContacts) {
        done(id, m, first_body, first_wall, true, finish);
        continue;
      }
      if (kind == HitKind::Body) {
        // The rest of the step against walls only. The queue being traced is never the one
        // pushed to here, so flushing that one first is safe.
        while (walls_only_.n == kBatch) trace(walls_only_, finish);
        push(walls_only_, id, m, t, contacts, first_body, first_wall);
        continue;
      }
      // Still flying: compact into the front of the same queue for the next round.
      b.x[kept] = m.x, b.y[kept] = m.y, b.ux[kept] = m.ux, b.uy[kept] = m.uy, b.vx[kept] = m.vx, b.vy[kept] = m.vy;
      b.t[kept] = t;
      q.id[kept] = id, q.contacts[kept] = contacts, q.first_body[kept] = first_body, q.first_wall[kept] = first_wall;
      ++kept;
    }
    q.n = kept;
  }

  // A particle at the end of its step. Exact contacts keep a ball out of walls; only a body can
  // push one into a wall (a squeeze), and a rattling one may have been stopped against one.
  template <class Finish>
  void done(uint32_t id, Mover& m, int16_t first_body, int16_t first_wall, bool rattled, Finish& finish) {
    const bool pushed = first_body >= 0 && !g_.safe.contains(m.x, m.y);
    Outcome out{HitKind::None, -1};
    if (pushed || rattled) out = settle(g_, bodies_, n_bodies_, dt_, m, first_body >= 0);
    if (first_body >= 0) out = {HitKind::Body, first_body};
    else if (out.kind == HitKind::None && first_wall >= 0) out = {HitKind::Wall, first_wall};
    finish(id, m, out);
  }

  const Geometry& g_;
  const BodyPath* bodies_ = nullptr;
  int n_bodies_ = 0;
  float dt_ = 0;
  Queue with_bodies_, walls_only_;
};

}  // namespace quantum::detail

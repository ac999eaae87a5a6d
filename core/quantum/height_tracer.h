// Traces particles with height through one step, contact by contact, many at a time: the
// batched search (batch_next_hits3) runs over a queue of particles per round of contacts, as
// StepTracer does on a flat field. Internal to core/quantum.
//
// A particle is searched with the bodies until it meets one; from then on it belongs to that
// body's purgatory and finishes the step against everything else. Every particle ends with an
// Outcome: the first body, goal or out it met, else the first surface it bounced off hard enough
// to be heard, else None. One rattling between surfaces stops after kMaxContacts.
#pragma once

#include <cstdint>
#include <vector>

#include "height.h"

namespace quantum::detail {

class StepTracer3 {
 public:
  StepTracer3(const Geometry& g, const Sky& s) : g_(g), s_(s) {}

  // Starts a step of length dt; bodies move as `bodies` say (none for a catch-up). The queues
  // are made at the first step, so a world on a flat field never makes them.
  void begin(const BodyPath* bodies, int n_bodies, float dt) {
    bodies_ = bodies, n_bodies_ = n_bodies, dt_ = dt;
    for (Queue* q : {&with_bodies_, &without_}) {
      if (!q->id.empty()) continue;
      q->batch.resize(kBatch);
      q->id.resize(kBatch);
      q->contacts.resize(kBatch);
      q->first_body.resize(kBatch);
      q->first_wall.resize(kBatch);
    }
  }

  // Queues particle `id`, at m at the start of the step. finish(id, const Mover3&, Outcome) is
  // called for every particle once its step is traced, in no particular order.
  template <class Finish>
  void add(uint32_t id, const Mover3& m, Finish&& finish) {
    Queue& q = n_bodies_ > 0 ? with_bodies_ : without_;
    while (q.n == kBatch) trace(q, finish);  // a round may keep every particle; each ends within kMaxContacts
    put(q, q.n++, id, m, 0, 0, -1, -1);
  }

  // Traces everything still queued.
  template <class Finish>
  void finish_all(Finish&& finish) {
    while (with_bodies_.n > 0 || without_.n > 0) trace(with_bodies_.n > 0 ? with_bodies_ : without_, finish);
  }

 private:
  static constexpr size_t kBatch = 512;
  static constexpr int kMaxContacts = 8;  // as the flat step: a particle rattling in a corner stops where it is

  struct Queue {
    Mover3Batch batch;
    std::vector<uint32_t> id;
    std::vector<uint8_t> contacts;
    std::vector<int16_t> first_body;  // body met earlier this step, -1 for none
    std::vector<int16_t> first_wall;  // surface bounced off audibly earlier this step, -1 for none
    size_t n = 0;
  };

  static void put(Queue& q, size_t j, uint32_t id, const Mover3& m, float t, uint8_t contacts, int16_t first_body,
                  int16_t first_wall) {
    q.batch.set(j, m, t);
    q.id[j] = id, q.contacts[j] = contacts, q.first_body[j] = first_body, q.first_wall[j] = first_wall;
  }

  static Outcome ending(int16_t first_body, int16_t first_wall) {
    if (first_body >= 0) return {HitKind::Body, first_body};
    if (first_wall >= 0) return {HitKind::Wall, first_wall};
    return {HitKind::None, -1};
  }

  // One round for every particle of q: find its next contact, move it there, resolve it.
  template <class Finish>
  void trace(Queue& q, Finish& finish) {
    const bool bodies_on = &q == &with_bodies_;
    Mover3Batch& b = q.batch;
    const size_t n = q.n;
    batch_next_hits3(g_, s_, bodies_, bodies_on ? n_bodies_ : 0, b, n, dt_, bodies_on);
    size_t kept = 0;
    for (size_t j = 0; j < n; ++j) {
      const Hit3 hit = b.hit(j);
      const uint32_t id = q.id[j];
      int16_t first_body = q.first_body[j], first_wall = q.first_wall[j];
      float t = b.t[j];
      if (hit.kind == HitKind::None) {
        finish(id, advanced(s_, b.mover(j), dt_ - t), ending(first_body, first_wall));
        continue;
      }
      Mover3 m = advanced(s_, b.mover(j), hit.dt);
      t += hit.dt;
      if (hit.kind == HitKind::Goal || hit.kind == HitKind::Out) {
        finish(id, m, first_body >= 0 ? Outcome{HitKind::Body, first_body} : Outcome{hit.kind, hit.index});
        continue;
      }
      // The ball's own velocity, not the Brownian drift: knowledge blurring into a wall makes no sound.
      if (hit.kind == HitKind::Wall && first_wall < 0 && impact_speed(hit, m) > g_.audible_bounce)
        first_wall = int16_t(hit.index);
      resolve3(g_, s_, bodies_, hit, t, m);
      if (hit.kind == HitKind::Body) first_body = int16_t(hit.index);
      const uint8_t contacts = uint8_t(q.contacts[j] + 1);
      if (contacts == kMaxContacts) {
        finish(id, m, ending(first_body, first_wall));
        continue;
      }
      if (hit.kind == HitKind::Body) {
        // The rest of the step without bodies. The queue being traced is never the one pushed to
        // here, so flushing that one first is safe.
        while (without_.n == kBatch) trace(without_, finish);
        put(without_, without_.n++, id, m, t, contacts, first_body, first_wall);
        continue;
      }
      // Still flying: compact into the front of the same queue for the next round (slot j has been read).
      put(q, kept++, id, m, t, contacts, first_body, first_wall);
    }
    q.n = kept;
  }

  const Geometry& g_;
  const Sky& s_;
  const BodyPath* bodies_ = nullptr;
  int n_bodies_ = 0;
  float dt_ = 0;
  Queue with_bodies_, without_;
};

}  // namespace quantum::detail

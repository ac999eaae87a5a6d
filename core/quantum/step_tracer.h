// Traces particles through one step, contact by contact, many at a time: the batched search runs
// over a queue of particles per round of contacts. Written once over the space (space.h): a flat
// field and one with height trace alike. Internal to core/quantum.
//
// A particle near a body is searched with the bodies until it meets one; from then on it belongs
// to that body's purgatory and finishes the step against everything else, so its state stays a
// valid ball state. Every particle ends with an Outcome: None, or the first body, goal or out it
// met, Crushed when no valid place is left for it, or else the first wall it bounced off hard
// enough to be heard (Geometry::audible_bounce) or the first landing, so the bounce or the
// landing can be decided and announced.
#pragma once

#include <cstdint>
#include <vector>

#include "space.h"

namespace quantum::detail {

template <class Space>
class StepTracer {
 public:
  using Mover = typename Space::Mover;

  explicit StepTracer(Space space) : space_(space) {
    for (Queue* q : {&with_bodies_, &without_}) {
      q->batch.resize(kBatch);
      q->id.resize(kBatch);
      q->contacts.resize(kBatch);
      q->first_body.resize(kBatch);
      q->first_sound.resize(kBatch);
    }
  }

  // Starts a step of length dt; bodies move as `bodies` say (none for a catch-up).
  void begin(const BodyPath* bodies, int n_bodies, float dt) { bodies_ = bodies, n_bodies_ = n_bodies, dt_ = dt; }

  // Queues particle `id`, at m at the start of the step; one that cannot come near a body this
  // step (`near_bodies` false) skips the bodies' search. finish(id, const Mover&, Outcome) is
  // called for every particle once its step is traced, in no particular order.
  template <class Finish>
  void add(uint32_t id, const Mover& m, bool near_bodies, Finish&& finish) {
    Queue& q = near_bodies && n_bodies_ > 0 ? with_bodies_ : without_;
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
  static constexpr int kMaxContacts = 8;  // a particle rattling in a corner stops where it is

  struct Queue {
    typename Space::Batch batch;
    std::vector<uint32_t> id;
    std::vector<uint8_t> contacts;
    std::vector<int16_t> first_body;   // body met earlier this step, -1 for none
    std::vector<int32_t> first_sound;  // wall bounced off audibly or landing earlier this step (hit_code), -1 for none
    size_t n = 0;
  };

  static void put(Queue& q, size_t j, uint32_t id, const Mover& m, float t, uint8_t contacts, int16_t first_body,
                  int32_t first_sound) {
    q.batch.set(j, m, t);
    q.id[j] = id, q.contacts[j] = contacts, q.first_body[j] = first_body, q.first_sound[j] = first_sound;
  }

  // One round for every particle of q: find its next contact, move it there, resolve it.
  template <class Finish>
  void trace(Queue& q, Finish& finish) {
    const bool bodies_on = &q == &with_bodies_;
    typename Space::Batch& b = q.batch;
    const size_t n = q.n;
    space_.search(bodies_, bodies_on ? n_bodies_ : 0, b, n, dt_);
    size_t kept = 0;
    for (size_t j = 0; j < n; ++j) {
      const typename Space::Hit hit = space_.hit(b, j);
      const uint32_t id = q.id[j];
      int16_t first_body = q.first_body[j];
      int32_t first_sound = q.first_sound[j];
      if (hit.kind == HitKind::None) {
        Mover m = space_.advanced(Space::mover(b, j), dt_ - b.t[j]);
        done(id, m, first_body, first_sound, false, finish);
        continue;
      }
      Mover m = space_.advanced(Space::mover(b, j), hit.dt);
      const float t = b.t[j] + hit.dt;
      if (hit.kind == HitKind::Goal || hit.kind == HitKind::Out) {
        finish(id, m, first_body >= 0 ? Outcome{HitKind::Body, first_body} : Outcome{hit.kind, hit.index});
        continue;
      }
      // The ball's own velocity, not the Brownian drift: knowledge blurring into a wall makes no sound.
      const bool sounds = hit.kind == HitKind::Wall || hit.kind == HitKind::Landing;
      if (sounds && first_sound < 0 && Space::impact_speed(hit, m) > space_.g.audible_bounce)
        first_sound = hit_code(hit.kind, hit.index);
      space_.resolve(bodies_, hit, t, m);
      if (hit.kind == HitKind::Body) first_body = int16_t(hit.index);
      const uint8_t contacts = uint8_t(q.contacts[j] + 1);
      if (contacts == kMaxContacts) {
        done(id, m, first_body, first_sound, true, finish);
        continue;
      }
      if (hit.kind == HitKind::Body) {
        // The rest of the step without bodies. The queue being traced is never the one pushed to
        // here, so flushing that one first is safe.
        while (without_.n == kBatch) trace(without_, finish);
        put(without_, without_.n++, id, m, t, contacts, first_body, first_sound);
        continue;
      }
      // Still flying: compact into the front of the same queue for the next round (slot j has been read).
      put(q, kept++, id, m, t, contacts, first_body, first_sound);
    }
    q.n = kept;
  }

  // A particle at the end of its step. Exact contacts keep a ball out of walls; on a flat field
  // only a body can push one into a wall (a squeeze), and a rattling one may have been stopped
  // against one, so those are settled. With height the ball is never settled: settle() knows the
  // walls' shadows only, not the floor, boards and rims, and would move a ball the search had
  // kept clear of them.
  template <class Finish>
  void done(uint32_t id, Mover& m, int16_t first_body, int32_t first_sound, bool rattled, Finish& finish) {
    Outcome out{HitKind::None, -1};
    if constexpr (!Space::kHeight) {
      const bool pushed = first_body >= 0 && !space_.g.safe.contains(m.x, m.y);
      if (pushed || rattled) out = settle(space_.g, bodies_, n_bodies_, dt_, m, first_body >= 0);
    }
    if (first_body >= 0) out = {HitKind::Body, first_body};
    else if (out.kind == HitKind::None && first_sound >= 0) out = {code_kind(first_sound), code_index(first_sound)};
    finish(id, m, out);
  }

  Space space_;
  const BodyPath* bodies_ = nullptr;
  int n_bodies_ = 0;
  float dt_ = 0;
  Queue with_bodies_, without_;
};

}  // namespace quantum::detail

// World's private working state that needs the internal contact types, and the scratch memory
// of its step and its prediction: made once, reused every frame, so a running match allocates
// nothing (as Box2D v3 keeps a step's scratch in its world).
#pragma once

#include <cmath>
#include <optional>
#include <vector>

#include "quantum/contact.h"
#include "quantum/fate.h"
#include "helper_thread.h"
#include "space.h"
#include "step_tracer.h"

namespace quantum {

struct Tally {
  // tweaked: what the option weighs in the draw; carried: the tweaked weight its particles
  // brought from their fates (the rest's weight is the cloud's less every option's).
  double tweaked = 0, carried = 0, newtonian = 0, cx = 0, cy = 0;
  uint32_t count = 0;
};

// The decision targets of a field in one flat list, one tally each: bodies, goals, out, walls,
// and on a field of landings one landing outside every area and one per area.
struct TargetSlots {
  int bodies = 0, goals = 0, walls = 0, landings = 0;

  int size() const { return bodies + goals + 1 + walls + landings; }
  int slot(Target t) const {
    switch (t.kind) {
      case TargetKind::Body: return t.index;
      case TargetKind::Goal: return bodies + t.index;
      case TargetKind::Out: return bodies + goals;
      case TargetKind::Wall: return bodies + goals + 1 + t.index;
      case TargetKind::Landing: return bodies + goals + 1 + walls + t.index;
      case TargetKind::Crushed:
      case TargetKind::Tackle: break;
    }
    return -1;
  }
  Target at(int slot) const {
    if (slot < bodies) return {TargetKind::Body, uint16_t(slot)};
    if (slot < bodies + goals) return {TargetKind::Goal, uint16_t(slot - bodies)};
    if (slot == bodies + goals) return {TargetKind::Out, 0};
    if (slot < bodies + goals + 1 + walls) return {TargetKind::Wall, uint16_t(slot - bodies - goals - 1)};
    return {TargetKind::Landing, uint16_t(slot - bodies - goals - 1 - walls)};
  }
};

// The particles the bodies touched in one step, kept for a few steps (the purgatory). One slot
// per step, shared by all bodies: a step's contacts never outnumber the cloud, so a slot sized
// for the cloud never grows, however many bodies the field has.
struct PurgatorySlot {
  Cloud touched;
  std::vector<uint16_t> body;  // which body touched each particle
  uint64_t step = 0;           // the step the slot was filled in
};

// Particles being traced by the prediction: a batch for the vectorized search, plus who they are
// (Flight on a flat field, Flight3 on one with height).
template <class Space>
struct FlightOf {
  using Batch = typename Space::Batch;
  // The batched search's fixed cost per round (a loop per wall, end point, goal and body) is paid
  // again in every round of a chunk's last few flights; 4,096 particles (about 200 KiB of batch,
  // within L2) made the 1M fate report about 15 % faster than 1,024, and 16,384 no faster.
  static constexpr size_t kChunk = 4096;
  Batch b;
  std::vector<uint32_t> id;
  std::vector<uint8_t> contacts;
  size_t n = 0;

  FlightOf() {
    b.resize(kChunk);
    id.resize(kChunk);
    contacts.resize(kChunk);
  }
  void push(const typename Space::Mover& m, float t, uint32_t who, uint8_t touched) {
    b.set(n, m, t);
    id[n] = who, contacts[n] = touched;
    ++n;
  }
};
using Flight = FlightOf<detail::Flat>;
using Flight3 = FlightOf<detail::Tall>;

// Fate groups by key: open addressing over a power-of-two table, grown (rarely: a frame with more
// fates than any before) to stay at most half full.
struct GroupIndex {
  std::vector<uint64_t> keys;
  std::vector<uint32_t> groups;  // group index + 1; 0 marks an empty slot
  size_t used = 0;

  void clear();
  // The group of `key`, or `fresh` (which the caller then creates) when it has none.
  uint32_t find_or_add(uint64_t key, uint32_t fresh);
};

// A fate group while it is summed: over a chunk's particles, then over the chunks. It keeps what
// the merge needs without reaching back into the cloud.
struct GroupTally {
  Fate fate;
  uint64_t key;
  double mass, tweaked_mass, heaviest;  // heaviest: the representative's weight
  uint32_t count, representative;
};

// One prediction thread's fates and groups. A chunk's fates live here while it is traced (80 KiB:
// they stay in L2, where a cloud-long array was a cache miss per contact); then the chunk is
// grouped here, so the report's serial part only merges each chunk's groups.
struct ChunkGrouping {
  // Room for a busy frame's groups, so the first frames of a match do not allocate here.
  ChunkGrouping() : fates(Flight::kChunk) { found.reserve(4096), merged.reserve(4096); }
  std::vector<Fate> fates;          // the chunk being traced, by place in the chunk
  GroupIndex index;                 // the chunk's groups by key
  std::vector<GroupTally> found;    // every chunk's groups this thread grouped, chunk after chunk
  std::vector<uint32_t> merged;     // each of those groups' place in the report, set by the merge
};

// Where a chunk's groups are: which thread's ChunkGrouping, from where, how many.
struct ChunkGroups {
  uint32_t thread = 0, first = 0, count = 0;
};

struct WorldInternals {
  explicit WorldInternals(const Field& field)
      : geometry(field), sky(field), tall(field.has_height()), flights(tall ? 0 : 4), flights3(tall ? 4 : 0) {
    tallies.reserve(kBusyFateGroups);
    if (tall) tall_tracer.emplace(detail::Tall{geometry, sky});
    else flat_tracer.emplace(detail::Flat{geometry});
  }
  detail::Geometry geometry;
  detail::Sky sky;
  bool tall;  // the field has height
  // Calls fn with the field's space (space.h): the tracers' code is written once over it.
  template <class Fn>
  decltype(auto) on_space(Fn&& fn) const {
    return tall ? fn(detail::Tall{geometry, sky}) : fn(detail::Flat{geometry});
  }
  // Carries purgatory particles forward at a realized hit: the one of the field's space.
  std::optional<detail::StepTracer<detail::Flat>> flat_tracer;
  std::optional<detail::StepTracer<detail::Tall>> tall_tracer;
  template <class Space>
  detail::StepTracer<Space>& tracer() {
    if constexpr (Space::kHeight) return *tall_tracer;
    else return *flat_tracer;
  }
  std::vector<detail::BodyPath> resting;  // bodies held at their current positions
  std::vector<Tally> tally;               // per decision target, reused every step
  TargetSlots targets;
  // Prediction's scratch.
  std::vector<detail::BodyPath> predicted_bodies;
  std::vector<uint8_t> body_kind, own_goal;
  // Flying and later, for each of two threads: flat fields use flights, fields with height flights3.
  std::vector<Flight> flights;
  std::vector<Flight3> flights3;
  template <class Space>
  std::vector<FlightOf<Space>>& flights_for() {
    if constexpr (Space::kHeight) return flights3;
    else return flights;
  }
  ChunkGrouping grouping[2];          // one per thread
  std::vector<ChunkGroups> chunks;    // per chunk of the cloud
  detail::HelperThread helper;        // shares the prediction's chunks
  GroupIndex index;                   // the report's groups by key, for the merge
  std::vector<GroupTally> tallies;    // the report's groups as the merge sums them
};

}  // namespace quantum

#include "quantum/fate.h"

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <type_traits>

#include "quantum/noise.h"
#include "quantum/world.h"
#include "world_internals.h"

namespace quantum {
namespace {

// A ball still rattling after this many contacts is taken to stay in the field.
constexpr int kMaxFateContacts = 64;

// Records a wall touch in the path; bouncing along one wall (two pieces of a chain) reads as one.
void add_to_path(Fate& f, int wall) {
  if (f.path_len > 0 && f.path[f.path_len - 1] == wall) return;
  if (f.path_len < kMaxPath) f.path[f.path_len++] = uint16_t(wall);
  else f.path_more = true;
}

// What ends a flight, decided once per prediction: the fate kind of meeting each body, and
// whether each goal would be an own goal (both depend on who touched the ball last).
struct Endings {
  const uint8_t* body_kind;  // FateKind per body
  const uint8_t* own_goal;   // 1 per goal its last toucher's team defends
};

// Ends f at a hit that is not a wall; false for walls (the flight goes on).
bool ends_at(Fate& f, detail::HitKind kind, int index, const Endings& ends) {
  switch (kind) {
    case detail::HitKind::Body: f.kind = FateKind(ends.body_kind[index]), f.target = index; return true;
    case detail::HitKind::Goal:
      f.kind = ends.own_goal[index] ? FateKind::OwnGoal : FateKind::Goal, f.target = index;
      return true;
    case detail::HitKind::Out: f.kind = FateKind::Out; return true;
    case detail::HitKind::Landing: f.kind = FateKind::Landing, f.target = index - 1; return true;
    default: return false;
  }
}

// The next step's Brownian offsets. They come from counter-based noise, so prediction can draw
// exactly the offsets the step will: it traces the first `dt` with them, and a particle that meets
// something during the next step is predicted to meet exactly that. Decisions draw on particles
// that met something, so tweaks land on the fates that really happen, even though later flight
// is traced without noise.
struct NextStep {
  float dt = 0;  // 0: no noise to replay
  uint32_t key = 0;
  float amplitude = 0;
};

// `span` is the step's flight time (dt without friction): the drift is traced over it, with the
// noise of a step of dt.
NextStep next_step(uint64_t seed, uint64_t step, float brownian, float dt, float span) {
  if (!(brownian > 0)) return {};
  return {span, step_key(seed, step + 1), noise_amplitude(brownian, dt)};
}

// Particle i at the start of the prediction: moving with the next step's drift, as the step moves
// it (the drift is horizontal only).
template <class Space>
typename Space::Mover start_of(const Space& space, const Cloud& c, size_t i, const NextStep& next) {
  typename Space::Mover m = Space::ball(c, i);
  if (next.dt <= 0) return m;
  float dx, dy;
  noise_offsets(noise_bits(uint32_t(i), next.key), next.amplitude, dx, dy);
  const float span = space.span(m, next.dt);
  const float x1 = c.x[i] + c.vx[i] * span + dx, y1 = c.y[i] + c.vy[i] * span + dy;
  m.ux = (x1 - c.x[i]) / span, m.uy = (y1 - c.y[i]) / span;
  return m;
}

// Follows one particle from contact to contact; `fly` sees every free flight (its start and
// length), so a picture can draw the path. Same searches and arithmetic as trace_fates, one
// particle at a time.
template <class Space, class Fly>
Fate trace_fate(const Space& space, const detail::BodyPath* bodies, int nb, const Endings& ends,
                typename Space::Mover m, float drift_end, float horizon, Fly&& fly) {
  Fate f;
  float t = 0, end = drift_end > 0 && drift_end < horizon ? drift_end : horizon;
  for (int contact = 0; contact < kMaxFateContacts;) {
    const typename Space::Hit hit = space.next_hit(bodies, nb, m, t, end);
    if (hit.kind == detail::HitKind::None) {
      fly(m, end - t);
      m = space.advanced(m, end - t);
      t = end;
      if (end == horizon) return f;
      m.ux = m.vx, m.uy = m.vy, end = horizon;  // the drift is spent: on without noise
      continue;
    }
    fly(m, hit.dt);
    m = space.advanced(m, hit.dt);
    t += hit.dt;
    if (ends_at(f, hit.kind, hit.index, ends)) return f;
    if (hit.kind == detail::HitKind::Wall) add_to_path(f, hit.index);  // a wormhole is no wall
    space.resolve(bodies, hit, t, m);
    ++contact;
  }
  return f;
}

// Whether m can meet nothing within `dt`: its path stays inside the safe box (no wall, goal line
// or bound within reach) and clear of every body's sweep. Most particles of a cloud can't; they
// skip the search for the drift step.
bool meets_nothing(const detail::Geometry& g, const detail::BodyPath* bodies, int nb, const detail::Mover& m,
                   float dt) {
  if (!g.safe.contains(m.x, m.y) || !g.safe.contains(m.x + m.ux * dt, m.y + m.uy * dt)) return false;
  const float travel = (std::fabs(m.ux) + std::fabs(m.uy)) * dt;
  for (size_t k = 0; k < g.mx.size(); ++k) {
    const float qx = m.x - g.mx[k], qy = m.y - g.my[k], reach = g.mr[k] + travel + 1e-3f;
    if (qx * qx + qy * qy < reach * reach) return false;
  }
  for (int k = 0; k < nb; ++k) {
    const detail::BodyPath& b = bodies[k];
    const float sweep = (std::fabs(b.ux) + std::fabs(b.uy)) * std::min(dt, b.stop);
    const float reach = b.radius + g.r + travel + sweep + 1e-3f;
    const float qx = m.x - b.x, qy = m.y - b.y;
    if (qx * qx + qy * qy < reach * reach) return false;
  }
  return true;
}

// The fates of a whole cloud, traced and grouped chunk by chunk. Chunks are independent (each
// writes only its own particles' places in `group_of` and its own ChunkGroups), so two threads
// share them out: each takes the next chunk from `next` until none is left, with its own pair of
// scratch flights and its own ChunkGrouping. Which thread takes a chunk changes nothing in it,
// so the report is the same on one thread or two.
template <class Space>
struct FateJob {
  using FlightT = FlightOf<Space>;
  const Space& space;
  const detail::BodyPath* bodies;
  int nb;
  const Endings& ends;
  const Cloud& c;
  const NextStep& next_step;
  float horizon;
  FlightT* scratch;                // two pairs: flying and later for each thread
  ChunkGrouping* grouping;         // one for each thread
  ChunkGroups* chunks;             // one for each chunk
  uint32_t* group_of;              // the particle's group within its chunk, until the merge
  std::atomic<size_t> next{0};     // the first particle of the next chunk to trace
  std::atomic<int> threads{0};     // which scratch a thread takes
};

// Adds `part` (one particle, or one chunk's tally of a fate) to the tally of its key among
// tallies[first, ...), which the first part of a key starts; returns that tally's place from
// `first`. Masses and counts add up, and the representative stays the first heaviest particle,
// whether the parts are particles or chunks taken in the cloud's order.
uint32_t add_to_tally(GroupIndex& index, std::vector<GroupTally>& tallies, size_t first, const GroupTally& part) {
  const uint32_t k = index.find_or_add(part.key, uint32_t(tallies.size() - first));
  if (first + k == tallies.size()) {
    tallies.push_back(part);
    return k;
  }
  GroupTally& tally = tallies[first + k];
  tally.mass += part.mass;
  tally.tweaked_mass += part.tweaked_mass;
  tally.count += part.count;
  if (part.heaviest > tally.heaviest) tally.heaviest = part.heaviest, tally.representative = part.representative;
  return k;
}

// The fates of chunk [begin, end) into its groups, in order of first appearance: each particle's
// place among them goes to group_of, the groups to the end of this thread's `found`.
template <class Space>
void group_chunk(FateJob<Space>& job, int thread, size_t begin, size_t end) {
  ChunkGrouping& mine = job.grouping[thread];
  ChunkGroups& chunk = job.chunks[begin / FateJob<Space>::FlightT::kChunk];
  const size_t first = mine.found.size();
  mine.index.clear();
  const Cloud& c = job.c;
  for (size_t i = begin; i < end; ++i) {
    const Fate& f = mine.fates[i - begin];
    job.group_of[i] = add_to_tally(mine.index, mine.found, first, {f, f.key(), c.w[i], c.tw[i], c.w[i], 1, uint32_t(i)});
  }
  chunk = {uint32_t(thread), uint32_t(first), uint32_t(mine.found.size() - first)};
}

// Each round searches all still-flying particles of a chunk at once (vectorized), then moves each
// to its contact. The first `drift_end` seconds run with the next step's drift (see NextStep), the
// rest without.
template <class Space>
void trace_fates(FateJob<Space>& job) {
  using FlightT = typename FateJob<Space>::FlightT;
  using Mover = typename Space::Mover;
  constexpr size_t kChunk = FlightT::kChunk;
  const int thread = job.threads.fetch_add(1);
  FlightT* flying = &job.scratch[2 * thread];
  FlightT* later = &job.scratch[2 * thread + 1];  // the drift's end, where the flight goes on without noise
  Fate* fates = job.grouping[thread].fates.data();
  const Space& space = job.space;
  const detail::BodyPath* bodies = job.bodies;
  const int nb = job.nb;
  const Cloud& c = job.c;
  const float horizon = job.horizon, dt = job.next_step.dt, drift_end = dt > 0 && dt < horizon ? dt : horizon;
  for (size_t begin; (begin = job.next.fetch_add(kChunk)) < c.size();) {
    const size_t end_of_chunk = std::min(begin + kChunk, c.size());
    flying->n = later->n = 0;
    std::fill(fates, fates + (end_of_chunk - begin), Fate{});
    for (size_t i = begin; i < end_of_chunk; ++i) {
      const Mover m = start_of(space, c, i, job.next_step);
      const uint32_t place = uint32_t(i - begin);
      // The flat safe box knows no floor, ceiling, hoop or board: with height every particle is searched.
      if constexpr (!Space::kHeight) {
        if (drift_end < horizon && meets_nothing(space.g, bodies, nb, m, drift_end)) {
          Mover at = space.advanced(m, drift_end);
          at.ux = at.vx, at.uy = at.vy;
          later->push(at, drift_end, place, 0);
          continue;
        }
      }
      flying->push(m, 0, place, 0);
    }
    for (float end = drift_end;; end = horizon) {
      while (flying->n > 0) {
        typename Space::Batch& b = flying->b;
        space.search(bodies, nb, b, flying->n, end);
        const size_t n = flying->n;
        flying->n = 0;  // compacted in place: slot j is read before anything is written to it
        for (size_t j = 0; j < n; ++j) {
          const typename Space::Hit hit = space.hit(b, j);
          if (hit.kind == detail::HitKind::None) {
            if (end == horizon) continue;  // stays in the field
            Mover m = space.advanced(Space::mover(b, j), end - b.t[j]);
            m.ux = m.vx, m.uy = m.vy;  // the drift is spent: on without noise
            later->push(m, end, flying->id[j], flying->contacts[j]);
            continue;
          }
          Fate& f = fates[flying->id[j]];
          if (ends_at(f, hit.kind, hit.index, job.ends)) continue;
          if (hit.kind == detail::HitKind::Wall) add_to_path(f, hit.index);  // a wormhole is no wall
          const uint8_t touched = uint8_t(flying->contacts[j] + 1);
          if (touched >= kMaxFateContacts) continue;
          const float t = b.t[j] + hit.dt;
          Mover m = space.advanced(Space::mover(b, j), hit.dt);
          space.resolve(bodies, hit, t, m);
          flying->push(m, t, flying->id[j], touched);
        }
      }
      if (end == horizon) break;
      std::swap(flying, later);
    }
    group_chunk(job, thread, begin, end_of_chunk);
  }
}

}  // namespace

FateKind catch_kind(const Field& field, int thrower, int catcher) {
  if (thrower < 0 || thrower == catcher) return FateKind::Catch;
  return field.bodies[size_t(thrower)].team == field.bodies[size_t(catcher)].team ? FateKind::Pass : FateKind::Intercept;
}

const char* to_string(FateKind kind) {
  switch (kind) {
    case FateKind::Goal: return "goal";
    case FateKind::OwnGoal: return "own_goal";
    case FateKind::Body: return "body";
    case FateKind::Out: return "out";
    case FateKind::Field: return "field";
    case FateKind::Catch: return "catch";
    case FateKind::Pass: return "pass";
    case FateKind::Intercept: return "intercept";
    case FateKind::Landing: return "landing";
    case FateKind::Hit: return "hit";
    case FateKind::Pickup: return "pickup";
    case FateKind::Tackle: return "tackle";
  }
  return "?";
}

uint64_t Fate::key() const {
  static_assert(kFateKindCount <= 16 && kMaxPath * 10 + 24 <= 64, "a fate's key holds its kind in 4 bits");
  uint64_t k = uint64_t(kind) | uint64_t(uint16_t(target + 1)) << 4 | uint64_t(path_len) << 20 |
               uint64_t(path_more) << 23;
  for (int i = 0; i < path_len; ++i) k |= uint64_t(path[i] & 0x3FF) << (24 + 10 * i);
  return k;
}

std::vector<std::string> fate_kind_names() {
  std::vector<std::string> out;
  for (FateKind k : kFateKinds) out.push_back(to_string(k));
  return out;
}

size_t write_via(const Fate& f, const Field& field, char* out, size_t size) {
  size_t n = 0;
  for (int i = 0; size > 0 && (i < f.path_len || (f.path_more && i == f.path_len)); ++i) {
    const char* wall = i < f.path_len ? field.wall_names[f.path[i]].c_str() : "...";
    const int wrote = std::snprintf(out + n, size - n, "%s%s", i == 0 ? "via " : ", ", wall);
    n = std::min(size - 1, n + size_t(std::max(wrote, 0)));
  }
  return n;
}

std::string describe(const Fate& f, const Field& field) {
  std::string s;
  switch (f.kind) {
    case FateKind::Goal: s = "goal (" + field.goals[f.target].name + ")"; break;
    case FateKind::OwnGoal: s = "own goal (" + field.goals[f.target].name + ")"; break;
    case FateKind::Body: s = field.bodies[f.target].name; break;
    case FateKind::Catch: s = "caught by " + field.bodies[f.target].name; break;
    case FateKind::Pass: s = "pass to " + field.bodies[f.target].name; break;
    case FateKind::Intercept: s = "intercepted by " + field.bodies[f.target].name; break;
    case FateKind::Hit: s = "hit by " + field.bodies[f.target].name; break;
    case FateKind::Pickup: s = "picked up by " + field.bodies[f.target].name; break;
    case FateKind::Tackle: s = "taken by " + field.bodies[f.target].name; break;
    case FateKind::Out: s = "out"; break;
    case FateKind::Field: s = "stays in field"; break;
    case FateKind::Landing:
      s = f.target >= 0 ? "lands in " + field.areas[f.target].name : "lands outside every area";
      break;
  }
  char via[256];
  if (const size_t n = write_via(f, field, via, sizeof via)) s += " " + std::string(via, n);
  return s;
}

std::string_view fate_actor(const Fate& f, const Field& field) {
  if (at_body(f.kind)) return field.bodies[size_t(f.target)].name;
  if (f.kind == FateKind::Goal || f.kind == FateKind::OwnGoal) return field.goals[size_t(f.target)].name;
  if (f.kind == FateKind::Landing && f.target >= 0) return field.areas[size_t(f.target)].name;
  return {};
}

double factor_by_kind(FateKind kind, const KindFactors& k) {
  switch (kind) {
    case FateKind::Goal: return k.goal;
    case FateKind::OwnGoal: return k.own_goal;
    case FateKind::Body: return k.body;
    case FateKind::Out:
    case FateKind::Landing: return k.out;
    case FateKind::Field: return k.field;
    case FateKind::Catch:
    case FateKind::Pass:
    case FateKind::Intercept:
    case FateKind::Pickup:
    case FateKind::Tackle: return k.catches;
    case FateKind::Hit: return k.hits;
  }
  return 1;
}

std::vector<double> factors_by_kind(const FateReport& report, const KindFactors& k) {
  std::vector<double> out;
  for (const FateGroup& g : report.groups) out.push_back(factor_by_kind(g.fate.kind, k));
  return out;
}

std::vector<double> factors_by_kind(std::span<const Fate> fates, const KindFactors& k) {
  std::vector<double> out;
  for (const Fate& f : fates) out.push_back(factor_by_kind(f.kind, k));
  return out;
}

void World::check_horizon(float horizon) const {
  if (!(std::isfinite(horizon) && horizon > 0 && horizon <= 600))
    throw std::invalid_argument("prediction horizon must be in (0, 600] seconds, got " + std::to_string(horizon));
}

// Bodies keep their last velocity for the lookahead, then hold: players rarely keep running in
// a straight line, and a body extrapolated for seconds would leave the field. Prediction runs in
// flight time (see Field::flight_time()): the body sweeps to the same place by the end of the lookahead.
void World::predicted_bodies(std::vector<detail::BodyPath>& bodies) const {
  bodies.resize(field_.bodies.size());
  const float stop = flight(config_.body_lookahead);
  const float sweep = stop > 0 ? config_.body_lookahead / stop : 1.0f;
  for (size_t k = 0; k < bodies.size(); ++k) {
    const Vec2 p = body_pos_[k], v = body_vel_[k];
    // A hitter the ball passes through now is taken to let it pass all the horizon: the window is
    // a fraction of a second, and the next frames' predictions see it close.
    bodies[k] = {p.x, p.y, v.x * sweep, v.y * sweep, stop, v.x, v.y, field_.bodies[k].radius, body_top_[k],
                 passes_now(int(k))};
  }
}

void World::endings(std::vector<uint8_t>& body_kind, std::vector<uint8_t>& own) const {
  own_goals(own);
  body_kind.resize(field_.bodies.size());
  const bool loose_now = field_.catching() && loose();  // only catchers pick up
  for (size_t k = 0; k < body_kind.size(); ++k) body_kind[k] = uint8_t(ending_at(int(k), loose_now));
}

FateKind World::ending_at(int body, bool loose) const {
  const BodySpec& b = field_.bodies[size_t(body)];
  if (b.hits) return FateKind::Hit;
  if (!b.catches) return FateKind::Body;
  return loose && last_touch_ >= 0 ? FateKind::Pickup : catch_kind(field_, last_touch_, body);
}

std::vector<Vec3> World::predict_path(size_t i, float horizon) const {
  check_horizon(horizon);
  if (i >= cloud_.size()) throw std::out_of_range("no live particle " + std::to_string(i));
  std::vector<detail::BodyPath> bodies;
  predicted_bodies(bodies);
  std::vector<uint8_t> body_kind, own;
  endings(body_kind, own);
  std::vector<Vec3> path;
  const NextStep next = next_step(config_.seed, step_, field_.brownian, last_dt_, flight(last_dt_));
  const Endings ends{body_kind.data(), own.data()};
  internals_->on_space([&](const auto& space) {
    using Space = std::decay_t<decltype(space)>;
    // A flat flight is a straight line; an arc is drawn as chords of at most this long in time,
    // smooth at any picture's scale.
    constexpr float kChord = 0.02f;
    trace_fate(space, bodies.data(), int(bodies.size()), ends, start_of(space, cloud_, i, next), next.dt,
               flight(horizon), [&](const typename Space::Mover& m, float seconds) {
                 const int pieces = Space::kHeight ? std::max(1, int(std::ceil(seconds / kChord))) : 1;
                 for (int k = path.empty() ? 0 : 1; k <= pieces; ++k)
                   path.push_back(Space::where(space.advanced(m, seconds * float(k) / float(pieces))));
               });
  });
  return path;
}

FateReport World::predict(float horizon) const {
  FateReport report;
  predict(report, horizon);
  return report;
}

void World::predict(FateReport& report, float horizon) const {
  check_horizon(horizon);
  WorldInternals& s = *internals_;
  predicted_bodies(s.predicted_bodies);
  endings(s.body_kind, s.own_goal);
  report.horizon = horizon;
  report.cloud_version = version_;
  report.groups.clear();
  report.group_of.resize(cloud_.size());
  const size_t chunk = Flight::kChunk;
  static_assert(Flight::kChunk == Flight3::kChunk, "both reports merge chunks of one size");
  s.chunks.resize((cloud_.size() + chunk - 1) / chunk);
  for (ChunkGrouping& grouping : s.grouping) grouping.found.clear();
  const Endings ends{s.body_kind.data(), s.own_goal.data()};
  const NextStep next = next_step(config_.seed, step_, field_.brownian, last_dt_, flight(last_dt_));
  // One chunk is not worth waking a second thread for.
  const bool shared = config_.threads > 1 && cloud_.size() > chunk;
  const auto run = [&](auto& job, void (*trace)(void*)) { shared ? s.helper.together(trace, &job) : trace(&job); };
  const int nb = int(s.predicted_bodies.size());
  uint32_t* group_of = report.group_of.data();
  // With height, flight() is the time itself: the tracer slows a rolling particle (Sky::roll).
  internals_->on_space([&](const auto& space) {
    using Space = std::decay_t<decltype(space)>;
    FateJob<Space> job{space, s.predicted_bodies.data(), nb, ends, cloud_, next, flight(horizon),
                       s.flights_for<Space>().data(), s.grouping, s.chunks.data(), group_of};
    run(job, [](void* j) { trace_fates(*static_cast<FateJob<Space>*>(j)); });
  });
  // The chunks' groups, merged in the cloud's order: the report's groups come in order of first
  // appearance and each keeps its first heaviest particle, as one pass over the cloud would give.
  // A group's mass is summed chunk by chunk, so it is the same whichever thread traced what.
  s.index.clear();
  s.tallies.clear();
  // How the chunks fell to the threads changes from frame to frame, so each thread's `found` is
  // given room for all of this frame's chunk groups: it then grows only in a frame with more of
  // them than any before, not whenever one thread happens to take more chunks.
  const size_t chunk_groups = s.grouping[0].found.size() + s.grouping[1].found.size();
  for (ChunkGrouping& grouping : s.grouping) {
    grouping.found.reserve(chunk_groups), grouping.merged.reserve(chunk_groups);
    grouping.merged.resize(grouping.found.size());
  }
  for (const ChunkGroups& part : s.chunks) {
    ChunkGrouping& from = s.grouping[part.thread];
    for (uint32_t j = part.first; j < part.first + part.count; ++j)
      from.merged[j] = add_to_tally(s.index, s.tallies, 0, from.found[j]);
  }
  for (size_t c = 0; c < s.chunks.size(); ++c) {
    const ChunkGroups& part = s.chunks[c];
    const uint32_t* merged = s.grouping[part.thread].merged.data() + part.first;
    for (size_t i = c * chunk; i < std::min((c + 1) * chunk, cloud_.size()); ++i) group_of[i] = merged[group_of[i]];
  }
  for (const GroupTally& t : s.tallies)
    report.groups.push_back({t.fate, t.mass / cloud_.mass, t.tweaked_mass / cloud_.tmass, t.count, t.representative});
}

void GroupIndex::clear() {
  // Room for a busy moment's fates at half load, so a busier one than any before
  // does not rehash (allocate) in its frame.
  if (keys.empty()) keys.resize(2 * kBusyFateGroups), groups.resize(2 * kBusyFateGroups);
  std::fill(groups.begin(), groups.end(), 0u);
  used = 0;
}

uint32_t GroupIndex::find_or_add(uint64_t key, uint32_t fresh) {
  if (2 * (used + 1) > keys.size()) {
    // Rehash into twice the room: only a frame with more fates than any before comes here.
    const std::vector<uint64_t> old_keys = std::move(keys);
    const std::vector<uint32_t> old_groups = std::move(groups);
    keys.assign(old_keys.size() * 2, 0);
    groups.assign(old_groups.size() * 2, 0u);
    used = 0;
    for (size_t k = 0; k < old_keys.size(); ++k)
      if (old_groups[k]) find_or_add(old_keys[k], old_groups[k] - 1);
  }
  const size_t mask = keys.size() - 1;
  // Fibonacci hashing spreads keys that differ only in their high bits (wall paths).
  for (size_t k = size_t((key * 0x9E3779B97F4A7C15ull) >> 32) & mask;; k = (k + 1) & mask) {
    if (groups[k] == 0) {
      keys[k] = key, groups[k] = fresh + 1;
      ++used;
      return fresh;
    }
    if (keys[k] == key) return groups[k] - 1;
  }
}

void World::tweak(FateReport& report, std::span<const double> factors) {
  if (report.cloud_version != version_ || report.group_of.size() != cloud_.size())
    throw std::logic_error("fate report is stale: the cloud changed since it was predicted");
  if (factors.size() != report.groups.size())
    throw std::invalid_argument("got " + std::to_string(factors.size()) + " fate factors for " +
                                std::to_string(report.groups.size()) + " fate groups");
  for (size_t k = 0; k < factors.size(); ++k)
    if (!(std::isfinite(factors[k]) && factors[k] >= 0))
      throw std::invalid_argument("fate factor " + std::to_string(k) + " must be a finite number >= 0");
  double sum = 0;
  fate_mass_.assign(factors.size(), 0.0);
  for (size_t i = 0; i < cloud_.size(); ++i) {
    const uint32_t g = report.group_of[i];
    cloud_.tw[i] = cloud_.w[i] * factors[g];
    cloud_.fate[i] = g;
    fate_mass_[g] += cloud_.w[i];
    sum += cloud_.tw[i];
  }
  if (!(sum > 0)) {
    cloud_.reset_tweak();
    forget_tweak();
    throw std::invalid_argument("fate factors leave every particle with zero weight");
  }
  cloud_.tmass = tmass_full_ = sum;
  tweak_groups_.assign(report.groups.begin(), report.groups.end());
  tweak_factors_.assign(factors.begin(), factors.end());
  for (FateGroup& group : report.groups) group.tweaked_mass = 0;
  for (size_t i = 0; i < cloud_.size(); ++i) report.groups[report.group_of[i]].tweaked_mass += cloud_.tw[i] / sum;
}

}  // namespace quantum

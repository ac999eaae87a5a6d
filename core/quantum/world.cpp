#include "quantum/world.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <type_traits>

#include "quantum/limits.h"
#include "world_internals.h"

namespace quantum {

const char* to_string(EventType type) {
  switch (type) {
    case EventType::Drop: return "drop";
    case EventType::Hit: return "hit";
    case EventType::Bounce: return "bounce";
    case EventType::Goal: return "goal";
    case EventType::OwnGoal: return "own_goal";
    case EventType::Out: return "out";
    case EventType::Catch: return "catch";
    case EventType::Throw: return "throw";
    case EventType::Landing: return "landing";
    case EventType::Pickup: return "pickup";
    case EventType::Tackle: return "tackle";
    case EventType::Kick: return "kick";
  }
  return "?";
}

std::string_view target_name(Target t, const Field& f) {
  switch (t.kind) {
    case TargetKind::Body:
    case TargetKind::Tackle: return f.bodies[t.index].name;
    case TargetKind::Goal: return f.goals[t.index].name;
    case TargetKind::Wall: return f.wall_names[t.index];
    case TargetKind::Landing: return t.index > 0 ? std::string_view(f.areas[t.index - 1].name) : "floor";
    case TargetKind::Out:
    case TargetKind::Crushed: break;
  }
  return "out";
}

int contact_index(Target t, const Field& f) {
  const int bodies = int(f.bodies.size()), goals = int(f.goals.size());
  switch (t.kind) {
    case TargetKind::Body: return t.index;
    case TargetKind::Goal: return bodies + t.index;
    case TargetKind::Out: return bodies + goals;
    case TargetKind::Landing: return bodies + goals + 1 + t.index;
    case TargetKind::Wall:
    case TargetKind::Tackle:
    case TargetKind::Crushed: break;
  }
  return -1;
}

EventActor actor_of(const Event& e, const Field& f) {
  switch (e.type) {
    case EventType::Drop: return {f.spots[e.actor].name, f.spots[e.actor].team};
    case EventType::Hit:
    case EventType::Catch:
    case EventType::Pickup:
    case EventType::Tackle:
    case EventType::Throw:
    case EventType::Kick: return {f.bodies[e.actor].name, f.bodies[e.actor].team};
    case EventType::Bounce: return {f.wall_names[e.actor], ""};
    case EventType::Goal:
    case EventType::OwnGoal: return {f.goals[e.actor].name, f.goals[e.actor].team};
    case EventType::Landing:
      if (e.actor >= 0) return {f.areas[e.actor].name, f.areas[e.actor].team};
      break;
    case EventType::Out: break;
  }
  return {};
}

World::World(Field field, WorldConfig config, std::unique_ptr<Backend> backend)
    : field_(std::move(field)), config_(config), rng_(config.seed) {
  finish_field(field_);
  if (config_.particles < 1) throw std::invalid_argument("the cloud needs at least one particle");
  if (config_.threads < 1 || config_.threads > 2)
    throw std::invalid_argument("threads must be 1 or 2, got " + std::to_string(config_.threads));
  if (config_.purgatory_frames < 1) throw std::invalid_argument("purgatory needs at least one frame");
  if (!(config_.split_jitter >= 0 && config_.split_jitter < 1.6f))
    throw std::invalid_argument("split jitter must be between 0 and 1.6 rad");
  if (!(config_.body_lookahead >= 0)) throw std::invalid_argument("body lookahead must be >= 0");
  internals_ = std::make_unique<WorldInternals>(field_);
  internals_->targets = {int(field_.bodies.size()), int(field_.goals.size()), int(field_.wall_names.size()),
                         field_.landings ? int(field_.areas.size()) + 1 : 0};
  internals_->tally.resize(size_t(internals_->targets.size()));
  contact_factor_.assign(internals_->tally.size(), 1.0);
  // What a draw tells of its making (Decision), with room for a busy moment's fate groups, so
  // that a match's frames do not allocate for it.
  constexpr size_t kFateGroups = kBusyFateGroups;
  for (auto* v : {&tweak_factors_, &fate_mass_, &decision_.fate_factors}) v->reserve(kFateGroups);
  tweak_groups_.reserve(kFateGroups), decision_.fates.reserve(kFateGroups);
  share_at_.reserve(internals_->tally.size() * (kFateGroups + 1));
  decision_.shares.reserve(8 * kFateGroups);
  decision_.options.reserve(internals_->tally.size());
  internals_->resting.resize(field_.bodies.size());
  const bool tall = field_.has_height();
  backend_ = backend ? std::move(backend) : tall ? make_height_backend(field_) : make_fast_backend(field_);
  const size_t nb = field_.bodies.size();
  for (const BodySpec& b : field_.bodies) body_pos_.push_back(b.start), body_vel_.push_back({0, 0});
  for (size_t k = 0; k < nb; ++k) body_top_.push_back(tall ? field_.reach_of(int(k)) : detail::kInf);
  motion_.resize(nb);
  pass_until_.assign(nb, -1);
  planned_.resize(nb);
  purgatory_.resize(config_.purgatory_frames);
  for (PurgatorySlot& slot : purgatory_)
    slot.touched.reserve(config_.particles, tall), slot.body.reserve(config_.particles);
  // The cloud and the scratch cloud trade places (std::swap) at every realized contact and
  // heard bounce, so each needs the room either may: twice the cloud (below). Sized only as the
  // cloud, a gathered shot that was larger than any before allocated in whichever frame first
  // met it with the smaller one.
  cloud_.reserve(2 * size_t(config_.particles), tall);
  // A prediction's chunks: the cloud starts as one particle at a drop and grows past N for a
  // while after a realized contact (the gathered shot before the split), so room made as it came
  // would be made in the first frame it is fuller than ever.
  internals_->chunks.reserve(2 * size_t(config_.particles) / Flight::kChunk + 1);
  // Twice the cloud: a realized contact gathers the body's touched particles from every purgatory
  // slot, which after a hard hit can be more than one cloud's worth.
  scratch_.reserve(2 * size_t(config_.particles), tall);
  contacts_.reserve(config_.particles);
  removed_.reserve(config_.particles);
}

World::~World() = default;

size_t World::purgatory_size(int body) const {
  size_t n = 0;
  for (const PurgatorySlot& slot : purgatory_) n += size_t(std::count(slot.body.begin(), slot.body.end(), uint16_t(body)));
  return n;
}

void World::clear_purgatory() {
  for (PurgatorySlot& slot : purgatory_) slot.touched.clear(), slot.body.clear();
}

void World::forget_tweak() {
  tweak_groups_.clear(), tweak_factors_.clear(), fate_mass_.clear();
  tmass_full_ = cloud_.tmass;
}

void World::sum_fate_mass() {
  fate_mass_.assign(tweak_groups_.size(), 0.0);
  for (size_t i = 0; i < cloud_.size(); ++i)
    if (cloud_.fate[i] != Cloud::kNoFate) fate_mass_[cloud_.fate[i]] += cloud_.w[i];
  tmass_full_ = cloud_.tmass;
}

void World::contact_fates(std::vector<Fate>& out) const {
  std::vector<uint8_t>& body_kind = internals_->body_kind;
  std::vector<uint8_t>& own = internals_->own_goal;
  endings(body_kind, own);
  out.clear();
  for (size_t k = 0; k < body_kind.size(); ++k) out.push_back({FateKind(body_kind[k]), int(k)});
  for (size_t g = 0; g < own.size(); ++g) out.push_back({own[g] ? FateKind::OwnGoal : FateKind::Goal, int(g)});
  out.push_back({FateKind::Out, -1});
  for (int a = 0; a < internals_->targets.landings; ++a) out.push_back({FateKind::Landing, a - 1});
}

std::vector<double> World::contact_factors() const {
  const size_t before_walls = size_t(internals_->targets.bodies + internals_->targets.goals + 1);
  std::vector<double> out(contact_factor_.begin(), contact_factor_.begin() + long(before_walls));
  out.insert(out.end(), contact_factor_.begin() + long(before_walls) + internals_->targets.walls, contact_factor_.end());
  return out;
}

void World::set_contact_factors(std::span<const double> factors) {
  const TargetSlots& targets = internals_->targets;
  const size_t walls = size_t(targets.walls), n = contact_factor_.size() - walls;
  if (factors.size() != n)
    throw std::invalid_argument("got " + std::to_string(factors.size()) + " contact factors for " + std::to_string(n) +
                                " contacts");
  for (size_t k = 0; k < n; ++k)
    if (!(std::isfinite(factors[k]) && factors[k] >= 0))
      throw std::invalid_argument("contact factor " + std::to_string(k) + " must be a finite number >= 0");
  // Bodies, goals and out come before the walls' slots, the landings after them.
  const size_t before_walls = size_t(targets.bodies + targets.goals + 1);
  for (size_t k = 0; k < n; ++k) contact_factor_[k < before_walls ? k : k + walls] = factors[k];
}

void World::drop(int spot, std::vector<Event>& events) {
  if (spot < 0 || spot >= int(field_.spots.size()))
    throw std::invalid_argument("no respawn spot " + std::to_string(spot) + " (the field has " +
                                std::to_string(field_.spots.size()) + ")");
  const Vec2 at = field_.spots[spot].at;
  cloud_.clear();
  // On a field with height the ball lies on the floor.
  if (field_.has_height()) cloud_.push(Vec3{at.x, at.y, field_.ball_radius}, Vec3{}, 1, 1);
  else cloud_.push(at.x, at.y, 0, 0, 1, 1);
  clear_purgatory();
  forget_tweak();
  live_ = true;
  holder_ = -1;
  last_touch_ = -1;
  ++version_;
  events.push_back({time_, EventType::Drop, spot, 1, 1, 1, at, {0, 0}});
}

// On a flat field the step and the prediction trace frictionless paths over flight times
// (Field::flight_time), and the step then slows the velocities by e^(-kt): the prediction stays
// exact, and without friction nothing changes. With height only a rolling particle slows, which
// the tracer knows (Sky::roll): its time is the time itself.
float World::flight(float seconds) const { return field_.has_height() ? seconds : field_.flight_time(seconds); }

void World::check_body(int body) const {
  if (body < 0 || body >= int(field_.bodies.size()))
    throw std::invalid_argument("no body " + std::to_string(body) + " (the field has " +
                                std::to_string(field_.bodies.size()) + ")");
}

void World::give(int body) {
  check_body(body);
  if (!field_.bodies[body].catches)
    throw std::invalid_argument(field_.bodies[body].name + " cannot hold the ball: its field body does not catch");
  cloud_.clear();
  clear_purgatory();
  forget_tweak();
  live_ = false;
  holder_ = body;
  last_touch_ = body;  // whoever throws it next passes it, or loses it to the other team
  ++version_;
}

// Where a throw leaves the hand: at arm's length from the holder in the throw's direction, just
// outside its reach, so the thrower does not catch its own throw at once; a wall, a goal line or
// the bounds on the way stop it short (the ball then meets them in the first step).
Vec2 World::release_point(int body, Vec2 direction) const {
  const detail::Geometry& g = internals_->geometry;
  const detail::Box& b = g.bounds;
  const float inset = g.r + 1e-3f;
  const Vec2 p = body_pos_[size_t(body)];
  detail::Mover m{std::clamp(p.x, b.x0 + inset, b.x1 - inset), std::clamp(p.y, b.y0 + inset, b.y1 - inset), 0, 0, 0, 0};
  detail::settle(g, nullptr, 0, 0, m, false);
  // Toward the point at arm's length (Field::release_point), stopping short of a wall or the bounds.
  const Vec2 arm = field_.release_point(body, p, {p.x + direction.x, p.y + direction.y});
  m.ux = m.vx = arm.x - p.x, m.uy = m.vy = arm.y - p.y;
  const detail::Hit hit = detail::next_hit(g, nullptr, 0, m, 0, 1, false);
  const float t = hit.kind == detail::HitKind::None ? 1.0f : hit.dt;
  return {m.x + m.ux * t, m.y + m.uy * t};
}

void World::release(int body, Vec3 velocity, ThrowSpread spread, std::vector<Event>& events, Release how) {
  if (body < 0 || body != holder_)
    throw std::invalid_argument(
        (body >= 0 && body < int(field_.bodies.size()) ? field_.bodies[body].name : "body " + std::to_string(body)) +
        " does not hold the ball" + (holder_ >= 0 ? " (" + field_.bodies[holder_].name + " does)" : ""));
  const bool tall = field_.has_height();
  if (const std::string fault = throw_fault(velocity, tall); !fault.empty()) throw std::invalid_argument(fault);
  const float flat = std::hypot(velocity.x, velocity.y);
  check_spread(spread);
  // Straight up, the ball leaves the hand on the side facing the field's middle.
  const Vec2 middle{0.5f * (field_.bounds_min.x + field_.bounds_max.x), 0.5f * (field_.bounds_min.y + field_.bounds_max.y)};
  const Vec2 p = body_pos_[size_t(body)];
  const float to_middle = std::hypot(middle.x - p.x, middle.y - p.y);
  const Vec2 direction = flat > 0 ? Vec2{velocity.x / flat, velocity.y / flat}
                         : to_middle > 0 ? Vec2{(middle.x - p.x) / to_middle, (middle.y - p.y) / to_middle}
                                         : Vec2{1, 0};
  const Vec2 at = release_point(body, direction);
  cloud_.clear();
  const bool kick = how == Release::Kick;
  if (kick && tall && velocity.z == 0) spread.elevation = 0;  // along the floor
  const float hand = !tall ? 0 : kick ? field_.ball_radius : std::min(body_top_[size_t(body)], internals_->sky.ceiling - 1e-3f);
  release_at({at.x, at.y, hand}, velocity, spread, kick && tall);
  cloud_.normalize();
  clear_purgatory();
  forget_tweak();
  live_ = true;
  holder_ = -1;
  last_touch_ = body;
  ++version_;
  events.push_back({time_, kick ? EventType::Kick : EventType::Throw, body, 1, 1, config_.particles, at,
                    {velocity.x, velocity.y}, tall ? hand : 0.0f, tall ? velocity.z : 0.0f});
}

World::Launch World::launch_of(Vec3 velocity) {
  const float flat = std::hypot(velocity.x, velocity.y);
  return {std::hypot(flat, velocity.z), std::atan2(velocity.y, velocity.x), std::atan2(velocity.z, flat)};
}

// Box-Muller: two standard normal numbers from two uniform ones. A flat launch scatters by one
// pair (direction, speed), one with height by two (and elevation).
Vec3 World::scattered(const Launch& l, ThrowSpread spread) {
  auto normal_pair = [&](float& a, float& b) {
    const double radius = std::sqrt(-2 * std::log(1 - rng_.uniform())), angle = 2 * std::numbers::pi * rng_.uniform();
    a = float(radius * std::cos(angle)), b = float(radius * std::sin(angle));
  };
  float n1, n2;
  normal_pair(n1, n2);
  const float h = l.heading + spread.direction * n1;
  // A launch never turns back on itself: the slowest particles keep a twentieth of its speed.
  const float s = l.speed * std::max(0.05f, 1 + spread.speed * n2);
  if (!field_.has_height()) return {s * std::cos(h), s * std::sin(h), 0};
  float n3, unused;
  normal_pair(n3, unused);
  const float e = l.elevation + spread.elevation * n3;
  return {s * std::cos(e) * std::cos(h), s * std::cos(e) * std::sin(h), s * std::sin(e)};
}

void World::release_at(Vec3 at, Vec3 velocity, ThrowSpread spread, bool from_floor) {
  const Launch l = launch_of(velocity);
  const bool tall = field_.has_height();
  for (uint32_t i = 0; i < config_.particles; ++i) {
    Vec3 v = scattered(l, spread);
    if (from_floor && v.z < 0) v.z = 0;
    if (tall) cloud_.push(at, v, 1, 1);
    else cloud_.push(at.x, at.y, v.x, v.y, 1, 1);
  }
}

void World::set_cloud(Cloud c) {
  const detail::Geometry& g = internals_->geometry;
  const bool tall = field_.has_height();
  if (tall && (c.z.size() != c.size() || c.vz.size() != c.size()))
    throw std::invalid_argument("the field has height: every particle needs z and vz");
  if (!tall && c.tall()) throw std::invalid_argument("the field is flat: particles have no height");
  for (size_t i = 0; i < c.size(); ++i) {
    const std::string which = "particle " + std::to_string(i) + ": ";
    if (tall && !(std::isfinite(c.z[i]) && std::isfinite(c.vz[i]) && c.z[i] >= g.r - 1e-4f &&
                  c.z[i] <= internals_->sky.ceiling + 1e-4f))
      throw std::invalid_argument(which + "height must be finite, the ball above the floor and below the ceiling");
    if (!std::isfinite(c.x[i]) || !std::isfinite(c.y[i]) || !std::isfinite(c.vx[i]) || !std::isfinite(c.vy[i]))
      throw std::invalid_argument(which + "position and velocity must be finite");
    if (!(c.w[i] >= 0 && std::isfinite(c.w[i]) && c.tw[i] >= 0 && std::isfinite(c.tw[i])))
      throw std::invalid_argument(which + "weights must be finite and >= 0");
    detail::Mover m{c.x[i], c.y[i], 0, 0, 0, 0};
    if (!g.bounds.contains(m.x, m.y)) throw std::invalid_argument(which + "lies outside the field's bounds");
    if (detail::settle(g, nullptr, 0, 0, m, false).kind != detail::HitKind::None || m.x != c.x[i] || m.y != c.y[i])
      throw std::invalid_argument(which + "overlaps a wall");
  }
  c.fate.assign(c.size(), Cloud::kNoFate);
  c.normalize();
  if (c.empty() || c.mass != 1) throw std::invalid_argument("the cloud needs particles with positive total weight");
  cloud_ = std::move(c);
  clear_purgatory();
  forget_tweak();
  live_ = true;
  holder_ = -1;
  ++version_;
}

void World::check_input(float dt, std::span<const BodyInput> input) const {
  if (!(std::isfinite(dt) && dt > 0 && dt <= 0.1f))
    throw InputError("step length must be a finite number of seconds in (0, 0.1], got " + std::to_string(dt));
  check_bodies(input);
}

BodyFault body_fault(const Field& field, const BodyInput& in) {
  // A body further than a field's size beyond the bounds is a tracking fault, not a player.
  const float slack = std::max(field.bounds_max.x - field.bounds_min.x, field.bounds_max.y - field.bounds_min.y);
  if (!std::isfinite(in.position.x) || !std::isfinite(in.position.y)) return BodyFault::Position;
  if (!std::isfinite(in.velocity.x) || !std::isfinite(in.velocity.y)) return BodyFault::Velocity;
  if (in.position.x < field.bounds_min.x - slack || in.position.x > field.bounds_max.x + slack ||
      in.position.y < field.bounds_min.y - slack || in.position.y > field.bounds_max.y + slack)
    return BodyFault::FarOut;
  if (std::hypot(in.velocity.x, in.velocity.y) > field.max_body_speed) return BodyFault::TooFast;
  return BodyFault::None;
}

void check_spread(ThrowSpread spread) {
  using limits::kSpreadRadians, limits::kSpeedSpread;
  if (!(kSpreadRadians.contains(spread.direction) && kSpeedSpread.contains(spread.speed) &&
        kSpreadRadians.contains(spread.elevation)))
    throw std::invalid_argument("a throw's spread must be in " + limits::stated(kSpreadRadians) +
                                " of direction and elevation and " + limits::stated(kSpeedSpread) + " of speed");
}

std::string throw_fault(Vec3 velocity, bool tall) {
  const float flat = std::hypot(velocity.x, velocity.y), speed = std::hypot(flat, velocity.z);
  if (!limits::kThrowSpeed.contains(speed)) return "a throw's speed " + limits::must_be_in(limits::kThrowSpeed, speed);
  if (!tall && velocity.z != 0) return "a throw upward needs a field with height (gravity); this field is flat";
  return "";
}

void World::check_bodies(std::span<const BodyInput> input) const {
  if (input.size() != field_.bodies.size())
    throw InputError("the field has " + std::to_string(field_.bodies.size()) + " bodies but the input moves " +
                     std::to_string(input.size()));
  // Messages are built only for a body that fails: checking runs every frame.
  auto who = [&](size_t k) { return "body " + std::to_string(k) + " (" + field_.bodies[k].name + "): "; };
  auto position = [](const BodyInput& in) {
    return "position (" + std::to_string(in.position.x) + ", " + std::to_string(in.position.y) + ")";
  };
  for (size_t k = 0; k < input.size(); ++k) {
    const BodyInput& in = input[k];
    switch (body_fault(field_, in)) {
      case BodyFault::None: break;
      case BodyFault::Position: throw InputError(who(k) + position(in) + " is not finite");
      case BodyFault::Velocity: throw InputError(who(k) + "velocity is not finite");
      case BodyFault::FarOut: throw InputError(who(k) + position(in) + " is far outside the field");
      case BodyFault::TooFast:
        throw InputError(who(k) + "speed " + std::to_string(std::hypot(in.velocity.x, in.velocity.y)) +
                         " m/s is above the field's max_body_speed " + std::to_string(field_.max_body_speed));
    }
  }
}

void World::step(float dt, std::span<const BodyInput> input, std::vector<Event>& events) {
  check_input(dt, input);
  const int nb = int(field_.bodies.size());
  for (int k = 0; k < nb; ++k)
    motion_[k] = {body_pos_[k], input[k].position, input[k].velocity, field_.bodies[k].radius, body_top_[k], passes_now(k)};
  ++step_;
  time_ += dt;
  last_dt_ = dt;
  // The oldest purgatory slot falls out; this step's contacts go in its place.
  PurgatorySlot& slot = purgatory_[step_ % config_.purgatory_frames];
  slot.touched.clear(), slot.body.clear();
  slot.step = step_;
  if (live_) {
    // Loose or not as the last prediction (or the match's watch) saw the ball: a catch is told as
    // the fate it was tweaked as. A world nobody predicts sums the ball's motion only when a catch
    // is realized: a pass over the cloud every step cost a 3D step half its time again.
    std::optional<bool> loose_seen;
    if (motion_version_ == version_) loose_seen = ball_motion_.speed < kLooseSpeed;
    contacts_.clear();
    const StepContext ctx{flight(dt), motion_.data(), nb, step_key(config_.seed, step_),
                          noise_amplitude(field_.brownian, dt)};
    backend_->advance(cloud_, ctx, contacts_);
    if (field_.friction > 0 && !field_.has_height()) {
      const float slow = std::exp(-field_.friction * dt);
      float* __restrict vx = cloud_.vx.data();
      float* __restrict vy = cloud_.vy.data();
      for (size_t i = 0; i < cloud_.size(); ++i) vx[i] *= slow, vy[i] *= slow;
    }
    ++version_;
    decide(dt, loose_seen, events);
  }
  for (int k = 0; k < nb; ++k) body_pos_[k] = input[k].position, body_vel_[k] = input[k].velocity;
  if (live_ && cloud_.size() < config_.particles) split_round(false);
}

void World::set_wormholes(std::vector<Wormhole> wormholes) {
  const detail::Geometry& g = internals_->geometry;
  for (size_t k = 0; k < wormholes.size(); ++k) {
    const Wormhole& w = wormholes[k];
    const std::string which = "wormhole " + std::to_string(k) + ": ";
    if (!(std::isfinite(w.radius) && w.radius > 0)) throw std::invalid_argument(which + "radius must be > 0");
    for (Vec2 p : {w.a, w.b}) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !g.bounds.contains(p.x, p.y))
        throw std::invalid_argument(which + "a mouth lies outside the field");
      // A ball coming out anywhere in the mouth must not overlap a wall.
      for (size_t s = 0; s < g.ax.size(); ++s) {
        const float px = p.x - g.ax[s], py = p.y - g.ay[s];
        const float along = std::clamp(px * g.tx[s] + py * g.ty[s], 0.0f, g.len[s]);
        if (std::hypot(px - along * g.tx[s], py - along * g.ty[s]) < w.radius + g.r)
          throw std::invalid_argument(which + "a mouth is within a ball's radius of a wall");
      }
    }
  }
  backend_->set_wormholes(wormholes);
  internals_->geometry.set_wormholes(wormholes);
  wormholes_ = std::move(wormholes);
  ++version_;
}

void World::place_bodies(std::span<const BodyInput> input) {
  check_bodies(input);
  for (size_t k = 0; k < input.size(); ++k) body_pos_[k] = input[k].position, body_vel_[k] = input[k].velocity;
  ++version_;
}

void World::set_reach(int body, float height) {
  if (!field_.has_height()) throw std::logic_error("a flat field has no heights to reach");
  check_body(body);
  if (!(height > 0 && height <= 100)) throw std::invalid_argument("a reach must be in (0, 100] m");
  body_top_[size_t(body)] = height;
  ++version_;
}

void World::plan_hit(int body, const HitPlan& plan) {
  check_body(body);
  const std::string who = field_.bodies[body].name;
  if (!field_.bodies[body].hits) throw std::invalid_argument(who + " does not hit the ball: its field body does not hit");
  const bool tall = field_.has_height();
  switch (plan.kind) {
    case HitPlan::Kind::Motion: break;
    case HitPlan::Kind::Velocity:
      if (const std::string fault = throw_fault(plan.velocity, tall); !fault.empty())
        throw std::invalid_argument(who + "'s hit: " + fault);
      break;
    case HitPlan::Kind::Point:
      for (float c : {plan.point.x, plan.point.y, plan.point.z})
        if (!std::isfinite(c)) throw std::invalid_argument(who + "'s hit: the point it aims at must be finite");
      limits::check(limits::kThrowSpeed, plan.speed, who + "'s hit: speed");
      if (!(plan.elevation >= 0 && plan.elevation < 1.5708f))
        throw std::invalid_argument(who + "'s hit: elevation must be in [0, 90) degrees");
      if (plan.elevation > 0 && !tall) throw std::invalid_argument(who + "'s hit: an elevation needs a field with height");
      break;
  }
  check_spread(plan.spread);
  planned_[size_t(body)] = plan;
}

Vec3 World::hit_velocity(const HitPlan& plan) const {
  if (plan.kind == HitPlan::Kind::Velocity) return plan.velocity;
  Vec3 from;
  for (size_t i = 0; i < cloud_.size(); ++i) {
    const float w = float(cloud_.weight(i));
    from.x += w * cloud_.x[i], from.y += w * cloud_.y[i], from.z += cloud_.tall() ? w * cloud_.z[i] : 0;
  }
  const float dx = plan.point.x - from.x, dy = plan.point.y - from.y, d = std::hypot(dx, dy);
  if (!field_.has_height()) return d > 0 ? Vec3{plan.speed * dx / d, plan.speed * dy / d, 0} : Vec3{};
  const Vec3 to{plan.point.x, plan.point.y, std::max(plan.point.z, field_.ball_radius)};
  const Vec3 arc = plan.elevation > 0 ? field_.arc_velocity(from, to, plan.elevation) : Vec3{};
  return arc.x != 0 || arc.y != 0 || arc.z != 0 ? arc : field_.throw_at(from, to, plan.speed);
}

void World::aim_hit(int body) {
  pass_until_[size_t(body)] = time_ + field_.rehit;
  HitPlan& plan = planned_[size_t(body)];
  const Vec3 velocity = plan.kind == HitPlan::Kind::Motion ? Vec3{} : hit_velocity(plan);
  const ThrowSpread spread = plan.spread;
  plan = {};  // a plan is for one touch
  // Off the hitter's motion, as off a mallet; and a point the ball is met on is no aim.
  if (!throw_fault(velocity, field_.has_height()).empty()) return;
  const Launch l = launch_of(velocity);
  const bool tall = field_.has_height();
  for (size_t i = 0; i < cloud_.size(); ++i) {
    const Vec3 v = scattered(l, spread);
    cloud_.vx[i] = v.x, cloud_.vy[i] = v.y;
    if (tall) cloud_.vz[i] = v.z;
  }
}

void World::challenge(std::span<const Challenge> challengers, std::vector<Event>& events) {
  if (holder_ < 0) throw std::invalid_argument("nobody holds the ball to take");
  double total = 0;
  for (const Challenge& c : challengers) {
    check_body(c.body);
    if (!field_.bodies[c.body].catches || c.body == holder_)
      throw std::invalid_argument(field_.bodies[c.body].name + " cannot take the ball: " +
                                  (c.body == holder_ ? "it holds it" : "its field body does not catch"));
    if (!(c.chance >= 0 && c.chance <= 1 && c.chance_newtonian >= 0 && c.chance_newtonian <= 1))
      throw std::invalid_argument("a chance to take the ball must be in [0, 1]");
    total += c.chance;
  }
  if (!(total <= 1 + 1e-9)) throw std::invalid_argument("the chances to take the ball sum past 1");
  if (challengers.empty()) return;
  const double u = rng_.uniform();
  decision_.t = time_;
  decision_.u = u;
  decision_.options.clear();
  decision_.shares.clear(), decision_.fates.clear(), decision_.fate_factors.clear();
  decision_.rest_mass = decision_.rest_weight = 0;
  decision_.all_met = false;
  decision_.realized = -1;
  double cumulative = 0;
  for (const Challenge& c : challengers) {
    cumulative += c.chance;
    if (decision_.realized < 0 && u < cumulative) decision_.realized = int(decision_.options.size());
    Decision::Option o{Target{TargetKind::Tackle, uint16_t(c.body)}, c.chance, c.chance_newtonian, 0};
    o.factor = c.factor;
    decision_.options.push_back(o);
  }
  decided_step_ = step_;
  if (decision_.realized < 0) return;
  const Challenge& c = challengers[size_t(decision_.realized)];
  events.push_back({time_, EventType::Tackle, c.body, c.chance, c.chance_newtonian, 0, body_pos_[size_t(c.body)], {0, 0}});
  holder_ = c.body;
  last_touch_ = c.body;
  ++version_;
}

void World::set_last_touch(int body) {
  if (body != -1) check_body(body);
  last_touch_ = body;
  ++version_;
}

const BallMotion& World::motion() const {
  if (motion_version_ == version_) return ball_motion_;
  motion_version_ = version_;
  const Cloud& c = cloud_;
  const float *x = c.x.data(), *y = c.y.data(), *vx = c.vx.data(), *vy = c.vy.data(), *vz = c.vz.data();
  const double* w = c.w.data();
  const bool tall = c.tall();
  double cx = 0, cy = 0, mvx = 0, mvy = 0, speed = 0, mass = 0;
  for (size_t i = 0; live_ && i < c.size(); ++i) {
    const double up = tall ? double(vz[i]) : 0.0;
    cx += w[i] * x[i], cy += w[i] * y[i], mvx += w[i] * vx[i], mvy += w[i] * vy[i];
    speed += w[i] * std::sqrt(double(vx[i]) * vx[i] + double(vy[i]) * vy[i] + up * up);
    mass += w[i];
  }
  ball_motion_ = mass > 0 ? BallMotion{{float(cx / mass), float(cy / mass)}, {float(mvx / mass), float(mvy / mass)}, speed / mass}
                          : BallMotion{};
  return ball_motion_;
}

void World::decide(float dt, std::optional<bool> loose_seen, std::vector<Event>& events) {
  if (contacts_.empty()) return;
  // Particle order makes the draw and the purgatory independent of the backend's visiting order.
  std::sort(contacts_.begin(), contacts_.end(),
            [](const Contact& a, const Contact& b) { return a.particle < b.particle; });
  const TargetSlots& targets = internals_->targets;
  const int n_targets = targets.size();
  std::vector<Tally>& tally = internals_->tally;
  std::fill(tally.begin(), tally.end(), Tally{});
  PurgatorySlot& slot = purgatory_[step_ % config_.purgatory_frames];
  removed_.clear();
  // Which fate groups each option's particles came from, for the log: a place per target and
  // group (the last for particles of no group), filled as met and reset after.
  const size_t fates = tweak_groups_.size() + 1;
  share_at_.resize(size_t(n_targets) * fates, -1);
  decision_.shares.clear();
  const double* contact = contact_factor_.data();
  // Contacts are scattered over a cloud of up to millions: fetch a few ahead, or every one of
  // them waits for memory.
  constexpr size_t kAhead = 8;
  for (size_t k = 0; k < contacts_.size(); ++k) {
    if (k + kAhead < contacts_.size()) {
      const uint32_t ahead = contacts_[k + kAhead].particle;
      for (const void* p : {(const void*)&cloud_.w[ahead], (const void*)&cloud_.tw[ahead], (const void*)&cloud_.x[ahead],
                            (const void*)&cloud_.y[ahead], (const void*)&cloud_.vx[ahead], (const void*)&cloud_.vy[ahead],
                            (const void*)&cloud_.fate[ahead]})
        __builtin_prefetch(p);
    }
    const Contact& c = contacts_[k];
    removed_.push_back(c.particle);
    if (c.target.kind == TargetKind::Crushed) continue;
    const int at = targets.slot(c.target);
    Tally& t = tally[size_t(at)];
    const double w = cloud_.w[c.particle], carried = cloud_.tw[c.particle];
    t.tweaked += c.target.kind == TargetKind::Wall ? carried : w * contact[at];
    t.carried += carried, t.newtonian += w, ++t.count;
    t.cx += w * cloud_.x[c.particle], t.cy += w * cloud_.y[c.particle];
    if (c.target.kind == TargetKind::Body) slot.touched.push_from(cloud_, c.particle), slot.body.push_back(c.target.index);
    const uint32_t fate = cloud_.fate[c.particle];
    int32_t& share = share_at_[size_t(at) * fates + (fate == Cloud::kNoFate ? fates - 1 : fate)];
    if (share < 0) share = int32_t(decision_.shares.size()), decision_.shares.push_back({fate, 0, 0});
    decision_.shares[size_t(share)].mass += w, ++decision_.shares[size_t(share)].particles;
  }
  // The chance that the ball met target k is the weight that met it over the cloud's, where the
  // particles that met something count with their option's weight. When nothing is left in the
  // field something must have happened, so the draw is conditioned on the contacts.
  const bool nothing_left = removed_.size() == cloud_.size();
  double options = 0, carried = 0, options_newtonian = 0;
  for (const Tally& t : tally) options += t.tweaked, carried += t.carried, options_newtonian += t.newtonian;
  const double rest = nothing_left ? 0 : std::max(0.0, cloud_.tmass - carried);
  const double total = rest + options;
  const double total_newtonian = nothing_left ? options_newtonian : cloud_.mass;
  int realized = -1;
  const double u = rng_.uniform();
  if (total > 0) {
    const double drawn = u * total;
    double cumulative = 0;
    for (int k = 0; k < n_targets && realized < 0; ++k) {
      if (tally[k].count == 0) continue;
      cumulative += tally[k].tweaked;
      if (drawn < cumulative) realized = k;
    }
    // Rounding may leave the draw a hair above the sum when the contacts are all there is.
    if (realized < 0 && nothing_left)
      for (int k = n_targets; k-- > 0 && realized < 0;)
        if (tally[k].count > 0 && tally[k].tweaked > 0) realized = k;
  }
  // What the draw was about and what made it, for whoever asks why (the decision log, a view).
  const double unit = cloud_.mass;  // the log's masses are fractions of the cloud
  decision_.t = time_;
  decision_.u = u;
  decision_.options.clear();
  decision_.realized = -1;
  decision_.all_met = nothing_left;
  decision_.rest_mass = (cloud_.mass - options_newtonian) / unit;
  decision_.rest_weight = rest / unit;
  decision_.fates.assign(tweak_groups_.begin(), tweak_groups_.end());
  decision_.fate_factors.assign(tweak_factors_.begin(), tweak_factors_.end());
  for (size_t g = 0; g < decision_.fates.size(); ++g) {
    decision_.fates[g].mass = fate_mass_[g] / unit;
    decision_.fates[g].tweaked_mass = decision_.fates[g].mass * tweak_factors_[g] / (cloud_.tmass / unit);
  }
  // The shares in option order, each option's together.
  std::vector<Decision::Share>& shares = decision_.shares;
  const size_t met = shares.size();
  for (int k = 0; k < n_targets; ++k) {
    if (tally[k].count == 0) continue;
    if (k == realized) decision_.realized = int(decision_.options.size());
    Decision::Option o{targets.at(k), total > 0 ? tally[k].tweaked / total : 0,
                       total_newtonian > 0 ? tally[k].newtonian / total_newtonian : 0, tally[k].count};
    o.mass = tally[k].newtonian / unit, o.weight = tally[k].tweaked / unit, o.factor = contact[k];
    o.first_share = uint32_t(shares.size() - met);
    for (size_t g = 0; g < fates; ++g) {
      int32_t& share = share_at_[size_t(k) * fates + g];
      if (share < 0) continue;
      Decision::Share copy = shares[size_t(share)];
      copy.mass /= unit;
      shares.push_back(copy);
      share = -1;
      ++o.shares;
    }
    decision_.options.push_back(o);
  }
  shares.erase(shares.begin(), shares.begin() + long(met));
  decided_step_ = step_;
  if (realized < 0) {
    for (uint32_t i : removed_)
      if (cloud_.fate[i] != Cloud::kNoFate) fate_mass_[cloud_.fate[i]] -= cloud_.w[i];
    cloud_.remove_sorted(removed_);
    if (cloud_.empty()) {
      remove_ball();
    } else if (!(cloud_.mass > 1e-3 && cloud_.tmass > 1e-3 * tmass_full_)) {
      // The sums are kept by subtraction; re-sum once they have shrunk a thousandfold, long
      // before rounding could show in the normalized weights (a pass every few hundred steps).
      const double scale = cloud_.normalize();
      for (double& m : fate_mass_) m /= scale;
      tmass_full_ = cloud_.tmass;
    }
    return;
  }
  const Tally& t = tally[size_t(realized)];
  const Target target = targets.at(realized);
  Event e{time_, EventType::Hit, target.index, t.tweaked / total, t.newtonian / total_newtonian, t.count,
          Vec2{float(t.cx / t.newtonian), float(t.cy / t.newtonian)}, Vec2{0, 0}};
  switch (target.kind) {
    case TargetKind::Body:
      if (field_.bodies[target.index].catches) {
        e.type = ending_at(target.index, loose_seen ? *loose_seen : loose()) == FateKind::Pickup ? EventType::Pickup
                                                                                        : EventType::Catch;
        give(target.index);
        break;
      }
      [[fallthrough]];
    case TargetKind::Wall:
    case TargetKind::Landing:
      if (target.kind == TargetKind::Body) {
        realize_body(target.index, dt);
      } else {
        // A landing is a bounce whose place matters: the ball goes on from the floor, and the
        // rules say whether that ends anything.
        e.type = target.kind == TargetKind::Landing ? EventType::Landing : EventType::Bounce;
        if (target.kind == TargetKind::Landing) e.actor = int(target.index) - 1;
        realize_bounce(target);
      }
      for (size_t i = 0; i < cloud_.size(); ++i)
        e.velocity.x += float(cloud_.weight(i) * cloud_.vx[i]), e.velocity.y += float(cloud_.weight(i) * cloud_.vy[i]);
      if (cloud_.tall())
        for (size_t i = 0; i < cloud_.size(); ++i)
          e.height += float(cloud_.weight(i) * cloud_.z[i]), e.up += float(cloud_.weight(i) * cloud_.vz[i]);
      break;
    case TargetKind::Goal: {
      const bool own = last_touch_ >= 0 && field_.bodies[last_touch_].team == field_.goals[target.index].team;
      e.type = own ? EventType::OwnGoal : EventType::Goal;
      remove_ball();
      break;
    }
    case TargetKind::Out:
    case TargetKind::Crushed:
    case TargetKind::Tackle:  // no particle's target: never in a tally
      e.type = EventType::Out;
      e.actor = -1;
      remove_ball();
      break;
  }
  events.push_back(e);
}

void World::remove_ball() {
  cloud_.clear();
  clear_purgatory();
  forget_tweak();
  live_ = false;
  holder_ = -1;
  ++version_;
}

namespace {

// The particles `body` touched in `slot`, carried forward `span` of flight time to now (slowed by
// `slow`, friction's share) into `out`. They are the ball after this contact, so they meet walls
// only; one that went in or out meanwhile is dropped, and one a body has since moved over is
// lifted out of it. Bouncing off a wall meanwhile is part of the flight.
template <class Space>
void catch_up(detail::StepTracer<Space>& tracer, const detail::Geometry& g, detail::BodyPath* now, int nb,
              const PurgatorySlot& slot, int body, float span, float slow, Cloud& out) {
  const Cloud& from = slot.touched;
  auto keep = [&](uint32_t i, const typename Space::Mover& m, detail::Outcome outcome) {
    if (outcome.kind != detail::HitKind::None && outcome.kind != detail::HitKind::Wall) return;
    detail::Mover flat = Space::shadow(m);
    // A particle above a body's hands (a ball met on top of them) is not inside it: only the
    // bodies it is level with lift it out, or a dig would leave from the hitter's side.
    if constexpr (Space::kHeight)
      for (int k = 0; k < nb; ++k) now[k].passes = m.z > now[k].top + g.r;
    if (detail::settle(g, now, nb, 0, flat, true).kind != detail::HitKind::None) return;
    if constexpr (Space::kHeight) out.push(Vec3{flat.x, flat.y, m.z}, Vec3{m.vx, m.vy, m.vz}, from.w[i], from.w[i]);
    else out.push(flat.x, flat.y, flat.vx * slow, flat.vy * slow, from.w[i], from.w[i]);
  };
  tracer.begin(nullptr, 0, span);
  for (size_t i = 0; i < from.size(); ++i) {
    if (slot.body[i] != body) continue;
    if (span == 0) keep(uint32_t(i), Space::ball(from, i), {detail::HitKind::None, -1});
    else tracer.add(uint32_t(i), Space::ball(from, i), false, keep);
  }
  tracer.finish_all(keep);
}

}  // namespace

void World::realize_body(int body, float dt) {
  // The shot is every particle this body touched within the purgatory window. Older ones are
  // carried forward to now (walls only: they are the ball after this contact) and lifted out of
  // any body that has since moved over them.
  const detail::Geometry& g = internals_->geometry;
  const int nb = int(field_.bodies.size());
  std::vector<detail::BodyPath>& now = internals_->resting;
  for (int k = 0; k < nb; ++k) {
    const Vec2 p = motion_[k].to;
    now[k] = {p.x, p.y, 0, 0, 0, 0, 0, field_.bodies[k].radius, body_top_[k]};
  }
  scratch_.clear();
  for (uint32_t age = config_.purgatory_frames; age-- > 0;) {
    if (age >= step_) continue;
    const PurgatorySlot& slot = purgatory_[(step_ - age) % config_.purgatory_frames];
    if (slot.step != step_ - age) continue;
    internals_->on_space([&](const auto& space) {
      using Space = std::decay_t<decltype(space)>;
      catch_up(internals_->tracer<Space>(), g, now.data(), nb, slot, body, flight(float(age) * dt),
               field_.friction > 0 && !field_.has_height() ? std::exp(-field_.friction * float(age) * dt) : 1.0f,
               scratch_);
    });
  }
  std::swap(cloud_, scratch_);
  clear_purgatory();
  forget_tweak();
  last_touch_ = body;
  ++version_;
  if (cloud_.empty()) {  // every particle of the shot went in or out while catching up
    remove_ball();
    return;
  }
  cloud_.normalize();
  // Particles split at the moment of collision leave in slightly different directions (a mallet's
  // rough surface), so the shot fans out instead of repeating one path. A planned hit scatters
  // every particle afresh instead.
  const bool hitter = field_.bodies[body].hits;
  refill(!(hitter && planned_[size_t(body)].kind != HitPlan::Kind::Motion));
  if (hitter) aim_hit(body);
}

void World::realize_bounce(Target wall) {
  // The ball is what bounced off the wall in this step, with the weights it had. Unlike a shot,
  // a bounce starts no new flight: the particles keep their tweak and fates, a wall is smooth
  // (no fanning out), and earlier bounces are not revived. Reviving them, as a body's purgatory
  // does, mixes in flights that met the wall at other times and skewed the outcomes away from the
  // tweaked odds (chi-square 452 on 16 degrees of freedom in Property.RealizedOutcomes...).
  scratch_.clear();
  for (const Contact& c : contacts_)
    if (c.target == wall) scratch_.push_from(cloud_, c.particle);
  std::swap(cloud_, scratch_);
  clear_purgatory();
  ++version_;
  cloud_.normalize();
  sum_fate_mass();
  refill(false);
}

void World::refill(bool jitter) {
  while (cloud_.size() < config_.particles) {
    const size_t before = cloud_.size();
    split_round(jitter);
    if (cloud_.size() == before) break;
  }
}

void World::split_round(bool jitter) {
  const size_t target = config_.particles, n = cloud_.size();
  if (n >= target) return;
  const double threshold = cloud_.mass / double(target);
  // Copies are written into room made once: after a rejected bounce this round makes hundreds of
  // thousands of them, and a push_back per array per copy was the round's main cost.
  const bool tall = cloud_.tall();
  for (auto* v : {&cloud_.x, &cloud_.y, &cloud_.vx, &cloud_.vy}) v->resize(target);
  for (auto* v : {&cloud_.w, &cloud_.tw}) v->resize(target);
  cloud_.fate.resize(target);
  if (tall) cloud_.z.resize(target), cloud_.vz.resize(target);
  float *x = cloud_.x.data(), *y = cloud_.y.data(), *vx = cloud_.vx.data(), *vy = cloud_.vy.data();
  float *z = cloud_.z.data(), *vz = cloud_.vz.data();
  double *w = cloud_.w.data(), *tw = cloud_.tw.data();
  uint32_t* fate = cloud_.fate.data();
  size_t end = n;
  // Resume where the last round stopped: particles near the front were split already, and
  // scanning past them every step would cost a pass over the cloud.
  if (split_cursor_ >= n) split_cursor_ = 0;
  for (size_t seen = 0; seen < n && end < target; ++seen, split_cursor_ = split_cursor_ + 1 == n ? 0 : split_cursor_ + 1) {
    const size_t i = split_cursor_;
    if (w[i] <= threshold) continue;
    w[i] *= 0.5, tw[i] *= 0.5;
    float cvx = vx[i], cvy = vy[i];
    if (jitter) {
      const float a = float((2 * rng_.uniform() - 1) * config_.split_jitter);
      const float c = std::cos(a), s = std::sin(a);
      const float rx = c * cvx - s * cvy, ry = s * cvx + c * cvy;
      cvx = rx, cvy = ry;
    }
    x[end] = x[i], y[end] = y[i], vx[end] = cvx, vy[end] = cvy, w[end] = w[i], tw[end] = tw[i], fate[end] = fate[i];
    if (tall) z[end] = z[i], vz[end] = vz[i];
    ++end;
  }
  // Halving a particle and adding its copy keeps both sums as they were.
  for (auto* v : {&cloud_.x, &cloud_.y, &cloud_.vx, &cloud_.vy}) v->resize(end);
  for (auto* v : {&cloud_.w, &cloud_.tw}) v->resize(end);
  cloud_.fate.resize(end);
  if (tall) cloud_.z.resize(end), cloud_.vz.resize(end);
  ++version_;
}

void World::own_goals(std::vector<uint8_t>& own) const {
  own.assign(field_.goals.size(), 0);
  if (last_touch_ >= 0)
    for (size_t g = 0; g < own.size(); ++g) own[g] = field_.goals[g].team == field_.bodies[last_touch_].team;
}

}  // namespace quantum

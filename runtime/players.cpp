#include "players.h"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "quantum/narrow.h"

namespace quantum::runtime {

using Status = PlayerSource::Status;
using TrackingStatus = tracking::TrackingInput::Status;

HandPlayers::HandPlayers(const Field& field, std::vector<double> skills, uint64_t seed, double throw_speed, int body,
                         const Hand& hand)
    : bots_(field, std::move(skills), seed, throw_speed), field_(field), body_(body), hand_(hand), thrown_(hand.throws) {
  if (body < 0 || body >= int(field.bodies.size())) throw std::invalid_argument("no player " + std::to_string(body));
}

Status HandPlayers::advance(double t, const game::Match& match, bool waiting) {
  bots_.advance(t, match, waiting);
  const std::span<const BodyInput> bots = bots_.bodies();
  bodies_.assign(bots.begin(), bots.end());
  // The bots' throws, but none for the hand's player: the person throws it.
  throws_.clear();
  for (const game::Throw& th : bots_.throws())
    if (th.player != body_) throws_.push_back(th);
  const BodySpec& b = field_.bodies[size_t(body_)];
  const BodyInput before = match.players().empty() ? BodyInput{b.start, {0, 0}}
                                                   : BodyInput{match.players()[size_t(body_)].position, {0, 0}};
  Vec2 at = hand_.over ? hand_.at : before.position;
  at.x = std::clamp(at.x, field_.bounds_min.x + b.radius, field_.bounds_max.x - b.radius);
  at.y = std::clamp(at.y, field_.bounds_min.y + b.radius, field_.bounds_max.y - b.radius);
  const double dt = 1.0 / match.fps();
  Vec2 v{float((at.x - before.position.x) / dt), float((at.y - before.position.y) / dt)};
  const double speed = std::hypot(v.x, v.y), most = 0.99 * field_.max_body_speed;
  if (speed > most) {
    // A hand faster than the field allows moves the body as far as it may go.
    const float k = float(most / speed);
    v = {v.x * k, v.y * k};
    at = {float(before.position.x + v.x * dt), float(before.position.y + v.y * dt)};
  }
  bodies_[size_t(body_)] = {at, v};
  // A person's arm swings the way they have been moving, not only in the frame of the click: the
  // mouse often stops just before it. A tenth of a second of motion decides the throw.
  const float keep = float(std::exp(-dt / kThrowMemory));
  recent_ = {keep * recent_.x + (1 - keep) * v.x, keep * recent_.y + (1 - keep) * v.y};
  if (hand_.throws != thrown_) {
    thrown_ = hand_.throws;
    Vec2 way = recent_;
    if (std::hypot(way.x, way.y) < 0.5) {  // a still hand throws at the other team's goal
      way = {1, 0};
      for (const Goal& g : field_.goals)
        if (g.team != b.team) way = {0.5f * (g.a.x + g.b.x) - at.x, 0.5f * (g.a.y + g.b.y) - at.y};
    }
    const double l = std::hypot(way.x, way.y), speed = match.config().throw_speed;
    if (l > 0) throws_.push_back({body_, {float(speed * way.x / l), float(speed * way.y / l)}});
  }
  return Status::Ready;
}

TrackedPlayers::TrackedPlayers(const std::string& spec, const Field& field, const tracking::SourceOptions& options,
                               std::ostream* warnings, std::optional<Vec2> size, tracking::SetupOptions setup)
    : field_(field), spec_(spec), tracked_(tracking::tracked_field(field, size)), input_(spec, tracked_, options),
      setup_(spec, tracking::tracked_field(field), setup), warnings_(warnings),
      dropped_(spec, "tracking value", DroppedValues::kTrackingWhy, warnings) {
  for (const BodySpec& b : field.bodies) bodies_.push_back({b.start, {0, 0}});
}

Status TrackedPlayers::advance(double t, const game::Match& match, bool waiting) {
  throws_.clear();
  // A live source is asked at most once a frame of the match: a Kinect blocks until its next
  // frame, and asking every step would hold the match to the camera's 30 Hz.
  if (live() && seen_ && t < next_ask_) return Status::Ready;
  const double timeout = waiting ? 0.1 : 0.0;
  for (;;) {
    if (!pending_) {
      tracking::TrackedFrame f;
      const TrackingStatus s = input_.next(f, timeout);
      if (s == TrackingStatus::Calibrating) continue;  // the match waits for the source
      // Nothing new: the bodies stay as they are; before the first frame the match waits, and a
      // tracker that sends only what is dropped is told while it does.
      if (s == TrackingStatus::Waiting || s == TrackingStatus::Lost) dropped_.tell(t, input_.dropped());
      if (s == TrackingStatus::Waiting) return seen_ ? Status::Ready : Status::Lost;
      if (s == TrackingStatus::Lost) return Status::Lost;
      if (s == TrackingStatus::Ended) return Status::Ended;
      for (const std::string& line : setup_.check(f, input_, tracked_))
        if (warnings_) *warnings_ << "quantum: " << line << '\n';
      if (!t0_) t0_ = f.t - t;
      f.t -= *t0_;
      pending_ = std::move(f);
    }
    if (pending_->t > t + 1e-9 && !live()) return Status::Ready;  // not due yet
    apply(*pending_, match.config().throw_speed);
    dropped_.tell(t, input_.dropped());
    seen_ = true;
    next_ask_ = pending_->t + 1.0 / 60;
    pending_.reset();
    if (live()) return Status::Ready;
  }
}

void DroppedValues::tell(double t, size_t elsewhere, bool last) {
  const size_t dropped = dropped_ + elsewhere;
  if (dropped == told_ || (!last && t - told_at_ < kWarnEvery)) return;
  if (warnings_)
    *warnings_ << "quantum: " << source_ << ": " << dropped - told_ << ' ' << what_ << (dropped - told_ > 1 ? "s" : "")
               << " dropped (" << why_ << "; " << dropped << " in all)"
               << (last ? " by the end of the match\n" : ", the match goes on\n");
  told_ = dropped, told_at_ = t;
}

// Tracking glitches must not stop a match: positions stay within a field's size of the bounds
// and speeds under the field's limit, as the core requires (values that are not numbers, or far
// out of range, the input has dropped and counted).
void TrackedPlayers::apply(const tracking::TrackedFrame& f, double throw_speed) {
  for (BodyInput& b : bodies_) b.velocity = {0, 0};  // no input: the body holds still
  const float slack = 0.5f * std::max(field_.bounds_max.x - field_.bounds_min.x, field_.bounds_max.y - field_.bounds_min.y);
  // A flat field throws along the floor; one with height takes the throw's upward share too.
  const double tall = field_.has_height() ? 1.0 : 0.0;
  for (const tracking::TrackedAction& a : f.actions) {
    const double l = std::hypot(std::hypot(a.dx, a.dy), tall * a.dz);
    if (a.type != "throw" || !(l > 0)) continue;
    for (size_t k = 0; k < field_.bodies.size(); ++k)
      if (field_.bodies[k].tracked_as() == a.player)
        throws_.push_back({int(k), {float(throw_speed * a.dx / l), float(throw_speed * a.dy / l)},
                           float(throw_speed * tall * a.dz / l)});
  }
  for (const tracking::TrackedPlayer& p : f.players) {
    for (size_t k = 0; k < field_.bodies.size(); ++k) {
      if (field_.bodies[k].tracked_as() != p.id) continue;
      bodies_[k].position = {std::clamp(to_float(p.x), field_.bounds_min.x - slack, field_.bounds_max.x + slack),
                             std::clamp(to_float(p.y), field_.bounds_min.y - slack, field_.bounds_max.y + slack)};
      const double speed = std::hypot(p.vx, p.vy), most = 0.99 * field_.max_body_speed;
      const double scale = speed > most ? most / speed : 1.0;
      bodies_[k].velocity = {float(p.vx * scale), float(p.vy * scale)};
    }
  }
}

}  // namespace quantum::runtime

#include "players.h"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "quantum/narrow.h"
#include "version.h"

namespace quantum::runtime {

using Status = PlayerSource::Status;

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

void DroppedValues::tell(double t, size_t elsewhere, bool last) {
  const size_t dropped = dropped_ + elsewhere;
  if (dropped == told_ || (!last && t - told_at_ < kWarnEvery)) return;
  if (warnings_)
    *warnings_ << "quantum: " << source_ << ": " << dropped - told_ << ' ' << what_ << (dropped - told_ > 1 ? "s" : "")
               << " dropped (" << why_ << "; " << dropped << " in all)"
               << (last ? " by the end of the match\n" : ", the match goes on\n");
  told_ = dropped, told_at_ = t;
}

#if !QUANTUM_WITH_TRACKING
std::unique_ptr<PlayerSource> tracked_players(const std::string& spec, const Field&, const tracking::SourceOptions&,
                                              std::ostream*, std::optional<Vec2>, tracking::SetupOptions) {
  throw std::invalid_argument("--input " + spec + ": " + built_without(Module::Tracking));
}
#endif

}  // namespace quantum::runtime

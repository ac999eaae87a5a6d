// Players from a tracking source (players.h: tracked_players), compiled only with tracking
// (QUANTUM_WITH_TRACKING).
#include "players.h"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "quantum/narrow.h"
#include "tracking/input.h"

namespace quantum::runtime {

namespace {

using Status = PlayerSource::Status;
using TrackingStatus = tracking::TrackingInput::Status;

class TrackedPlayers final : public PlayerSource {
 public:
  TrackedPlayers(const std::string& spec, const Field& field, const tracking::SourceOptions& options,
                 std::ostream* warnings, std::optional<Vec2> size, tracking::SetupOptions setup);
  Status advance(double t, const game::Match& match, bool waiting) override;
  std::span<const BodyInput> bodies() const override { return bodies_; }
  // A tracked throw goes the way the tracker says, at the sport's throw speed.
  std::span<const game::Throw> throws() const override { return throws_; }
  bool live() const override { return input_.live(); }
  void resync() override { t0_.reset(), next_ask_ = 0; }
  void finish(double t) override { dropped_.tell(t, input_.dropped(), true); }

 private:
  void apply(const tracking::TrackedFrame& f, double throw_speed);

  Field field_;
  std::string spec_;
  tracking::TrackedField tracked_;
  tracking::TrackingInput input_;
  tracking::SetupCheck setup_;
  std::ostream* warnings_;
  std::vector<BodyInput> bodies_;
  std::vector<game::Throw> throws_;
  std::optional<tracking::TrackedFrame> pending_;
  // Source time at match time 0: negative for a recording, whose 0 s plays at the first step's end.
  std::optional<double> t0_;
  bool seen_ = false;     // a frame has come
  double next_ask_ = 0;   // match time from which a live source is asked again
  // What the input dropped (tracking::TrackingInput::dropped), told.
  DroppedValues dropped_;
};

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

}  // namespace

std::unique_ptr<PlayerSource> tracked_players(const std::string& spec, const Field& field,
                                              const tracking::SourceOptions& options, std::ostream* warnings,
                                              std::optional<Vec2> size, tracking::SetupOptions setup) {
  return std::make_unique<TrackedPlayers>(spec, field, options, warnings, size, setup);
}

}  // namespace quantum::runtime

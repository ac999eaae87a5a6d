// Where a match's players come from, frame by frame: simulated players (game/bots.h), a tracking
// source (core/tracking/input.h, tracked_players.cpp), or a script (the rule specs' scenario). The session asks its
// source once a frame and hands it the frame's events. Besides where every body is, a source
// says who threw (an accelerometer's whip, a bot's pass, a click at the desk); the session lets
// a throw go only from the player who holds the ball.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "game/bots.h"
#include "game/game.h"
#include "tracking/options.h"

namespace quantum::runtime {

class PlayerSource {
 public:
  enum class Status {
    Ready,  // bodies() holds the players for the frame
    Lost,   // a live source lost the players: the match pauses until they are back
    Ended,  // a recording is over: so is the match
  };
  virtual ~PlayerSource() = default;
  // Brings the players up to match time `t`, the end of the frame about to be stepped.
  // `waiting`: the match is paused, and the source may take a moment to answer.
  virtual Status advance(double t, const game::Match& match, bool waiting) = 0;
  virtual std::span<const BodyInput> bodies() const = 0;
  // The throws made since the last frame.
  virtual std::span<const game::Throw> throws() const { return {}; }
  // Who moves body k: a simulated player of that skill in [0, 1], or a person (none).
  virtual std::optional<double> skill(size_t /*body*/) const { return std::nullopt; }
  // What the announcer just told everyone.
  virtual void hear(std::span<const game::GameEvent>) {}
  // A live source (a camera, a tracker): the match runs in real time with it.
  virtual bool live() const { return false; }
  // After a pause the source's clock went on without the match's.
  virtual void resync() {}
  // The match is over at match time `t`: a source that drops values tells those it has not told.
  virtual void finish(double /*t*/) {}
  // Scripts to load again before the next frame: a replay's source brings the reloads its
  // recording made, at the frames they were made.
  virtual std::vector<std::filesystem::path> files_to_reload() { return {}; }
};

// Input values dropped (not numbers, out of range, malformed): data, never a reason to stop. They
// are counted, and told at most every kWarnEvery seconds of the match, e.g. "quantum: tuio:3333:
// 12 tracking values dropped (WHY; 14 in all), the match goes on".
class DroppedValues {
 public:
  // What a tracking source drops, as told: `DroppedValues(spec, "tracking value", kTrackingWhy, ...)`.
  static constexpr const char* kTrackingWhy =
      "not a number or out of range, not a sample, not a whole OSC packet, a line too long, a recorded frame that "
      "cannot be read or placed in time, or the oldest of more players than a source keeps";
  // `source` names where they came from, `what` one value ("tracking value"), `why` the reasons.
  DroppedValues(std::string source, std::string what, std::string why, std::ostream* warnings)
      : source_(std::move(source)), what_(std::move(what)), why_(std::move(why)), warnings_(warnings) {}
  void count() { ++dropped_; }
  // At match time `t`; `elsewhere`: more dropped values, counted by the source itself. `last`:
  // the match is over, and what was not told yet is told now ("... by the end of the match").
  void tell(double t, size_t elsewhere = 0, bool last = false);

 private:
  static constexpr double kWarnEvery = 5;
  std::string source_, what_, why_;
  std::ostream* warnings_;
  size_t dropped_ = 0, told_ = 0;
  double told_at_ = -kWarnEvery;
};

// Simulated players, one skill each (0 to 1): they strike the ball, or hold, throw and catch it
// when the field's bodies catch (game::make_bots). `throw_speed`: the sport's (m/s).
class BotPlayers final : public PlayerSource {
 public:
  BotPlayers(const Field& field, std::vector<double> skills, uint64_t seed, double throw_speed)
      : skills_(skills), bots_(game::make_bots(field, std::move(skills), seed, throw_speed)) {}
  Status advance(double t, const game::Match& match, bool) override {
    moves_ = bots_->move(t, 1.0 / match.fps(), match.players());
    return Status::Ready;
  }
  std::span<const BodyInput> bodies() const override { return moves_; }
  std::span<const game::Throw> throws() const override { return bots_->throws(); }
  std::optional<double> skill(size_t body) const override { return skills_.at(body); }
  void hear(std::span<const game::GameEvent> events) override {
    for (const game::GameEvent& e : events) bots_->hear(e);
  }

 private:
  std::vector<double> skills_;
  std::unique_ptr<game::SimulatedPlayers> bots_;
  std::span<const BodyInput> moves_;
};

// Where a person's hand is (the desk's mouse over the field), in field metres; `over` is false
// while it is off the field. `throws` counts the times the person threw (a click, a key): each
// new one throws the ball if the hand's player holds it. The front end that reads the mouse
// writes it every frame.
struct Hand {
  Vec2 at;
  bool over = false;
  int throws = 0;
};

// Simulated players, but one of them moves where a person's hand is: a designer plays their own
// sport at a desk. The hand's body takes the hand's velocity (from its motion), within the
// field and its speed limit; a throw goes the way the hand has just been moving (toward the
// opponents' goal when it is still), at the sport's throw speed.
class HandPlayers final : public PlayerSource {
 public:
  HandPlayers(const Field& field, std::vector<double> skills, uint64_t seed, double throw_speed, int body,
              const Hand& hand);
  Status advance(double t, const game::Match& match, bool waiting) override;
  std::span<const BodyInput> bodies() const override { return bodies_; }
  std::span<const game::Throw> throws() const override { return throws_; }
  // The hand's player is the person at the desk.
  std::optional<double> skill(size_t body) const override {
    return int(body) == body_ ? std::nullopt : bots_.skill(body);
  }
  void hear(std::span<const game::GameEvent> events) override { bots_.hear(events); }

 private:
  BotPlayers bots_;
  const Field field_;
  int body_;
  const Hand& hand_;
  int thrown_;  // the hand's throws already made
  static constexpr double kThrowMemory = 0.1;  // s: how long the hand's motion counts for a throw
  Vec2 recent_{0, 0};  // the hand's velocity over the last kThrowMemory
  std::vector<BodyInput> bodies_;
  std::vector<game::Throw> throws_;
};

// Players from a tracking source: each tracked id moves the body of that name. Recordings are
// replayed in match time; live sources as their frames come. `spec`: fakenect:DIR, kinect,
// video:FILE, camera:N or tuio:PORT (see tracking/input.h); `options`: accelerometers for throws
// (any source) and a camera's field of view. A Kinect's calibration, a table that is not the
// field and a source that sees nobody for its first seconds are told once to `warnings`
// (tracking::SetupCheck); `size` overrides the measured table. In a quantum built without
// tracking (QUANTUM_WITH_TRACKING), throws std::invalid_argument saying so.
std::unique_ptr<PlayerSource> tracked_players(const std::string& spec, const Field& field,
                                              const tracking::SourceOptions& options = {},
                                              std::ostream* warnings = nullptr, std::optional<Vec2> size = std::nullopt,
                                              tracking::SetupOptions setup = {});

}  // namespace quantum::runtime

// The quantum core: a field, the particle cloud on it, the bodies that move through it, and the
// decisions that turn particle contacts into announced events.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "quantum/backend.h"
#include "quantum/cloud.h"
#include "quantum/fate.h"
#include "quantum/field.h"
#include "quantum/noise.h"

namespace quantum {

namespace detail {
struct BodyPath;
}
struct PurgatorySlot;

struct WorldConfig {
  uint32_t particles = 1000;      // target cloud size; splitting grows the cloud to it
  uint32_t purgatory_frames = 3;  // how many steps a body keeps the particles it touched
  uint64_t seed = 1;
  float split_jitter = 0.05f;     // rad: largest turn given to a particle split at a collision
  float body_lookahead = 0.25f;   // s: prediction moves bodies on their velocity this long, then holds them
  // A fate report shares a large cloud's chunks among this many threads (1 or 2; more than 4,096
  // particles; docs/PERFORMANCE.md). The report is the same either way.
  uint32_t threads = 2;
};

// Catch: a body that catches met the ball and holds it now. Throw: its holder let it go; Kick:
// from its feet (World::Release). Landing: on a field of landings, the ball came down on the
// floor (and bounced on). Pickup: a catch of a loose ball someone touched (see World::loose).
// Tackle: a player took the held ball from its holder (World::challenge).
enum class EventType { Drop, Hit, Bounce, Goal, OwnGoal, Out, Catch, Throw, Landing, Pickup, Tackle, Kick };
// "drop", "hit", "bounce", "goal", "own_goal", "out", "catch", "throw", "landing", "pickup",
// "tackle", "kick"
const char* to_string(EventType type);

struct Event {
  double t;
  EventType type;
  int actor;            // spot (drop), body (hit, catch, throw, kick), wall (bounce), goal (goal, own goal), area (landing; -1 outside every area); -1 for out
  double p;             // probability with which this outcome was drawn (fate factors applied)
  double p_newtonian;   // the same without fate factors
  uint32_t particles;   // particles that carried the outcome
  Vec2 at;              // weighted centre of those particles
  Vec2 velocity;        // hit, bounce, throw, kick: the ball's mean velocity afterwards (what a player makes of it); else 0
  // Fields with height, for the same events: how high the ball's centre is and how fast it rises
  // afterwards (what a player sees of a lob); else 0.
  float height = 0, up = 0;
};

// How a thrown ball's particles scatter: standard deviations of their direction (rad) and of
// their speed (a share of the throw's). A person's throw is never exact, and the spread is what
// lets the engine choose among plausible throws (the paper, section 8.2).
// On a field with height, `elevation` (rad) scatters the angle above the horizontal too.
struct ThrowSpread {
  float direction = 0.06f, speed = 0.1f, elevation = 0.03f;
};

// One step's draw: what the particles met, each with the chance that the ball met it, and what
// was realized, with everything those chances were made of (the decision log writes it all, so
// that anyone can check a draw from the file: docs/decisions.md). Masses and weights are
// fractions of the cloud's Newtonian mass at the draw.
struct Decision {
  // The particles of one fate group (an index into `fates`, or Cloud::kNoFate) that met an option.
  struct Share {
    uint32_t fate;
    double mass;
    uint32_t particles;
  };
  struct Option {
    Target target;
    double chance, chance_newtonian;
    uint32_t particles;
    double mass = 0, weight = 0;  // Newtonian weight, and the weight it counts with in the draw
    double factor = 1;            // its contact factor (World::set_contact_factors); a wall's is unused
    uint32_t first_share = 0, shares = 0;  // its fate groups: shares[first_share, first_share + shares)
  };
  double t = 0;
  double u = 0;                 // the uniform number drawn, in [0, 1)
  std::vector<Option> options;  // in the order the draw adds them up
  std::vector<Share> shares;
  // The fate groups of the tweak in force (World::tweak; none when the cloud is new since), with
  // `mass` the group's Newtonian mass at the draw, and the factor each was given.
  std::vector<FateGroup> fates;
  std::vector<double> fate_factors;
  double rest_mass = 0, rest_weight = 0;  // the particles that met nothing
  bool all_met = false;         // nothing was left in the field: the chances are over the options alone
  int realized = -1;            // index into options; -1: nothing happened, the ball flies on
};

// A player's try to take the held ball this step (World::challenge): its chance, tweaked and
// Newtonian.
struct Challenge {
  int body;
  double chance, chance_newtonian;
  double factor = 1;  // what made chance of chance_newtonian, for the decision log
};

// Who an event is about, by the field's names: the spot (drop), the body (hit, catch, throw), the
// wall (bounce), the goal and the team defending it (goal, own goal) or the area a landing is in
// and its team; nothing for out or a landing outside every area.
struct EventActor {
  std::string_view name, team;
};
EventActor actor_of(const Event& e, const Field& field);
// What a draw's option is, by the field's names: the body, goal or wall; the area of a landing
// ("floor" outside every area); "out" for the bounds.
std::string_view target_name(Target target, const Field& field);
// A draw's option's place among World::contact_fates: -1 for a wall or a tackle.
int contact_index(Target target, const Field& field);

struct BodyInput {
  Vec2 position, velocity;
};

// The ball in play as a whole: its particles' weighted centre and mean velocity along the floor,
// and their weighted mean speed (upward speed counts on a field with height).
struct BallMotion {
  Vec2 centre, velocity;
  double speed = 0;
};

// m/s: a ball in play whose particles' weighted mean speed is below this lies loose: whoever
// reaches it picks it up (FateKind::Pickup), and the match tells it loose.
inline constexpr double kLooseSpeed = 0.5;

// Bad input to step(): the message names the body and the value.
struct InputError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// What World::step() refuses in one body's input, so that a source of players can drop it
// first (a replay's damaged frame): None when the input may be stepped.
enum class BodyFault { None, Position, Velocity, FarOut, TooFast };
BodyFault body_fault(const Field& field, const BodyInput& in);

// Where a body that hits sends the ball it next meets (World::plan_hit). Motion: off the body's
// motion, as off a mallet (a person's swing nobody measured). Velocity: at `velocity`. Point:
// through `point` from wherever the ball is met, at `speed` m/s (with height the flattest arc
// at that speed, or the arc leaving at `elevation` rad when that is > 0). The plan's velocity is
// scattered by `spread`, as a throw's is.
struct HitPlan {
  enum class Kind : uint8_t { Motion, Velocity, Point } kind = Kind::Motion;
  Vec3 velocity, point;
  float speed = 10, elevation = 0;
  ThrowSpread spread;
};

// Throws std::invalid_argument for a spread outside [0, 1.6] rad of direction and elevation and
// [0, 1] of speed.
void check_spread(ThrowSpread spread);

// Why World::release() refuses a throw at `velocity` on a field with (`tall`) or without height;
// "" when it takes it.
std::string throw_fault(Vec3 velocity, bool tall);

class World {
 public:
  // Throws FieldError for an invalid field. Without a backend the fast one is used.
  World(Field field, WorldConfig config, std::unique_ptr<Backend> backend = nullptr);
  ~World();

  // Puts the ball back: one particle of weight 1 at the spot, grown by splitting in later steps.
  void drop(int spot, std::vector<Event>& events);

  // Takes the ball off the field: the cloud and the purgatory are emptied (or the holder lets
  // go), and nothing more is decided until the next drop (a dead ball, ended by the rules).
  void remove_ball();

  // Puts the ball in the hands of `body`, which must catch (a throw-in, a throw-off): the cloud
  // is removed, and the ball goes where the body goes. Throws std::invalid_argument for an
  // unknown body or one that does not catch.
  void give(int body);

  // The holder `body` throws the ball: it leaves the hand at arm's length (the body's radius) in
  // the throw's direction, as `particles` particles whose directions and speeds scatter around
  // `velocity` by `spread`. Appends a Throw event. Throws std::invalid_argument when `body` does
  // not hold the ball or the velocity is not finite and > 0 (or faster than 1000 m/s).
  // On a field with height the ball leaves the hand at the body's reach (Field::reach_of) with
  // the vertical velocity velocity.z; on a flat field velocity.z must be 0.
  // A Kick leaves the feet instead, and a Kick event is appended: with height the ball starts on
  // the floor, rolling along it when velocity.z is 0 (no particle is scattered upward) and
  // lofted otherwise (a particle scattered below the horizontal rolls); on a flat field a kick
  // goes as a throw does.
  enum class Release : uint8_t { Throw, Kick };
  void release(int body, Vec3 velocity, ThrowSpread spread, std::vector<Event>& events,
               Release how = Release::Throw);

  // How a body that hits (BodySpec::hits) sends on the ball it next meets (a simulated player's
  // choice, a rule's aim, a swing an accelerometer felt). A plan is for one touch: the hit uses
  // it up, and the next goes off the body's motion unless planned again. Throws
  // std::invalid_argument for an unknown body, one that does not hit, or a velocity, point,
  // speed, elevation or spread that a throw would not take.
  void plan_hit(int body, const HitPlan& plan);
  const HitPlan& planned_hit(int body) const { return planned_.at(size_t(body)); }
  // Whether the ball passes through `body` now: it hit it less than Field::rehit seconds ago.
  bool passes_now(int body) const { return time_ < pass_until_[size_t(body)]; }

  // Draws once among players trying to take the ball from its holder in this step (tackles,
  // steals): each takes it with its chance, the rest of the chance is nothing. The draw is the
  // step's decision; the one it realizes holds the ball now, and a Tackle event is appended.
  // Throws std::invalid_argument when nobody holds the ball, for a challenger that is unknown,
  // does not catch or holds the ball, or for chances outside [0, 1] or summing past 1.
  void challenge(std::span<const Challenge> challengers, std::vector<Event>& events);

  // Fields with height: how high `body` reaches from now on (m; its field reach when standing,
  // more while it jumps). Throws std::invalid_argument for an unknown body or a height outside
  // (0, 100] m, and std::logic_error on a flat field.
  void set_reach(int body, float height);
  float reach(int body) const { return body_top_.at(size_t(body)); }

  // Replaces the ball with the given particles (a scene set up by a test, a benchmark or a
  // tool). Throws std::invalid_argument for non-finite values, particles outside the bounds or
  // inside a wall, or weights that are negative or sum to zero.
  void set_cloud(Cloud cloud);

  // One frame: bodies move to their new input, particles diffuse, move and collide, and every
  // body, goal, wall (bounced off audibly) and the bounds that particles reached is drawn
  // against. Realized outcomes are appended to `events`. Throws InputError (and changes
  // nothing) for bad input.
  void step(float dt, std::span<const BodyInput> input, std::vector<Event>& events);

  // Puts the bodies where `input` says without a step (setting up a scene). Throws InputError
  // for bad input, like step().
  void place_bodies(std::span<const BodyInput> input);

  // Opens these wormholes, replacing any open ones (an empty list closes them all). Throws
  // std::invalid_argument for a mouth that is not finite, not positive, outside the bounds or
  // within a ball's radius of a wall, and std::logic_error from a backend without wormholes.
  void set_wormholes(std::vector<Wormhole> wormholes);
  const std::vector<Wormhole>& wormholes() const { return wormholes_; }

  // Says who touched the ball last (a body, or -1 for nobody), which decides own goals. For
  // setting up a scene, like set_cloud(). Throws std::invalid_argument for an unknown body.
  void set_last_touch(int body);

  // Forward-simulates every live particle up to `horizon` seconds, jumping from contact to
  // contact; bodies move on their last velocity for config.body_lookahead, then hold. The first
  // step (as long as the last one) carries the Brownian offsets the next step() will draw; the
  // rest is traced without noise. The second form refills `report` in place: with the world's own
  // scratch, a match's every-frame prediction allocates nothing once warm. Not thread-safe: one
  // world predicts on one thread at a time.
  FateReport predict(float horizon = 3.0f) const;
  void predict(FateReport& report, float horizon = 3.0f) const;

  // The predicted path of one live particle, as predict() traces it: start, contacts, end. Only
  // pictures need it (a fate group's representative particle shows the group's way).
  // On a flat field every point's z is 0.
  std::vector<Vec3> predict_path(size_t particle, float horizon = 3.0f) const;

  // Multiplies every particle's Newtonian weight by its group's factor; later decisions draw
  // from the result. Updates the groups' tweaked masses. The report must be of the current cloud.
  void tweak(FateReport& report, std::span<const double> group_factors);

  // The fate of meeting each body, each goal, the bounds and, on a field of landings, the floor
  // outside every area and each area, now and directly (a wall ends no fate), in that order.
  void contact_fates(std::vector<Fate>& out) const;
  // One factor per contact fate, in contact_fates' order. The particles that meet a body, a goal,
  // the bounds or a landing area count in a draw with their Newtonian weight times its factor,
  // whatever fate they were predicted: a player moves onto particles predicted elsewhere, and a
  // player given 0 must never get the ball. Those bouncing off a wall keep their fate's weight (a
  // bounce ends no fate). Every factor is 1 until set; the factors outlive the cloud (a drop, a
  // throw). Throws std::invalid_argument for a wrong count or a factor not finite and >= 0.
  void set_contact_factors(std::span<const double> factors);
  std::vector<double> contact_factors() const;  // in contact_fates' order

  const Field& field() const { return field_; }
  const WorldConfig& config() const { return config_; }
  const Cloud& cloud() const { return cloud_; }
  double time() const { return time_; }
  uint64_t steps() const { return step_; }
  bool live() const { return live_; }           // a cloud is in play
  int holder() const { return holder_; }        // the body holding the ball, -1 for none
  bool in_play() const { return live_ || holder_ >= 0; }
  // The live ball's motion (all zero when no ball is live), summed once per change of the cloud:
  // the match's every-frame reads share one pass over it.
  const BallMotion& motion() const;
  bool loose() const { return live_ && motion().speed < kLooseSpeed; }
  int last_touch() const { return last_touch_; }  // body of the last realized hit or catch, -1 after a drop
  // The last step's draw, or null when no particle met anything in it.
  const Decision* decision() const { return decided_step_ == step_ && step_ > 0 ? &decision_ : nullptr; }
  const std::vector<Vec2>& body_positions() const { return body_pos_; }
  const std::vector<Vec2>& body_velocities() const { return body_vel_; }
  size_t purgatory_size(int body) const;

 private:
  void check_input(float dt, std::span<const BodyInput> input) const;
  void check_body(int body) const;  // throws std::invalid_argument for an unknown body
  void check_bodies(std::span<const BodyInput> input) const;
  void decide(float dt, std::optional<bool> loose_seen, std::vector<Event>& events);
  // The FateKind of `body` meeting the ball now (see FateKind), the ball loose or not.
  FateKind ending_at(int body, bool loose) const;
  void realize_body(int body, float dt);
  void realize_catch(int body);
  Vec2 release_point(int body, Vec2 direction) const;
  struct Launch {
    float speed, heading, elevation;  // a velocity as a spread scatters it
  };
  static Launch launch_of(Vec3 velocity);
  Vec3 scattered(const Launch& launch, ThrowSpread spread);  // one particle's velocity; draws from the rng
  // config.particles particles (z ignored when flat); from the floor none goes down into it.
  void release_at(Vec3 at, Vec3 velocity, ThrowSpread spread, bool from_floor = false);
  void aim_hit(int body);  // a realized hit: the plan's velocities, and the ball passes through the hitter a while
  Vec3 hit_velocity(const HitPlan& plan) const;  // the plan's velocity from where the cloud is now
  float flight(float seconds) const;  // Field::flight_time
  void realize_bounce(Target wall);
  void refill(bool jitter);
  void split_round(bool jitter);
  void clear_purgatory();
  void forget_tweak();     // the cloud is new: no particle has a fate
  void sum_fate_mass();    // fate_mass_ from the cloud
  void own_goals(std::vector<uint8_t>& own) const;  // per goal: 1 when the last toucher's team defends it
  // Per body, the FateKind of meeting it (see FateKind); per goal, whether it is an own goal.
  void endings(std::vector<uint8_t>& body_kind, std::vector<uint8_t>& own) const;
  void predicted_bodies(std::vector<detail::BodyPath>& bodies) const;
  void check_horizon(float horizon) const;

  Field field_;
  WorldConfig config_;
  std::unique_ptr<Backend> backend_;
  std::unique_ptr<struct WorldInternals> internals_;
  Cloud cloud_, scratch_;
  std::vector<PurgatorySlot> purgatory_;  // one per step kept, in a ring
  std::vector<Wormhole> wormholes_;
  std::vector<Vec2> body_pos_, body_vel_;
  std::vector<float> body_top_;  // fields with height: each body's reach now
  std::vector<HitPlan> planned_;     // per body: its next hit's plan
  std::vector<double> pass_until_;   // per body: the ball passes through it until then (after its hit)
  std::vector<BodyMotion> motion_;
  // The tweak in force: its groups, their factors and Newtonian weight in the cloud now (kept as
  // particles leave), and the contact factors per decision target (walls unused).
  std::vector<FateGroup> tweak_groups_;
  std::vector<double> tweak_factors_, fate_mass_, contact_factor_;
  std::vector<int32_t> share_at_;  // decide()'s scratch: per target and fate, its place in decision_.shares
  std::vector<Contact> contacts_;
  std::vector<uint32_t> removed_;
  DecisionRng rng_;
  Decision decision_;
  uint64_t decided_step_ = 0;
  double tmass_full_ = 1;  // the cloud's tweaked mass when last summed exactly
  double time_ = 0;
  float last_dt_ = 1.0f / 60;  // the next step is taken to be as long as the last
  uint64_t step_ = 0;
  uint64_t version_ = 0;
  mutable BallMotion ball_motion_;  // motion(), as of motion_version_
  mutable uint64_t motion_version_ = ~uint64_t(0);
  size_t split_cursor_ = 0;
  bool live_ = false;
  int holder_ = -1;
  int last_touch_ = -1;
};

}  // namespace quantum

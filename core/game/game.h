// The game engine's decision host: a match on top of the quantum core. Each frame it steps the
// world, turns the core's realized outcomes into game events (shot, intercept, goal, ...), asks
// the sport's rules what to do about them, and keeps the fates tweaked by the rules' factors.
// The rules see fates, players and the score, never particles; they are written in Lua
// (bindings/) behind the Rules interface, so this library does not know Lua.
//
// A running match allocates nothing per frame once warm: events, phrases and fates live in
// buffers the match keeps and refills (see docs/PERFORMANCE.md, "Allocations").
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "quantum/limits.h"
#include "quantum/world.h"
#include "system/slots.h"

namespace quantum::game {

// What the rules are told. Retouch is the same player meeting the ball again within 0.25 s of
// its last touch (one swing); Dead is a ball the rules ended while it still moved; Paused and
// Resumed come from the runtime when a live tracking source loses the players and finds them.
// With players who catch: Throw (the holder let go), Pass (a teammate of the thrower caught it),
// Intercept (an opponent did: the same event as a mallet's intercept), Catch (anyone else: a
// loose ball picked up, a throw caught again by the thrower), Give (the rules handed it over).
// Stalled: nothing was played for the sport's bound (MatchConfig::stall; see counts_as_play);
// Loose: the ball in play slowed below kLooseSpeed and lies loose where the event says. Pickup: a
// player who catches took a loose ball someone had touched (World::loose). Tackle: a player took
// the held ball from its holder (MatchConfig::tackle_rate); `previous` is who lost it.
// On a field of landings, Landing: the ball came down on the floor (actor: the area it is in).
// Hit: a player who hits (field.lua: hits = true) touched the ball and sent it on. Kick: the
// holder let go from its feet (a throw along the floor or lofted from it).
enum class EventKind : uint8_t {
  Drop, Shot, Intercept, Retouch, Bounce, Goal, OwnGoal, Out, Dead, TimeUp, MatchEnd, Powerup, PowerupEnd,
  Paused, Resumed, Catch, Pass, Throw, Give, Stalled, Loose, Landing, Hit, Pickup, Tackle, Kick,
};
constexpr int kEventKinds = int(EventKind::Kick) + 1;
const char* to_string(EventKind kind);  // "drop", "shot", ..., "own_goal", "time_up", "powerup_end", ...
// The kind named `name`, or none.
std::optional<EventKind> event_kind(std::string_view name);
// Every kind's name, in order: for error messages and the strict readers.
const std::vector<std::string>& event_names();
// Whether an event of this kind is play that keeps a match alive: a touch, a throw, an outcome or
// a restart. A bounce is not (a ball rolling dead along a wall bounces on and on with nobody
// playing it), nor a power-up, nor what the engine says about a ball nobody plays (stalled,
// loose).
bool counts_as_play(EventKind kind);


// Names are views into the field (or the match, for a winner): they stay valid while the match
// lives, and events cost no allocation.
struct GameEvent {
  double t = 0;
  EventKind type = EventKind::Drop;
  std::string_view actor;     // the spot, the player, the wall, the goal, the area landed in, the winner ("" for out, dead, time_up)
  std::string_view team;      // the actor's team (goal: the team defending it; an area's team; "" for a wall)
  std::string_view by;        // the last player to touch the ball (for a touch: the toucher itself)
  std::string_view by_team;
  std::string_view previous;  // the player who touched it before `by` this rally (who passed), "" for none
  std::string_view previous_team;
  std::string_view holder;    // who holds the ball once this happened ("" when nobody does)
  double p = 1, p_newtonian = 1;
  uint32_t particles = 0;
  Vec2 at, velocity;   // where it happened; for a touch or bounce the ball's mean velocity after it
  float height = 0, up = 0;  // fields with height, for a touch or bounce: the ball's height and upward speed after it
  int actor_index = -1;  // spot, body, wall or goal index in the field
  std::string powerup;   // powerup, powerup_end: the power-up's name (actor is its holder)
};

// A fate as the rules see it.
struct FateView {
  Fate fate;                   // kind, target, and the walls on the way (fate.path)
  std::string_view actor;      // the goal's, the body's or a landing's area's name, "" otherwise
  std::string_view team;       // the body's team, the team defending the goal, or the area's team
  // The team this outcome is good for: the body's (a catcher's), or the one attacking the goal or
  // the area landed in.
  std::string_view favours;
  double mass = 0;             // Newtonian probability
  double tweaked = 0;          // probability after the current factors
  uint32_t count = 0;
  // The ball meeting `actor` now, whatever was predicted (World::set_contact_factors): no
  // particle's fate, so mass, tweaked and count are 0.
  bool contact = false;

  const char* kind() const { return to_string(fate.kind); }
};

class Match;

// One term of a fate's factor, by where it came from: the decision log splits every factor by
// them (docs/decisions.md). A factor is its terms multiplied in order, the product stopping at
// kMostFactor after each, and the handicap (always last) times that.
struct FactorTerm {
  enum class Source : uint8_t { Sport, Modifier, Powerup, Handicap };
  Source source = Source::Sport;
  int index = 0;        // Modifier: its place in sport.modifiers (from 1); Powerup: its name (Match::powerup_names)
  int player = -1;      // Powerup: its holder; Handicap: the player (-1: the mean of the team `team`)
  std::string_view team;
  double strength = 0;  // Powerup: its strength parameter, when has_strength
  bool has_strength = false;
  double value = 1;
};

// The terms of a list of fates' factors, fate after fate; `skipped` when the rules' factors were
// all 0 and the fates were given 1 instead (Rules::factors).
class FactorTerms {
 public:
  void clear() { terms_.clear(), first_.assign(1, 0), skipped_ = false; }
  // Terms are added fate by fate, in order: add(k, ...) after add(k - 1, ...).
  void add(size_t fate, const FactorTerm& term);
  std::span<const FactorTerm> of(size_t fate) const;
  size_t fates() const { return first_.size() - 1; }
  bool skipped() const { return skipped_; }
  void skip() { skipped_ = true; }
  void reserve(size_t fates, size_t terms) { first_.reserve(fates + 1), terms_.reserve(terms); }
  void swap(FactorTerms& other) noexcept;

 private:
  std::vector<FactorTerm> terms_;
  std::vector<uint32_t> first_{0};  // fate k's terms start at first_[k]; past the last fate, its end
  bool skipped_ = false;
};

// A sport's rules. The host calls them outside the frame's hot loop; they may fail, and the host
// reports and skips a failed rule instead of stopping the match.
class Rules {
 public:
  virtual ~Rules() = default;
  // Writes one multiplier per fate into `out` (fate factor x modifiers x power-ups; the host
  // adds the handicaps), each finite and >= 0, and its terms into `terms` (cleared by the host);
  // a fate given no terms is taken as one of the sport's of the whole factor. Some fates are
  // contacts (FateView::contact, World::contact_fates). Reads the match; a failing modifier is reported through
  // match.report_error.
  virtual void factors(std::span<const FateView> fates, Match& match, std::span<double> out, FactorTerms& terms) = 0;
  // Reacts to an event through the match's actions (say, award, respawn, finish).
  virtual void on_event(const GameEvent& event, Match& match) = 0;
  // Once a frame, after its events: what the rules scheduled for this time (timers).
  virtual void tick(Match&) {}
  // Once a frame, before anything of it (scripted rules start the frame's budget afresh).
  virtual void begin_frame(Match&) {}
};

// Handicaps are in limits::kHandicap.
inline bool handicap_ok(double h) { return limits::kHandicap.contains(h); }  // false for NaN too

// A fate factor, and each term of it, is in limits::kFactor, [0, kMostFactor].
inline constexpr double kMostFactor = limits::kFactor.hi;

// A term of a factor as a script gives it: in bounds it is kept; above them (math.huge too) it
// is taken as kMostFactor; NaN or below 0 is refused and taken as 1, as if it were not given.
// `problem` says which, nullptr when in bounds.
struct BoundedFactor {
  double value;
  const char* problem;
};
inline BoundedFactor bounded_factor(double v) {
  if (v >= 0 && v <= kMostFactor) return {v, nullptr};
  if (v > kMostFactor) return {kMostFactor, "more than 1e6, the most a factor may be (taken as 1e6)"};
  if (v < 0) return {1, "a number below 0, not a factor in [0, 1e6] (skipped)"};
  return {1, "nan, not a factor in [0, 1e6] (skipped)"};
}

// What one award may add to a score (or take from it, below 0).
inline constexpr double kMostAward = 1000;
// A score saturates at ±kMostScore (docs/lua-api.md): the int's range, but for its lowest value,
// which has no positive twin.
inline constexpr int kMostScore = std::numeric_limits<int>::max();

struct MatchConfig {
  uint32_t particles = 1000;
  uint64_t seed = 1;
  uint32_t threads = 2;       // the world's threads (WorldConfig::threads): 1 or 2
  double fps = 60;
  double seconds = 120;       // time limit; the rules hear time_up when it runs out
  int first_spot = 0;         // where the first ball drops, at once...
  int first_holder = -1;      // ...unless a player (a body that catches) starts with it in hand
  // Automatic balance: for every goal a team trails by, its players' handicaps are multiplied by
  // (1 + balance_per_goal), up to balance_most times their own. 0 is off.
  double balance_per_goal = 0;
  double balance_most = 2;
  // Throws (fields whose bodies catch): the speed of a throw that gives none (m/s; a rule's aimed
  // throw, an accelerometer's), and how every throw scatters.
  double throw_speed = 10;
  ThrowSpread throw_spread;
  // Seconds a match may go without play (counts_as_play) before the rules hear `stalled`; when
  // they do nothing about it, the match restarts play itself (see Match::step). In
  // limits::kStall.
  double stall = 20;
  // Tackles (players who catch): per second, how often an opponent within reach of the holder
  // (their bodies touching) takes the ball, before the fate factors of kind `tackle`; each
  // frame's chance is 1 - e^(-rate x factor / fps). 0, the default, is no tackles. In
  // limits::kTackleRate.
  double tackle_rate = 0;
};

struct Said {
  double t = 0;
  std::string text;
  int event = -1;             // the event (index into events()) whose handler said it; -1 for none
  const char* cause = "";     // that event's type, or "timer", or "" when said outside any handler
  std::string recording;      // a sound file to play instead of speaking the text ("" to speak it)
};

// A power-up a player holds: its script's name, until when, and its numbers (strength, and
// whatever its start stored). The host keeps them, so they survive a reload of the scripts.
struct ActivePowerup {
  std::string name;
  int player = -1;  // body index
  double until = 0;
  std::map<std::string, double> params;
  int name_id = -1;  // Match::powerup_names()[name_id] is `name`: a factor's term names it by this
};

struct RallyStats {
  int rallies = 0;      // balls dropped that ended (goal, own goal, out or dead)
  int contacts = 0;     // shots, intercepts, catches and hits within those rallies
  int goals = 0;
  int passes = 0;       // catches by a teammate of the thrower
  int possessions = 0;  // times a team gained the ball (a catch, intercept or give after the other team had it)
  int stalls = 0;       // stalled events: times the match went the sport's bound without play
  double seconds = 0;   // match time played
};

// Where a simulated player should send the ball (the sport's hint, game.aim): a goal (across its
// mouth), a wall (the point of it nearest the ball) or a point; none: the opponents' goal.
struct Aim {
  enum class Kind : uint8_t { Default, Goal, Wall, Point } kind = Kind::Default;
  int index = -1;  // the goal or wall
  Vec2 point;
};

// A throw a player makes: who, and the ball's velocity as it leaves the hand: along the floor,
// and upward (`up`, m/s; fields with height only, 0 on a flat one).
struct Throw {
  int player = -1;
  Vec2 velocity;
  float up = 0;
};

struct Player {
  std::string name, team;  // the body's name and team in the field
  double handicap = 1;     // multiplies the fates that favour this player (see docs/lua-api.md)
  Vec2 position, velocity;
  // Hints to simulated players (game.turn, game.aim): whether it is this player's turn to play
  // the ball, and where to send it.
  bool turn = true;
  Aim aim;
  // A restart's place for this player (game.place, a give at a spot): simulated players walk
  // there and wait; it holds until the ball is next played.
  std::optional<Vec2> place;
  // A simulated player's skill in [0, 1]; none for a person (tracked, at the desk, a spec's script).
  std::optional<double> skill;
};

class Match {
 public:
  Match(Field field, MatchConfig config, Rules& rules, std::vector<double> handicaps = {});

  // One frame with the players' new positions (one input per body of the field).
  void step(std::span<const BodyInput> input);

  // Hands the match to new rules between two frames (a reloaded sport); everything the match
  // holds (score, players, power-ups, the ball) stays.
  void set_rules(Rules& rules) { rules_ = &rules; }

  // --- Actions for the rules.
  void say(std::string_view text, std::string_view recording = {});
  // Points are a whole number in [-kMostAward, kMostAward]; a score saturates at ±kMostScore.
  void award(const std::string& team, double points = 1);
  // Drops the ball at `spot` after `delay` seconds (a goal's celebration); replaces a pending drop.
  // A ball still in play is dead first (see dead_ball).
  void respawn(int spot, double delay);
  // Ends the rally while the ball is in play (moving, or held): the ball is removed, a `dead`
  // event is told, and nothing more happens until the next drop. Nothing happens when no ball is
  // in play.
  void dead_ball();
  // Puts the ball in player k's hands (a throw-off, a throw-in, a free throw) after `delay`
  // seconds: a ball in play is dead at once, a pending drop or give is replaced, and a `give`
  // event is told when k gets it. Given `at` (a corner, the spot a ball went out), k is placed
  // there, and the ball waits for k to stand within kTakePlace of it, or kMostPlaceWait seconds
  // at most. Throws std::invalid_argument for a player who does not catch (field.lua: catches =
  // true), a delay outside [0, 60] s or a place that is not finite or outside the bounds.
  void give(int k, double delay = 0, std::optional<Vec2> at = std::nullopt);
  static constexpr double kTakePlace = 1.0, kMostPlaceWait = 10.0;
  // Asks player k to take a place (a formation, a restart) or, with none, frees it: see
  // Player::place. Throws std::invalid_argument for an unknown player or a place that is not
  // finite or outside the bounds.
  void place(int k, std::optional<Vec2> at);
  // Player k, who holds the ball, throws it at `velocity` (m/s; upward velocity.z only on a field
  // with height), scattered by `spread` (the sport's when none): a `throw` event is told, or a
  // `kick` for a ball kicked from the feet (World::release). Throws std::invalid_argument when k
  // does not hold the ball, or for a bad velocity or spread.
  void throw_ball(int k, Vec3 velocity, std::optional<ThrowSpread> spread = std::nullopt,
                  World::Release how = World::Release::Throw);
  // A throw a player made (a simulated player's, an accelerometer's): it goes only from the
  // player who holds the ball (anyone else's arm swings at nothing), from the feet of a player
  // who kicks (field.lua: kicks), else from the hands. From a player who hits it is a swing.
  void let_go(const Throw& t);
  // Player k, who hits, sends the ball it next meets at `velocity` (upward velocity.z only on a
  // field with height), scattered by the sport's spread: a swing as an accelerometer felt it, or
  // a simulated player's. It replaces a rule's plan (game.hit), as a person's swing would.
  // Throws std::invalid_argument as plan_hit does.
  void swing(int k, Vec3 velocity);
  // How player k, who hits (field.lua: hits = true), sends on the ball it next meets (see
  // World::plan_hit): a rule's aim, a simulated player's choice. Throws std::invalid_argument
  // for what the world refuses.
  void plan_hit(int k, const HitPlan& plan);
  void finish(const std::string& winner);  // "" for a draw
  // Sets player k's own handicap (> 0) from now on: a sport's rules may change it during a match.
  void set_handicap(int k, double handicap);
  // Hints to simulated players: whether it is player k's turn, and where player k aims.
  void set_turn(int k, bool turn);
  void set_aim(int k, Aim aim);
  // Who plays player k: a simulated player of that skill, in [0, 1], or a person (none). The
  // session tells it once its players are known; the rules read it. Throws
  // std::invalid_argument for an unknown player or a skill outside [0, 1].
  void set_skill(int k, std::optional<double> skill);
  // Fields with height: player k jumps, reaching `height` m higher for `seconds` (a block, a
  // rebound). Throws std::invalid_argument for an unknown player, a height outside (0, 3] m or
  // seconds outside (0, 2], and std::logic_error on a flat field. A rule or a spec that does not
  // say jumps kJumpHeight for kJumpSeconds.
  void jump(int k, double height, double seconds);
  static constexpr double kJumpHeight = 0.5, kJumpSeconds = 0.5;

  // Opens these wormholes on the field, replacing any (an empty list closes them). Throws
  // std::invalid_argument for wormholes the core refuses.
  void set_wormholes(std::vector<Wormhole> wormholes);

  // Gives `player` (a body index) a power-up for `seconds`; it ends with a powerup_end event. A
  // second one of the same name replaces the first. Throws std::invalid_argument for bad values.
  void grant(int player, const std::string& name, double seconds, std::map<std::string, double> params);

  // Puts the players where (and as fast as) `input` says without a step (a rule spec's scene).
  // Throws InputError like step(), and then changes nothing.
  void place_players(std::span<const BodyInput> input);

  // Sets up a scene (a rule spec): the players where (and as fast as) `input` says, the ball replaced by
  // `cloud`, a pending drop cancelled, `last_touch` (a body, or -1) the last player to touch it.
  // Throws std::invalid_argument for what the world refuses.
  void set_scene(std::span<const BodyInput> input, Cloud cloud, int last_touch = -1);

  // --- What the rules and the outside world read.
  const World& world() const { return world_; }
  const Field& field() const { return world_.field(); }
  const std::vector<Player>& players() const { return players_; }
  const std::map<std::string, int>& score() const { return score_; }
  const std::vector<std::string>& teams() const { return teams_; }
  double time() const { return world_.time(); }
  double fps() const { return config_.fps; }
  bool finished() const { return finished_; }
  const std::string& winner() const { return winner_; }
  const RallyStats& stats() const { return stats_; }
  const std::vector<ActivePowerup>& powerups() const { return powerups_; }
  int last_toucher() const { return last_toucher_; }  // body of the last announced touch this rally, -1 for none
  int holder() const { return world_.holder(); }     // body holding the ball, -1 for none
  const MatchConfig& config() const { return config_; }
  // Player k's handicap as it applies now: its own, times the automatic balance's boost while
  // its team trails.
  double handicap_now(int k) const;

  // What happened since the last clear_news(), in order: events, phrases (each naming its
  // event), rule errors ("rules/x/sport.lua:12: ... (on goal skipped)"). The spans stay valid
  // until the next action on the match.
  std::span<const GameEvent> events() const { return events_; }
  std::span<const Said> said() const { return said_.used(); }
  std::span<const std::string> errors() const { return errors_; }
  // Forgets the news once every consumer has read it; the buffers keep their room.
  void clear_news();
  void report_error(std::string message);
  // Phrases said from now on belong to no event but `cause` (a timer), until the next event.
  void set_cause(const char* cause);
  // Records an event of the host's own (the runtime's paused and resumed) without telling the
  // rules; phrases said next belong to it.
  void note(EventKind type);

  // The current fates as the rules see them (fresh prediction; empty when no ball is live).
  std::vector<FateView> fates() const;

  // The last frame's draw (null when nothing met anything), with the fates its chances came
  // from (Decision::fates), and the terms of every factor it was weighed with: its fates' in
  // order, then from decision_contacts_from() its contacts' (World::contact_fates' order); for
  // a draw of tackles, each tackle's in the draw's order.
  const Decision* decision() const { return world_.decision(); }
  const FactorTerms& decision_terms() const { return decision_terms_; }
  size_t decision_contacts_from() const { return decision_contacts_from_; }
  // Every power-up's name granted so far, by the id its factors' terms give (FactorTerm::index).
  std::span<const std::string> powerup_names() const { return powerup_names_; }
  // The prediction this frame's tweak made: the groups, and each live particle's group (views
  // and pictures colour the cloud by fate with it).
  const FateReport& report() const { return report_; }

 private:
  void handle(const Event& e);
  void expire_powerups();
  void powerup_event(EventKind type, int player, const std::string& name);
  GameEvent& new_event(EventKind type);
  void name_touchers(GameEvent& e) const;  // by and previous, from the rally's touches
  void end_rally(bool goal);               // the statistics of a rally that ended
  void took(int k, double t);              // player k touched the ball at t (a catch, a hit, a tackle): one more contact
  void gained(int k);                      // player k has the ball: a new possession if the other team had it
  void hand_over(int k);                   // the ball into k's hands now, told as `give`
  bool at_place(int k) const;              // k has no place, or stands within kTakePlace of it
  bool is_player(int k) const;             // k is a body of the field
  void check_player(int k) const;          // throws unless k is a player
  void check_catcher(int k) const;         // throws unless k is a player who catches
  // A touch within this many seconds of the same player's last is the same swing (Retouch).
  static constexpr double kRetouch = 0.25;
  void stalled();                          // tells the rules, and restarts play when they do not
  void watch_ball();                       // tells `loose` when the ball in play slows to a stop
  void tell_rules(size_t event);
  void retweak();
  void contest(std::span<const BodyInput> input);  // the opponents within reach may take the held ball
  // The handicap of the player an outcome favours, and who that is (-1: its team's mean).
  struct Favoured {
    double handicap = 1;
    int player = -1;
  };
  Favoured handicap_for(const FateView& v) const;
  // Completes the rules' factors of views_ into factors_ and `terms`: a fate they gave no terms
  // becomes one term of the sport's, and the handicap multiplies in as the last term.
  void add_handicaps(FactorTerms& terms);
  FateView view(const FateGroup& g) const;

  World world_;
  MatchConfig config_;
  Rules* rules_;
  std::vector<Player> players_;
  std::vector<double> landing_;  // per player: when its jump ends (-1: on the floor)
  std::vector<std::string> teams_;
  std::vector<ActivePowerup> powerups_;
  std::map<std::string, int> score_;
  std::vector<GameEvent> events_;
  system::Slots<Said> said_;  // the news, and behind them slots that keep their strings' room
  std::vector<std::string> errors_;
  std::vector<Event> core_events_;
  FateReport report_;              // this frame's prediction, refilled in place
  std::vector<FateView> views_;
  std::vector<Challenge> challenges_;  // this frame's tries to take the held ball (room kept)
  std::vector<Fate> contact_fates_;
  std::vector<double> factors_;
  FactorTerms terms_, decision_terms_, scratch_terms_;  // the tweak in force's, the last draw's
  size_t contacts_from_ = 0, decision_contacts_from_ = 0;
  std::vector<std::string> powerup_names_;  // every power-up granted, by FactorTerm::index
  RallyStats stats_;
  double respawn_at_ = -1;
  int respawn_spot_ = 0;
  int respawn_holder_ = -1;    // the player the pending respawn gives the ball to; -1: it drops at the spot
  int rally_contacts_ = 0;
  int last_toucher_ = -1;      // body of the last announced touch this rally
  int previous_toucher_ = -1;  // the one before it (another touch, or the same player's earlier one)
  std::string_view possession_;  // the team that has had the ball since it last changed sides, "" for none
  std::vector<Event> thrown_;    // the throw a rule or a player makes between steps (room kept)
  double last_touch_t_ = 0;
  double last_play_t_ = 0;     // when the last event that counts as play was told
  uint64_t plays_ = 0;         // events told that count as play (did a stalled handler act?)
  bool rolling_ = false;       // the ball in play has been fast since it was last told loose or dropped
  bool finished_ = false, time_up_told_ = false;
  std::string winner_;
  int handling_ = -1;          // the event the rules are handling
  const char* cause_ = "";     // its type, or what else is speaking
};

}  // namespace quantum::game

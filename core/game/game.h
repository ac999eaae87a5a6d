// The game engine's decision host: a match on top of the quantum core. Each frame it steps the
// world, turns the core's realized outcomes into game events (shot, intercept, goal, ...), asks
// the sport's rules what to do about them, and keeps the fates tweaked by the rules' factors.
// The rules see fates, players and the score, never particles; they are written in Lua
// (bindings/) behind the Rules interface, so this library does not know Lua.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "quantum/world.h"

namespace quantum::game {

struct Player {
  std::string name, team;  // the body's name and team in the field
  double handicap = 1;     // multiplies the fates that favour this player (see docs/lua-api.md)
  Vec2 position, velocity;
};

// What the rules are told. type: drop, shot, intercept, retouch (the same player meeting the
// ball again within 0.25 s of its last touch: one swing), bounce (off a wall, audibly), goal,
// own_goal, out, time_up, match_end; powerup and powerup_end when a power-up starts and ends.
struct GameEvent {
  double t = 0;
  std::string type;
  std::string actor;   // the spot, the player, the wall, the goal ("" for out and time_up)
  std::string team;    // the actor's team (goal: the team defending it; "" for a wall)
  std::string by;      // all but drop, time_up and match_end: the last player to touch the ball
  std::string by_team;
  double p = 1, p_newtonian = 1;
  uint32_t particles = 0;
  Vec2 at, velocity;   // where it happened; for a shot, intercept or bounce the ball's mean velocity after it
  int actor_index = -1;  // spot, body, wall or goal index in the field
  std::string powerup;   // powerup, powerup_end: the power-up's name (actor is its holder)
};

// A fate as the rules see it.
struct FateView {
  std::string kind;     // goal, own_goal, body, out, field
  std::string actor;    // the goal's or the body's name, "" otherwise
  std::string team;     // the body's team, or the team defending the goal
  std::string favours;  // the team this outcome is good for: the body's, or the one attacking the goal
  std::string via;      // "via left wall, Red's end", "" when direct
  std::vector<std::string> path;
  double mass = 0;      // Newtonian probability
  double tweaked = 0;   // probability after the current factors
  uint32_t count = 0;
};

class Match;

// A sport's rules. The host calls them outside the frame's hot loop; they may fail, and the host
// reports and skips a failed rule instead of stopping the match.
class Rules {
 public:
  virtual ~Rules() = default;
  // One multiplier per fate (fate factor x modifiers; the host adds the handicaps), each finite
  // and >= 0. Reads the match; a failing modifier is reported through match.report_error.
  virtual std::vector<double> factors(std::span<const FateView> fates, Match& match) = 0;
  // Reacts to an event through the match's actions (say, award, respawn, finish).
  virtual void on_event(const GameEvent& event, Match& match) = 0;
};

struct MatchConfig {
  uint32_t particles = 1000;
  uint64_t seed = 1;
  double fps = 60;
  double seconds = 120;       // time limit; the rules hear time_up when it runs out
  int first_spot = 0;         // where the first ball drops, at once
  // Automatic balance: for every goal a team trails by, its players' handicaps are multiplied by
  // (1 + balance_per_goal), up to balance_most times their own. 0 is off.
  double balance_per_goal = 0;
  double balance_most = 2;
};

struct Said {
  double t;
  std::string text;
  std::string event;      // the type of the event whose handler said it
  std::string recording;  // a sound file to play instead of speaking the text ("" to speak it)
};

// A power-up a player holds: its script's name (rules/powerups/<name>.lua), until when, and its
// numbers (strength, and whatever its start stored). The host keeps them, so they survive a
// reload of the scripts.
struct ActivePowerup {
  std::string name;
  int player = -1;  // body index
  double until = 0;
  std::map<std::string, double> params;
};

struct RallyStats {
  int rallies = 0;      // balls dropped that ended (goal, own goal or out)
  int contacts = 0;     // shots and intercepts within those rallies
  int goals = 0;
  double seconds = 0;   // match time played
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
  void say(std::string text, std::string recording = {});
  void award(const std::string& team, int goals = 1);
  // Drops the ball at `spot` after `delay` seconds (a goal's celebration); replaces a pending drop.
  void respawn(int spot, double delay);
  void finish(const std::string& winner);  // "" for a draw
  // Sets player k's own handicap (> 0) from now on: a sport's rules may change it during a match.
  void set_handicap(int k, double handicap);

  // Opens these wormholes on the field, replacing any (an empty list closes them). Throws
  // std::invalid_argument for mouths the core refuses.
  void set_wormholes(std::vector<Wormhole> wormholes);

  // Gives `player` (a body index) a power-up for `seconds`; it ends with a powerup_end event. A
  // second one of the same name replaces the first. Throws std::invalid_argument for bad values.
  void grant(int player, const std::string& name, double seconds, std::map<std::string, double> params);

  // Puts the players where (and as fast as) `input` says without a step (a rule spec's scene).
  // Throws InputError like step().
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
  std::vector<std::string> teams() const;
  double time() const { return world_.time(); }
  bool finished() const { return finished_; }
  const std::string& winner() const { return winner_; }
  const RallyStats& stats() const { return stats_; }
  const std::vector<ActivePowerup>& powerups() const { return powerups_; }
  int last_toucher() const { return last_toucher_; }  // body of the last announced touch this rally, -1 for none
  // Player k's handicap as it applies now: its own, times the automatic balance's boost while
  // its team trails.
  double handicap_now(int k) const;
  int spot_of(const std::string& team_or_name) const;  // -1 when there is none

  // Events and phrases since the last call, in order.
  std::vector<GameEvent> take_events();
  std::vector<Said> take_said();
  // Rule errors since the last call ("rules/x/sport.lua:12: ... (on goal skipped)").
  std::vector<std::string> take_errors();
  void report_error(std::string message);

  // The current fates as the rules see them (fresh prediction; empty when no ball is live).
  std::vector<FateView> fates() const;

 private:
  void handle(const Event& e);
  void expire_powerups();
  void powerup_event(const char* type, int player, const std::string& name);  // powerup, powerup_end
  void tell_rules(const GameEvent& e);
  void retweak();
  FateView view(const FateGroup& g) const;

  World world_;
  MatchConfig config_;
  Rules* rules_;
  std::vector<Player> players_;
  std::vector<ActivePowerup> powerups_;
  std::map<std::string, int> score_;
  std::vector<GameEvent> events_;
  std::vector<Said> said_;
  std::vector<std::string> errors_;
  std::vector<Event> core_events_;
  RallyStats stats_;
  double respawn_at_ = -1;
  int respawn_spot_ = 0;
  int rally_contacts_ = 0;
  int last_toucher_ = -1;  // body of the last announced touch this rally
  double last_touch_t_ = 0;
  bool finished_ = false, time_up_told_ = false;
  std::string winner_;
  std::string handling_;  // type of the event the rules are handling
};

}  // namespace quantum::game

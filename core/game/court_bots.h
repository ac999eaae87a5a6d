// Simulated players for sports of hitting over a net (fields whose bodies hit: volleyball, sepak
// takraw, or any "A vs B" sport built the same way). They know the court: each team's side (the
// field's box area with the team's name, else its half of the bounds), the net between the
// sides (its top is the highest board's), and their own zone (where the field starts them: a
// role's place). They see where everyone stands, as players on a court do, and they never see
// the particles: the ball is what the announcer said ("Ada hits", where it was met) and what
// they saw of the swing (which way, how fast, how steeply), flown under the field's gravity in
// their imagination, with their skill's noise.
//
// A ball coming down on a team's side draws whichever of its players gets under it first (not
// the one who touched it last); the others go back to their zones. A team's first touch goes up
// to the setter's place a step off the net, its second up for the attacker at the net, its third
// over the net into the open court (the sport's hint, game.aim, when it gives a point). A ball
// lying on a team's side of the net (a serve at its spot) is sent over by the player whose turn
// it is (game.turn), else by the nearest. While the other team sets up its attack, the player
// nearest the net stands at it in the ball's way: a block is the rules' to call. A restart's
// place (game.place) comes first.
//
// Their touches are swings (Match::let_go from throws()): a velocity, recorded and replayed as a
// tracked player's accelerometer would be.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "game/bots.h"
#include "game/bot_common.h"
#include "game/game.h"
#include "game/team_bots.h"

namespace quantum::game {

class CourtBots final : public SimulatedPlayers {
 public:
  // One skill in [0, 1] per body of the field; `hit_speed` is the sport's usual throw speed (m/s),
  // which an expert's attack doubles. Throws std::invalid_argument unless the field's bodies
  // make two teams.
  CourtBots(const Field& field, std::vector<double> skills, uint64_t seed, double hit_speed);

  void hear(const GameEvent& e) override;
  const std::vector<BodyInput>& move(double t, double dt, std::span<const Player> players) override;
  std::span<const Throw> throws() const override { return swings_; }

 private:
  struct Side {
    Vec2 lo, hi;      // the court: lines it defends
    Vec2 toward;      // unit, from this side across the net
  };
  // What a bot believes about the ball.
  struct Ball {
    enum class State : uint8_t { None, Lying, Flying } state = State::None;
    Vec3 at, velocity;  // at time `since`
    double since = 0;
    int version = 0;    // counts what it heard, so a swing is made once for each
  };
  struct Bot {
    int body, team;  // team: 0 or 1
    TeamSkill skill;
    Vec2 pos, home;
    Ball ball;
    int touches = 0;      // its team's touches this rally, as it counted them
    int last_team = -1;   // the team that touched last (-1: nobody this rally)
    int last_hitter = -1;
    int swung_for = -1;   // the ball version it last swung for
    std::vector<Heard> heard;
    std::mt19937_64 rng;
  };
  // Where the imagined ball comes within reach: when, and where on the floor.
  struct Meeting {
    double t = -1;  // -1: never, in the look-ahead
    Vec2 at;
  };

  void imagine(Bot& b, const Heard& h);
  Vec3 ball_at(const Ball& ball, double t) const;
  Meeting meeting(const Ball& ball, double now, float height) const;
  float side_of(int team, Vec2 p) const;  // < 0 on the team's own side of the net
  Vec2 off_net(int team, Vec2 p, float off) const;  // level with p, `off` m back from the net on the team's side
  Vec2 setter_place(int team) const;  // where a team's first touch goes: mid-court, a step off the net
  // Of b's team, but not `except`, the player for whom `measure(position)` is least; -1 for none.
  template <class Measure>
  int nearest_mate(const Bot& b, int except, std::span<const Player> players, Measure measure) const;
  Vec2 decide(Bot& b, double t, std::span<const Player> players);
  int receiver(const Bot& b, Vec2 at, std::span<const Player> players, bool serve) const;
  Vec2 open_court(Bot& b, std::span<const Player> players, bool deep);
  Vec3 over_the_net(const Bot& b, Vec3 from, Vec2 to);
  void swing(Bot& b, Vec3 from, int touch, std::span<const Player> players);
  Vec2 on_own_side(const Bot& b, Vec2 p) const;

  Field field_;
  std::vector<std::string> teams_;
  Side sides_[2];
  Vec2 net_;          // a point on the net
  float net_top_ = 0; // the net's top (m)
  std::vector<Bot> bots_;
  std::vector<BodyInput> moves_;
  std::vector<Throw> swings_;
  double hit_speed_;
  Vec2 lo_, hi_;  // where a player may stand: the bounds
};

}  // namespace quantum::game

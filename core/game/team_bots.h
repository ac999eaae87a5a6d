// Simulated players for sports of holding, throwing and catching (fields whose bodies catch): team
// handball, or any "A vs B" sport built the same way. Like the mallet bots they know the field
// (goals, goal areas, its friction and gravity) and what the announcer said, and they see where
// everyone stands, as players on a court do; they never see the particles. Who holds the ball they
// know only from the announcements, and a thrown ball only as the announcer's "Anna throws" and
// the direction (and, with height, the steepness) they saw her throw in. Under gravity a ball
// flies on without slowing until it comes down, bounces and rolls, and it can be caught only
// below a player's reach: a lob over a player's head is run after, not waited for.
//
// The holder looks for a shot, else for an open teammate (one who calls for the ball counts
// more), and throws before the sport's three seconds are up. Teammates run into space and call
// for the ball when nobody marks them. With a goal at each end the team keeps the formation of
// its start places, moved up the field with the ball until its foremost stand just outside the
// opponents' goal area: backs stay behind forwards, and a keeper's throw after a save finds
// teammates near, where all of them used to wait at the far area's edge. Round one goal for both
// (a hoop) they take a fan of places. The other team marks them
// man to man between them and the goal and presses the holder. Goalkeepers keep to their goal
// area, between the ball and the goal. A flying ball draws whoever of each team can reach its
// path first; a loose one (the announcer's `loose`: where it lies), the nearest of each team,
// who looks about the place it was told to lie when the ball is not where it imagined. Field
// players stay out of goal areas (around a goal's mouth on the floor, not under a hoop);
// goalkeepers stay in their own. A field may give each team a
// side (a box area named after the team that holds no goal: a court's half beyond a net): that
// team's players keep to it and leave a ball beyond it to the others. A body's `zone` (a rectangle:
// its role's part of the field, a back's own two thirds) is kept to likewise, but for a loose ball,
// which is anyone's wherever it lies. Players who kick (soccer) dribble
// for longer before they must let go, and are marked and pressed from further off, since a ball
// along the ground meets every foot on its line.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "game/bots.h"
#include "game/bot_common.h"
#include "game/game.h"

namespace quantum::game {

// Skill 0 is a beginner, 1 an expert.
struct TeamSkill {
  double reaction;       // s from hearing an event to acting on it
  double throw_noise;    // rad, standard deviation of a throw's direction
  double imagine_noise;  // m, standard deviation of where it places an announced ball
  double run_speed;      // m/s
  double throw_speed;    // m/s of its hardest throw (a shot)
  double vision;         // 0..1: how well it picks the open teammate (1 always the best)
};
TeamSkill team_skill(double skill);

class TeamBots final : public SimulatedPlayers {
 public:
  // One skill in [0, 1] per body of the field; `throw_speed` is the sport's usual throw (m/s).
  TeamBots(const Field& field, std::vector<double> skills, uint64_t seed, double throw_speed);

  void hear(const GameEvent& e) override;
  const std::vector<BodyInput>& move(double t, double dt, std::span<const Player> players) override;
  std::span<const Throw> throws() const override { return throws_; }

 private:
  // What a bot believes about the ball.
  struct Ball {
    enum class State : uint8_t { None, Held, Flying } state = State::None;
    int holder = -1;    // Held: the body holding it
    int thrower = -1;   // Flying: who threw it (-1: dropped, or off a wall)
    Vec2 at, velocity;  // Flying: where it was and how fast across the field, as imagined
    Vec2 told;          // where the announcer last placed it
    float z = 0, up = 0;  // Flying, on a field with height: how high it is and how fast it rises
  };
  struct Bot {
    int body;
    TeamSkill skill;
    bool keeper;
    int own_goal = -1, their_goal = -1;  // goal indices (-1: none)
    int own_area = -1;                   // the goal area it keeps (a goalkeeper's), -1 for none
    int side = -1;                       // the area its team keeps to (its side of a court), -1: the whole field
    Vec2 pos, home, spot;                // where it is, starts, and stands in full attack
    float foremost = 0, front = 0;       // how far up from its own goal its team's foremost start, and attack
    Ball ball;
    double got_ball = -1;                // when it learnt it holds the ball
    double throw_at = 0;                 // when it throws at the latest
    bool calling = false;                // open, and asking for the ball
    double phase = 0;                    // of its runs into space
    std::vector<int> mates, opponents;   // the field players (no goalkeepers) of its team, itself too, and of the others
    std::vector<Heard> heard;
    std::mt19937_64 rng;
  };

  void imagine(Bot& b, const Heard& h);
  void fly(Ball& ball, double dt) const;
  double airborne(Ball& ball, double dt) const;
  bool lies_loose(const Ball& ball) const;
  bool within_reach(const Ball& ball, int body) const;
  Vec2 decide(Bot& b, double t, std::span<const Player> players);
  Vec2 holding(Bot& b, double t, std::span<const Player> players);
  Vec2 attacking(const Bot& b, double t, std::span<const Player> players) const;
  Vec2 attacking_place(const Bot& b, std::span<const Player> players) const;
  struct Axis {
    Vec2 from, forward;
    float length;
  };
  Axis attack_axis(const Bot& b) const;
  Vec2 open_lane(const Bot& b, Vec2 p, std::span<const Player> players) const;
  Vec2 defending(const Bot& b, std::span<const Player> players) const;
  Vec2 keeping(const Bot& b, std::span<const Player> players) const;
  Vec2 chasing(const Bot& b, std::span<const Player> players, bool& chase) const;
  bool open_shot(const Bot& b, std::span<const Player> players, Vec2& aim) const;
  float shooting_distance(const Bot& b) const;
  int open_teammate(Bot& b, std::span<const Player> players, Vec2& aim, bool forced);
  Vec2 pass_velocity(Bot& b, Vec2 from, Vec2 to, double most);
  Throw arc(Bot& b, Vec2 from, Vec2 aim, Vec2 velocity, int goal);
  float clearance(const Bot& b, std::span<const Player> players, Vec2 from, Vec2 to, float speed, bool keepers) const;
  Vec2 allowed(const Bot& b, Vec2 p, bool in_zone = true) const;
  Vec2 holder_position(const Bot& b, std::span<const Player> players) const;
  bool team_has_ball(const Bot& b) const;
  double most_hold(const Bot& b) const;  // s it may hold the ball before it must let go

  Field field_;
  std::vector<Bot> bots_;
  std::vector<bool> goal_area_;  // per field area: whether it holds a goal's mouth (field players keep out)
  std::vector<BodyInput> moves_;
  std::vector<Throw> throws_;
  double throw_speed_;
  Vec2 lo_, hi_;  // where a player may stand: the bounds
};

}  // namespace quantum::game

// Simulated players: an input source that plays like a person would. A bot knows the field (its
// walls, its goal and the other) and what the announcer said: where the ball was dropped, who
// shot from where and roughly which way, goals. It never sees the particles. It imagines the
// ball from what it heard, with its skill's noise, and moves its body to defend and to shoot.
#pragma once

#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <vector>

#include "game/bot_common.h"
#include "game/game.h"

namespace quantum::game {

// Skill 0 is a beginner, 1 an expert.
struct SkillModel {
  double reaction;       // s from hearing an event to acting on it
  double aim_noise;      // rad, standard deviation of a shot's direction
  double imagine_noise;  // m, standard deviation of where it places an announced ball
  double speed_noise;    // relative error of an announced shot's speed
  double max_speed;      // m/s the body moves at
  double strike_speed;   // m/s of a strike through the ball
  double discipline;     // 1 keeps the defence in front of its goal mouth; 0 follows the ball anywhere
};
SkillModel skill_model(double skill);

// Simulated players of any sport: they hear the announcer and move every body.
class SimulatedPlayers {
 public:
  virtual ~SimulatedPlayers() = default;
  // An announced event; the bots act on it after their reaction time.
  virtual void hear(const GameEvent& e) = 0;
  // Where every body goes this frame, and its velocity. `players` carries the sport's hints
  // (whose turn it is, where to aim: game.turn, game.aim).
  virtual const std::vector<BodyInput>& move(double t, double dt, std::span<const Player> players) = 0;
  // The throws they made in the last move (a sport of catching).
  virtual std::span<const Throw> throws() const { return {}; }
};

// The simulated players for `field`: TeamBots when its bodies catch, CourtBots when they hit
// over a net (a field with height), Bots when they strike.
// One skill in [0, 1] per body; `throw_speed` is the sport's (m/s).
std::unique_ptr<SimulatedPlayers> make_bots(const Field& field, std::vector<double> skills, uint64_t seed,
                                            double throw_speed);

// Players who strike the ball with a mallet (air hockey).
class Bots final : public SimulatedPlayers {
 public:
  // One skill in [0, 1] per body of the field.
  Bots(const Field& field, std::vector<double> skills, uint64_t seed);

  void hear(const GameEvent& e) override;
  const std::vector<BodyInput>& move(double t, double dt, std::span<const Player> players) override;

 private:
  // What a bot keeps of an event: only what is said about the ball.
  enum class Plan { Home, Approach, Strike, Defend };
  struct Bot {
    int body;
    SkillModel skill;
    Vec2 pos, home;
    float radius;
    float attack_x;  // +1 when the opponents' goal is toward +x
    float mouth_lo, mouth_hi;  // the own goal mouth's extent across the field
    bool knows_ball = false;
    Vec2 ball, ball_v;  // the imagined ball
    Plan plan = Plan::Home;
    Vec2 aim;          // unit direction of the strike being set up
    double strike_end = 0;
    std::vector<Heard> heard;
    std::mt19937_64 rng;
  };

  void imagine(Bot& b, const Heard& e);
  void fly(Vec2& ball, Vec2& velocity, double dt) const;
  Vec2 decide(Bot& b, double t, std::span<const Player> players, bool whole_field);
  Vec2 target(const Bot& b, const Aim& aim) const;
  Vec2 goal_target(const Bot& b, const Goal& goal) const;
  Vec2 out_of_the_way(const Bot& b) const;
  float guarded(const Bot& b, float y) const;
  Vec2 clamp_to_reach(const Bot& b, Vec2 p, bool whole_field) const;

  Field field_;
  std::vector<Bot> bots_;
  std::vector<BodyInput> moves_;
  Vec2 lo_, hi_;  // where a ball centre can be: the walls' box less the ball's radius
  float mid_x_;
};

}  // namespace quantum::game

#include "game/bots.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "game/court_bots.h"
#include "game/bot_common.h"
#include "game/plane.h"
#include "game/team_bots.h"

namespace quantum::game {
namespace {

constexpr double kStrikeTime = 0.18;   // s a strike drives through the ball
constexpr float kBehind = 0.10f;       // m behind the ball where a strike starts
constexpr float kSetUp = 0.03f;        // m: close enough to the start to strike

}  // namespace

SkillModel skill_model(double s) {
  if (!(s >= 0 && s <= 1)) throw std::invalid_argument("skill must be in [0, 1], got " + std::to_string(s));
  return {0.40 - 0.28 * s, 0.45 - 0.38 * s, 0.10 - 0.08 * s, 0.40 - 0.30 * s, 1.2 + 2.3 * s, 2.5, s};
}

Bots::Bots(const Field& field, std::vector<double> skills, uint64_t seed) : field_(field) {
  check_count(skills.size(), "skills", field.bodies.size(), "players");
  lo_ = field.bounds_max, hi_ = field.bounds_min;
  for (const Segment& s : field.segments)
    for (Vec2 p : {s.a, s.b})
      lo_ = {std::min(lo_.x, p.x), std::min(lo_.y, p.y)}, hi_ = {std::max(hi_.x, p.x), std::max(hi_.y, p.y)};
  lo_ = lo_ + Vec2{field.ball_radius, field.ball_radius}, hi_ = hi_ - Vec2{field.ball_radius, field.ball_radius};
  mid_x_ = 0.5f * (lo_.x + hi_.x);
  for (size_t k = 0; k < skills.size(); ++k) {
    const BodySpec& spec = field.bodies[k];
    Bot b;
    b.body = int(k);
    b.skill = skill_model(skills[k]);
    b.pos = b.home = spec.start;
    b.radius = spec.radius;
    b.attack_x = spec.start.x < mid_x_ ? 1.0f : -1.0f;
    b.mouth_lo = b.mouth_hi = spec.start.y;
    for (const Goal& g : field.goals)
      if (g.team == spec.team) b.mouth_lo = std::min(g.a.y, g.b.y), b.mouth_hi = std::max(g.a.y, g.b.y);
    b.rng.seed(seed * 0x9E3779B97F4A7C15ull + k);
    b.heard.reserve(64);  // a reaction time's worth of events, and more
    bots_.push_back(std::move(b));
  }
  moves_.resize(bots_.size());
}

void Bots::hear(const GameEvent& e) {
  switch (e.type) {
    case EventKind::Drop: case EventKind::Shot: case EventKind::Intercept: case EventKind::Retouch:
    case EventKind::Bounce: case EventKind::Goal: case EventKind::OwnGoal: case EventKind::Out: case EventKind::Dead:
    case EventKind::Loose:
      for (Bot& b : bots_) b.heard.push_back(heard(e, b.skill.reaction));
      return;
    default: return;  // nothing about the ball
  }
}

// What a player makes of an announcement: the ball where it was said to be, give or take.
void Bots::imagine(Bot& b, const Heard& e) {
  std::normal_distribution<double> noise(0, 1);
  switch (e.type) {
    case EventKind::Drop: b.knows_ball = true, b.ball = e.where, b.ball_v = {0, 0}; break;
    case EventKind::Shot:
    case EventKind::Intercept:
    case EventKind::Retouch:
    case EventKind::Bounce:
    case EventKind::Loose: {
      const double err = b.skill.imagine_noise;
      b.knows_ball = true;
      b.ball = e.where + Vec2{float(err * noise(b.rng)), float(err * noise(b.rng))};
      const float speed = length(e.velocity) * float(std::max(0.2, 1 + b.skill.speed_noise * noise(b.rng)));
      b.ball_v = speed * rotated(unit(e.velocity), b.skill.aim_noise * 0.5 * noise(b.rng));
      // The ball has flown on while the news travelled.
      fly(b.ball, b.ball_v, std::max(0.0, b.skill.reaction));
      break;
    }
    default: b.knows_ball = false; break;  // goal, own goal, out, dead: gone until the next drop
  }
  b.plan = Plan::Home;
}

// The imagined ball flies straight and bounces off the walls' box.
void Bots::fly(Vec2& ball, Vec2& velocity, double dt) const {
  for (double left = dt; left > 1e-9;) {
    const double h = std::min(left, 1.0 / 120);
    ball = ball + float(h) * velocity;
    if (ball.x < lo_.x || ball.x > hi_.x) ball.x = std::clamp(ball.x, lo_.x, hi_.x), velocity.x *= -0.9f;
    if (ball.y < lo_.y || ball.y > hi_.y) ball.y = std::clamp(ball.y, lo_.y, hi_.y), velocity.y *= -0.9f;
    left -= h;
  }
}

// A player keeps to its own half, unless the sport plays by turns: then whoever has the turn may
// go anywhere on the field.
Vec2 Bots::clamp_to_reach(const Bot& b, Vec2 p, bool whole_field) const {
  const float r = b.radius;
  float x0 = lo_.x + r, x1 = hi_.x - r;
  if (!whole_field) {
    if (b.attack_x > 0) x1 = std::min(x1, mid_x_ - r);
    else x0 = std::max(x0, mid_x_ + r);
  }
  return {std::clamp(p.x, x0, x1), std::clamp(p.y, lo_.y + r, hi_.y - r)};
}

// Where to shoot: where the sport's hint says (a point; a wall, at its point nearest the ball; a
// goal), or by default into the opponents' goal that leaves the clearest path.
Vec2 Bots::target(const Bot& b, const Aim& aim) const {
  switch (aim.kind) {
    case Aim::Kind::Point: return aim.point;
    case Aim::Kind::Goal: return goal_target(b, field_.goals[size_t(aim.index)]);
    case Aim::Kind::Wall: return nearest_on_wall(field_, aim.index, b.ball);
    case Aim::Kind::Default: break;
  }
  Vec2 best{b.ball.x + b.attack_x, b.ball.y};
  float best_clearance = -1;
  for (const Goal& g : field_.goals) {
    if (g.team == field_.bodies[b.body].team) continue;
    const Vec2 at = goal_target(b, g);
    float clearance = 1e9f;
    for (const Bot& other : bots_)
      if (field_.bodies[other.body].team != field_.bodies[b.body].team)
        clearance = std::min(clearance, distance_to_segment(other.pos, b.ball, at));
    if (clearance > best_clearance) best_clearance = clearance, best = at;
  }
  return best;
}

// Where to shoot at one goal, as a player who sees the opponents' mallets would choose: points
// across its mouth, straight or banked off either side wall (aimed at the point mirrored
// through the wall), taking the path that passes furthest from every opponent.
Vec2 Bots::goal_target(const Bot& b, const Goal& goal) const {
  Vec2 best = centre(goal);
  float best_clearance = -1;
  for (int i = 0; i < 5; ++i) {
    const float f = 0.15f + 0.7f * float(i) / 4;  // stay inside the posts
    const Vec2 spot = goal.a + f * (goal.b - goal.a);
    // Mirror through nothing, the high side wall, the low side wall.
    for (int wall = 0; wall < 3; ++wall) {
      auto mirror = [&](Vec2 p) -> Vec2 {
        if (wall == 1) return {p.x, 2 * hi_.y - p.y};
        if (wall == 2) return {p.x, 2 * lo_.y - p.y};
        return p;
      };
      const Vec2 aim = mirror(spot);
      float clearance = 1e9f;
      for (const Bot& other : bots_) {
        if (field_.bodies[other.body].team == field_.bodies[b.body].team) continue;
        clearance = std::min({clearance, distance_to_segment(other.pos, b.ball, aim),
                              distance_to_segment(mirror(other.pos), b.ball, aim)});
      }
      if (wall > 0) clearance *= 0.8f;  // a bank shot loses speed and is harder to place
      if (clearance > best_clearance) best_clearance = clearance, best = aim;
    }
  }
  return best;
}

// A defender's place across the field: a disciplined one never leaves the front of its goal
// mouth (a ball that crosses the line beside it hits the end wall); a careless one follows
// the ball wherever it imagines it.
float Bots::guarded(const Bot& b, float y) const {
  const float slack = float(1 - b.skill.discipline) * (hi_.y - lo_.y);
  return std::clamp(y, b.mouth_lo - slack, b.mouth_hi + slack);
}

// Out of turn a player keeps clear of the ball: of its place at home and beside it on either
// side, the one the imagined ball's next second passes furthest from.
Vec2 Bots::out_of_the_way(const Bot& b) const {
  const float margin = b.radius + field_.ball_radius + 0.05f;
  const Vec2 places[] = {b.home, {b.home.x, lo_.y + margin}, {b.home.x, hi_.y - margin}};
  Vec2 best = b.home;
  float best_clearance = -1;
  for (const Vec2& place : places) {
    Vec2 ball = b.ball, velocity = b.ball_v;
    float clearance = length(ball - place);
    for (int k = 0; k < 20; ++k) {
      fly(ball, velocity, 0.05);
      clearance = std::min(clearance, length(ball - place));
    }
    if (clearance > best_clearance + 0.05f) best_clearance = clearance, best = place;
  }
  return best;
}

// Where the bot wants its body now. Out of turn it keeps clear of the ball; with the turn in a
// sport that plays by turns, the ball is its to play wherever it is.
Vec2 Bots::decide(Bot& b, double t, std::span<const Player> players, bool whole_field) {
  const Player& me = players[size_t(b.body)];
  if (!b.knows_ball) return b.home;
  if (!me.turn) {
    b.plan = Plan::Home;
    return out_of_the_way(b);
  }
  const bool mine = whole_field || (b.ball.x - mid_x_) * b.attack_x < 0;
  const float toward_me = -b.attack_x * b.ball_v.x;
  const float speed = length(b.ball_v);
  if (b.plan == Plan::Strike) {
    if (t < b.strike_end) return b.ball + 0.3f * b.aim;
    b.plan = Plan::Home;
  }
  if (mine && (speed < 0.6f || toward_me < 0.3f || whole_field)) {
    // A slow ball on my side: get behind it and strike toward the target.
    if (b.plan != Plan::Approach) {
      std::normal_distribution<double> noise(0, b.skill.aim_noise);
      b.aim = rotated(unit(target(b, me.aim) - b.ball), noise(b.rng));
      b.plan = Plan::Approach;
    }
    const Vec2 start = b.ball - (kBehind + b.radius) * b.aim;
    if (length(clamp_to_reach(b, start, whole_field) - b.pos) < kSetUp) {
      b.plan = Plan::Strike;
      b.strike_end = t + kStrikeTime;
      return start;
    }
    // Going straight there would run through the ball: go round it, beside the strike line.
    const float keep_off = b.radius + field_.ball_radius + 0.04f;
    if (distance_to_segment(b.ball, b.pos, start) < keep_off) {
      const Vec2 side{-b.aim.y, b.aim.x};
      const float which = (b.pos.x - b.ball.x) * side.x + (b.pos.y - b.ball.y) * side.y >= 0 ? 1.0f : -1.0f;
      return b.ball + (which * (keep_off + 0.02f)) * side - (0.5f * keep_off) * b.aim;
    }
    return start;
  }
  b.plan = Plan::Defend;
  if (toward_me > 0.3f) {
    // Coming at me: meet it on my defence line, where the imagined flight crosses it.
    const float line = b.home.x;
    const float when = (line - b.ball.x) / b.ball_v.x;
    Vec2 ball = b.ball, velocity = b.ball_v;
    fly(ball, velocity, std::clamp(double(when), 0.0, 2.0));
    return {line, guarded(b, ball.y)};
  }
  return {b.home.x, guarded(b, b.home.y + 0.5f * (b.ball.y - b.home.y))};
}

const std::vector<BodyInput>& Bots::move(double t, double dt, std::span<const Player> players) {
  check_count(players.size(), "players", bots_.size(), "bots");
  // A sport that gives the turn to some players only plays by turns.
  const bool by_turns = std::any_of(players.begin(), players.end(), [](const Player& p) { return !p.turn; });
  for (size_t k = 0; k < bots_.size(); ++k) {
    Bot& b = bots_[k];
    act_on_due(b.heard, t, [&](const Heard& h) { imagine(b, h); });  // in place: no allocation
    if (b.knows_ball) fly(b.ball, b.ball_v, dt);
    const bool whole_field = by_turns && players[k].turn;
    // A restart's place comes first (game.place).
    const Vec2 decided = decide(b, t, players, whole_field);
    const Vec2 want = players[k].place ? *players[k].place : clamp_to_reach(b, decided, whole_field);
    const double limit = b.plan == Plan::Strike ? b.skill.strike_speed : b.skill.max_speed;
    Vec2 step = want - b.pos;
    const float l = length(step), most = float(limit * dt);
    if (l > most) step = (most / l) * step;
    b.pos = b.pos + step;
    moves_[k] = {b.pos, (1 / float(dt)) * step};
  }
  return moves_;
}

std::unique_ptr<SimulatedPlayers> make_bots(const Field& field, std::vector<double> skills, uint64_t seed,
                                            double throw_speed) {
  if (field.catching()) return std::make_unique<TeamBots>(field, std::move(skills), seed, throw_speed);
  const bool hitting = std::any_of(field.bodies.begin(), field.bodies.end(), [](const BodySpec& b) { return b.hits; });
  if (hitting && field.has_height()) return std::make_unique<CourtBots>(field, std::move(skills), seed, throw_speed);
  return std::make_unique<Bots>(field, std::move(skills), seed);
}

}  // namespace quantum::game

#include "game/court_bots.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "game/bot_common.h"
#include "game/plane.h"

namespace quantum::game {
namespace {

constexpr double kLook = 4.0;          // s of an imagined flight a player reads ahead
constexpr double kLookStep = 1.0 / 60;
constexpr float kMeetShare = 0.9f;     // of its reach: where a player meets a ball coming down (hands up)
constexpr float kSetterOff = 1.5f;     // m off the net: where a first touch goes
constexpr float kAttackOff = 1.0f;     // m off the net: where a second touch goes, for the attack
constexpr float kBlockOff = 0.4f;      // m off the net a blocker stands (its body clear of it)
constexpr float kClear = 0.3f;         // m above the net's top an attack crosses it
constexpr float kInset = 0.8f;         // m inside the lines an attack aims...
constexpr float kServeInset = 1.5f;    // ...and a serve
constexpr float kDig = 1.13f;          // rad (65 degrees): a first touch goes up...
constexpr float kSet = 1.22f;          // ...a second one higher (70 degrees)
constexpr double kServeReach = 3.0;    // m: a server decides its serve this far from the ball

Vec2 flat(Vec3 v) { return {v.x, v.y}; }

}  // namespace

CourtBots::CourtBots(const Field& field, std::vector<double> skills, uint64_t seed, double hit_speed)
    : field_(field), hit_speed_(hit_speed) {
  check_count(skills.size(), "skills", field.bodies.size(), "players");
  if (!(hit_speed > 0)) throw std::invalid_argument("a hit's speed must be > 0");
  if (!field.has_height()) throw std::invalid_argument("players who hit over a net need a field with height");
  for (const BodySpec& b : field.bodies)
    if (std::find(teams_.begin(), teams_.end(), b.team) == teams_.end()) teams_.push_back(b.team);
  if (teams_.size() != 2)
    throw std::invalid_argument("players who hit over a net make two teams; the field's make " + std::to_string(teams_.size()));
  lo_ = field.bounds_min + Vec2{0.3f, 0.3f}, hi_ = field.bounds_max - Vec2{0.3f, 0.3f};

  // Each team's court: its box area, else its half of the bounds across the line between the
  // teams' starting places.
  Vec2 start[2] = {{0, 0}, {0, 0}};
  int n[2] = {0, 0};
  for (const BodySpec& b : field.bodies) {
    const int team = b.team == teams_[0] ? 0 : 1;
    start[team] = start[team] + b.start, ++n[team];
  }
  for (int i = 0; i < 2; ++i) start[i] = (1.0f / float(n[i])) * start[i];
  bool boxed[2] = {false, false};
  for (int i = 0; i < 2; ++i)
    for (const Area& a : field.areas)
      if (!boxed[i] && a.box && a.team == teams_[size_t(i)]) sides_[i].lo = a.a, sides_[i].hi = a.b, boxed[i] = true;
  net_ = 0.5f * (start[0] + start[1]);
  if (boxed[0] && boxed[1]) net_ = 0.25f * (sides_[0].lo + sides_[0].hi + sides_[1].lo + sides_[1].hi);
  for (const Board& board : field.boards) net_top_ = std::max(net_top_, board.top);
  if (!field.boards.empty()) net_ = 0.5f * (field.boards[0].a + field.boards[0].b);
  for (int i = 0; i < 2; ++i) {
    const Vec2 own = boxed[i] ? 0.5f * (sides_[i].lo + sides_[i].hi) : start[i];
    const Vec2 other = boxed[1 - i] ? 0.5f * (sides_[1 - i].lo + sides_[1 - i].hi) : start[1 - i];
    sides_[i].toward = unit(other - own);
  }
  for (int i = 0; i < 2; ++i) {
    if (boxed[i]) continue;
    // The bounds, cut at the net along the axis the teams face each other on.
    Side& s = sides_[i];
    s.lo = field.bounds_min, s.hi = field.bounds_max;
    if (std::abs(s.toward.x) >= std::abs(s.toward.y)) (s.toward.x > 0 ? s.hi.x : s.lo.x) = net_.x;
    else (s.toward.y > 0 ? s.hi.y : s.lo.y) = net_.y;
  }

  for (size_t k = 0; k < field.bodies.size(); ++k) {
    Bot b;
    b.body = int(k);
    b.team = field.bodies[k].team == teams_[0] ? 0 : 1;
    b.skill = team_skill(skills[k]);
    b.pos = b.home = field.bodies[k].start;
    b.rng.seed(seed * 0x9E3779B97F4A7C15ull + k);
    b.heard.reserve(64);
    bots_.push_back(std::move(b));
  }
  moves_.resize(bots_.size());
  swings_.reserve(bots_.size());
}

void CourtBots::hear(const GameEvent& e) {
  switch (e.type) {
    case EventKind::Drop: case EventKind::Hit: case EventKind::Throw: case EventKind::Kick: case EventKind::Bounce:
    case EventKind::Landing: case EventKind::Loose: case EventKind::Goal: case EventKind::OwnGoal: case EventKind::Out:
    case EventKind::Dead:
      for (Bot& b : bots_)
        b.heard.push_back(heard(e, b.skill.reaction));
      return;
    default: return;  // nothing about the ball
  }
}

void CourtBots::imagine(Bot& b, const Heard& h) {
  std::normal_distribution<double> noise(0, 1);
  Ball& ball = b.ball;
  ++ball.version;
  ball.since = h.at - b.skill.reaction;
  const float lying = field_.ball_radius;
  switch (h.type) {
    case EventKind::Drop:
    case EventKind::Loose:
      if (h.type == EventKind::Drop) b.touches = 0, b.last_team = b.last_hitter = -1;
      ball.state = Ball::State::Lying;
      ball.at = {h.where.x, h.where.y, lying}, ball.velocity = {};
      return;
    case EventKind::Hit:
    case EventKind::Throw:
    case EventKind::Kick:
    case EventKind::Bounce:
    case EventKind::Landing: {
      if (h.type == EventKind::Hit) {
        const int team = bots_[size_t(h.actor)].team;  // bots_ is in the field's body order
        b.touches = team == b.last_team ? b.touches + 1 : 1;
        b.last_team = team, b.last_hitter = h.actor;
      }
      if (h.type == EventKind::Landing) b.touches = 0, b.last_team = b.last_hitter = -1;  // off the floor: a new ball
      const double err = b.skill.imagine_noise;
      const Vec2 at = h.where + Vec2{float(err * noise(b.rng)), float(err * noise(b.rng))};
      const Vec2 v = float(std::max(0.3, 1 + 0.1 * noise(b.rng))) * rotated(h.velocity, 0.05 * noise(b.rng));
      ball.state = Ball::State::Flying;
      ball.at = {at.x, at.y, std::max(h.height, lying)};
      ball.velocity = {v.x, v.y, float(h.up * std::max(0.3, 1 + 0.1 * noise(b.rng)))};
      return;
    }
    default: ball.state = Ball::State::None; return;  // out, a goal, a dead ball: nothing to play until the next drop
  }
}

// The imagined ball at time t: in flight under gravity, and lying where it came down.
Vec3 CourtBots::ball_at(const Ball& ball, double t) const {
  if (ball.state != Ball::State::Flying) return ball.at;
  const float g = field_.gravity, r = field_.ball_radius;
  const Vec3 a = ball.at, v = ball.velocity;
  // z(s) = a.z + v.z s - g s^2 / 2 reaches the floor at the larger root.
  const float down = (v.z + std::sqrt(v.z * v.z + 2 * g * std::max(0.0f, a.z - r))) / g;
  const float s = std::min(float(t - ball.since), down);
  return {a.x + v.x * s, a.y + v.y * s, std::max(r, a.z + v.z * s - 0.5f * g * s * s)};
}

CourtBots::Meeting CourtBots::meeting(const Ball& ball, double now, float height) const {
  if (ball.state == Ball::State::Lying) return {now, flat(ball.at)};
  if (ball.state != Ball::State::Flying) return {};
  for (double s = 0; s <= kLook; s += kLookStep) {
    const double t = now + s;
    const Vec3 p = ball_at(ball, t);
    const float rising = ball.velocity.z - field_.gravity * float(t - ball.since);
    if (rising <= 0 && p.z <= height) return {t, flat(p)};
  }
  return {};
}

float CourtBots::side_of(int team, Vec2 p) const { return dot(p - net_, sides_[team].toward); }

Vec2 CourtBots::off_net(int team, Vec2 p, float off) const { return p - (side_of(team, p) + off) * sides_[team].toward; }

Vec2 CourtBots::setter_place(int team) const { return off_net(team, 0.5f * (sides_[team].lo + sides_[team].hi), kSetterOff); }

template <class Measure>
int CourtBots::nearest_mate(const Bot& b, int except, std::span<const Player> players, Measure measure) const {
  float least = 1e30f;
  int best = -1;
  for (const Bot& o : bots_)
    if (o.team == b.team && o.body != except)
      if (const float m = measure(players[size_t(o.body)].position); m < least) least = m, best = o.body;
  return best;
}

Vec2 CourtBots::on_own_side(const Bot& b, Vec2 p) const {
  const float over = side_of(b.team, p) + field_.bodies[size_t(b.body)].radius + 0.05f;
  if (over > 0) p = p - over * sides_[b.team].toward;
  return clamped(p, lo_, hi_);
}

// Who of b's team plays a ball met at `at`: whoever its turn allows that gets there first, never
// the player who touched it last (a double touch).
int CourtBots::receiver(const Bot& b, Vec2 at, std::span<const Player> players, bool serve) const {
  int best = -1;
  double soonest = 1e30;
  for (const Bot& o : bots_) {
    if (o.team != b.team || !players[size_t(o.body)].turn) continue;
    if (!serve && b.last_team == b.team && o.body == b.last_hitter) continue;
    const double t = length(players[size_t(o.body)].position - at) / o.skill.run_speed;
    if (t < soonest) soonest = t, best = o.body;
  }
  return best;
}

// An open place in the other court: the one furthest from every opponent, as well as b sees it;
// a serve (`deep`) goes beyond the first third. The sport's aim replaces it: a point, a goal's
// centre, a wall's point nearest the hitter.
Vec2 CourtBots::open_court(Bot& b, std::span<const Player> players, bool deep) {
  const Aim& aim = players[size_t(b.body)].aim;
  switch (aim.kind) {
    case Aim::Kind::Point: return aim.point;
    case Aim::Kind::Goal: return centre(field_.goals[size_t(aim.index)]);
    case Aim::Kind::Wall: return nearest_on_wall(field_, aim.index, players[size_t(b.body)].position);
    case Aim::Kind::Default: break;
  }
  const Side& them = sides_[1 - b.team];
  std::normal_distribution<double> noise(0, 1);
  const double blur = 1.5 * (1 - b.skill.vision);
  Vec2 best = 0.5f * (them.lo + them.hi);
  double widest = -1e30;
  // A serve, from behind the far line, keeps further inside them: it flies furthest.
  const float inset = deep ? kServeInset : kInset;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const Vec2 p{them.lo.x + inset + (them.hi.x - them.lo.x - 2 * inset) * float(i) / 3,
                   them.lo.y + inset + (them.hi.y - them.lo.y - 2 * inset) * float(j) / 3};
      if (deep && side_of(b.team, p) < std::abs(dot(them.hi - them.lo, sides_[b.team].toward)) / 3) continue;
      double open = 1e30;
      for (const Bot& o : bots_)
        if (o.team != b.team) open = std::min(open, double(length(players[size_t(o.body)].position - p)));
      open += blur * noise(b.rng);
      if (open > widest) widest = open, best = p;
    }
  return best;
}

// The flattest arc from `from` into the other court at `to` that clears the net, no faster than
// b hits; the steepest it tried when none does.
Vec3 CourtBots::over_the_net(const Bot& b, Vec3 from, Vec2 to) {
  const float most = float(hit_speed_ * b.skill.throw_speed), g = field_.gravity;
  const Vec3 floor{to.x, to.y, field_.ball_radius};
  Vec3 v{};
  for (int degrees = 5; degrees <= 60; degrees += 5) {
    v = field_.arc_velocity(from, floor, float(degrees) * 0.0174533f);
    const float along = dot(flat(v), sides_[b.team].toward);
    if (!(along > 0) || std::hypot(std::hypot(v.x, v.y), v.z) > most) continue;
    const float s = -side_of(b.team, flat(from)) / along;  // when it crosses the net
    if (s <= 0 || from.z + v.z * s - 0.5f * g * s * s >= net_top_ + kClear) return v;
  }
  return v;
}

void CourtBots::swing(Bot& b, Vec3 from, int touch, std::span<const Player> players) {
  std::normal_distribution<double> noise(0, 1);
  Vec3 v;
  if (touch >= 3 || b.ball.state == Ball::State::Lying) {
    v = over_the_net(b, from, open_court(b, players, b.ball.state == Ball::State::Lying));
  } else {
    // Up for a teammate a step off the net: the setter's place, or for the second touch the
    // attacker's (the teammate nearest the net), where its hands will be.
    Vec2 to = setter_place(b.team);
    if (touch == 2) {
      const int attacker = nearest_mate(b, b.body, players, [&](Vec2 p) { return -side_of(b.team, p); });
      if (attacker >= 0) to = off_net(b.team, players[size_t(attacker)].position, kAttackOff);
      else to = off_net(b.team, setter_place(b.team), kAttackOff);
    }
    const Vec3 hands{to.x, to.y, kMeetShare * field_.reach_of(b.body)};
    v = field_.arc_velocity(from, hands, touch == 2 ? kSet : kDig);
    if (v.x == 0 && v.y == 0 && v.z == 0) v = field_.throw_at(from, hands, float(hit_speed_));
  }
  const Vec2 way = rotated(flat(v), b.skill.throw_noise * noise(b.rng));
  const float speed = float(std::max(0.5, 1 + 0.5 * b.skill.throw_noise * noise(b.rng)));
  swings_.push_back({b.body, speed * way, speed * v.z});
  b.swung_for = b.ball.version;
}

Vec2 CourtBots::decide(Bot& b, double t, std::span<const Player> players) {
  const Ball& ball = b.ball;
  if (ball.state == Ball::State::None) return b.home;
  const float reach = kMeetShare * field_.reach_of(b.body);
  const Meeting m = meeting(ball, t, reach);
  if (m.t < 0) return b.home;
  if (side_of(b.team, m.at) < 0) {
    // On our side: one of us plays it.
    const bool serve = ball.state == Ball::State::Lying;
    const int who = receiver(b, m.at, players, serve);
    if (who == b.body) {
      const bool near = length(b.pos - m.at) < kServeReach;
      if (b.swung_for != ball.version && (!serve || near))
        swing(b, {m.at.x, m.at.y, serve ? field_.ball_radius : reach}, b.last_team == b.team ? b.touches + 1 : 1, players);
      return m.at;
    }
    // The next to play it after a first touch waits at the setter's place.
    if (!serve && b.last_team != b.team) {
      const Vec2 setter = setter_place(b.team);
      if (nearest_mate(b, who, players, [&](Vec2 p) { return length(p - setter); }) == b.body) return setter;
    }
    return b.home;
  }
  // On their side: when their next touch is their attack, the one of us nearest the net blocks.
  if (b.last_team == 1 - b.team && b.touches == 2 &&
      nearest_mate(b, -1, players, [&](Vec2 p) { return -side_of(b.team, p); }) == b.body)
    return off_net(b.team, m.at, kBlockOff + field_.bodies[size_t(b.body)].radius);
  return b.home;
}

const std::vector<BodyInput>& CourtBots::move(double t, double dt, std::span<const Player> players) {
  check_count(players.size(), "players", bots_.size(), "bots");
  swings_.clear();
  for (Bot& b : bots_) {
    act_on_due(b.heard, t, [&](const Heard& h) { imagine(b, h); });
  }
  for (size_t k = 0; k < bots_.size(); ++k) {
    Bot& b = bots_[k];
    b.pos = players[k].position;  // where it really is (a rule spec may have placed it)
    const Vec2 decided = decide(b, t, players);
    // Anywhere on its own side, behind the lines too (a serve), but never under the net.
    const Vec2 want = on_own_side(b, players[k].place.value_or(decided));
    Vec2 step = want - b.pos;
    const float l = length(step), most = float(std::min(b.skill.run_speed, 0.99 * field_.max_body_speed) * dt);
    if (l > most) step = (most / l) * step;
    b.pos = b.pos + step;
    moves_[k] = {b.pos, (1 / float(dt)) * step};
  }
  return moves_;
}

}  // namespace quantum::game

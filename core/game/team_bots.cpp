#include "game/team_bots.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "game/bot_common.h"
#include "game/plane.h"

namespace quantum::game {
namespace {

constexpr double kMostHold = 2.6;  // s: a handball player lets go within three seconds...
constexpr double kMostDribble = 6.0;  // ...one with the ball at its feet may dribble on, but not for ever
constexpr float kOpen = 2.5f;      // m: nobody nearer than this marks a player, who calls for the ball
constexpr float kLaneClear = 2.0f; // m: a passing lane this clear of every opponent's reach is open enough
constexpr float kMark = 1.3f;      // m a marker keeps from its attacker, on the goal side
// ...and from one who kicks: a ball kicked along the ground meets a marker's feet wherever it
// passes, where a throw goes over the hands, so a marker stands off far enough to leave the
// pass a chance (at 1.3 m it took 10 % of soccer's kicks for certain).
constexpr float kMarkKicker = 2.6f;
constexpr float kPress = 1.6f;     // m the nearest defender keeps from the holder (kMarkKicker from one who kicks)...
constexpr float kClosest = 1.3f;   // ...and not nearer, when a goal area is in the way
constexpr float kLoose = 0.8f;     // m/s: an imagined ball slower than this lies loose
constexpr float kHop = 0.5f;       // m/s: a ball that bounces off the floor slower than this rolls
constexpr float kSearched = 0.2f;  // m from where it imagines a loose ball: a player has looked there
constexpr double kSearch = 2.0;    // m about the told place a player looks for a loose ball
constexpr float kArrive = 7.0f;    // m/s a pass should still have when it reaches the catcher
constexpr double kLook = 3.0;      // s of an imagined flight a player reads ahead
constexpr double kLookStep = 0.05;

bool is_keeper(const BodySpec& b) { return b.role == "goalkeeper" || b.role == "keeper"; }

// The point nearest p inside (shrink > 0) or outside (shrink < 0) the area's edge moved in by
// `shrink`; p itself when it already is.
Vec2 to_area_edge(const Area& a, Vec2 p, float shrink, bool inside) {
  if (a.box) {
    const Vec2 lo{a.a.x + shrink, a.a.y + shrink}, hi{a.b.x - shrink, a.b.y - shrink};
    const Vec2 held{std::clamp(p.x, lo.x, std::max(lo.x, hi.x)), std::clamp(p.y, lo.y, std::max(lo.y, hi.y))};
    if (inside || held.x != p.x || held.y != p.y) return inside ? held : p;
    // Inside a box it must leave: out by its nearest side.
    const float left = p.x - lo.x, right = hi.x - p.x, low = p.y - lo.y, high = hi.y - p.y;
    const float least = std::min({left, right, low, high});
    if (least == left) return {lo.x, p.y};
    if (least == right) return {hi.x, p.y};
    return least == low ? Vec2{p.x, lo.y} : Vec2{p.x, hi.y};
  }
  const Vec2 on = nearest_on_segment(p, a.a, a.b);
  const float d = length(p - on), edge = a.radius - shrink;
  if (inside ? d <= edge : d >= edge) return p;
  return on + std::max(edge, 0.0f) * unit(d > 0 ? p - on : Vec2{0, 1});
}

}  // namespace

TeamSkill team_skill(double s) {
  if (!(s >= 0 && s <= 1)) throw std::invalid_argument("skill must be in [0, 1], got " + std::to_string(s));
  return {0.40 - 0.25 * s, 0.10 - 0.08 * s, 0.8 - 0.6 * s, 3.5 + 3.5 * s, 1.4 + 0.6 * s, 0.3 + 0.7 * s};
}

TeamBots::TeamBots(const Field& field, std::vector<double> skills, uint64_t seed, double throw_speed)
    : field_(field), throw_speed_(throw_speed) {
  check_count(skills.size(), "skills", field.bodies.size(), "players");
  if (!(throw_speed > 0)) throw std::invalid_argument("a throw's speed must be > 0");
  lo_ = field.bounds_min + Vec2{0.3f, 0.3f}, hi_ = field.bounds_max - Vec2{0.3f, 0.3f};
  const Vec2 middle = 0.5f * (field.bounds_min + field.bounds_max);
  for (size_t k = 0; k < field.bodies.size(); ++k) {
    const BodySpec& spec = field.bodies[k];
    Bot b;
    b.body = int(k);
    b.skill = team_skill(skills[k]);
    b.keeper = is_keeper(spec);
    b.pos = b.home = b.spot = spec.start;
    float own = 1e30f, theirs = 1e30f;
    for (size_t g = 0; g < field.goals.size(); ++g) {
      const float d = length(centre(field.goals[g]) - spec.start);
      if (field.goals[g].team == spec.team && d < own) own = d, b.own_goal = int(g);
      if (field.goals[g].team != spec.team && d < theirs) theirs = d, b.their_goal = int(g);
    }
    for (size_t a = 0; a < field.areas.size() && b.keeper; ++a)
      if (b.own_area < 0 && b.own_goal >= 0 && field.areas[a].contains(centre(field.goals[size_t(b.own_goal)])))
        b.own_area = int(a);
    b.rng.seed(seed * 0x9E3779B97F4A7C15ull + k);
    b.heard.reserve(64);
    bots_.push_back(std::move(b));
  }
  // A hoop's mouth is in the air: the area under it (basketball's arc) is open to everyone.
  for (const Area& a : field.areas)
    goal_area_.push_back(std::any_of(field.goals.begin(), field.goals.end(),
                                     [&](const Goal& g) { return !g.hoop() && a.contains(centre(g)); }));
  for (Bot& b : bots_)
    for (size_t a = 0; a < field.areas.size() && b.side < 0; ++a)
      if (field.areas[a].box && !goal_area_[a] && field.areas[a].team == field.bodies[size_t(b.body)].team) b.side = int(a);
  for (Bot& b : bots_)
    for (const Bot& o : bots_)
      if (!o.keeper) (field.bodies[size_t(o.body)].team == field.bodies[size_t(b.body)].team ? b.mates : b.opponents).push_back(o.body);
  // Attacking places. With a goal at each end, the team's formation moved up the field: every
  // field player keeps its start place's depth behind the foremost and its place across, and the
  // foremost arrives just outside the opponents' goal area (or a third of the field out), so that
  // backs hold behind forwards as the designer placed them. With one goal for both teams
  // (basketball's hoop) there is no depth to keep: a fan of places around it.
  for (Bot& b : bots_) {
    if (b.keeper || b.their_goal < 0) continue;
    const Goal& goal = field.goals[size_t(b.their_goal)];
    const std::vector<int>& mates = b.mates;
    const size_t j = size_t(std::find(mates.begin(), mates.end(), b.body) - mates.begin());
    // Weaving by rank in the team: each team's runs are the other's turned half a turn, so
    // neither team's timing is the better one.
    b.phase = 1.7 * double(j);
    float radius = 0.3f * (field.bounds_max.x - field.bounds_min.x);
    for (const Area& a : field.areas)
      if (a.team == goal.team) radius = a.radius + 2.0f;
    Vec2 p;
    if (b.own_goal >= 0) {
      const Axis axis = attack_axis(b);
      float foremost = -1e30f;
      for (int m : mates) foremost = std::max(foremost, dot(field.bodies[size_t(m)].start - axis.from, axis.forward));
      // A formation that starts beyond that line (a small field) holds its start places.
      b.foremost = foremost, b.front = std::max(axis.length - radius, foremost);
      p = b.home + (b.front - foremost) * axis.forward;
    } else {
      const double fan = std::min(0.9, 2.1 / double(mates.size()));
      const double angle = (double(j) - 0.5 * double(mates.size() - 1)) * fan;
      p = centre(goal) + radius * rotated(unit(middle - centre(goal)), angle);
    }
    b.spot = clamped(p, lo_ + Vec2{0.5f, 0.5f}, hi_ - Vec2{0.5f, 0.5f});
  }
  moves_.resize(bots_.size());
  throws_.reserve(bots_.size());
}

void TeamBots::hear(const GameEvent& e) {
  switch (e.type) {
    case EventKind::Drop: case EventKind::Give: case EventKind::Catch: case EventKind::Pickup: case EventKind::Tackle:
    case EventKind::Pass:
    case EventKind::Intercept: case EventKind::Throw: case EventKind::Kick: case EventKind::Hit: case EventKind::Bounce: case EventKind::Landing:
    case EventKind::Goal: case EventKind::OwnGoal: case EventKind::Out: case EventKind::Dead: case EventKind::Loose:
      for (Bot& b : bots_) b.heard.push_back(heard(e, b.skill.reaction));
      return;
    default: return;  // nothing about the ball
  }
}

void TeamBots::imagine(Bot& b, const Heard& h) {
  std::normal_distribution<double> noise(0, 1);
  Ball& ball = b.ball;
  switch (h.type) {
    case EventKind::Give:
    case EventKind::Catch:
    case EventKind::Pickup:
    case EventKind::Tackle:
    case EventKind::Pass:
    case EventKind::Intercept:
      ball = {Ball::State::Held, h.actor, -1, {}, {}, {}};
      if (h.actor == b.body) {
        std::uniform_real_distribution<double> pause(0.3, 1.0);
        b.got_ball = h.at;
        b.throw_at = std::min(h.at + pause(b.rng), h.at - b.skill.reaction + most_hold(b));
      }
      return;
    case EventKind::Drop:
    case EventKind::Throw:
    case EventKind::Kick:
    case EventKind::Hit:  // sent on at once, as a throw is
    case EventKind::Bounce:
    case EventKind::Landing:  // the ball bounces on from the floor
    case EventKind::Loose: {  // a loose ball is anyone's, its last thrower's too
      const double err = b.skill.imagine_noise;
      const bool bounced = h.type == EventKind::Bounce || h.type == EventKind::Landing;
      const bool sent = h.type == EventKind::Throw || h.type == EventKind::Kick || h.type == EventKind::Hit;
      const int thrower = sent ? h.actor : bounced ? ball.thrower : -1;
      ball = {Ball::State::Flying, -1, thrower,
              h.where + Vec2{float(err * noise(b.rng)), float(err * noise(b.rng))},
              float(std::max(0.3, 1 + 0.1 * noise(b.rng))) * rotated(h.velocity, 0.05 * noise(b.rng)), h.where};
      if (field_.has_height())
        ball.z = std::max(h.height, field_.ball_radius), ball.up = float(h.up * std::max(0.3, 1 + 0.1 * noise(b.rng)));
      fly(ball, b.skill.reaction);  // it flew on while the news travelled
      if (h.actor == b.body && sent) b.got_ball = -1;
      return;
    }
    default: ball = {}; return;  // goal, out, dead: no ball until the next drop or give
  }
}

// The imagined ball flies on for dt: through the air under gravity, then (or on a flat field)
// rolling, slowed by the field's friction; it stops at the bounds.
void TeamBots::fly(Ball& ball, double dt) const {
  if (field_.has_height()) dt = airborne(ball, dt);
  if (dt > 0) {
    ball.at = ball.at + field_.flight_time(float(dt)) * ball.velocity;
    ball.velocity = float(std::exp(-field_.friction * dt)) * ball.velocity;
  }
  Vec2& at = ball.at;
  if (at.x < field_.bounds_min.x || at.x > field_.bounds_max.x || at.y < field_.bounds_min.y ||
      at.y > field_.bounds_max.y) {
    at = {std::clamp(at.x, field_.bounds_min.x, field_.bounds_max.x), std::clamp(at.y, field_.bounds_min.y, field_.bounds_max.y)};
    ball.velocity = {0, 0};
    ball.z = std::min(ball.z, field_.ball_radius), ball.up = 0;
  }
}

// Up to dt of the ball's flight through the air: across at its speed (only a rolling ball slows)
// and down under gravity, bouncing off the floor as the field's floor does. Returns the time left
// once it rolls, 0 while it is still in the air.
double TeamBots::airborne(Ball& ball, double dt) const {
  const float g = field_.gravity, r = field_.ball_radius;
  while (dt > 0 && (ball.up > 0 || ball.z > r)) {
    const double down = (ball.up + std::sqrt(double(ball.up) * ball.up + 2.0 * g * std::max(0.0f, ball.z - r))) / g;
    const double s = std::min(dt, down);
    ball.at = ball.at + float(s) * ball.velocity;
    ball.z = float(ball.z + ball.up * s - 0.5 * g * s * s);
    ball.up = float(ball.up - g * s);
    dt -= s;
    if (s == down) {
      ball.z = r;
      ball.up = -field_.floor_restitution * ball.up;
      if (ball.up < kHop) ball.up = 0;
    }
  }
  return dt;
}

// A ball that rolls slowly on the floor: anyone's to pick up.
bool TeamBots::lies_loose(const Ball& ball) const {
  return length(ball.velocity) < kLoose && ball.up == 0 && ball.z <= field_.ball_radius;
}

// Whether the body's hands get to the ball where it flies (always on a flat field).
bool TeamBots::within_reach(const Ball& ball, int body) const {
  return !field_.has_height() || ball.z <= field_.reach_of(body);
}

double TeamBots::most_hold(const Bot& b) const { return field_.bodies[size_t(b.body)].kicks ? kMostDribble : kMostHold; }

bool TeamBots::team_has_ball(const Bot& b) const {
  return b.ball.state == Ball::State::Held && field_.bodies[size_t(b.ball.holder)].team == field_.bodies[size_t(b.body)].team;
}

Vec2 TeamBots::holder_position(const Bot& b, std::span<const Player> players) const {
  switch (b.ball.state) {
    case Ball::State::Held: return players[size_t(b.ball.holder)].position;
    case Ball::State::Flying: return b.ball.at;
    case Ball::State::None: break;
  }
  return 0.5f * (field_.bounds_min + field_.bounds_max);
}

// Where a player may stand: inside the bounds, its zone (`in_zone`, if the field gives it one)
// and its team's side (likewise); a goalkeeper in its goal area, anyone else out of every goal
// area (an area around a goal's mouth; other areas, an end zone say, are open to all).
Vec2 TeamBots::allowed(const Bot& b, Vec2 p, bool in_zone) const {
  const BodySpec& spec = field_.bodies[size_t(b.body)];
  if (in_zone && spec.zoned) p = clamped(p, spec.zone_min, spec.zone_max);
  p = clamped(p, lo_, hi_);
  if (b.side >= 0) p = to_area_edge(field_.areas[size_t(b.side)], p, 0.3f, true);
  if (b.keeper) return b.own_area >= 0 ? to_area_edge(field_.areas[size_t(b.own_area)], p, 0.3f, true) : p;
  for (size_t a = 0; a < field_.areas.size(); ++a)
    if (goal_area_[a]) p = to_area_edge(field_.areas[a], p, -0.3f, false);
  return clamped(p, lo_, hi_);
}

// How far the nearest opponent's reach stays from a ball flying from `from` to `to` at `speed`,
// after the steps the opponent can take toward its line before it passes, as this player
// judges an opponent's reaction and pace by its own (`keepers`: goalkeepers count too).
float TeamBots::clearance(const Bot& b, std::span<const Player> players, Vec2 from, Vec2 to, float speed,
                          bool keepers) const {
  float clear = 1e9f;
  for (size_t k = 0; k < players.size(); ++k) {
    if (players[k].team == players[size_t(b.body)].team || (!keepers && bots_[k].keeper)) continue;
    const Vec2 near = nearest_on_segment(players[k].position, from, to);
    const float reacts = float(std::max(0.0, length(near - from) / speed - b.skill.reaction));
    clear = std::min(clear, length(players[k].position - near) - field_.bodies[k].radius -
                                float(b.skill.run_speed) * reacts);
  }
  return clear;
}

// A shot at the opponents' goal from within range, past every field player, at the point of its
// mouth the keeper covers least (a keeper's fingertips on the line are worth a try).
bool TeamBots::open_shot(const Bot& b, std::span<const Player> players, Vec2& aim) const {
  if (b.their_goal < 0) return false;
  const Goal& goal = field_.goals[size_t(b.their_goal)];
  const Vec2 me = players[size_t(b.body)].position;
  if (length(centre(goal) - me) > shooting_distance(b) + 1.0f) return false;
  float best = -1e9f;
  for (float f : {0.1f, 0.5f, 0.9f}) {
    const Vec2 spot = goal.a + f * (goal.b - goal.a);
    const float speed = float(throw_speed_ * b.skill.throw_speed);
    if (clearance(b, players, me, spot, speed, false) < 0.15f) continue;
    const float clear = clearance(b, players, me, spot, speed, true);
    if (clear > best) best = clear, aim = spot;
  }
  return best > -0.3f;
}

// The teammate to pass to: the clearest line, the most ground won toward the goal, and calls for
// the ball count; a beginner weighs them less well. -1 when nobody is open enough, unless
// `forced` (the holder must let go): then the best there is.
int TeamBots::open_teammate(Bot& b, std::span<const Player> players, Vec2& aim, bool forced) {
  const Vec2 me = players[size_t(b.body)].position;
  const Vec2 goal = b.their_goal >= 0 ? centre(field_.goals[size_t(b.their_goal)]) : me;
  std::normal_distribution<double> misjudge(0, 1.5 * (1 - b.skill.vision));
  int best = -1;
  double best_score = -1e9;
  for (const Bot& o : bots_) {
    const Player& p = players[size_t(o.body)];
    if (o.body == b.body || p.team != players[size_t(b.body)].team) continue;
    const float d = length(p.position - me);
    if (d < 2.0f) continue;
    const float flight = d / (0.5f * (kArrive + float(throw_speed_)));
    // Where it will be when the ball gets there, if it runs on as it runs now, but no further
    // than it may go: a pass led over the side line is a throw out.
    const Vec2 lead = allowed(o, p.position + flight * p.velocity);
    const float clear = std::min(clearance(b, players, me, lead, kArrive, true), 3.0f);
    const float gain = std::clamp(length(goal - me) - length(goal - lead), -3.0f, 3.0f);
    const double score = clear + 0.3 * gain + (o.calling ? 1.0 : 0.0) - (o.keeper ? 1.5 : 0.0) -
                         0.1 * std::max(0.0f, d - 10) + misjudge(b.rng);
    if (score > best_score) best_score = score, best = o.body, aim = lead;
  }
  return best_score > 1.0 || forced ? best : -1;
}

// A throw from `from` that reaches `to` still at kArrive: friction takes k m/s per metre flown
// (v = v0 - k x), give or take the thrower's aim.
Vec2 TeamBots::pass_velocity(Bot& b, Vec2 from, Vec2 to, double most) {
  std::normal_distribution<double> noise(0, 1);
  const float d = length(to - from);
  const double speed = std::clamp(double(kArrive + field_.friction * d), 0.6 * throw_speed_, most);
  return float(speed * (1 + 0.05 * noise(b.rng))) * rotated(unit(to - from), b.skill.throw_noise * noise(b.rng));
}

// On a field with height: the throw `velocity` (its heading and the thrower's error in it) as an
// arc from the hand through `aim`: at a hoop (`goal`, -1 for none) a shot dropping in at
// kShotElevation, give or take the thrower's aim; else the flattest throw at that speed,
// arriving at chest height.
Throw TeamBots::arc(Bot& b, Vec2 from, Vec2 aim, Vec2 velocity, int goal) {
  const Goal* hoop = goal >= 0 && field_.goals[size_t(goal)].hoop() ? &field_.goals[size_t(goal)] : nullptr;
  const Vec2 arm = field_.release_point(b.body, from, aim);
  const Vec3 hand{arm.x, arm.y, field_.reach_of(b.body)};
  const float speed = length(velocity);
  Vec3 v = hoop ? field_.arc_velocity(hand, {aim.x, aim.y, hoop->rim_height}, kShotElevation)
                : field_.throw_at(hand, {aim.x, aim.y, kChestShare * field_.reach_of(b.body)}, speed);
  if (hoop) {
    // A shot's length is its hardest part: the thrower's error in speed as in direction.
    std::normal_distribution<double> noise(0, 1);
    const float s = float(1 + 0.5 * b.skill.throw_noise * noise(b.rng));
    v = {v.x * s, v.y * s, v.z * s};
  }
  const float flat = std::hypot(v.x, v.y);
  return {b.body, flat > 0 ? flat / std::max(speed, 1e-6f) * velocity : velocity, v.z};
}

// The holder steps toward the goal it attacks (if any), up to a shooting distance, and when its
// moment comes shoots or passes. The sport's aim comes first: at a point the ball is sent to
// arrive there as a pass does, at a goal or a wall it is shot hard (docs/lua-api.md, "Simulated
// players and hints").
Vec2 TeamBots::holding(Bot& b, double t, std::span<const Player> players) {
  const Player& me = players[size_t(b.body)];
  const Vec2 goal = b.their_goal >= 0 ? centre(field_.goals[size_t(b.their_goal)]) : me.position;
  const Vec2 step = b.their_goal >= 0 && length(goal - me.position) > shooting_distance(b) - 1.0f
                        ? allowed(b, me.position + 1.0f * unit(goal - me.position))
                        : me.position;
  if (b.got_ball < 0 || t < b.throw_at) return step;
  const double shot = throw_speed_ * b.skill.throw_speed;
  const bool forced = t >= b.got_ball + most_hold(b) - b.skill.reaction;
  Vec2 aim;
  Vec2 velocity;
  int shot_at = -1;  // the goal shot at
  auto shoot = [&] {
    std::normal_distribution<double> noise(0, b.skill.throw_noise);
    velocity = float(shot) * rotated(unit(aim - me.position), noise(b.rng));
  };
  if (me.aim.kind == Aim::Kind::Point) {
    aim = me.aim.point;
    velocity = pass_velocity(b, me.position, aim, shot);
  } else if (me.aim.kind == Aim::Kind::Goal) {
    aim = centre(field_.goals[size_t(me.aim.index)]), shot_at = me.aim.index;
    shoot();
  } else if (me.aim.kind == Aim::Kind::Wall) {
    aim = nearest_on_wall(field_, me.aim.index, me.position);
    shoot();
  } else if (open_shot(b, players, aim)) {
    shoot();
    shot_at = b.their_goal;
  } else if (open_teammate(b, players, aim, forced) >= 0) {
    velocity = pass_velocity(b, me.position, aim, shot);
  } else if (forced) {  // nobody to pass to at all (a team of one): at the goal, from wherever
    velocity = pass_velocity(b, me.position, goal, shot);
    aim = goal, shot_at = b.their_goal;
  } else {
    return step;  // nobody open yet: look again next frame
  }
  // A player who kicks plays the ball along the ground; with height, anyone else throws in an arc.
  const bool arcs = field_.has_height() && !field_.bodies[size_t(b.body)].kicks;
  throws_.push_back(arcs ? arc(b, me.position, aim, velocity, shot_at) : Throw{b.body, velocity});
  b.got_ball = -1;
  return step;
}

// Running into space: its attacking place, weaving across, away from whoever marks it.
Vec2 TeamBots::attacking(const Bot& b, double t, std::span<const Player> players) const {
  const Vec2 goal = b.their_goal >= 0 ? centre(field_.goals[size_t(b.their_goal)]) : b.spot;
  const Vec2 place = attacking_place(b, players);
  const Vec2 across = rotated(unit(place - goal), 1.5707963);
  Vec2 p = place + float(1.2 * std::sin(b.phase + 0.7 * t)) * across;
  for (size_t k = 0; k < players.size(); ++k) {
    if (players[k].team == players[size_t(b.body)].team) continue;
    const float d = length(p - players[k].position);
    if (d < kOpen) p = p + (kOpen - d) * unit(p - players[k].position);
  }
  return open_lane(b, allowed(b, p), players);
}

// From b's own goal toward the one it attacks (both goals given): the line a formation moves on.
TeamBots::Axis TeamBots::attack_axis(const Bot& b) const {
  const Vec2 from = centre(field_.goals[size_t(b.own_goal)]), to = centre(field_.goals[size_t(b.their_goal)]);
  return {from, unit(to - from), length(to - from)};
}

// A formation goes up the field with the ball, all of it alike: its foremost keep as far ahead of
// the ball as the front line is from the goal they attack, from their start places (the ball at
// their own goal) up to that line. A fan round a shared goal stays put.
Vec2 TeamBots::attacking_place(const Bot& b, std::span<const Player> players) const {
  if (b.own_goal < 0) return b.spot;
  const Axis axis = attack_axis(b);
  const float ahead = axis.length - b.front, ball = dot(holder_position(b, players) - axis.from, axis.forward);
  const float up = std::clamp(ball + ahead - b.foremost, 0.0f, b.front - b.foremost);
  return b.home + (up / std::max(b.front - b.foremost, 1e-3f)) * (b.spot - b.home);
}

// Of a few places across the line from a teammate holding the ball to `p`, the one whose line
// stays clearest of the opponents' reach, so that a pass can find it (with or without a goal
// to attack: keep-away is all this).
Vec2 TeamBots::open_lane(const Bot& b, Vec2 p, std::span<const Player> players) const {
  if (b.ball.state != Ball::State::Held || b.ball.holder == b.body) return p;
  const Vec2 holder = players[size_t(b.ball.holder)].position;
  if (length(p - holder) < 0.5f) return p;
  const Vec2 across = rotated(unit(p - holder), 1.5707963);
  Vec2 best = p;
  float best_score = -1e30f;
  for (const float side : {0.0f, 1.5f, -1.5f, 3.0f, -3.0f}) {
    const Vec2 q = allowed(b, p + side * across);
    float clear = kLaneClear;
    for (size_t k = 0; k < players.size(); ++k)
      if (players[k].team != players[size_t(b.body)].team)
        clear = std::min(clear, length(players[k].position - nearest_on_segment(players[k].position, holder, q)) -
                                    field_.bodies[k].radius);
    const float score = clear - 0.2f * std::abs(side);
    if (score > best_score) best_score = score, best = q;
  }
  return best;
}

// How far from the opponents' goal a player likes to shoot: a little outside its goal area, or a
// third of the field out.
float TeamBots::shooting_distance(const Bot& b) const {
  if (b.their_goal < 0) return 0;
  float d = 0.3f * (field_.bounds_max.x - field_.bounds_min.x);
  for (const Area& a : field_.areas)
    if (a.team == field_.goals[size_t(b.their_goal)].team) d = a.radius + 1.5f;
  return d;
}

// Marking: the attacker of the same rank, from its goal side; the defender nearest the holder
// presses the holder, never nearer than an arm's length and a step.
Vec2 TeamBots::defending(const Bot& b, std::span<const Player> players) const {
  const Vec2 goal = b.own_goal >= 0 ? centre(field_.goals[size_t(b.own_goal)]) : b.home;
  const std::vector<int>& mine = b.mates;
  const std::vector<int>& theirs = b.opponents;
  if (theirs.empty()) return allowed(b, b.home);
  if (b.ball.state == Ball::State::Held) {
    const Vec2 holder = players[size_t(b.ball.holder)].position;
    int nearest = -1;
    float best = 1e30f;
    for (int k : mine)
      if (length(players[size_t(k)].position - holder) < best) best = length(players[size_t(k)].position - holder), nearest = k;
    if (nearest == b.body) {
      Vec2 p = field_.bodies[size_t(b.ball.holder)].kicks ? allowed(b, holder + kMarkKicker * unit(goal - holder))
                                                          : allowed(b, holder + kPress * unit(goal - holder));
      if (length(p - holder) < kClosest) p = allowed(b, holder + kClosest * rotated(unit(goal - holder), 0.8));
      return p;
    }
  }
  const size_t rank = size_t(std::find(mine.begin(), mine.end(), b.body) - mine.begin());
  const int marked = theirs[rank % theirs.size()];
  const Vec2 mark = players[size_t(marked)].position;
  // Each distance in an expression of its own: one shared through a variable is rounded
  // differently (fused multiply-adds), and would move every marker of the other sports a little.
  if (field_.bodies[size_t(marked)].kicks) return allowed(b, mark + kMarkKicker * unit(goal - mark));
  return allowed(b, mark + kMark * unit(goal - mark));
}

// A goalkeeper stands off its goal's centre toward the ball.
Vec2 TeamBots::keeping(const Bot& b, std::span<const Player> players) const {
  if (b.own_goal < 0) return allowed(b, b.home);
  const Vec2 goal = centre(field_.goals[size_t(b.own_goal)]);
  const Vec2 ball = holder_position(b, players);
  const float out = b.own_area >= 0 ? std::min(0.7f, field_.areas[size_t(b.own_area)].radius * 0.4f) : 0.7f;
  return allowed(b, goal + out * unit(ball - goal));
}

// A flying or loose ball: whoever of the team reaches its imagined path first goes for it (the
// thrower leaves its own throw to the others). A ball in flight is played in one's zone; a loose
// one anywhere, lest it lie where no zone reaches. `chase` says whether that is this bot.
Vec2 TeamBots::chasing(const Bot& b, std::span<const Player> players, bool& chase) const {
  chase = false;
  const std::string& team = field_.bodies[size_t(b.body)].team;
  const bool loose = lies_loose(b.ball);
  double first = 1e30;
  Vec2 where = b.ball.at;
  int who = -1;
  for (const Bot& o : bots_) {
    if (field_.bodies[size_t(o.body)].team != team || (o.body == b.ball.thrower && !loose)) continue;
    const Vec2 from = players[size_t(o.body)].position;
    const float reach = field_.bodies[size_t(o.body)].radius;
    Ball ball = b.ball;
    const Vec2& at = ball.at;
    for (double s = 0; s <= kLook; s += kLookStep) {
      if (s > 0) fly(ball, kLookStep);
      const Vec2 ground = allowed(o, at, !loose);
      if (ground.x != at.x || ground.y != at.y) continue;  // not its ground
      if (!within_reach(ball, o.body)) continue;  // over its head
      if (length(at - from) - reach <= o.skill.run_speed * s || (loose && s + kLookStep > kLook)) {
        if (s < first) first = s, who = o.body, where = at;
        break;
      }
      if (length(ball.velocity) < 0.05f && ball.up == 0 && ball.z <= field_.ball_radius) {
        // It lies still: a loose ball is whoever's gets there first, however long the run (a
        // bot that broke off here left a ball lying loose until the match stalled).
        const double arrive = s + std::max(0.0, double(length(at - from) - reach) / o.skill.run_speed);
        if (loose && arrive < first) first = arrive, who = o.body, where = at;
        break;
      }
    }
  }
  if (who != b.body) return b.pos;
  chase = true;
  return allowed(b, where, !loose);
}

Vec2 TeamBots::decide(Bot& b, double t, std::span<const Player> players) {
  b.calling = false;
  switch (b.ball.state) {
    case Ball::State::None: return b.keeper ? keeping(b, players) : allowed(b, b.home);
    case Ball::State::Held:
      if (b.ball.holder == b.body) return holding(b, t, players);
      if (b.keeper) return keeping(b, players);
      if (team_has_ball(b)) {
        float marked = 1e30f;
        for (const Player& p : players)
          if (p.team != players[size_t(b.body)].team) marked = std::min(marked, length(p.position - b.pos));
        b.calling = marked > kOpen;
        return attacking(b, t, players);
      }
      return defending(b, players);
    case Ball::State::Flying: {
      bool chase = false;
      const Vec2 p = chasing(b, players, chase);
      if (chase && lies_loose(b.ball) && length(p - b.pos) < kSearched) {
        // There, and no ball: a loose ball's cloud may lie spread over metres, so look somewhere
        // else about the place where it was told to lie, as a player would.
        std::uniform_real_distribution<double> turn(0, 6.283185307), out(0.3, kSearch);
        b.ball.at = b.ball.told + float(out(b.rng)) * rotated(Vec2{1, 0}, turn(b.rng));
        return allowed(b, b.ball.at, false);
      }
      if (chase) return p;
      if (b.keeper) return keeping(b, players);
      const bool ours = b.ball.thrower >= 0 &&
                        field_.bodies[size_t(b.ball.thrower)].team == field_.bodies[size_t(b.body)].team;
      return ours ? attacking(b, t, players) : defending(b, players);
    }
  }
  return b.pos;
}

const std::vector<BodyInput>& TeamBots::move(double t, double dt, std::span<const Player> players) {
  check_count(players.size(), "players", bots_.size(), "bots");
  throws_.clear();
  for (Bot& b : bots_) {
    act_on_due(b.heard, t, [&](const Heard& h) { imagine(b, h); });
    if (b.ball.state == Ball::State::Flying) fly(b.ball, dt);
  }
  for (size_t k = 0; k < bots_.size(); ++k) {
    Bot& b = bots_[k];
    b.pos = players[k].position;  // where it really is (a rule spec may have placed it)
    // A restart's place comes first; the holder still decides its throw.
    const Vec2 decided = decide(b, t, players);
    Vec2 step = players[k].place.value_or(decided) - b.pos;
    // A player with the ball takes a few steps, no more (the ball is to be thrown, not carried);
    // a goalkeeper moves across its goal in short side steps.
    const bool holds = b.ball.state == Ball::State::Held && b.ball.holder == b.body;
    const float l = length(step), most = float((holds ? 0.4 : b.keeper ? 0.6 : 1.0) * b.skill.run_speed * dt);
    if (l > most) step = (most / l) * step;
    b.pos = b.pos + step;
    moves_[k] = {b.pos, (1 / float(dt)) * step};
  }
  return moves_;
}

}  // namespace quantum::game

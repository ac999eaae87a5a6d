// What a match's rules (and the runtime, for a device's throw) may do to it: the actions
// game.h lists under "Actions for the rules". Each one checks what it is given, against the
// table in quantum/limits.h where it is a range: a Lua call hands its values on unchanged, so
// these checks are the Lua calls' too.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <stdexcept>

#include "game/game.h"
#include "quantum/limits.h"

namespace quantum::game {

bool Match::is_player(int k) const { return k >= 0 && k < int(players_.size()); }

void Match::check_player(int k) const {
  if (!is_player(k)) throw std::invalid_argument("no player " + std::to_string(k));
}

void Match::check_catcher(int k) const {
  check_player(k);
  if (!field().bodies[size_t(k)].catches)
    throw std::invalid_argument(players_[size_t(k)].name + " cannot hold the ball: its field body does not catch");
}

void Match::say(std::string_view text, std::string_view recording) {
  Said& s = said_.next();
  s.t = time();
  s.text.assign(text);
  s.recording.assign(recording);
  s.event = handling_;
  s.cause = cause_;
}

void Match::award(const std::string& team, double points) {
  if (!score_.count(team)) throw std::invalid_argument("award: no team '" + team + "' in this field");
  if (!(std::abs(points) <= kMostAward && points == std::trunc(points)))
    throw std::invalid_argument("award: points must be a whole number from -1000 to 1000");
  // Saturates, never wraps, at ±kMostScore: a team awarded past it stays there.
  int& score = score_[team];
  score = int(std::clamp<int64_t>(int64_t(score) + int64_t(points), -kMostScore, kMostScore));
}

void Match::respawn(int spot, double delay) {
  if (spot < 0 || spot >= int(field().spots.size()))
    throw std::invalid_argument("respawn: no spot " + std::to_string(spot));
  limits::check(limits::kRestartDelay, delay, "respawn: delay");
  dead_ball();
  respawn_spot_ = spot;
  respawn_holder_ = -1;
  respawn_at_ = time() + delay;
}

void Match::give(int k, double delay, std::optional<Vec2> at) {
  check_catcher(k);
  limits::check(limits::kRestartDelay, delay, "give: delay");
  if (at) place(k, at);
  dead_ball();
  respawn_at_ = -1;
  if (delay > 0 || (at && !at_place(k))) {
    respawn_holder_ = k;
    respawn_at_ = time() + delay;
    return;
  }
  hand_over(k);
}

void Match::place(int k, std::optional<Vec2> at) {
  check_player(k);
  const Field& f = field();
  if (at && !(std::isfinite(at->x) && std::isfinite(at->y) && at->x >= f.bounds_min.x && at->x <= f.bounds_max.x &&
              at->y >= f.bounds_min.y && at->y <= f.bounds_max.y))
    throw std::invalid_argument("a place must be a finite point within the bounds");
  players_[size_t(k)].place = at;
}

bool Match::at_place(int k) const {
  const Player& p = players_[size_t(k)];
  return !p.place || std::hypot(p.position.x - p.place->x, p.position.y - p.place->y) <= kTakePlace;
}

void Match::hand_over(int k) {
  world_.give(k);
  report_.groups.clear();
  previous_toucher_ = -1;
  last_toucher_ = k;
  last_touch_t_ = time();
  gained(k);
  GameEvent& e = new_event(EventKind::Give);
  e.actor = players_[size_t(k)].name, e.team = players_[size_t(k)].team, e.actor_index = k;
  e.at = players_[size_t(k)].position;
  name_touchers(e);
  tell_rules(events_.size() - 1);
}

void Match::throw_ball(int k, Vec3 velocity, std::optional<ThrowSpread> spread, World::Release how) {
  check_player(k);
  thrown_.clear();
  world_.release(k, velocity, spread.value_or(config_.throw_spread), thrown_, how);
  const Event e = thrown_.back();  // a copy: the rules told of it may throw again
  handle(e);
  // The new flight's fates, so the next draw is already tweaked.
  if (world_.live()) retweak();
}

void Match::let_go(const Throw& t) {
  if (is_player(t.player) && field().bodies[size_t(t.player)].hits) {
    const Vec3 v{t.velocity.x, t.velocity.y, t.up};
    if (throw_fault(v, field().has_height()).empty()) swing(t.player, v);  // else a swing at nothing
    return;
  }
  if (t.player < 0 || t.player != holder()) return;
  throw_ball(t.player, {t.velocity.x, t.velocity.y, t.up}, std::nullopt,
             field().bodies[size_t(t.player)].kicks ? World::Release::Kick : World::Release::Throw);
}

void Match::plan_hit(int k, const HitPlan& plan) {
  check_player(k);
  world_.plan_hit(k, plan);
}

void Match::swing(int k, Vec3 velocity) {
  HitPlan plan;
  plan.kind = HitPlan::Kind::Velocity;
  plan.velocity = velocity;
  plan.spread = config_.throw_spread;
  plan_hit(k, plan);
}

void Match::dead_ball() {
  if (!world_.in_play()) return;
  world_.remove_ball();
  end_rally(false);
  name_touchers(new_event(EventKind::Dead));
  tell_rules(events_.size() - 1);
}

void Match::finish(const std::string& winner) {
  if (finished_) return;
  finished_ = true;
  winner_ = winner;
  GameEvent& e = new_event(EventKind::MatchEnd);
  e.actor = e.team = winner_;
  tell_rules(events_.size() - 1);
}

void Match::grant(int player, const std::string& name, double seconds, std::map<std::string, double> params) {
  check_player(player);
  limits::check(limits::kPowerupSeconds, seconds, "grant: seconds");
  std::erase_if(powerups_, [&](const ActivePowerup& p) { return p.player == player && p.name == name; });
  auto known = std::find(powerup_names_.begin(), powerup_names_.end(), name);
  if (known == powerup_names_.end()) known = powerup_names_.insert(known, name);
  powerups_.push_back({name, player, time() + seconds, std::move(params), int(known - powerup_names_.begin())});
  powerup_event(EventKind::Powerup, player, name);
}

void Match::powerup_event(EventKind type, int player, const std::string& name) {
  GameEvent& e = new_event(type);
  const Player& p = players_[size_t(player)];
  e.actor = p.name, e.team = p.team, e.actor_index = player;
  e.powerup = name;
  e.at = p.position;
  tell_rules(events_.size() - 1);
}

void Match::set_handicap(int k, double handicap) {
  check_player(k);
  limits::check(limits::kHandicap, handicap, "a handicap");
  players_[size_t(k)].handicap = handicap;
}

void Match::set_turn(int k, bool turn) {
  check_player(k);
  players_[size_t(k)].turn = turn;
}

void Match::set_aim(int k, Aim aim) {
  check_player(k);
  const int most = aim.kind == Aim::Kind::Goal ? int(field().goals.size())
                   : aim.kind == Aim::Kind::Wall ? int(field().wall_names.size())
                                                 : 0;
  if ((aim.kind == Aim::Kind::Goal || aim.kind == Aim::Kind::Wall) && (aim.index < 0 || aim.index >= most))
    throw std::invalid_argument("no such goal or wall to aim at");
  if (aim.kind == Aim::Kind::Point && !(std::isfinite(aim.point.x) && std::isfinite(aim.point.y)))
    throw std::invalid_argument("a point to aim at must be finite");
  players_[size_t(k)].aim = aim;
}

void Match::set_skill(int k, std::optional<double> skill) {
  check_player(k);
  if (skill) limits::check(limits::kSkill, *skill, players_[size_t(k)].name + "'s skill");
  players_[size_t(k)].skill = skill;
}

void Match::set_wormholes(std::vector<Wormhole> wormholes) {
  world_.set_wormholes(std::move(wormholes));
  if (world_.live()) retweak();  // the fates go through them from now on
}

void Match::place_players(std::span<const BodyInput> input) {
  world_.place_bodies(input);
  for (size_t k = 0; k < players_.size(); ++k) players_[k].position = input[k].position, players_[k].velocity = input[k].velocity;
}

void Match::set_scene(std::span<const BodyInput> input, Cloud cloud, int last_touch) {
  place_players(input);
  world_.set_cloud(std::move(cloud));
  world_.set_last_touch(last_touch);
  respawn_at_ = -1;
  respawn_holder_ = -1;
  last_toucher_ = last_touch;
  previous_toucher_ = -1;
  last_touch_t_ = -kRetouch;  // a scene's last touch is no swing in progress
  last_play_t_ = time();      // a scene starts play afresh
  rolling_ = false;
  rally_contacts_ = 0;
  retweak();
}

void Match::jump(int k, double height, double seconds) {
  if (!field().has_height()) throw std::logic_error("jumping needs a field with height (gravity)");
  check_player(k);
  limits::check(limits::kJumpHeight, height, "a jump's height");
  if (!limits::kJumpSeconds.contains(seconds))
    throw std::invalid_argument("a jump must last " + limits::stated(limits::kJumpSeconds) + ", got " + limits::number_text(seconds));
  landing_.resize(players_.size(), -1);
  world_.set_reach(k, field().reach_of(k) + float(height));
  landing_[size_t(k)] = time() + seconds;
}

}  // namespace quantum::game

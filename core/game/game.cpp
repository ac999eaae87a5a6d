#include "game/game.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <stdexcept>

namespace quantum::game {

constexpr double kRetouch = 0.25;  // s

Match::Match(Field field, MatchConfig config, Rules& rules, std::vector<double> handicaps)
    : world_(std::move(field), WorldConfig{config.particles, 3, config.seed}), config_(config), rules_(&rules) {
  if (!(config.fps >= 10 && config.fps <= 1000)) throw std::invalid_argument("fps must be in [10, 1000]");
  if (!(config.seconds > 0)) throw std::invalid_argument("a match needs a positive time limit");
  if (!(config.balance_per_goal >= 0 && config.balance_per_goal <= 10 && config.balance_most >= 1))
    throw std::invalid_argument("automatic balance: per goal must be in [0, 10] and the most >= 1");
  const Field& f = world_.field();
  if (!handicaps.empty() && handicaps.size() != f.bodies.size())
    throw std::invalid_argument("got " + std::to_string(handicaps.size()) + " handicaps for " +
                                std::to_string(f.bodies.size()) + " players");
  for (size_t k = 0; k < f.bodies.size(); ++k) {
    const double h = handicaps.empty() ? 1.0 : handicaps[k];
    if (!(std::isfinite(h) && h > 0)) throw std::invalid_argument("handicap of " + f.bodies[k].name + " must be > 0");
    players_.push_back({f.bodies[k].name, f.bodies[k].team, h, f.bodies[k].start, {0, 0}});
  }
  for (const std::string& team : teams()) score_[team] = 0;
  respawn(config.first_spot, 0);
}

std::vector<std::string> Match::teams() const {
  std::vector<std::string> out;
  auto add = [&](const std::string& t) {
    if (!t.empty() && std::find(out.begin(), out.end(), t) == out.end()) out.push_back(t);
  };
  for (const BodySpec& b : field().bodies) add(b.team);
  for (const Goal& g : field().goals) add(g.team);
  return out;
}

int Match::spot_of(const std::string& key) const {
  const std::vector<Spot>& spots = field().spots;
  for (size_t s = 0; s < spots.size(); ++s)
    if (spots[s].name == key) return int(s);
  return field().spot_of_team(key);
}

void Match::say(std::string text, std::string recording) {
  said_.push_back({time(), std::move(text), handling_, std::move(recording)});
}

void Match::award(const std::string& team, int goals) {
  if (!score_.count(team)) throw std::invalid_argument("award: no team '" + team + "' in this field");
  score_[team] += goals;
}

void Match::respawn(int spot, double delay) {
  if (spot < 0 || spot >= int(field().spots.size()))
    throw std::invalid_argument("respawn: no spot " + std::to_string(spot));
  if (!(delay >= 0 && delay <= 60)) throw std::invalid_argument("respawn: delay must be in [0, 60] s");
  respawn_spot_ = spot;
  respawn_at_ = time() + delay;
}

void Match::finish(const std::string& winner) {
  if (finished_) return;
  finished_ = true;
  winner_ = winner;
  GameEvent e;
  e.t = time();
  e.type = "match_end";
  e.actor = e.team = winner;
  events_.push_back(e);
  tell_rules(e);
}

void Match::grant(int player, const std::string& name, double seconds, std::map<std::string, double> params) {
  if (player < 0 || player >= int(players_.size())) throw std::invalid_argument("grant: no player " + std::to_string(player));
  if (!(seconds > 0 && seconds <= 3600)) throw std::invalid_argument("grant: seconds must be in (0, 3600]");
  std::erase_if(powerups_, [&](const ActivePowerup& p) { return p.player == player && p.name == name; });
  powerups_.push_back({name, player, time() + seconds, std::move(params)});
  powerup_event("powerup", player, name);
}

void Match::powerup_event(const char* type, int player, const std::string& name) {
  GameEvent e;
  e.t = time();
  e.type = type;
  e.actor = players_[size_t(player)].name, e.team = players_[size_t(player)].team, e.actor_index = player;
  e.powerup = name;
  e.at = players_[size_t(player)].position;
  events_.push_back(e);
  tell_rules(e);
}

void Match::set_handicap(int k, double handicap) {
  if (k < 0 || k >= int(players_.size())) throw std::invalid_argument("no player " + std::to_string(k));
  if (!(std::isfinite(handicap) && handicap > 0)) throw std::invalid_argument("a handicap must be > 0");
  players_[size_t(k)].handicap = handicap;
}

void Match::set_wormholes(std::vector<Wormhole> wormholes) {
  world_.set_wormholes(std::move(wormholes));
  if (world_.live()) retweak();  // the fates go through them from now on
}

void Match::expire_powerups() {
  for (size_t k = 0; k < powerups_.size();) {
    if (time() < powerups_[k].until - 1e-9) {
      ++k;
      continue;
    }
    const ActivePowerup p = powerups_[k];
    powerups_.erase(powerups_.begin() + long(k));
    powerup_event("powerup_end", p.player, p.name);
  }
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
  last_toucher_ = last_touch;
  last_touch_t_ = -kRetouch;  // a scene's last touch is no swing in progress
  rally_contacts_ = 0;
  retweak();
}

void Match::report_error(std::string message) { errors_.push_back(std::move(message)); }

std::vector<GameEvent> Match::take_events() { return std::exchange(events_, {}); }
std::vector<Said> Match::take_said() { return std::exchange(said_, {}); }
std::vector<std::string> Match::take_errors() { return std::exchange(errors_, {}); }

void Match::step(std::span<const BodyInput> input) {
  if (finished_) return;
  const float dt = float(1.0 / config_.fps);
  core_events_.clear();
  if (respawn_at_ >= 0 && time() >= respawn_at_ - 1e-9) {
    respawn_at_ = -1;
    world_.drop(respawn_spot_, core_events_);
  }
  world_.step(dt, input, core_events_);
  for (size_t k = 0; k < players_.size(); ++k)
    players_[k].position = input[k].position, players_[k].velocity = input[k].velocity;
  stats_.seconds = time();
  for (const Event& e : core_events_) handle(e);
  expire_powerups();
  // A ball gone without an outcome that brings it back (crushed away, or a shot that left while its
  // contact was caught up): it comes back where it was dropped.
  if (!world_.live() && respawn_at_ < 0 && !finished_) respawn(respawn_spot_, 1.0);
  if (!finished_ && !time_up_told_ && time() >= config_.seconds - 1e-9) {
    time_up_told_ = true;
    GameEvent e;
    e.t = time();
    e.type = "time_up";
    events_.push_back(e);
    tell_rules(e);
    if (!finished_) {  // rules that ignore the clock: the leader wins, equal scores draw
      std::string best;
      int most = -1, leaders = 0;
      for (const auto& [team, goals] : score_) {
        if (goals > most) most = goals, best = team, leaders = 1;
        else if (goals == most) ++leaders;
      }
      finish(leaders == 1 ? best : "");
    }
  }
  // Fates are predicted without noise, and Brownian motion moves particles between fates within
  // a few frames; tweaked weights on stale fates land on particles that will meet something else,
  // and the factors lose most of their effect. Predicting every frame keeps each draw on the
  // distribution the rules asked for (measured: a handicap's 0.077 came out 0.185 with a
  // prediction every 0.5 s, 0.100 every frame; see rules/airhockey/spec).
  if (!finished_ && world_.live()) retweak();
}

void Match::handle(const Event& e) {
  const Field& f = field();
  GameEvent g;
  g.t = e.t, g.p = e.p, g.p_newtonian = e.p_newtonian, g.particles = e.particles, g.at = e.at;
  g.velocity = e.velocity, g.actor_index = e.actor;
  switch (e.type) {
    case EventType::Drop:
      g.type = "drop", g.actor = f.spots[e.actor].name, g.team = f.spots[e.actor].team;
      rally_contacts_ = 0;
      last_toucher_ = -1;
      break;
    case EventType::Hit: {
      const bool other_team = last_toucher_ >= 0 && f.bodies[last_toucher_].team != f.bodies[e.actor].team;
      // A swing goes on through the puck and may meet it again a few frames later: that is the
      // same touch, not a new shot.
      const bool again = e.actor == last_toucher_ && e.t - last_touch_t_ < kRetouch;
      g.type = again ? "retouch" : other_team ? "intercept" : "shot";
      g.actor = f.bodies[e.actor].name, g.team = f.bodies[e.actor].team, g.by = g.actor, g.by_team = g.team;
      last_toucher_ = e.actor;
      last_touch_t_ = e.t;
      rally_contacts_ += again ? 0 : 1;
      break;
    }
    case EventType::Bounce:
      g.type = "bounce", g.actor = f.wall_names[e.actor];
      break;
    case EventType::Goal:
    case EventType::OwnGoal:
      g.type = e.type == EventType::Goal ? "goal" : "own_goal";
      g.actor = f.goals[e.actor].name, g.team = f.goals[e.actor].team;
      break;
    case EventType::Out: g.type = "out"; break;
  }
  if (e.type != EventType::Drop && e.type != EventType::Hit && last_toucher_ >= 0)
    g.by = f.bodies[last_toucher_].name, g.by_team = f.bodies[last_toucher_].team;
  if (e.type == EventType::Goal || e.type == EventType::OwnGoal || e.type == EventType::Out) {
    ++stats_.rallies;
    stats_.contacts += rally_contacts_;
    stats_.goals += e.type == EventType::Out ? 0 : 1;
  }
  events_.push_back(g);
  tell_rules(g);
}

void Match::tell_rules(const GameEvent& e) {
  const std::string outer = std::exchange(handling_, e.type);
  rules_->on_event(e, *this);
  handling_ = outer;
}

FateView Match::view(const FateGroup& group) const {
  const Field& f = field();
  const Fate& fate = group.fate;
  FateView v;
  v.kind = to_string(fate.kind);
  v.mass = group.mass, v.tweaked = group.tweaked_mass, v.count = group.count;
  if (fate.kind == FateKind::Body) {
    v.actor = f.bodies[fate.target].name, v.team = v.favours = f.bodies[fate.target].team;
  } else if (fate.kind == FateKind::Goal || fate.kind == FateKind::OwnGoal) {
    v.actor = f.goals[fate.target].name, v.team = f.goals[fate.target].team;
    // A goal is good for the other side; with more than two teams, for the shooter's.
    for (const std::string& t : teams())
      if (t != v.team && (v.favours.empty() || (last_toucher_ >= 0 && f.bodies[last_toucher_].team == t))) v.favours = t;
  }
  for (int i = 0; i < fate.path_len; ++i) {
    v.path.push_back(f.wall_names[fate.path[i]]);
    v.via += (i == 0 ? "via " : ", ") + f.wall_names[fate.path[i]];
  }
  if (fate.path_more) v.via += ", ...";
  return v;
}

std::vector<FateView> Match::fates() const {
  std::vector<FateView> out;
  if (!world_.live()) return out;
  const FateReport report = world_.predict();
  for (const FateGroup& g : report.groups) out.push_back(view(g));
  return out;
}

double Match::handicap_now(int k) const {
  const Player& p = players_[size_t(k)];
  if (config_.balance_per_goal <= 0) return p.handicap;
  int lead = 0;
  for (const auto& [team, goals] : score_) lead = std::max(lead, goals);
  const auto own = score_.find(p.team);
  const int behind = lead - (own == score_.end() ? 0 : own->second);
  return p.handicap * std::min(config_.balance_most, std::pow(1 + config_.balance_per_goal, behind));
}

void Match::retweak() {
  FateReport report = world_.predict();
  std::vector<FateView> views;
  for (const FateGroup& g : report.groups) views.push_back(view(g));
  std::vector<double> factors = rules_->factors(views, *this);
  if (factors.size() != views.size()) {
    report_error("rules gave " + std::to_string(factors.size()) + " factors for " + std::to_string(views.size()) +
                 " fates; factors skipped");
    return;
  }
  // The handicap of the player an outcome favours: the one it reaches, or for a goal the shooter
  // when on the favoured team, else that team's mean.
  for (size_t k = 0; k < views.size(); ++k) {
    const FateView& v = views[k];
    double h = 1;
    if (v.kind == "body") {
      h = handicap_now(report.groups[k].fate.target);
    } else if (!v.favours.empty()) {
      if (last_toucher_ >= 0 && players_[last_toucher_].team == v.favours) {
        h = handicap_now(last_toucher_);
      } else {
        double sum = 0;
        int n = 0;
        for (size_t p = 0; p < players_.size(); ++p)
          if (players_[p].team == v.favours) sum += handicap_now(int(p)), ++n;
        if (n > 0) h = sum / n;
      }
    }
    factors[k] *= h;
  }
  try {
    world_.tweak(report, factors);
  } catch (const std::invalid_argument& e) {
    report_error(std::string("fate factors refused: ") + e.what());
  }
}

}  // namespace quantum::game

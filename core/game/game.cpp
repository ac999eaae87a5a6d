#include "game/game.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <stdexcept>

#include "game/plane.h"
#include "quantum/limits.h"

namespace quantum::game {

namespace {

constexpr std::array<const char*, kEventKinds> kEventNames = {
    "drop", "shot", "intercept", "retouch", "bounce", "goal", "own_goal", "out", "dead", "time_up", "match_end",
    "powerup", "powerup_end", "paused", "resumed", "catch", "pass", "throw", "give", "stalled", "loose", "landing", "hit", "pickup", "tackle",
    "kick"};

}  // namespace

const char* to_string(EventKind kind) { return kEventNames[size_t(kind)]; }

std::optional<EventKind> event_kind(std::string_view name) {
  for (size_t k = 0; k < kEventNames.size(); ++k)
    if (name == kEventNames[k]) return EventKind(k);
  return std::nullopt;
}

const std::vector<std::string>& event_names() {
  static const std::vector<std::string> names(kEventNames.begin(), kEventNames.end());
  return names;
}

bool counts_as_play(EventKind kind) {
  switch (kind) {
    case EventKind::Bounce: case EventKind::Powerup: case EventKind::PowerupEnd: case EventKind::Stalled:
    case EventKind::Loose:
      return false;
    default: return true;
  }
}

Match::Match(Field field, MatchConfig config, Rules& rules, std::vector<double> handicaps)
    : world_(std::move(field),
             WorldConfig{.particles = config.particles, .purgatory_frames = 3, .seed = config.seed, .threads = config.threads}),
      config_(config),
      rules_(&rules) {
  // The sport's file and the command line checked these where they entered (limits.h); the
  // stall bound and the balance are the match's own to refuse (a rule spec may set them).
  assert(limits::kFps.contains(config.fps) && limits::kTackleRate.contains(config.tackle_rate) &&
         limits::kThrowSpeed.contains(config.throw_speed) && config.seconds > 0);
  limits::check(limits::kStall, config.stall, "a match's stall bound");
  limits::check(limits::kBalancePerGoal, config.balance_per_goal, "automatic balance: per goal");
  limits::check(limits::kBalanceMost, config.balance_most, "automatic balance: the most");
  check_spread(config.throw_spread);
  const Field& f = world_.field();
  if (!handicaps.empty() && handicaps.size() != f.bodies.size())
    throw std::invalid_argument("got " + std::to_string(handicaps.size()) + " handicaps for " +
                                std::to_string(f.bodies.size()) + " players");
  for (size_t k = 0; k < f.bodies.size(); ++k) {
    const double h = handicaps.empty() ? 1.0 : handicaps[k];
    assert(handicap_ok(h));
    players_.push_back({f.bodies[k].name, f.bodies[k].team, h, f.bodies[k].start, {0, 0}, true, {}, {}, {}});
  }
  teams_ = f.teams();
  for (const std::string& team : teams_) score_[team] = 0;
  // A frame rarely tells more than a few events and phrases; room for more than that keeps the
  // first busy frames from allocating.
  events_.reserve(64);
  said_.make(64);
  // Room for a busy moment's fate groups keeps a busier moment than any before from allocating
  // in its frame (the prediction, its views, factors and their terms).
  constexpr size_t kFateGroups = kBusyFateGroups;
  report_.groups.reserve(kFateGroups);
  // The contacts' views and factors follow the fates'.
  const size_t contacts = world_.field().bodies.size() + world_.field().goals.size() + world_.field().areas.size() + 2;
  contact_fates_.reserve(contacts);
  views_.reserve(kFateGroups + contacts);
  factors_.reserve(kFateGroups + contacts);
  for (FactorTerms* t : {&terms_, &decision_terms_, &scratch_terms_}) t->reserve(kFateGroups + contacts, 2 * (kFateGroups + contacts));
  challenges_.reserve(world_.field().bodies.size());
  report_.group_of.reserve(2 * size_t(config.particles));  // one a particle, as World::predict's own fates
  respawn(config.first_spot, 0);
  if (config.first_holder >= 0) check_catcher(config.first_holder), respawn_holder_ = config.first_holder;
}

void FactorTerms::add(size_t fate, const FactorTerm& term) {
  while (first_.size() < fate + 2) first_.push_back(first_.back());
  terms_.push_back(term);
  ++first_.back();
}

std::span<const FactorTerm> FactorTerms::of(size_t fate) const {
  return {terms_.data() + first_[fate], first_[fate + 1] - first_[fate]};
}

void FactorTerms::swap(FactorTerms& other) noexcept {
  terms_.swap(other.terms_), first_.swap(other.first_), std::swap(skipped_, other.skipped_);
}

void Match::clear_news() {
  events_.clear();
  said_.clear();
  errors_.clear();
}

void Match::set_cause(const char* cause) {
  handling_ = -1;
  cause_ = cause;
}

void Match::note(EventKind type) {
  new_event(type);
  handling_ = int(events_.size() - 1);
  cause_ = to_string(type);
}

GameEvent& Match::new_event(EventKind type) {
  GameEvent& e = events_.emplace_back();
  e.t = time();
  e.type = type;
  if (counts_as_play(type)) last_play_t_ = time(), ++plays_;
  if (world_.holder() >= 0) e.holder = players_[size_t(world_.holder())].name;
  return e;
}

void Match::took(int k, double t) {
  previous_toucher_ = last_toucher_;
  last_toucher_ = k;
  last_touch_t_ = t;
  ++rally_contacts_;
  gained(k);
}

void Match::gained(int k) {
  const std::string_view team = players_[size_t(k)].team;
  if (team != possession_) ++stats_.possessions;
  possession_ = team;
}

void Match::expire_powerups() {
  for (size_t k = 0; k < powerups_.size();) {
    if (time() < powerups_[k].until - 1e-9) {
      ++k;
      continue;
    }
    const ActivePowerup p = powerups_[k];
    powerups_.erase(powerups_.begin() + long(k));
    powerup_event(EventKind::PowerupEnd, p.player, p.name);
  }
}

void Match::report_error(std::string message) { errors_.push_back(std::move(message)); }

void Match::step(std::span<const BodyInput> input) {
  if (finished_) return;
  rules_->begin_frame(*this);
  const float dt = float(1.0 / config_.fps);
  core_events_.clear();
  for (size_t k = 0; k < landing_.size(); ++k)
    if (landing_[k] >= 0 && time() >= landing_[k] - 1e-9) world_.set_reach(int(k), field().reach_of(int(k))), landing_[k] = -1;
  // A give at a place waits for its taker to get there, but not for ever.
  const bool waiting = respawn_holder_ >= 0 && !at_place(respawn_holder_) && time() < respawn_at_ + kMostPlaceWait;
  if (respawn_at_ >= 0 && time() >= respawn_at_ - 1e-9 && !waiting) {
    respawn_at_ = -1;
    if (respawn_holder_ >= 0) {
      hand_over(std::exchange(respawn_holder_, -1));
    } else {
      world_.drop(respawn_spot_, core_events_);
      retweak();  // the new ball's fates, and its contacts' factors with nobody its last toucher
    }
  }
  world_.step(dt, input, core_events_);
  if (world_.decision()) decision_terms_ = terms_, decision_contacts_from_ = contacts_from_;
  // No tackle in the frame a catch was decided: one draw a frame, and the catch comes first.
  else if (world_.holder() >= 0 && config_.tackle_rate > 0) contest(input);
  for (size_t k = 0; k < players_.size(); ++k)
    players_[k].position = input[k].position, players_[k].velocity = input[k].velocity;
  stats_.seconds = time();
  for (const Event& e : core_events_) handle(e);
  expire_powerups();
  rules_->tick(*this);
  set_cause("");
  // A ball gone without an outcome that brings it back (crushed away, or a shot that left while its
  // contact was caught up): it comes back where it was dropped.
  if (!world_.in_play() && respawn_at_ < 0 && !finished_) respawn(respawn_spot_, 1.0);
  watch_ball();
  // A restart on its way (a drop or give after a delay) is play to come, not a stall.
  if (!finished_ && respawn_at_ < 0 && time() - last_play_t_ >= config_.stall - 1e-9) stalled();
  if (!finished_ && !time_up_told_ && time() >= config_.seconds - 1e-9) {
    time_up_told_ = true;
    new_event(EventKind::TimeUp);
    tell_rules(events_.size() - 1);
    if (!finished_) {  // rules that ignore the clock: the leader wins, equal scores draw
      std::string best;
      int most = std::numeric_limits<int>::min(), leaders = 0;  // below any score: a leader at -3 wins too
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

void Match::watch_ball() {
  if (!world_.live()) {
    rolling_ = false;  // a dropped ball lies still, and is told as a drop
    return;
  }
  // A ball must have been twice as fast since it was last told loose to be told loose again.
  const BallMotion& m = world_.motion();
  if (m.speed >= 2 * kLooseSpeed) rolling_ = true;
  if (!rolling_ || m.speed >= kLooseSpeed) return;
  rolling_ = false;
  GameEvent& e = new_event(EventKind::Loose);
  e.at = m.centre, e.velocity = m.velocity;
  name_touchers(e);
  tell_rules(events_.size() - 1);
}

void Match::stalled() {
  ++stats_.stalls;
  const uint64_t plays = plays_;
  const int holder = world_.holder();
  GameEvent& e = new_event(EventKind::Stalled);
  if (holder >= 0) {
    e.actor = players_[size_t(holder)].name, e.team = players_[size_t(holder)].team, e.actor_index = holder;
    e.at = players_[size_t(holder)].position;
  } else {
    const BallMotion& m = world_.motion();
    e.at = m.centre, e.velocity = m.velocity;
  }
  name_touchers(e);
  const Vec2 at = e.at;
  tell_rules(events_.size() - 1);
  // Rules that dropped, gave, threw or ended the ball told play of their own (their restart).
  if (finished_ || plays_ != plays || respawn_at_ >= 0) return;
  // The rules did nothing about it: the ball goes to the player who catches nearest it (not its
  // holder, who kept it all this time), or else drops at the spot nearest it.
  int nearest = -1;
  float best = 1e30f;
  for (size_t k = 0; k < players_.size(); ++k) {
    const float d = length(players_[k].position - at);
    if (field().bodies[k].catches && int(k) != holder && d < best) best = d, nearest = int(k);
  }
  if (nearest >= 0) return give(nearest);
  int spot = 0;
  best = 1e30f;
  for (size_t s = 0; s < field().spots.size(); ++s)
    if (const float d = length(field().spots[s].at - at); d < best) best = d, spot = int(s);
  respawn(spot, 0);
}

void Match::handle(const Event& e) {
  const Field& f = field();
  EventKind type = EventKind::Out;
  switch (e.type) {
    case EventType::Drop: type = EventKind::Drop; break;
    case EventType::Hit: {
      if (f.bodies[e.actor].hits) {  // one touch, sent on at once: no swing to fold into it
        type = EventKind::Hit;
        took(e.actor, e.t);
        break;
      }
      const bool other_team = last_toucher_ >= 0 && f.bodies[last_toucher_].team != f.bodies[e.actor].team;
      // A swing goes on through the puck and may meet it again a few frames later: that is the
      // same touch, not a new shot.
      const bool again = e.actor == last_toucher_ && e.t - last_touch_t_ < kRetouch;
      type = again ? EventKind::Retouch : other_team ? EventKind::Intercept : EventKind::Shot;
      if (!again) previous_toucher_ = last_toucher_;
      last_toucher_ = e.actor;
      last_touch_t_ = e.t;
      rally_contacts_ += again ? 0 : 1;
      break;
    }
    case EventType::Catch:
    case EventType::Pickup: {
      const FateKind kind = e.type == EventType::Pickup ? FateKind::Pickup : catch_kind(f, last_toucher_, e.actor);
      type = kind == FateKind::Pass        ? EventKind::Pass
             : kind == FateKind::Intercept ? EventKind::Intercept
             : kind == FateKind::Pickup    ? EventKind::Pickup
                                           : EventKind::Catch;
      took(e.actor, e.t);
      stats_.passes += type == EventKind::Pass;
      break;
    }
    case EventType::Tackle:
      type = EventKind::Tackle;
      took(e.actor, e.t);  // `previous`: the holder who lost it
      break;
    case EventType::Throw:
    case EventType::Kick:
      type = e.type == EventType::Kick ? EventKind::Kick : EventKind::Throw;
      if (last_toucher_ != e.actor) previous_toucher_ = last_toucher_, last_toucher_ = e.actor;
      last_touch_t_ = e.t;
      break;
    case EventType::Bounce: type = EventKind::Bounce; break;
    case EventType::Goal: type = EventKind::Goal; break;
    case EventType::OwnGoal: type = EventKind::OwnGoal; break;
    case EventType::Out: type = EventKind::Out; break;
    case EventType::Landing: type = EventKind::Landing; break;
  }
  if (type == EventKind::Drop) rally_contacts_ = 0, last_toucher_ = previous_toucher_ = -1, possession_ = {};
  // The ball is played again: a restart's places are free.
  const bool played = e.type == EventType::Hit || e.type == EventType::Catch || e.type == EventType::Pickup ||
                      e.type == EventType::Tackle || e.type == EventType::Throw || e.type == EventType::Kick;
  if (played)
    for (Player& p : players_) p.place.reset();
  GameEvent& g = new_event(type);
  g.t = e.t, g.p = e.p, g.p_newtonian = e.p_newtonian, g.particles = e.particles, g.at = e.at;
  g.velocity = e.velocity, g.height = e.height, g.up = e.up, g.actor_index = e.actor;
  const EventActor actor = actor_of(e, f);
  g.actor = actor.name, g.team = actor.team;
  if (type != EventKind::Drop) name_touchers(g);
  if (e.type == EventType::Goal || e.type == EventType::OwnGoal || e.type == EventType::Out)
    end_rally(e.type != EventType::Out);
  tell_rules(events_.size() - 1);
}

void Match::name_touchers(GameEvent& e) const {
  if (last_toucher_ >= 0) e.by = players_[size_t(last_toucher_)].name, e.by_team = players_[size_t(last_toucher_)].team;
  if (previous_toucher_ >= 0)
    e.previous = players_[size_t(previous_toucher_)].name, e.previous_team = players_[size_t(previous_toucher_)].team;
}

void Match::end_rally(bool goal) {
  ++stats_.rallies;
  stats_.contacts += rally_contacts_;
  stats_.goals += goal ? 1 : 0;
}

void Match::tell_rules(size_t event) {
  // Phrases said while the rules handle it are this event's; whatever happens, the outer event
  // is the one speaking again afterwards.
  struct Handling {
    Match& m;
    int outer;
    const char* outer_cause;
    ~Handling() { m.handling_ = outer, m.cause_ = outer_cause; }
  } handling{*this, std::exchange(handling_, int(event)), std::exchange(cause_, to_string(events_[event].type))};
  // A copy: the handler's own actions may add events and move the list.
  const GameEvent e = events_[event];
  rules_->on_event(e, *this);
}

FateView Match::view(const FateGroup& group) const {
  const Field& f = field();
  const Fate& fate = group.fate;
  FateView v;
  v.fate = fate;
  v.mass = group.mass, v.tweaked = group.tweaked_mass, v.count = group.count;
  v.actor = fate_actor(fate, f);
  if (at_body(fate.kind)) {
    v.team = v.favours = f.bodies[fate.target].team;
  } else if (!v.actor.empty()) {
    v.team = fate.kind == FateKind::Landing ? f.areas[fate.target].team : f.goals[fate.target].team;
    // A goal, or a landing in a team's area, is good for the other side; with more than two
    // teams, for the last toucher's.
    for (const std::string& t : teams_)
      if (t != v.team && (v.favours.empty() || (last_toucher_ >= 0 && f.bodies[last_toucher_].team == t))) v.favours = t;
  }
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
  // In doubles: a lead of 2^31 - 1 over a team at -(2^31 - 1) is beyond an int.
  const double behind = double(lead) - double(own == score_.end() ? 0 : own->second);
  return p.handicap * std::min(config_.balance_most, std::pow(1 + config_.balance_per_goal, behind));
}

// The handicap of the player an outcome favours: the one it reaches, or for a goal the shooter
// when on the favoured team, else that team's mean.
Match::Favoured Match::handicap_for(const FateView& v) const {
  if (at_body(v.fate.kind)) return {handicap_now(v.fate.target), v.fate.target};
  if (v.favours.empty()) return {};
  if (last_toucher_ >= 0 && players_[last_toucher_].team == v.favours) return {handicap_now(last_toucher_), last_toucher_};
  double sum = 0;
  int n = 0;
  for (size_t p = 0; p < players_.size(); ++p)
    if (players_[p].team == v.favours) sum += handicap_now(int(p)), ++n;
  return {n > 0 ? sum / n : 1, -1};
}

// A tackle is a hazard, not a flight's end: while an opponent's body touches the holder's, it
// takes the ball at the sport's rate, made likelier or rarer by the fate factors of kind
// `tackle` (modifiers, power-ups, handicaps) as any fate is. The frame's chances go to the core,
// which draws once among them and logs the draw as the frame's decision.
void Match::contest(std::span<const BodyInput> input) {
  const int h = world_.holder();
  const Field& f = field();
  const double frame = 1 / config_.fps;
  views_.clear();
  for (size_t k = 0; k < players_.size(); ++k) {
    if (int(k) == h || !f.bodies[k].catches || f.bodies[k].team == f.bodies[size_t(h)].team) continue;
    if (length(input[k].position - input[size_t(h)].position) > f.bodies[k].radius + f.bodies[size_t(h)].radius) continue;
    FateView v;
    v.fate.kind = FateKind::Tackle, v.fate.target = int(k);
    v.actor = f.bodies[k].name, v.team = v.favours = f.bodies[k].team;
    v.mass = v.tweaked = -std::expm1(-config_.tackle_rate * frame);
    views_.push_back(v);
  }
  if (views_.empty()) return;
  factors_.assign(views_.size(), 1.0);
  decision_terms_.clear();
  rules_->factors(views_, *this, factors_, decision_terms_);
  add_handicaps(decision_terms_);
  challenges_.clear();
  double total = 0;
  for (size_t k = 0; k < views_.size(); ++k) {
    const double chance = -std::expm1(-config_.tackle_rate * factors_[k] * frame);
    challenges_.push_back({views_[k].fate.target, chance, views_[k].mass, factors_[k]});
    total += chance;
  }
  // Several sure tackles at once: one of them happens, each as likely as its share.
  if (total > 1)
    for (Challenge& c : challenges_) c.chance /= total;
  world_.challenge(challenges_, core_events_);
}

void Match::add_handicaps(FactorTerms& terms) {
  scratch_terms_.clear();
  if (terms.skipped()) scratch_terms_.skip();
  for (size_t k = 0; k < views_.size(); ++k) {
    const std::span<const FactorTerm> given = k < terms.fates() ? terms.of(k) : std::span<const FactorTerm>{};
    for (const FactorTerm& t : given) scratch_terms_.add(k, t);
    if (given.empty()) scratch_terms_.add(k, {FactorTerm::Source::Sport, 0, -1, {}, 0, false, factors_[k]});
    const FateView& v = views_[k];
    if (terms.skipped() && !v.contact) continue;  // the fates' factors are all 1 in a skipped frame
    const Favoured h = handicap_for(v);
    if (h.handicap == 1) continue;
    factors_[k] *= h.handicap;
    scratch_terms_.add(k, {FactorTerm::Source::Handicap, 0, h.player, h.player < 0 ? v.favours : std::string_view{}, 0,
                           false, h.handicap});
  }
  terms.swap(scratch_terms_);
}

void Match::retweak() {
  const bool live = world_.live();
  views_.clear();
  if (live) {
    world_.predict(report_);
    for (const FateGroup& g : report_.groups) views_.push_back(view(g));
  } else {
    report_.groups.clear();
  }
  contacts_from_ = views_.size();
  world_.contact_fates(contact_fates_);
  for (const Fate& f : contact_fates_) {
    views_.push_back(view(FateGroup{f, 0, 0, 0, 0}));
    views_.back().contact = true;
  }
  factors_.assign(views_.size(), 1.0);
  terms_.clear();
  rules_->factors(views_, *this, factors_, terms_);
  add_handicaps(terms_);
  const std::span<const double> factors(factors_);
  try {
    if (live) world_.tweak(report_, factors.first(contacts_from_));
    world_.set_contact_factors(factors.subspan(contacts_from_));
  } catch (const std::invalid_argument& e) {
    report_error(std::string("fate factors refused: ") + e.what());
  }
}

}  // namespace quantum::game

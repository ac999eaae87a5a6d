// The `quantum` module of the rule-spec runner: quantum.scenario(...) makes a scenario, a match
// of a sport driven by a spec instead of players (place and move bodies over time, put the ball
// somewhere, run, and read the events, phrases and fates), and quantum.chi_square_p(...) tests
// frequencies. A scenario runs its match through a runtime::Session, like `quantum play`.
// Runs inside `quantum test` (the trusted spec runner), so it may use the full Lua library.
#include "wrap_scenario.h"

#include <boost/math/distributions/chi_squared.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>

#include "lua_push.h"
#include "lua_reader.h"
#include "lua_wrap.h"
#include "lua_sport.h"
#include "quantum/narrow.h"
#include "session.h"

namespace quantum::lua {
namespace {

constexpr const char* kType = "scenario";
constexpr double kMostVerticalSpeed = 1000;  // m/s: as fast as a throw may be (throw_fault)

// Bodies moved by the spec: each holds still, or moves in a straight line at constant speed
// toward a target until a given time.
class ScriptedPlayers final : public runtime::PlayerSource {
 public:
  struct Motion {
    Vec2 position, velocity, target;
    double until = 0;  // moving toward target until this time
  };
  // Every body at rest where the field starts it.
  void start(const Field& field) {
    for (const BodySpec& b : field.bodies) motions.push_back({b.start, {0, 0}, b.start, 0});
    bodies_.resize(motions.size());
  }
  Status advance(double t, const game::Match& match, bool) override {
    const double dt = 1.0 / match.fps();
    for (size_t k = 0; k < motions.size(); ++k) {
      Motion& m = motions[k];
      if (m.until > 0 && t >= m.until) m.position = m.target, m.velocity = {0, 0}, m.until = 0;
      else if (m.until > 0) m.position = {m.position.x + float(m.velocity.x * dt), m.position.y + float(m.velocity.y * dt)};
      bodies_[k] = {m.position, m.velocity};
    }
    return Status::Ready;
  }
  std::span<const BodyInput> bodies() const override { return bodies_; }
  // The bodies as `motions` has them now.
  const std::vector<BodyInput>& now() {
    for (size_t k = 0; k < motions.size(); ++k) bodies_[k] = {motions[k].position, motions[k].velocity};
    return bodies_;
  }

  std::vector<Motion> motions;

 private:
  std::vector<BodyInput> bodies_;
};

struct Told {
  game::GameEvent event;
  std::vector<std::string> said;  // what its own handlers said
};

struct Scenario {
  std::ostringstream warnings;
  std::unique_ptr<runtime::Session> session;
  ScriptedPlayers* bodies = nullptr;  // owned by the session
  std::vector<Told> events;
  std::vector<std::string> said, errors;
  size_t run_from = 0;            // the first event no run has returned yet
  std::optional<game::EventKind> stop;
  bool stopped = false;

  game::Match& match() { return session->match(); }

  void hear(const runtime::News& news) {
    for (size_t k = 0; k < news.events.size(); ++k) {
      Told t{news.events[k], {}};
      for (const game::Said& s : news.said)
        if (s.event == int(k)) t.said.push_back(s.text);
      stopped |= stop && news.events[k].type == *stop;
      events.push_back(std::move(t));
    }
    for (const game::Said& s : news.said) said.push_back(s.text);
    errors.insert(errors.end(), news.errors.begin(), news.errors.end());
  }
};

Scenario& self(lua_State* L) {
  Scenario* s = object<Scenario>(L);
  if (!s) throw std::logic_error("this scenario is gone");
  return *s;
}

int body_index(Scenario& s, const std::string& name) { return player_index(s.match(), name); }

// Fails on a key of the options table at `index` that is not in `known` (option() then checks
// each value's type).
void check_options(lua_State* L, int index, std::initializer_list<const char*> known, const char* what) {
  if (lua_isnoneornil(L, index)) return;
  check_table(L, index);
  try {
    Reader(L).only_keys(index, what, known);
  } catch (const ReadError& e) {
    throw ArgError(e.what());
  }
}

double option(lua_State* L, int index, const char* key, double fallback) {
  if (!lua_istable(L, index)) return fallback;
  lua_getfield(L, index, key);
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    return fallback;
  }
  if (!lua_isnumber(L, -1)) throw ArgError(std::string(key) + ": expected a number, got " + luaL_typename(L, -1));
  const double v = lua_tonumber(L, -1);
  lua_pop(L, 1);
  return v;
}

// A number as an error message shows it: 2.5, 1e+300, nan; a field's float with `digits` 6.
std::string number_text(double v, int digits = 14) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

// A whole-number option in [lo, hi), which `range` says in words: a spec's -1 or 1e300 fails
// naming the option instead of becoming some other seed or count.
double whole_option(lua_State* L, int index, const char* key, double fallback, double lo, double hi, const char* range) {
  const double v = option(L, index, key, fallback);
  if (!(v >= lo && v < hi && v == std::floor(v)))
    throw ArgError(std::string(key) + ": expected a whole number from " + range + ", got " + number_text(v));
  return v;
}

void push_told(lua_State* L, const Told& t) {
  push_event(L, t.event);
  push_strings(L, t.said);
  lua_setfield(L, -2, "said");
}

// The sport's --param's from {params = {length = 40, ...}}, as NAME=VALUE.
std::vector<std::string> params_of(lua_State* L, int index) {
  std::vector<std::string> out;
  if (!lua_istable(L, index)) return out;
  lua_getfield(L, index, "params");
  if (!lua_isnil(L, -1)) {
    if (!lua_istable(L, -1)) throw ArgError("params: expected a table {name = value}");
    lua_pushnil(L);
    while (lua_next(L, -2)) {
      if (lua_type(L, -2) != LUA_TSTRING) throw ArgError("params: expected names as keys");
      if (!lua_isstring(L, -1) && !lua_isboolean(L, -1)) throw ArgError("params: expected a number, string or boolean");
      const std::string value = lua_isboolean(L, -1) ? (lua_toboolean(L, -1) ? "true" : "false") : lua_tostring(L, -1);
      out.push_back(std::string(lua_tostring(L, -2)) + "=" + value);
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  return out;
}

// Sets what a table {[player] = number} of the options at `index` gives under `key`, player by
// player, with set(player, value).
template <class Set>
void per_player_option(lua_State* L, int index, Scenario& s, const char* key, const char* what, Set set) {
  if (!lua_istable(L, index)) return;
  lua_getfield(L, index, key);
  if (!lua_isnil(L, -1)) {
    if (!lua_istable(L, -1)) throw ArgError(std::string(key) + ": expected a table {[player] = " + what + "}");
    lua_pushnil(L);
    while (lua_next(L, -2)) {
      if (lua_type(L, -2) != LUA_TSTRING) throw ArgError(std::string(key) + ": expected player names as keys");
      const int k = body_index(s, lua_tostring(L, -2));
      if (!lua_isnumber(L, -1)) throw ArgError(std::string(key) + ": expected a number for each player");
      set(k, lua_tonumber(L, -1));
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
}

// quantum.scenario(sport_folder [, {seed =, particles =, seconds = (time limit), handicaps = {...},
//                                   skills = {...}, params = {name = value} (as --param)}])
int scenario(lua_State* L) {
  const std::string folder = check_string(L, 1);
  check_options(L, 2, {"seed", "particles", "seconds", "handicaps", "skills", "params"}, "quantum.scenario's options");
  auto s = std::make_unique<Scenario>();
  runtime::SessionOptions o;
  o.sport = folder;
  o.seed = uint64_t(whole_option(L, 2, "seed", 1, 0, 0x1p64, "0 to 2^64 - 1"));
  o.particles = uint32_t(whole_option(L, 2, "particles", 0, 0, 10'000'001, "0 (the sport's) to 10000000"));
  o.seconds = option(L, 2, "seconds", 0);
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  o.params = params_of(L, 2);
  auto bodies = std::make_unique<ScriptedPlayers>();
  s->bodies = bodies.get();
  s->session = std::make_unique<runtime::Session>(o, tools::lua_sport, nullptr, s->warnings, std::move(bodies));
  s->bodies->start(s->match().field());
  // Handicaps by player name, over the sport's; the spec's players are people (no skill) unless
  // it plays some as simulated players of a skill, for the rules to read.
  game::Match& m = s->match();
  per_player_option(L, 2, *s, "handicaps", "handicap", [&](int k, double h) { m.set_handicap(k, h); });
  per_player_option(L, 2, *s, "skills", "skill in [0, 1]", [&](int k, double skill) { m.set_skill(k, skill); });
  Scenario* raw = s.get();
  s->session->watch([raw](const runtime::News& news) { raw->hear(news); });
  auto** box = static_cast<Scenario**>(lua_newuserdata(L, sizeof(Scenario*)));
  *box = s.release();
  luaL_getmetatable(L, kType);
  lua_setmetatable(L, -2);
  return 1;
}

int gc(lua_State* L) {
  auto** box = static_cast<Scenario**>(luaL_checkudata(L, 1, kType));
  delete *box;
  *box = nullptr;
  return 0;
}

// The match sees the bodies as the scenario has them now (power-ups read their motion). Throws,
// and changes nothing, for bodies the match refuses.
void show(Scenario& s, const std::vector<ScriptedPlayers::Motion>& motions) {
  const std::vector<ScriptedPlayers::Motion> before = s.bodies->motions;
  s.bodies->motions = motions;
  try {
    s.match().place_players(s.bodies->now());
  } catch (...) {
    s.bodies->motions = before;
    s.bodies->now();
    throw;
  }
}

// s:place(player, x, y): the body is there, at rest.
int place(lua_State* L) {
  Scenario& s = self(L);
  std::vector<ScriptedPlayers::Motion> motions = s.bodies->motions;
  ScriptedPlayers::Motion& m = motions[size_t(body_index(s, check_string(L, 2)))];
  m.position = m.target = {to_float(check_number(L, 3)), to_float(check_number(L, 4))};
  m.velocity = {0, 0}, m.until = 0;
  show(s, motions);
  return 0;
}

// s:move(player, x, y, seconds): moves there in a straight line at constant speed.
int move(lua_State* L) {
  Scenario& s = self(L);
  std::vector<ScriptedPlayers::Motion> motions = s.bodies->motions;
  ScriptedPlayers::Motion& m = motions[size_t(body_index(s, check_string(L, 2)))];
  const double seconds = check_number(L, 5);
  if (!(seconds > 0 && std::isfinite(seconds))) throw ArgError("seconds must be > 0");
  m.target = {to_float(check_number(L, 3)), to_float(check_number(L, 4))};
  m.velocity = {to_float((m.target.x - m.position.x) / seconds), to_float((m.target.y - m.position.y) / seconds)};
  m.until = s.match().time() + seconds;
  show(s, motions);
  return 0;
}

// s:grant(player, powerup [, {seconds =, strength =, ...}]): as game.grant, from the spec.
int grant(lua_State* L) {
  Scenario& s = self(L);
  const int player = body_index(s, check_string(L, 2));
  const std::string name = check_string(L, 3);
  if (!lua_isnoneornil(L, 4)) check_table(L, 4);
  tools::scripted_rules(*s.session).grant(s.match(), player, name, numbers_of(L, 4));
  s.session->tell();
  return 0;
}

// The ball's height and vertical speed a spec gives on a field with height: z from the floor
// (the ball resting on it, by default) up to the ceiling, vz within what a throw may be.
struct BallHeight {
  float z = 0, vz = 0;
};

BallHeight ball_height(lua_State* L, int index, const Field& f) {
  lua_getfield(L, index, "z");
  lua_getfield(L, index, "vz");
  const bool given = !lua_isnil(L, -2) || !lua_isnil(L, -1);
  lua_pop(L, 2);
  if (!f.has_height()) {
    if (given) throw ArgError("z, vz: " + f.name + " is flat (no gravity): a ball has no height there");
    return {};
  }
  const double z = option(L, index, "z", f.ball_radius), vz = option(L, index, "vz", 0);
  const double top = f.ceiling > 0 ? f.ceiling - f.ball_radius : std::numeric_limits<float>::max();
  if (!(z >= f.ball_radius && z <= top))
    throw ArgError("z: expected a height from " + number_text(f.ball_radius, 6) + " m (the ball on the floor)" +
                   (f.ceiling > 0 ? " to " + number_text(top, 6) + " m (under the ceiling)" : std::string(" up")) +
                   ", got " + number_text(z));
  if (!(std::abs(vz) <= kMostVerticalSpeed))
    throw ArgError("vz: expected a vertical speed in [-1000, 1000] m/s, got " + number_text(vz));
  return {float(z), float(vz)};
}

// s:ball{x =, y =, z =, vx =, vy =, vz =, spread = 0.01 (m), turn = 0.05 (rad), count = 400,
// by = player}: the ball is a bundle of that many particles around (x, y), heading (vx, vy)
// give or take `turn`, last touched by `by` (nobody when absent); on a field with height at
// height z moving up at vz (the floor and at rest by default).
int ball(lua_State* L) {
  Scenario& s = self(L);
  check_options(L, 2, {"x", "y", "z", "vx", "vy", "vz", "spread", "turn", "count", "by"}, "the ball");
  check_table(L, 2);
  const Field& f = s.match().field();
  const double x = option(L, 2, "x", 0), y = option(L, 2, "y", 0);
  const double vx = option(L, 2, "vx", 0), vy = option(L, 2, "vy", 0);
  const BallHeight height = ball_height(L, 2, f);
  const double spread = option(L, 2, "spread", 0.01), turn = option(L, 2, "turn", 0.05);
  const int n = int(whole_option(L, 2, "count", 400, 1, 10'000'001, "1 to 10000000"));
  Cloud c;
  c.reserve(size_t(n), f.has_height());
  const double speed = std::hypot(vx, vy), heading = std::atan2(vy, vx);
  // A deterministic lattice: spread and turn cover their ranges evenly, so specs need no seed.
  for (int i = 0; i < n; ++i) {
    const double u = n > 1 ? double(i) / (n - 1) - 0.5 : 0;
    const double a = heading + 2 * turn * u;
    const double side = spread * std::sin(2 * M_PI * 7.3 * u);
    const Vec3 at{to_float(x - side * std::sin(heading)), to_float(y + side * std::cos(heading)), height.z};
    const Vec3 v{to_float(speed * std::cos(a)), to_float(speed * std::sin(a)), height.vz};
    if (f.has_height()) c.push(at, v, 1.0 / n, 1.0 / n);
    else c.push(at.x, at.y, v.x, v.y, 1.0 / n, 1.0 / n);
  }
  int by = -1;
  lua_getfield(L, 2, "by");
  if (!lua_isnil(L, -1)) by = body_index(s, check_string(L, lua_gettop(L)));
  lua_pop(L, 1);
  s.match().set_scene(s.bodies->now(), std::move(c), by);
  s.session->tell();
  return 0;
}

// s:give(player): the ball is in that player's hands now (a player who catches), told as `give`.
int give(lua_State* L) {
  Scenario& s = self(L);
  s.match().give(body_index(s, check_string(L, 2)));
  s.session->tell();
  return 0;
}

// s:throw(player, vx, vy [, vz]): the holder throws, as from its accelerometer (vz upward, on a
// field with height): the sport's spread scatters the cloud, and its rules hear the throw.
// s:kick(player, vx, vy [, vz]) kicks it from the feet (World::release): along the floor, or
// lofted with vz.
int release(lua_State* L, World::Release how) {
  Scenario& s = self(L);
  const int k = body_index(s, check_string(L, 2));
  if (s.match().holder() != k) throw ArgError(check_string(L, 2) + " does not hold the ball");
  s.match().throw_ball(k, {to_float(check_number(L, 3)), to_float(check_number(L, 4)), to_float(opt_number(L, 5, 0))},
                       std::nullopt, how);
  s.session->tell();
  return 0;
}

int throw_ball(lua_State* L) { return release(L, World::Release::Throw); }
int kick(lua_State* L) { return release(L, World::Release::Kick); }

// s:hit(player, vx, vy [, vz]): the player, who hits, sends the ball it next meets at that
// velocity, as a swing its accelerometer felt (the sport's spread scatters it); s:hit(player)
// sends it off the player's motion.
int hit(lua_State* L) {
  Scenario& s = self(L);
  const int k = body_index(s, check_string(L, 2));
  if (!lua_isnoneornil(L, 3)) {
    s.match().swing(k, {to_float(check_number(L, 3)), to_float(check_number(L, 4)), to_float(opt_number(L, 5, 0))});
    return 0;
  }
  HitPlan plan;  // off the player's motion
  plan.spread = s.match().config().throw_spread;
  s.match().plan_hit(k, plan);
  return 0;
}

// s:jump(player [, height [, seconds]]): as game.jump, from the spec (a field with height).
int jump(lua_State* L) {
  Scenario& s = self(L);
  s.match().jump(body_index(s, check_string(L, 2)), opt_number(L, 3, game::Match::kJumpHeight),
                 opt_number(L, 4, game::Match::kJumpSeconds));
  return 0;
}

// s:holder(): who holds the ball, nil when nobody does.
int holder(lua_State* L) {
  Scenario& s = self(L);
  const int k = s.match().holder();
  if (k < 0) lua_pushnil(L);
  else lua_pushstring(L, s.match().players()[size_t(k)].name.c_str());
  return 1;
}

// s:run(seconds [, stop_type]): runs the match; returns the events of this run (each with the
// phrases its handlers said, `said`), stopping after the first of `stop_type`.
int run(lua_State* L) {
  Scenario& s = self(L);
  const double seconds = check_number(L, 2);
  if (!(seconds > 0 && seconds <= 3600)) throw ArgError("seconds must be in (0, 3600]");
  s.stop.reset();
  if (const std::optional<std::string> stop = opt_string(L, 3)) {
    s.stop = game::event_kind(*stop);
    if (!s.stop) throw ArgError(unknown_key(*stop, game::event_names(), "event type"));
  }
  s.stopped = false;
  // What was told since the last run (a grant, say) belongs to this one.
  const size_t first = s.run_from;
  const double end = s.match().time() + seconds - 1e-9;
  while (s.match().time() < end && !s.stopped && s.session->frame()) {
  }
  s.run_from = s.events.size();
  lua_createtable(L, int(s.events.size() - first), 0);
  for (size_t i = first; i < s.events.size(); ++i) {
    push_told(L, s.events[i]);
    lua_rawseti(L, -2, int(i - first + 1));
  }
  return 1;
}

int events(lua_State* L) {
  Scenario& s = self(L);
  lua_createtable(L, int(s.events.size()), 0);
  for (size_t i = 0; i < s.events.size(); ++i) {
    push_told(L, s.events[i]);
    lua_rawseti(L, -2, int(i + 1));
  }
  return 1;
}

int said(lua_State* L) {
  push_strings(L, self(L).said);
  return 1;
}

int errors(lua_State* L) {
  push_strings(L, self(L).errors);
  return 1;
}

// s:fates(): the current fates, as modifiers see them (see lua_push.h).
int fates(lua_State* L) {
  Scenario& s = self(L);
  const std::vector<game::FateView> list = s.match().fates();
  lua_createtable(L, int(list.size()), 0);
  for (size_t i = 0; i < list.size(); ++i) {
    lua_newtable(L);
    fill_fate(L, list[i], s.match().field());
    lua_rawseti(L, -2, int(i + 1));
  }
  return 1;
}

// s:players(): the players as game.players() gives them (with the sport's hints: `turn`).
int players(lua_State* L) {
  push_players(L, self(L).match());
  return 1;
}

int score(lua_State* L) {
  push_score(L, self(L).match().score());
  return 1;
}

int time(lua_State* L) {
  lua_pushnumber(L, self(L).match().time());
  return 1;
}

// quantum.chi_square_p(chi2, degrees_of_freedom): the upper tail probability.
int chi_square_p(lua_State* L) {
  const double chi2 = check_number(L, 1), df = check_number(L, 2);
  if (!(chi2 >= 0 && df >= 1)) throw ArgError("needs chi2 >= 0 and df >= 1");
  lua_pushnumber(L, boost::math::cdf(boost::math::complement(boost::math::chi_squared(df), chi2)));
  return 1;
}

}  // namespace

void open_scenario(lua_State* L) {
  register_type(L, kType,
                {{"place", guard<place>},   {"move", guard<move>},     {"ball", guard<ball>},
                 {"run", guard<run>},       {"grant", guard<grant>},   {"events", guard<events>},
                 {"said", guard<said>},     {"errors", guard<errors>}, {"fates", guard<fates>},
                 {"players", guard<players>}, {"score", guard<score>}, {"time", guard<time>},
                 {"give", guard<give>},     {"throw", guard<throw_ball>}, {"kick", guard<kick>},
                 {"hit", guard<hit>},
                 {"holder", guard<holder>},
                 {"jump", guard<jump>}},
                gc);
  push_module(L, "quantum", {{"scenario", guard<scenario>}, {"chi_square_p", guard<chi_square_p>}}, nullptr);
  lua_setglobal(L, "quantum");
}

}  // namespace quantum::lua

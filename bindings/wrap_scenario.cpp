// `quantum.scenario`: a sport's match driven by a rule spec instead of players: place and move
// bodies over time, put the ball somewhere, step, and read the events, phrases and fates.
// Runs inside `quantum test` (the trusted spec runner), so it may use the full Lua library.
#include "wrap_scenario.h"

#include <boost/math/distributions/chi_squared.hpp>

#include <cmath>
#include <memory>

#include "lua_push.h"
#include "sport.h"

namespace quantum::lua {
namespace {

constexpr const char* kMeta = "quantum.scenario";
constexpr double kFps = 60;

struct Motion {
  Vec2 position, velocity, target;
  double until = 0;  // moving toward target until this time
};

struct Scenario {
  std::unique_ptr<Sport> sport;
  std::unique_ptr<game::Match> match;
  std::vector<Motion> bodies;
  std::vector<game::GameEvent> events;
  std::vector<game::Said> said;
  std::vector<std::string> errors;
};

Scenario& check(lua_State* L) { return **static_cast<Scenario**>(luaL_checkudata(L, 1, kMeta)); }

double field_number(lua_State* L, int t, const char* key, double fallback) {
  lua_getfield(L, t, key);
  const double v = lua_isnumber(L, -1) ? lua_tonumber(L, -1) : fallback;
  lua_pop(L, 1);
  return v;
}

int body_index(lua_State* L, Scenario& s, int arg) {
  const std::string name = luaL_checkstring(L, arg);
  const Field& f = s.match->field();
  for (size_t k = 0; k < f.bodies.size(); ++k)
    if (f.bodies[k].name == name) return int(k);
  return luaL_error(L, "no player '%s' in %s", name.c_str(), s.sport->name().c_str());
}

// quantum.scenario(sport_folder [, {seed =, particles =, seconds = (time limit), handicaps = {...}}])
int scenario(lua_State* L) {
  const std::string folder = luaL_checkstring(L, 1);
  return guarded(L, [&] {
    auto s = std::make_unique<Scenario>();
    s->sport = std::make_unique<Sport>(folder);
    game::MatchConfig config;
    config.particles = s->sport->particles();
    config.seconds = s->sport->seconds();
    config.first_spot = s->sport->first_spot();
    config.balance_per_goal = s->sport->balance_per_goal();
    config.balance_most = s->sport->balance_most();
    std::vector<double> handicaps = s->sport->handicaps();
    if (lua_istable(L, 2)) {
      config.seed = uint64_t(field_number(L, 2, "seed", 1));
      config.particles = uint32_t(field_number(L, 2, "particles", config.particles));
      config.seconds = field_number(L, 2, "seconds", config.seconds);
      lua_getfield(L, 2, "handicaps");
      if (lua_istable(L, -1))
        for (size_t k = 0; k < handicaps.size(); ++k)
          handicaps[k] = field_number(L, lua_gettop(L), s->sport->field().bodies[k].name.c_str(), handicaps[k]);
      lua_pop(L, 1);
    }
    s->match = std::make_unique<game::Match>(s->sport->field(), config, *s->sport, handicaps);
    for (const BodySpec& b : s->match->field().bodies) s->bodies.push_back({b.start, {0, 0}, b.start, 0});
    auto** box = static_cast<Scenario**>(lua_newuserdata(L, sizeof(Scenario*)));
    *box = s.release();
    luaL_getmetatable(L, kMeta);
    lua_setmetatable(L, -2);
    return 1;
  });
}

int gc(lua_State* L) {
  auto** box = static_cast<Scenario**>(luaL_checkudata(L, 1, kMeta));
  delete *box;
  *box = nullptr;
  return 0;
}

// The match sees the bodies as the scenario has them now (power-ups read their motion).
int show(lua_State* L, Scenario& s) {
  std::vector<BodyInput> input;
  for (const Motion& m : s.bodies) input.push_back({m.position, m.velocity});
  return guarded(L, [&] {
    s.match->place_players(input);
    return 0;
  });
}

// s:place(player, x, y): the body is there, at rest.
int place(lua_State* L) {
  Scenario& s = check(L);
  Motion& m = s.bodies[body_index(L, s, 2)];
  m.position = m.target = {float(luaL_checknumber(L, 3)), float(luaL_checknumber(L, 4))};
  m.velocity = {0, 0}, m.until = 0;
  return show(L, s);
}

// s:grant(player, powerup [, {seconds =, strength =, ...}]): as game.grant, from the spec.
int grant(lua_State* L) {
  Scenario& s = check(L);
  const int player = body_index(L, s, 2);
  const std::string name = luaL_checkstring(L, 3);
  std::map<std::string, double> opts = numbers_of(L, 4);
  return guarded(L, [&] {
    s.sport->grant(*s.match, player, name, std::move(opts));
    return 0;
  });
}

// s:move(player, x, y, seconds): moves there in a straight line at constant speed.
int move(lua_State* L) {
  Scenario& s = check(L);
  Motion& m = s.bodies[body_index(L, s, 2)];
  const double seconds = luaL_checknumber(L, 5);
  if (!(seconds > 0)) return luaL_error(L, "move: seconds must be > 0");
  m.target = {float(luaL_checknumber(L, 3)), float(luaL_checknumber(L, 4))};
  m.velocity = {float((m.target.x - m.position.x) / seconds), float((m.target.y - m.position.y) / seconds)};
  m.until = s.match->time() + seconds;
  return show(L, s);
}

// s:ball{x =, y =, vx =, vy =, spread = 0.01 (m), turn = 0.05 (rad), count = 400, by = player}:
// the ball is a bundle of that many particles around (x, y), heading (vx, vy) give or take
// `turn`, last touched by `by` (nobody when absent).
int ball(lua_State* L) {
  Scenario& s = check(L);
  luaL_checktype(L, 2, LUA_TTABLE);
  const double x = field_number(L, 2, "x", 0), y = field_number(L, 2, "y", 0);
  const double vx = field_number(L, 2, "vx", 0), vy = field_number(L, 2, "vy", 0);
  const double spread = field_number(L, 2, "spread", 0.01), turn = field_number(L, 2, "turn", 0.05);
  const int count = int(field_number(L, 2, "count", 400));
  if (count < 1 || count > 10'000'000) return luaL_error(L, "ball: count must be in [1, 10000000]");
  Cloud c;
  const double speed = std::hypot(vx, vy), heading = std::atan2(vy, vx);
  // A deterministic lattice: spread and turn cover their ranges evenly, so specs need no seed.
  for (int i = 0; i < count; ++i) {
    const double u = count > 1 ? double(i) / (count - 1) - 0.5 : 0;
    const double a = heading + 2 * turn * u;
    const double side = spread * std::sin(2 * M_PI * 7.3 * u);
    c.push(float(x - side * std::sin(heading)), float(y + side * std::cos(heading)), float(speed * std::cos(a)),
           float(speed * std::sin(a)), 1.0 / count, 1.0 / count);
  }
  int by = -1;
  lua_getfield(L, 2, "by");
  if (!lua_isnil(L, -1)) by = body_index(L, s, lua_gettop(L));
  lua_pop(L, 1);
  std::vector<BodyInput> input;
  for (const Motion& m : s.bodies) input.push_back({m.position, m.velocity});
  return guarded(L, [&] {
    s.match->set_scene(input, std::move(c), by);
    return 0;
  });
}

// s:run(seconds [, stop_at_type]): steps the match; returns the events of this run.
int run(lua_State* L) {
  Scenario& s = check(L);
  const double seconds = luaL_checknumber(L, 2);
  const std::string stop = luaL_optstring(L, 3, "");
  if (!(seconds > 0 && seconds <= 3600)) return luaL_error(L, "run: seconds must be in (0, 3600]");
  std::vector<game::GameEvent> fresh;
  const double dt = 1 / kFps;
  const double end = s.match->time() + seconds - 1e-9;
  bool stopped = false;
  std::string error;
  try {
    while (s.match->time() < end && !s.match->finished() && !stopped) {
      std::vector<BodyInput> input;
      const double t = s.match->time() + dt;
      for (Motion& m : s.bodies) {
        if (m.until > 0 && t >= m.until) m.position = m.target, m.velocity = {0, 0}, m.until = 0;
        else if (m.until > 0) m.position = {m.position.x + float(m.velocity.x * dt), m.position.y + float(m.velocity.y * dt)};
        input.push_back({m.position, m.velocity});
      }
      s.match->step(input);
      for (const game::GameEvent& e : s.match->take_events()) {
        fresh.push_back(e);
        stopped |= e.type == stop;
      }
      for (game::Said& said : s.match->take_said()) s.said.push_back(std::move(said));
      for (std::string& e : s.match->take_errors()) s.errors.push_back(std::move(e));
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!error.empty()) return luaL_error(L, "%s", error.c_str());
  s.events.insert(s.events.end(), fresh.begin(), fresh.end());
  lua_createtable(L, int(fresh.size()), 0);
  for (size_t i = 0; i < fresh.size(); ++i) {
    push_event(L, fresh[i]);
    lua_rawseti(L, -2, int(i + 1));
  }
  return 1;
}

int events(lua_State* L) {
  Scenario& s = check(L);
  lua_createtable(L, int(s.events.size()), 0);
  for (size_t i = 0; i < s.events.size(); ++i) {
    push_event(L, s.events[i]);
    lua_rawseti(L, -2, int(i + 1));
  }
  return 1;
}

int said(lua_State* L) {
  std::vector<std::string> texts;
  for (const game::Said& s : check(L).said) texts.push_back(s.text);
  push_strings(L, texts);
  return 1;
}

int errors(lua_State* L) {
  push_strings(L, check(L).errors);
  return 1;
}

// s:fates(): the current fates, as rules see them (see lua_push.h).
int fates(lua_State* L) {
  Scenario& s = check(L);
  return guarded(L, [&] {
    const std::vector<game::FateView> list = s.match->fates();
    lua_createtable(L, int(list.size()), 0);
    for (size_t i = 0; i < list.size(); ++i) {
      push_fate(L, list[i]);
      lua_rawseti(L, -2, int(i + 1));
    }
    return 1;
  });
}

int score(lua_State* L) {
  push_score(L, check(L).match->score());
  return 1;
}

int time(lua_State* L) {
  lua_pushnumber(L, check(L).match->time());
  return 1;
}

// quantum.chi_square_p(chi2, degrees_of_freedom): the upper tail probability.
int chi_square_p(lua_State* L) {
  const double chi2 = luaL_checknumber(L, 1), df = luaL_checknumber(L, 2);
  if (!(chi2 >= 0 && df >= 1)) return luaL_error(L, "chi_square_p: needs chi2 >= 0 and df >= 1");
  lua_pushnumber(L, boost::math::cdf(boost::math::complement(boost::math::chi_squared(df), chi2)));
  return 1;
}

}  // namespace

void open_scenario(lua_State* L) {
  const luaL_Reg methods[] = {{"place", place}, {"move", move},     {"ball", ball},   {"run", run}, {"grant", grant},
                              {"events", events}, {"said", said},   {"errors", errors}, {"fates", fates},
                              {"score", score},   {"time", time}};
  luaL_newmetatable(L, kMeta);
  lua_pushcfunction(L, gc);
  lua_setfield(L, -2, "__gc");
  lua_newtable(L);
  for (const luaL_Reg& m : methods) {
    lua_pushcfunction(L, m.func);
    lua_setfield(L, -2, m.name);
  }
  lua_setfield(L, -2, "__index");
  lua_pop(L, 1);
  lua_newtable(L);
  lua_pushcfunction(L, scenario);
  lua_setfield(L, -2, "scenario");
  lua_pushcfunction(L, chi_square_p);
  lua_setfield(L, -2, "chi_square_p");
  lua_setglobal(L, "quantum");
}

}  // namespace quantum::lua

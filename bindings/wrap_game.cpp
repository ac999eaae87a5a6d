// The `game` module a sport's handlers, timers, modifiers and power-ups receive: the match's
// actions and what the rules may read. Fates, players and the score; never particle positions.
// Called with a dot (game.say(...)); see lua_wrap.h and docs/lua-api.md.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "lua_push.h"
#include "lua_reader.h"
#include "lua_wrap.h"
#include "quantum/limits.h"
#include "quantum/narrow.h"
#include "scripted_rules.h"

namespace quantum::lua {
namespace {

ScriptedRules& sport_of(lua_State* L) { return upvalue_self<ScriptedRules>(L); }

// Actions change the match: only handlers, timers, on_reload and a power-up's start and stop may
// take them; factors only compute, so a fate's odds never depend on when they were computed.
game::Match& acting(lua_State* L) {
  game::Match* m = sport_of(L).match();
  if (!m) throw std::logic_error("only event handlers (on.*), timers and a power-up's start and stop may act on the "
                                 "match; modifiers and power-up factors only compute a number");
  return *m;
}

const game::Match& reading(lua_State* L) {
  const game::Match* m = sport_of(L).reading();
  if (!m) throw std::logic_error("no match is running");
  return *m;
}

// game.say(key_or_text [, vars]): a phrase of the sport (or text to speak) with {placeholders}.
int say(lua_State* L) {
  game::Match& m = acting(L);
  const std::string_view key = check_view(L, 1);
  if (!lua_isnoneornil(L, 2)) check_table(L, 2);
  sport_of(L).say(m, key, [&](std::string_view name) { return phrase_value(L, 2, name); });
  return 0;
}

// game.award(team [, points])
int award(lua_State* L) {
  acting(L).award(check_string(L, 1), opt_number(L, 2, 1));
  return 0;
}

// game.respawn(spot_name_or_team [, delay_seconds]): the next drop; a ball still in play is dead.
int respawn(lua_State* L) {
  game::Match& m = acting(L);
  const std::string where = check_string(L, 1);
  const int spot = m.field().spot_of(where);
  if (spot < 0) throw ArgError("no spot or team '" + where + "' in this field");
  m.respawn(spot, opt_number(L, 2, 1.0));
  return 0;
}

// game.dead_ball(): the rally ends now, the ball still moving; `dead` is told.
int dead_ball(lua_State* L) {
  acting(L).dead_ball();
  return 0;
}

// game.finish([winner]): ends the match; nil or "" for a draw.
int finish(lua_State* L) {
  acting(L).finish(opt_string(L, 1).value_or(""));
  return 0;
}

// game.grant(player, powerup [, {seconds =, strength =, ...}]): see docs/writing-a-powerup.md.
int grant(lua_State* L) {
  game::Match& m = acting(L);
  const int player = player_index(m, check_string(L, 1));
  const std::string name = check_string(L, 2);
  if (!lua_isnoneornil(L, 3)) check_table(L, 3);
  sport_of(L).grant(m, player, name, numbers_of(L, 3));
  return 0;
}

// game.wormhole(ax, ay, bx, by [, radius]): what enters the mouth at (ax, ay) leaves the one at
// (bx, by), and back (radius 0.1 m by default); game.wormhole() closes it.
int wormhole(lua_State* L) {
  game::Match& m = acting(L);
  std::vector<Wormhole> holes;
  if (lua_gettop(L) > 0)
    holes.push_back({{to_float(check_number(L, 1)), to_float(check_number(L, 2))},
                     {to_float(check_number(L, 3)), to_float(check_number(L, 4))}, to_float(opt_number(L, 5, 0.1))});
  m.set_wormholes(std::move(holes));
  return 0;
}

// game.handicap(player, value): the player's own handicap from now on (> 0).
int handicap(lua_State* L) {
  game::Match& m = acting(L);
  m.set_handicap(player_index(m, check_string(L, 1)), check_number(L, 2));
  return 0;
}

// game.after(seconds, fn): fn(game) runs once, that much later, as a handler does; returns an id
// for game.cancel.
int after(lua_State* L) {
  game::Match& m = acting(L);
  const double seconds = check_number(L, 1);
  if (!lua_isfunction(L, 2)) throw ArgError("argument 2: expected a function, got " + std::string(luaL_typename(L, 2)));
  lua_settop(L, 2);
  lua_pushinteger(L, sport_of(L).add_timer(m, seconds));
  return 1;
}

// game.cancel(id): a timer that has not run yet never will.
int cancel(lua_State* L) {
  acting(L);
  // Ids are whole numbers game.after gave; any other number names no timer.
  const double id = check_number(L, 1);
  if (id >= 1 && id <= std::numeric_limits<int>::max() && id == std::floor(id)) sport_of(L).cancel_timer(int(id));
  return 0;
}

// game.turn(who): whose turn it is to play the ball (a player or a team; nil: everyone's), for
// the simulated players. Others keep clear; the one with the turn plays the ball anywhere.
int turn(lua_State* L) {
  game::Match& m = acting(L);
  const std::optional<std::string> who = opt_string(L, 1);
  auto has_turn = [&](const game::Player& p) { return !who || p.name == *who || p.team == *who; };
  if (std::none_of(m.players().begin(), m.players().end(), has_turn)) player_index(m, *who);  // names the nearest
  for (size_t k = 0; k < m.players().size(); ++k) m.set_turn(int(k), has_turn(m.players()[k]));
  return 0;
}

// game.aim(who, where): where a player (or a team's players) sends the ball: a goal, a wall or a
// spot by name, or a point {x, y}; nil: the opponents' goal again.
int aim(lua_State* L) {
  game::Match& m = acting(L);
  const std::string who = check_string(L, 1);
  const Field& f = m.field();
  game::Aim aim;
  if (lua_istable(L, 2)) {
    lua_rawgeti(L, 2, 1);
    lua_rawgeti(L, 2, 2);
    if (!lua_isnumber(L, -2) || !lua_isnumber(L, -1)) throw ArgError("argument 2: expected a point {x, y}");
    aim = {game::Aim::Kind::Point, -1, {to_float(lua_tonumber(L, -2)), to_float(lua_tonumber(L, -1))}};
  } else if (!lua_isnoneornil(L, 2)) {
    const std::string where = check_string(L, 2);
    std::vector<std::string> names;
    for (size_t g = 0; g < f.goals.size(); ++g) {
      if (f.goals[g].name == where) aim = {game::Aim::Kind::Goal, int(g), {}};
      names.push_back(f.goals[g].name);
    }
    for (size_t w = 0; w < f.wall_names.size() && aim.kind == game::Aim::Kind::Default; ++w) {
      if (f.wall_names[w] == where) aim = {game::Aim::Kind::Wall, int(w), {}};
      names.push_back(f.wall_names[w]);
    }
    for (const Spot& s : f.spots) {
      if (s.name == where && aim.kind == game::Aim::Kind::Default) aim = {game::Aim::Kind::Point, -1, s.at};
      names.push_back(s.name);
    }
    if (aim.kind == game::Aim::Kind::Default) throw ArgError(unknown_key(where, names, "goal, wall or spot"));
  }
  bool any = false;
  for (size_t k = 0; k < m.players().size(); ++k)
    if (m.players()[k].name == who || m.players()[k].team == who) m.set_aim(int(k), aim), any = true;
  if (!any) player_index(m, who);
  return 0;
}

// A restart's place at argument `arg`: a spot's name or a point {x = .., y = ..}; its name as the
// announcer says it into `said`.
Vec2 place_at(lua_State* L, const game::Match& m, int arg, std::string& said) {
  if (lua_istable(L, arg)) {
    raw_field(L, arg, "x");
    raw_field(L, arg, "y");
    if (!lua_isnumber(L, -2) || !lua_isnumber(L, -1))
      throw ArgError("argument " + std::to_string(script_arg(L, arg)) + ": expected a spot's name or a point {x = .., y = ..}");
    const Vec2 p{to_float(lua_tonumber(L, -2)), to_float(lua_tonumber(L, -1))};
    lua_pop(L, 2);
    char text[64];
    std::snprintf(text, sizeof text, "%.1f, %.1f", double(p.x), double(p.y));
    said = text;
    return p;
  }
  const std::string name = check_string(L, arg);
  std::vector<std::string> names;
  for (const Spot& s : m.field().spots) {
    if (s.name == name) return said = name, s.at;
    names.push_back(s.name);
  }
  throw ArgError(unknown_key(name, names, "spot"));
}

// A person (not a simulated player) is told a place by the announcer: the sport's phrase `place`
// ({player}, {place}) when it has one.
void tell_place(lua_State* L, game::Match& m, int k, const std::string& where) {
  if (m.players()[size_t(k)].skill) return;
  const std::string& who = m.players()[size_t(k)].name;
  sport_of(L).say_or(m, "place", "{player}, to {place}", [&](std::string_view name) {
    return name == "player" ? std::optional<PhraseValue>({who, {}})
           : name == "place" ? std::optional<PhraseValue>({where, {}})
                             : std::optional<PhraseValue>();
  });
}

// game.give(player [, delay [, {at = spot_or_point}]]): the ball into the player's hands (a
// throw-off, a throw-in, a free throw), at once or `delay` seconds from now; a ball in play is
// dead at once. With `at`, the player is placed there and the ball waits for them (see
// Match::give). `give` is told when the player has it.
int give(lua_State* L) {
  game::Match& m = acting(L);
  const int k = player_index(m, check_string(L, 1));
  const double delay = opt_number(L, 2, 0);
  std::optional<Vec2> at;
  std::string where;
  if (!lua_isnoneornil(L, 3)) {
    check_table(L, 3);
    Reader(L).only_keys(3, "argument 3", {"at"});
    raw_field(L, 3, "at");
    if (!lua_isnil(L, -1)) at = place_at(L, m, lua_gettop(L), where);
    lua_pop(L, 1);
  }
  m.give(k, delay, at);
  if (at) tell_place(L, m, k, where);
  return 0;
}

// game.place(player [, spot_or_point]): the player takes that place for a restart (a formation,
// a kick-off); without one, the place is freed. Places hold until the ball is next played.
int place(lua_State* L) {
  game::Match& m = acting(L);
  const int k = player_index(m, check_string(L, 1));
  if (lua_isnoneornil(L, 2)) {
    m.place(k, std::nullopt);
    return 0;
  }
  std::string where;
  m.place(k, place_at(L, m, 2, where));
  tell_place(L, m, k, where);
  return 0;
}

// Where a throw at `to` goes: a velocity {vx, vy} ({vx, vy, vz} with height), or at a point
// {x = .., y = .. [, z = ..]} or the name of a player (where they will be when the ball arrives,
// as they run now; with height, at their chest), a goal (a hoop's ring) or a spot.
struct ThrowTarget {
  bool velocity = false;
  Vec3 v;      // the velocity, when given
  Vec3 point;  // else where the ball should go
};

// A number as an error shows it: "nan" whatever its sign bit (0/0 sets it), "inf", "2.5".
std::string number_text(double v) { return std::isnan(v) ? "nan" : (std::ostringstream() << v).str(); }

// A velocity or point a script gave (argument `arg`): NaN or infinite (a float's range passed
// counts as infinite) is refused here, naming the argument, before the world sees it.
Vec3 finite_vector(lua_State* L, int arg, const char* what) {
  const Vec3 v{to_float(lua_tonumber(L, -3)), to_float(lua_tonumber(L, -2)), to_float(lua_tonumber(L, -1))};
  lua_pop(L, 3);
  if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)))
    throw ArgError("argument " + std::to_string(script_arg(L, arg)) + ": " + what + " must be finite, got {" +
                   number_text(v.x) + ", " + number_text(v.y) + ", " + number_text(v.z) + "}");
  return v;
}

ThrowTarget throw_target(lua_State* L, const game::Match& m, int thrower, int to, double speed) {
  const Field& f = m.field();
  const Vec2 from = m.players()[size_t(thrower)].position;
  if (lua_istable(L, to)) {
    lua_rawgeti(L, to, 1);
    lua_rawgeti(L, to, 2);
    lua_rawgeti(L, to, 3);
    if (lua_isnumber(L, -3) && lua_isnumber(L, -2)) return {true, finite_vector(L, to, "a velocity"), {}};
    lua_pop(L, 3);
    raw_field(L, to, "x");
    raw_field(L, to, "y");
    raw_field(L, to, "z");
    if (!lua_isnumber(L, -3) || !lua_isnumber(L, -2))
      throw ArgError("argument " + std::to_string(script_arg(L, to)) +
                     ": expected a velocity {vx, vy}, a point {x = .., y = ..} or a name");
    return {false, {}, finite_vector(L, to, "a point")};
  }
  const std::string name = check_string(L, to);
  std::vector<std::string> names;
  for (size_t k = 0; k < m.players().size(); ++k) {
    const game::Player& p = m.players()[k];
    names.push_back(p.name);
    if (p.name != name) continue;
    // Friction makes the ball take longer than distance / speed; one too slow ever to arrive
    // is aimed where the player is going in a second.
    const double flight = f.travel_time(std::hypot(p.position.x - from.x, p.position.y - from.y), speed);
    const float lead = float(std::isfinite(flight) ? flight : 1.0);
    const float chest = f.has_height() ? kChestShare * f.reach_of(int(k)) : 0;
    return {false, {}, {p.position.x + p.velocity.x * lead, p.position.y + p.velocity.y * lead, chest}};
  }
  for (const Goal& g : f.goals) {
    names.push_back(g.name);
    if (g.name == name) return {false, {}, {0.5f * (g.a.x + g.b.x), 0.5f * (g.a.y + g.b.y), g.rim_height}};
  }
  for (const Spot& s : f.spots) {
    names.push_back(s.name);
    if (s.name == name) return {false, {}, {s.at.x, s.at.y, f.ball_radius}};
  }
  throw ArgError(unknown_key(name, names, "player, goal or spot"));
}

// A throw's or a hit's options (argument `arg`, a table or nil): speed (the sport's throw speed by
// default), spread and speed_spread (the sport's `throws`), elevation (none when not given) and
// elevation_spread.
struct Launch {
  double speed;
  std::optional<double> elevation;
  ThrowSpread spread;
};

Launch launch_options(lua_State* L, const game::Match& m, int arg) {
  if (!lua_isnoneornil(L, arg)) check_table(L, arg);
  const game::MatchConfig& c = m.config();
  double speed = c.throw_speed, degrees = c.throw_spread.direction / kRadiansPerDegree, share = c.throw_spread.speed;
  double up_spread = c.throw_spread.elevation / kRadiansPerDegree;
  std::optional<double> elevation;
  if (lua_istable(L, arg)) {
    const Reader r(L);
    const std::string place = "argument " + std::to_string(script_arg(L, arg));
    r.only_keys(arg, place, {"speed", "spread", "speed_spread", "elevation", "elevation_spread"});
    // A number given is one: NaN (a script's 0/0) is no option left out, and infinity no most.
    const auto given = [&](const char* key) -> std::optional<double> {
      if (!r.field(arg, key)) return std::nullopt;
      r.expect(LUA_TNUMBER, place + "." + key);
      const double v = lua_tonumber(L, -1);
      lua_pop(L, 1);
      if (!std::isfinite(v)) throw ArgError(place + "." + key + ": expected a finite number, got " + number_text(v));
      return v;
    };
    speed = given("speed").value_or(speed);
    degrees = given("spread").value_or(degrees);
    share = given("speed_spread").value_or(share);
    elevation = given("elevation");
    up_spread = given("elevation_spread").value_or(up_spread);
  }
  const auto check = [](const limits::Range& range, double v, const char* what) {
    if (!range.contains(v)) throw ArgError(std::string(what) + " " + limits::must_be_in(range, v));
  };
  check(limits::kThrowSpeed, speed, "speed");
  check(limits::kSpreadDegrees, degrees, "spread");
  check(limits::kSpeedSpread, share, "speed_spread");
  check(limits::kSpreadDegrees, up_spread, "elevation_spread");
  if (elevation) check(limits::kElevationDegrees, *elevation, "elevation");
  if (elevation && !m.field().has_height()) throw ArgError("elevation needs a field with height (gravity)");
  return {speed, elevation, {float(degrees * kRadiansPerDegree), float(share), float(up_spread * kRadiansPerDegree)}};
}

// game.throw(player, to [, {speed =, spread =, speed_spread =, elevation =, elevation_spread =}]):
// the player, who holds the ball, throws it at `to` (see throw_target) at `speed` m/s (the
// sport's by default; a velocity gives its own), scattered by `spread` degrees of direction and
// `speed_spread` of speed (the sport's `throws` by default). With height the ball flies in an
// arc through the target: the flattest one at that speed, or the one leaving at `elevation`
// degrees (its speed follows; at a hoop 52 unless given); `elevation_spread` scatters the angle.
// `throw` is told. game.kick(player, to [, opts]) is the same from the feet: with height the ball
// leaves the floor, along it at `speed` (slowed by the field's friction) unless `elevation`
// lofts it; `kick` is told.
int release(lua_State* L, World::Release how) {
  game::Match& m = acting(L);
  const Field& f = m.field();
  const int player = player_index(m, check_string(L, 1));
  Launch launch = launch_options(L, m, 3);
  std::optional<double>& elevation = launch.elevation;
  const double speed = launch.speed;
  const bool kick = how == World::Release::Kick;
  const std::string verb = kick ? "kick" : "throw";
  if (lua_isnoneornil(L, 2)) throw ArgError("argument 2: expected where to " + verb);
  const ThrowTarget to = throw_target(L, m, player, 2, speed);
  Vec3 velocity = to.v;
  if (!to.velocity) {
    const Vec2 p = m.players()[size_t(player)].position;
    if (!(std::hypot(to.point.x - p.x, to.point.y - p.y) > 0))
      throw ArgError("the " + verb + "er stands on the point it " + verb + "s at");
    if (!f.has_height() || (kick && !elevation)) {
      const float dx = to.point.x - p.x, dy = to.point.y - p.y, d = std::hypot(dx, dy);
      velocity = {float(speed * dx / d), float(speed * dy / d), 0};
    } else {
      const Vec2 arm = f.release_point(player, p, {to.point.x, to.point.y});
      const Vec3 from{arm.x, arm.y, kick ? f.ball_radius : m.world().reach(player)};
      const bool hoop = lua_type(L, 2) == LUA_TSTRING && m.field().goals.end() !=
          std::find_if(f.goals.begin(), f.goals.end(), [&](const Goal& g) { return g.hoop() && g.name == lua_tostring(L, 2); });
      if (!elevation && hoop) elevation = kShotElevation / kRadiansPerDegree;
      velocity = !elevation ? f.throw_at(from, to.point, float(speed))
                            : f.arc_velocity(from, to.point, float(*elevation * kRadiansPerDegree));
      if (velocity.x == 0 && velocity.y == 0 && velocity.z == 0)
        throw ArgError("no " + verb + " at " + std::to_string(elevation.value_or(NAN)) + " degrees reaches that point: " +
                       verb + " higher");
    }
  }
  m.throw_ball(player, velocity, launch.spread, how);
  return 0;
}

int throw_ball(lua_State* L) { return release(L, World::Release::Throw); }
int kick(lua_State* L) { return release(L, World::Release::Kick); }

// game.hit(player [, to [, {speed =, spread =, ...}]]): the player, who hits (field.lua: hits =
// true), sends the ball it next meets toward `to` (a velocity {vx, vy [, vz]}, a point, a
// player's hands, a goal or a spot, as game.throw's), from wherever it meets it, with game.throw's
// options; without `to`, off its own motion (a swing nobody planned). One touch uses the plan up.
int hit(lua_State* L) {
  game::Match& m = acting(L);
  const int player = player_index(m, check_string(L, 1));
  const Launch launch = launch_options(L, m, 3);
  HitPlan plan;
  plan.spread = launch.spread;
  if (!lua_isnoneornil(L, 2)) {
    const ThrowTarget to = throw_target(L, m, player, 2, launch.speed);
    plan.kind = to.velocity ? HitPlan::Kind::Velocity : HitPlan::Kind::Point;
    plan.velocity = to.v, plan.point = to.point, plan.speed = float(launch.speed);
    plan.elevation = float(launch.elevation.value_or(0) * kRadiansPerDegree);
  }
  m.plan_hit(player, plan);
  return 0;
}

// game.jump(player [, height [, seconds]]): on a field with height the player reaches `height`
// m higher (0.5 by default) for `seconds` (0.5): a block, a rebound.
int jump(lua_State* L) {
  game::Match& m = acting(L);
  m.jump(player_index(m, check_string(L, 1)), opt_number(L, 2, game::Match::kJumpHeight),
         opt_number(L, 3, game::Match::kJumpSeconds));
  return 0;
}

// game.holder(): who holds the ball, or nil.
int holder(lua_State* L) {
  const game::Match& m = reading(L);
  if (m.holder() < 0) return 0;
  lua_pushstring(L, m.players()[size_t(m.holder())].name.c_str());
  return 1;
}

// game.field(): the field's geometry and players (lua_push.h, push_field).
int field(lua_State* L) {
  push_field(L, reading(L).field());
  return 1;
}

// game.area(x, y): the name and team of the field's area at that point (field.lua's `areas`), or nil.
int area(lua_State* L) {
  const Field& f = reading(L).field();
  const int a = f.area_at({to_float(check_number(L, 1)), to_float(check_number(L, 2))});
  if (a < 0) return 0;
  lua_pushstring(L, f.areas[size_t(a)].name.c_str());
  lua_pushstring(L, f.areas[size_t(a)].team.c_str());
  return 2;
}

int score(lua_State* L) {
  push_score(L, reading(L).score());
  return 1;
}

int time(lua_State* L) {
  lua_pushnumber(L, reading(L).time());
  return 1;
}

// game.length(): the match's time limit as it runs: --seconds (or a scenario's `seconds`) when
// given, else the sport's match.seconds, which stays what the sport asked for.
int length(lua_State* L) {
  lua_pushnumber(L, reading(L).config().seconds);
  return 1;
}

int teams(lua_State* L) {
  push_strings(L, reading(L).teams());
  return 1;
}

// game.team_name(team): the team's name as the announcer says it (sport.lua's `teams`).
int team_name(lua_State* L) {
  const std::string name = sport_of(L).spec().team_name(check_string(L, 1));
  lua_pushlstring(L, name.data(), name.size());
  return 1;
}

// game.players(): {name, team, role, area, holds, x, y, vx, vy, speed, handicap, skill,
// reach_height, turn, powerups} for each player, in the field's order.
int players(lua_State* L) {
  push_players(L, reading(L));
  return 1;
}

// game.powerups(): {name, player, remaining, <its numbers>} for each active power-up.
int powerups(lua_State* L) {
  const game::Match& m = reading(L);
  lua_createtable(L, int(m.powerups().size()), 0);
  for (size_t i = 0; i < m.powerups().size(); ++i) {
    lua_newtable(L);
    fill_powerup(L, m, m.powerups()[i]);
    lua_rawseti(L, -2, int(i + 1));
  }
  return 1;
}

// game.last_touch(): the last player to touch the ball this rally, or nil.
int last_touch(lua_State* L) {
  const game::Match& m = reading(L);
  if (m.last_toucher() < 0) return 0;
  lua_pushstring(L, m.players()[size_t(m.last_toucher())].name.c_str());
  return 1;
}

}  // namespace

int player_index(const game::Match& m, const std::string& name) {
  for (size_t k = 0; k < m.players().size(); ++k)
    if (m.players()[k].name == name) return int(k);
  std::vector<std::string> names;
  for (const game::Player& p : m.players()) names.push_back(p.name);
  throw ArgError(unknown_key(name, names, "player"));
}

void push_game_api(lua_State* L, ScriptedRules* sport) {
  push_module(L, "game",
              {{"say", guard<say>},           {"award", guard<award>},       {"respawn", guard<respawn>},
               {"dead_ball", guard<dead_ball>}, {"finish", guard<finish>},   {"grant", guard<grant>},
               {"handicap", guard<handicap>}, {"wormhole", guard<wormhole>}, {"after", guard<after>},
               {"cancel", guard<cancel>},     {"turn", guard<turn>},         {"aim", guard<aim>},
               {"score", guard<score>},       {"time", guard<time>},         {"length", guard<length>},         {"teams", guard<teams>},
               {"team_name", guard<team_name>}, {"players", guard<players>}, {"powerups", guard<powerups>},
               {"last_touch", guard<last_touch>}, {"give", guard<give>},      {"place", guard<place>}, {"throw", guard<throw_ball>}, {"kick", guard<kick>}, {"hit", guard<hit>}, {"jump", guard<jump>},
               {"holder", guard<holder>},     {"area", guard<area>},         {"field", guard<field>}},
              sport);
}

}  // namespace quantum::lua

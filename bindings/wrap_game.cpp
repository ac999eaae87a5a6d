// The `game` table a sport's handlers and modifiers receive: the match's actions and what the
// rules may read. Fates, players and the score; never particle positions. See docs/lua-api.md.
#include <cmath>

#include "lua_push.h"
#include "sport.h"

namespace quantum::lua {
namespace {

Sport* sport_of(lua_State* L) { return static_cast<Sport*>(lua_touserdata(L, lua_upvalueindex(1))); }

// Actions change the match: only event handlers may take them, not fate modifiers.
game::Match& acting(lua_State* L, const char* what) {
  game::Match* m = sport_of(L)->match();
  if (!m) luaL_error(L, "game.%s: only event handlers (on.*) may act on the match", what);
  return *m;
}

const game::Match& reading(lua_State* L) {
  const game::Match* m = sport_of(L)->reading();
  if (!m) luaL_error(L, "game: no match is running");
  return *m;
}

// game.say(key_or_text [, vars]): a phrase of the sport (or literal text) with {placeholders}.
int say(lua_State* L) {
  game::Match& m = acting(L, "say");
  const std::string key = luaL_checkstring(L, 1);
  std::map<std::string, std::string> vars;
  if (lua_istable(L, 2)) {
    lua_pushnil(L);
    while (lua_next(L, 2)) {
      if (lua_type(L, -2) == LUA_TSTRING && (lua_isstring(L, -1)))
        vars[lua_tostring(L, -2)] = lua_tostring(L, -1);
      lua_pop(L, 1);
    }
  }
  const auto& recorded = sport_of(L)->audio().recorded;
  const auto file = recorded.find(key);
  m.say(sport_of(L)->phrase(key, vars), file == recorded.end() ? std::string() : file->second);
  return 0;
}

// game.award(team [, goals])
int award(lua_State* L) {
  game::Match& m = acting(L, "award");
  const std::string team = luaL_checkstring(L, 1);
  const int goals = int(luaL_optinteger(L, 2, 1));
  return guarded(L, [&] { m.award(team, goals); return 0; });
}

// game.respawn(spot_name_or_team [, delay_seconds]): the next drop.
int respawn(lua_State* L) {
  game::Match& m = acting(L, "respawn");
  const std::string where = luaL_checkstring(L, 1);
  const double delay = luaL_optnumber(L, 2, 1.0);
  const int spot = m.spot_of(where);
  if (spot < 0) return luaL_error(L, "game.respawn: no spot or team '%s' in this field", where.c_str());
  return guarded(L, [&] { m.respawn(spot, delay); return 0; });
}

// game.finish([winner]): ends the match; nil or "" for a draw.
int finish(lua_State* L) {
  game::Match& m = acting(L, "finish");
  m.finish(luaL_optstring(L, 1, ""));
  return 0;
}

int score(lua_State* L) {
  push_score(L, reading(L).score());
  return 1;
}

int time(lua_State* L) {
  lua_pushnumber(L, reading(L).time());
  return 1;
}

int teams(lua_State* L) {
  push_strings(L, reading(L).teams());
  return 1;
}

// game.players(): {name, team, x, y, vx, vy, speed, handicap, powerups} for each player, in the
// field's order.
int players(lua_State* L) {
  const game::Match& m = reading(L);
  lua_createtable(L, int(m.players().size()), 0);
  for (size_t i = 0; i < m.players().size(); ++i) {
    push_player(L, m, i);
    lua_rawseti(L, -2, int(i + 1));
  }
  return 1;
}

int player_index(lua_State* L, const game::Match& m, int arg) {
  const std::string name = luaL_checkstring(L, arg);
  for (size_t k = 0; k < m.players().size(); ++k)
    if (m.players()[k].name == name) return int(k);
  return luaL_error(L, "no player '%s' in this field", name.c_str());
}

// game.grant(player, powerup [, {seconds =, strength =, ...}]): see docs/writing-a-powerup.md.
int grant(lua_State* L) {
  game::Match& m = acting(L, "grant");
  const int player = player_index(L, m, 1);
  const std::string name = luaL_checkstring(L, 2);
  std::map<std::string, double> opts = numbers_of(L, 3);
  return guarded(L, [&] {
    sport_of(L)->grant(m, player, name, std::move(opts));
    return 0;
  });
}

// game.wormhole(ax, ay, bx, by [, radius]): what enters the mouth at (ax, ay) leaves the one at
// (bx, by), and back (radius 0.1 m by default); game.wormhole() closes it.
int wormhole(lua_State* L) {
  game::Match& m = acting(L, "wormhole");
  std::vector<Wormhole> holes;
  if (lua_gettop(L) > 0)
    holes.push_back({{float(luaL_checknumber(L, 1)), float(luaL_checknumber(L, 2))},
                     {float(luaL_checknumber(L, 3)), float(luaL_checknumber(L, 4))},
                     float(luaL_optnumber(L, 5, 0.1))});
  return guarded(L, [&] {
    m.set_wormholes(std::move(holes));
    return 0;
  });
}

// game.handicap(player, value): the player's own handicap from now on (> 0).
int handicap(lua_State* L) {
  game::Match& m = acting(L, "handicap");
  const int player = player_index(L, m, 1);
  const double value = luaL_checknumber(L, 2);
  return guarded(L, [&] {
    m.set_handicap(player, value);
    return 0;
  });
}

// game.powerups(): {name, player, remaining, <its numbers>} for each active power-up.
int powerups(lua_State* L) {
  const game::Match& m = reading(L);
  lua_createtable(L, int(m.powerups().size()), 0);
  for (size_t i = 0; i < m.powerups().size(); ++i) {
    push_powerup(L, m, m.powerups()[i]);
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

void push_game_api(lua_State* L, Sport* sport) {
  const luaL_Reg functions[] = {{"say", say},         {"award", award},       {"respawn", respawn},
                                {"finish", finish},   {"grant", grant},       {"score", score},
                                {"time", time},       {"teams", teams},       {"players", players},
                                {"powerups", powerups}, {"last_touch", last_touch}, {"wormhole", wormhole},
                                {"handicap", handicap}};
  lua_newtable(L);
  for (const luaL_Reg& f : functions) {
    lua_pushlightuserdata(L, sport);
    lua_pushcclosure(L, f.func, 1);
    lua_setfield(L, -2, f.name);
  }
}

}  // namespace quantum::lua

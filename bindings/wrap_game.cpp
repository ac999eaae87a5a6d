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

// game.players(): {name, team, speed, handicap} for each player, in the field's order.
int players(lua_State* L) {
  const std::vector<game::Player>& ps = reading(L).players();
  lua_createtable(L, int(ps.size()), 0);
  for (size_t i = 0; i < ps.size(); ++i) {
    lua_createtable(L, 0, 4);
    lua_pushstring(L, ps[i].name.c_str());
    lua_setfield(L, -2, "name");
    lua_pushstring(L, ps[i].team.c_str());
    lua_setfield(L, -2, "team");
    lua_pushnumber(L, std::hypot(ps[i].velocity.x, ps[i].velocity.y));
    lua_setfield(L, -2, "speed");
    lua_pushnumber(L, ps[i].handicap);
    lua_setfield(L, -2, "handicap");
    lua_rawseti(L, -2, int(i + 1));
  }
  return 1;
}

}  // namespace

void push_game_api(lua_State* L, Sport* sport) {
  const luaL_Reg functions[] = {{"say", say},     {"award", award}, {"respawn", respawn}, {"finish", finish},
                                {"score", score}, {"time", time},   {"teams", teams},     {"players", players}};
  lua_newtable(L);
  for (const luaL_Reg& f : functions) {
    lua_pushlightuserdata(L, sport);
    lua_pushcclosure(L, f.func, 1);
    lua_setfield(L, -2, f.name);
  }
}

}  // namespace quantum::lua

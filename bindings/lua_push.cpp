#include "lua_push.h"

#include <algorithm>
#include <cmath>

namespace quantum::lua {
namespace {

void set(lua_State* L, const char* key, const std::string& value) {
  lua_pushstring(L, value.c_str());
  lua_setfield(L, -2, key);
}

void set(lua_State* L, const char* key, double value) {
  lua_pushnumber(L, value);
  lua_setfield(L, -2, key);
}

}  // namespace

void push_strings(lua_State* L, const std::vector<std::string>& list) {
  lua_createtable(L, int(list.size()), 0);
  for (size_t i = 0; i < list.size(); ++i) {
    lua_pushstring(L, list[i].c_str());
    lua_rawseti(L, -2, int(i + 1));
  }
}

void push_score(lua_State* L, const std::map<std::string, int>& score) {
  lua_createtable(L, 0, int(score.size()));
  for (const auto& [team, goals] : score) {
    lua_pushinteger(L, goals);
    lua_setfield(L, -2, team.c_str());
  }
}

void push_event(lua_State* L, const game::GameEvent& e) {
  lua_createtable(L, 0, 14);
  set(L, "type", e.type), set(L, "actor", e.actor), set(L, "team", e.team);
  set(L, "by", e.by), set(L, "by_team", e.by_team);
  set(L, "t", e.t), set(L, "p", e.p), set(L, "p_newtonian", e.p_newtonian), set(L, "particles", double(e.particles));
  set(L, "x", e.at.x), set(L, "y", e.at.y), set(L, "vx", e.velocity.x), set(L, "vy", e.velocity.y);
  set(L, "speed", std::hypot(e.velocity.x, e.velocity.y));
  if (!e.powerup.empty()) set(L, "powerup", e.powerup);
}

void push_fate(lua_State* L, const game::FateView& f) {
  lua_createtable(L, 0, 9);
  set(L, "kind", f.kind), set(L, "actor", f.actor), set(L, "team", f.team), set(L, "favours", f.favours);
  set(L, "via", f.via);
  set(L, "mass", f.mass), set(L, "tweaked", f.tweaked), set(L, "count", double(f.count));
  push_strings(L, f.path);
  lua_setfield(L, -2, "path");
}

void push_player(lua_State* L, const game::Match& match, size_t k) {
  const game::Player& p = match.players()[k];
  lua_createtable(L, 0, 9);
  set(L, "name", p.name), set(L, "team", p.team);
  set(L, "x", p.position.x), set(L, "y", p.position.y), set(L, "vx", p.velocity.x), set(L, "vy", p.velocity.y);
  set(L, "speed", std::hypot(p.velocity.x, p.velocity.y));
  set(L, "handicap", match.handicap_now(int(k)));
  std::vector<std::string> held;
  for (const game::ActivePowerup& a : match.powerups())
    if (a.player == int(k)) held.push_back(a.name);
  push_strings(L, held);
  lua_setfield(L, -2, "powerups");
}

void push_powerup(lua_State* L, const game::Match& match, const game::ActivePowerup& p) {
  lua_createtable(L, 0, int(p.params.size()) + 3);
  for (const auto& [key, value] : p.params) set(L, key.c_str(), value);
  set(L, "name", p.name);
  set(L, "player", match.players()[size_t(p.player)].name);
  set(L, "remaining", std::max(0.0, p.until - match.time()));
}

std::map<std::string, double> numbers_of(lua_State* L, int index) {
  std::map<std::string, double> out;
  if (!lua_istable(L, index)) return out;
  lua_pushnil(L);
  while (lua_next(L, index)) {
    if (lua_type(L, -2) == LUA_TSTRING && lua_type(L, -1) == LUA_TNUMBER) out[lua_tostring(L, -2)] = lua_tonumber(L, -1);
    lua_pop(L, 1);
  }
  return out;
}

}  // namespace quantum::lua

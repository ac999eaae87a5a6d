// The game's values as Lua tables, one shape everywhere scripts see them (sport rules,
// modifiers, the rule-spec scenario API), and C++ errors as Lua errors.
#pragma once

#include <lua.hpp>

#include <map>
#include <string>
#include <vector>

#include "game/game.h"

namespace quantum::lua {

void push_strings(lua_State* L, const std::vector<std::string>& list);  // {"a", "b", ...}
void push_score(lua_State* L, const std::map<std::string, int>& score);  // {blue = 2, red = 1}
// {type, actor, team, by, by_team, t, p, p_newtonian, particles, x, y, vx, vy, speed, powerup}
void push_event(lua_State* L, const game::GameEvent& e);
// {name, team, x, y, vx, vy, speed, handicap, powerups = {names}} of player k of the match
void push_player(lua_State* L, const game::Match& match, size_t k);
// {name, player, remaining, <params>} of an active power-up
void push_powerup(lua_State* L, const game::Match& match, const game::ActivePowerup& p);
// A table of numbers {key = value} from the table at `index`; non-numbers are skipped.
std::map<std::string, double> numbers_of(lua_State* L, int index);
// {kind, actor, team, favours, via, path = {...}, mass, tweaked, count}
void push_fate(lua_State* L, const game::FateView& f);

// Runs f (returning the number of results); an exception from the C++ side becomes a Lua error
// at the script's line. The message is copied out first: luaL_error does not return.
template <class F>
int guarded(lua_State* L, F&& f) {
  std::string error;
  try {
    return f();
  } catch (const std::exception& e) {
    error = e.what();
  }
  return luaL_error(L, "%s", error.c_str());
}

}  // namespace quantum::lua

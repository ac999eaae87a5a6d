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
// {type, actor, team, by, by_team, t, p, p_newtonian, particles, speed}
void push_event(lua_State* L, const game::GameEvent& e);
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

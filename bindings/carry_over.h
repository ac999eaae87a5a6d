// What a reload carries over: a sport's `state` table, copied from the old version's Lua state
// into the new one's as plain data (numbers, strings, booleans, tables), within bounds.
// ScriptedRules::take_over hands it to the new version's on_reload.
#pragma once

#include <lua.hpp>

#include <string>

namespace quantum::lua {

// Pushes onto `to` a copy of the `state` field of the table at registry reference `sport` in
// `from`: nil for none. Functions and the like belong to the old scripts and are left out. Runs
// under `to`'s budget (Sandbox::check_budget). A state past kMaxValues values or nested more than
// kMaxDepth tables deep, or one `to` has no memory for, is refused whole rather than carried over
// in part: then nil is pushed and the reason returned; "" when it was copied.
std::string copy_state(lua_State* from, int sport, lua_State* to);

}  // namespace quantum::lua

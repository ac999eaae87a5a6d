// Lua library functions whose work a count hook cannot see, replaced in a sandbox by bounded ones.
//
// LuaJIT's pattern functions run in C: a backtracking pattern (".-.-.-.-b" over a few thousand
// characters) runs for minutes without one Lua instruction, and string.gsub calling a function
// that calls string.gsub again recurses on the C stack until the process dies. Here find, match,
// gmatch and gsub are Lua 5.1's patterns matched again by hand (the one way to count their work):
// every step of the matcher counts against the sandbox's budget, and callbacks nest at most
// Sandbox::kMostNested deep. table.sort, table.concat, tonumber, string.upper, lower, reverse and
// rep are charged for their length before they run. xpcall's handler does not run once the
// budget is spent (LuaJIT would call a failing handler forever).
#pragma once

#include <lua.hpp>

namespace quantum::lua {

// Replaces string.find, match, gmatch, gsub, upper, lower, reverse and rep, table.sort and
// concat, tonumber and xpcall in L's libraries (so in the string metatable's methods too). L
// must be a Sandbox's state.
void install_bounded(lua_State* L);

}  // namespace quantum::lua

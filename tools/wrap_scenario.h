// The `quantum` table of the rule-spec runner: quantum.scenario(...) and quantum.chi_square_p(...).
#pragma once

#include <lua.hpp>

namespace quantum::lua {

// Sets the global `quantum` in L (a trusted state: the spec runner's).
void open_scenario(lua_State* L);

}  // namespace quantum::lua

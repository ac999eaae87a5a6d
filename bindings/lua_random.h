// Each script's own random numbers. LuaJIT keeps one generator per Lua state, and a sport, its
// modules and its power-ups share a state: a power-up's factor calling math.randomseed(12345)
// made the sport's math.random() give the same numbers at every event. In a sandbox every script
// environment has a math.random and math.randomseed of its own, over a generator of its own, so
// no script can change the numbers another draws (docs/lua-api.md, "What scripts may use").
//
// A script's stream starts at its first draw, from the seed of the match being played
// (Sandbox::set_seed) and the script's name: the same match seed gives the same numbers, and two
// scripts draw different ones. Drawn while files load, before any match, it starts from seed 0,
// and it starts again from the match's seed once one is played. math.randomseed(x) starts it
// from x alone, as Lua's does, and the match's seed no longer moves it.
#pragma once

#include <lua.hpp>

#include <string>

namespace quantum::lua {

// The name a script's stream is seeded with: its folder and file ("airhockey/sport.lua",
// "powerups/penalty.lua"), the same wherever the sport is installed or a replay copied it.
std::string stream_name(const std::string& file);

// Sets `math` in the script environment at stack index `env`: read-only, Lua's math library but
// for random and randomseed, which draw from a generator of the environment's own, seeded with
// `name`. L must be a Sandbox's state.
void set_own_math(lua_State* L, int env, const std::string& name);

}  // namespace quantum::lua

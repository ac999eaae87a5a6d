// The game's values as Lua tables, one shape everywhere scripts see them (sport rules,
// modifiers, power-ups, the rule-spec scenario API).
//
// Fates, and the players and power-ups handed to power-up factors, are seen many times a frame;
// their tables come from a TablePool and are refilled in place, so a frame makes no Lua garbage.
// A script that wants to keep one past its call copies what it needs.
#pragma once

#include <lua.hpp>

#include <map>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "game/game.h"
#include "phrases.h"

namespace quantum::lua {

// Scripts give angles in degrees (a throw's spread); the engine works in radians.
inline constexpr double kRadiansPerDegree = std::numbers::pi / 180;

// The engine reads and writes scripts' tables raw: a table a script was handed may have been
// given a metatable, and its code must not run inside the engine's work, which the sandbox never
// abandons half done (lua_sandbox.h).
// Pushes t[key] of the table at `index`.
void raw_field(lua_State* L, int index, const char* key);
// t[key] = the value on top (popped), for the table below it.
void raw_set(lua_State* L, const char* key);

void push_strings(lua_State* L, std::span<const std::string> list);  // {"a", "b", ...}
void push_score(lua_State* L, const std::map<std::string, int>& score);  // {blue = 2, red = 1}
// {name, bounds = {{x0, y0}, {x1, y1}}, ball_radius, friction, goals = {{name, team, from, to}},
// spots = {{name, team, at}}, areas = {{name, team, from, to, radius}}, players = {{name, team,
// role, reach, catches}}, walls = {names}}: the field as game.field() gives it.
void push_field(lua_State* L, const Field& field);
// {type, actor, team, by, by_team, previous, previous_team, holder, t, p, p_newtonian, particles,
//  x, y, vx, vy, speed, powerup}: a fresh table (handlers may keep events)
void push_event(lua_State* L, const game::GameEvent& e);
// A phrase placeholder's value from the Lua table at `vars` (a string, a number or a boolean), or
// none. Strings stay valid while the table is on the stack.
std::optional<PhraseValue> phrase_value(lua_State* L, int vars, std::string_view name);
// A table of numbers {key = value} from the table at `index`; non-numbers are skipped.
std::map<std::string, double> numbers_of(lua_State* L, int index);

// Tables kept in the registry and handed out again: push(L, k) pushes the k-th, made on first use.
class TablePool {
 public:
  void push(lua_State* L, size_t k);

 private:
  int ref_ = LUA_NOREF;
};

// Fill the table at the top of the stack (fields it had before are overwritten).
// {kind, actor, team, favours, via, path = {walls...}, mass, tweaked, count}
void fill_fate(lua_State* L, const game::FateView& f, const Field& field);
// {name, team, role, area, holds, x, y, vx, vy, speed, handicap, skill, reach_height, turn,
// powerups = {names}} of player k of the match (skill nil for a person, reach_height nil on a
// flat field)
void fill_player(lua_State* L, const game::Match& match, size_t k);
// A fresh list of every player's table, in the field's order (game.players()).
void push_players(lua_State* L, const game::Match& match);
// {name, player, remaining, <params>} of an active power-up
void fill_powerup(lua_State* L, const game::Match& match, const game::ActivePowerup& p);

}  // namespace quantum::lua

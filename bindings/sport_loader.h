// Loading a sport written in Lua: rules/<sport>/sport.lua runs in the sport's sandbox and what it
// returns is checked, key by key, into a game::SportSpec (field, match settings, handicaps,
// phrases, audio). What the scripts do while a match runs is scripted_rules.h's. The keys and
// their bounds are documented in docs/lua-api.md.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "game/sport_spec.h"
#include "lua_sandbox.h"
#include "params.h"

namespace quantum::lua {

// What loading sport.lua and the modules it requires may spend before a match: a second of CPU,
// as a field file gets (on a slow machine, or under the sanitizers, loading alone passed a
// frame's 20 ms). A reload loads between two frames of a running match: Limits{}, a frame's
// (ScriptedRules::reload).
inline constexpr Limits kLoadLimits{64u << 20, 100'000'000, 1.0};

// Where a sport's scripts come from. `folder` holds sport.lua (lexically normal); `engine` is
// where the engine's own power-ups and helpers are (a replay uses the copy it recorded).
struct SportFolders {
  SportFolders(const std::string& folder, const std::filesystem::path& engine);
  std::string folder;
  std::filesystem::path engine;
  // Where power-up scripts are looked for, in order: the sport's own powerups/, the one beside
  // the sport's folder, the engine's.
  std::vector<std::filesystem::path> powerups;
  // Where require() looks for the sport's Lua modules: the sport's folder, the engine's helpers.
  std::vector<std::filesystem::path> modules;
};

// Runs `where`'s sport.lua in `sandbox` (made with `where.modules`, its budget set) with `params`
// installed, and checks what it returns into `spec`: the field file it names is loaded (in a
// sandbox of its own), unless `playing` is given (a reload joins the match's field, which it
// keeps). Returns the registry reference of the table sport.lua returned. Throws ScriptError
// naming the file (and line, or the place in the table), FieldError for a bad field, and
// std::invalid_argument for a parameter no script reads.
int load_sport(Sandbox& sandbox, Params& params, const SportFolders& where, const Field* playing, game::SportSpec& spec);

}  // namespace quantum::lua

#include "spec.h"

#include <lua.hpp>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "scripted_rules.h"
#include "wrap_scenario.h"

namespace quantum::tools {

int run_specs(const std::vector<std::string>& given) {
  // A checkout's specs by default, else the engine's own (an installed engine run from anywhere).
  std::vector<std::string> paths = given;
  if (paths.empty()) paths.push_back(std::filesystem::is_directory("rules") ? "rules" : lua::engine_rules_folder().string());
  for (std::string& p : paths) {
    if (std::filesystem::exists(p)) continue;
    if (lua::is_sport_name(p)) {
      try {
        p = lua::find_sport(p).string();  // a sport by name: its specs
        continue;
      } catch (const std::invalid_argument& e) {
        std::cerr << "quantum test: " << e.what() << '\n';
        return 1;
      }
    }
    std::cerr << "quantum test: " << p << ": no such file or folder\n";
    return 1;
  }
  lua_State* L = luaL_newstate();
  if (!L) throw std::runtime_error("cannot create a Lua state");
  luaL_openlibs(L);
  lua::open_scenario(L);
  // Specs anywhere on disk may require the engine's spec helpers (rules/spec_helpers.lua).
  lua_getglobal(L, "package");
  lua_getfield(L, -1, "path");
  const std::string path = (lua::engine_rules_folder() / "?.lua").string() + ";" + lua_tostring(L, -1);
  lua_pop(L, 1);
  lua_pushstring(L, path.c_str());
  lua_setfield(L, -2, "path");
  lua_pop(L, 1);
  // busted reads its command line from the global `arg`.
  lua_createtable(L, int(paths.size()) + 2, 1);
  lua_pushstring(L, "quantum test");
  lua_rawseti(L, -2, 0);
  lua_pushstring(L, "--output=quantum_spec_output");
  lua_rawseti(L, -2, 1);
  for (size_t i = 0; i < paths.size(); ++i) {
    lua_pushstring(L, paths[i].c_str());
    lua_rawseti(L, -2, int(i + 2));
  }
  lua_setglobal(L, "arg");
  // busted's own dots and failure report, with each spec file's name and result as it runs.
  // busted would end the process itself with the number of failures; its exit is caught so
  // that every command of quantum's exits alike (0 ok, 2 failed specs).
  const char* boot =
      "local ok, compatibility = pcall(require, 'busted.compatibility')\n"
      "if not ok then error('busted is not installed (Debian package lua-busted): ' .. compatibility, 0) end\n"
      "compatibility.exit = function(code) error({ quantum_exit = code }, 0) end  -- before the runner keeps it\n"
      "local runner = require 'busted.runner'\n"
      "package.preload.quantum_spec_output = function() return function(options)\n"
      "  local busted = require 'busted'\n"
      "  local plain = require 'busted.outputHandlers.plainTerminal'(options)\n"
      "  local specs, failed = 0, 0\n"
      "  busted.subscribe({ 'file', 'start' }, function(file)\n"
      "    specs, failed = 0, 0; io.write(file.name, ' '); io.flush(); return nil, true end)\n"
      "  busted.subscribe({ 'test', 'end' }, function(element, parent, status)\n"
      "    specs = specs + 1\n"
      "    if status == 'failure' or status == 'error' then failed = failed + 1 end\n"
      "    return nil, true end)\n"
      "  busted.subscribe({ 'file', 'end' }, function(file)\n"
      "    io.write(failed == 0 and ' ok' or (' FAILED ' .. failed .. ' of'), ' ', specs, ' specs\\n'); io.flush()\n"
      "    return nil, true end)\n"
      "  return plain\n"
      "end end\n"
      "local ran, err = pcall(runner, { standalone = false })\n"
      "if ran then return 0 end\n"
      "if type(err) == 'table' and err.quantum_exit then return err.quantum_exit end\n"
      "error(err, 0)\n";
  const auto started = std::chrono::steady_clock::now();
  int status = luaL_loadbuffer(L, boot, std::strlen(boot), "=quantum test");
  if (status == 0) status = lua_pcall(L, 0, 1, 0);
  if (status != 0) {
    std::cerr << "quantum test: " << (lua_tostring(L, -1) ? lua_tostring(L, -1) : "error") << '\n';
    lua_close(L);
    return 1;
  }
  const int failures = int(lua_tointeger(L, -1));
  lua_close(L);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::cout << "quantum test: " << (failures == 0 ? "every spec passed" : std::to_string(failures) + " failed")
            << " in " << std::fixed << std::setprecision(1) << seconds << " s\n";
  return failures == 0 ? 0 : 2;
}

}  // namespace quantum::tools

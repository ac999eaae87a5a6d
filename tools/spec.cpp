#include "spec.h"

#include <lua.hpp>

#include <cstring>
#include <filesystem>
#include <iostream>

#include "sport.h"
#include "wrap_scenario.h"

namespace quantum::tools {

int run_specs(const std::vector<std::string>& given) {
  const std::vector<std::string> paths = given.empty() ? std::vector<std::string>{"rules"} : given;
  for (const std::string& p : paths)
    if (!std::filesystem::exists(p)) {
      std::cerr << "quantum test: " << p << ": no such file or folder\n";
      return 2;
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
  lua_pushstring(L, "--output=plainTerminal");
  lua_rawseti(L, -2, 1);
  for (size_t i = 0; i < paths.size(); ++i) {
    lua_pushstring(L, paths[i].c_str());
    lua_rawseti(L, -2, int(i + 2));
  }
  lua_setglobal(L, "arg");
  const char* boot = "local ok, runner = pcall(require, 'busted.runner')\n"
                     "if not ok then error('busted is not installed (Debian package lua-busted): ' .. runner, 0) end\n"
                     "runner({ standalone = false })\n";
  int status = luaL_loadbuffer(L, boot, std::strlen(boot), "=quantum test");
  if (status == 0) status = lua_pcall(L, 0, 0, 0);
  if (status != 0) {
    std::cerr << "quantum test: " << (lua_tostring(L, -1) ? lua_tostring(L, -1) : "error") << '\n';
    lua_close(L);
    return 1;
  }
  lua_close(L);
  return 0;  // busted exits the process itself when a spec failed
}

}  // namespace quantum::tools

#include "lua_sandbox.h"

#include <luajit.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "lua_wrap.h"

namespace quantum::lua {
namespace {

int require_module(lua_State* L) {
  upvalue_self<Sandbox>(L).require_module(check_string(L, 1));
  return 1;
}

}  // namespace

void* Sandbox::alloc(void* ud, void* ptr, size_t old_size, size_t new_size) {
  auto* budget = static_cast<Budget*>(ud);
  if (new_size == 0) {
    budget->used -= old_size;
    std::free(ptr);
    return nullptr;
  }
  if (ptr == nullptr) old_size = 0;
  if (new_size > old_size && budget->used + (new_size - old_size) > budget->limit) return nullptr;
  ++budget->calls;
  void* p = std::realloc(ptr, new_size);
  if (p) budget->used = budget->used + new_size - old_size;
  return p;
}

void Sandbox::on_budget_spent(lua_State* L, lua_Debug*) { luaL_error(L, "script runs too long (endless loop?)"); }

Sandbox::Sandbox(size_t memory_budget, int instruction_budget, bool rules,
                 std::vector<std::filesystem::path> module_folders)
    : instructions_(instruction_budget), module_folders_(std::move(module_folders)) {
  budget_.limit = memory_budget;
  L_ = lua_newstate(alloc, &budget_);
  if (!L_) L_ = luaL_newstate();  // builds whose allocator cannot be replaced: no memory cap
  if (!L_) throw std::runtime_error("cannot create a Lua state");
  luaL_openlibs(L_);
  // Count hooks do not fire inside compiled traces, so the budget needs the interpreter. Rules
  // run a few times a second; the JIT would not pay for itself. (After openlibs: opening the
  // jit library switches it back on.)
  luaJIT_setmode(L_, 0, LUAJIT_MODE_ENGINE | LUAJIT_MODE_OFF);
  lua_newtable(L_);
  const int env = lua_gettop(L_);
  const char* base[] = {"assert", "error",    "ipairs", "next",   "pairs",  "pcall",  "select", "tonumber",
                        "tostring", "type", "unpack", "rawequal", "rawget", "rawset", "setmetatable",
                        "getmetatable", "xpcall", "print"};
  for (const char* name : base) {
    lua_getglobal(L_, name);
    lua_setfield(L_, env, name);
  }
  for (const char* name : {"math", "string", "table"}) {
    lua_getglobal(L_, name);
    lua_setfield(L_, env, name);
  }
  // Of os, only its clock: a rule may time itself, never touch the machine.
  lua_newtable(L_);
  lua_getglobal(L_, "os");
  lua_getfield(L_, -1, "clock");
  lua_setfield(L_, -3, "clock");
  lua_pop(L_, 1);
  lua_setfield(L_, env, "os");
  if (rules) {
    push_module(L_, "", {{"require", guard<lua::require_module>}}, this);
    lua_getfield(L_, -1, "require");
    lua_setfield(L_, env, "require");
    lua_pop(L_, 1);
    lua_newtable(L_);
    modules_ = luaL_ref(L_, LUA_REGISTRYINDEX);
  }
  lua_pushvalue(L_, env);
  lua_setfield(L_, env, "_G");
  env_ = luaL_ref(L_, LUA_REGISTRYINDEX);
}

std::filesystem::path find_in(const std::vector<std::filesystem::path>& folders, const std::filesystem::path& relative,
                              std::string& looked) {
  for (const std::filesystem::path& folder : folders) {
    const std::filesystem::path file = folder / relative;
    if (!looked.empty()) looked += ", ";
    looked += file.string();
    if (std::filesystem::is_regular_file(file)) return file;
  }
  return {};
}

void Sandbox::require_module(const std::string& name) {
  namespace fs = std::filesystem;
  bool valid = !name.empty() && name.front() != '.' && name.back() != '.' && name.find("..") == std::string::npos;
  for (char c : name) valid &= (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '.';
  if (!valid)
    throw ScriptError("'" + name + "' is not a module name: lower-case words joined by dots, e.g. 'util' or 'lib.util'");
  lua_rawgeti(L_, LUA_REGISTRYINDEX, modules_);
  lua_getfield(L_, -1, name.c_str());
  if (!lua_isnil(L_, -1)) {
    lua_remove(L_, -2);
    return;
  }
  lua_pop(L_, 2);
  std::string relative = name;
  std::replace(relative.begin(), relative.end(), '.', '/');
  relative += ".lua";
  std::string looked;
  if (const fs::path file = find_in(module_folders_, relative, looked); !file.empty()) {
    run_file(file.string());
    if (lua_isnil(L_, -1)) {  // a module that returns nothing is loaded all the same
      lua_pop(L_, 1);
      lua_pushboolean(L_, 1);
    }
    lua_rawgeti(L_, LUA_REGISTRYINDEX, modules_);
    lua_pushvalue(L_, -2);
    lua_setfield(L_, -2, name.c_str());
    lua_pop(L_, 1);
    return;
  }
  throw ScriptError("no module '" + name + "': the sandbox loads only the sport's own Lua modules (" +
                    (looked.empty() ? std::string("no folders") : looked) +
                    "); Lua's own libraries beyond math, string, table and os.clock, and native modules, are "
                    "not available to rules");
}

Sandbox::~Sandbox() { lua_close(L_); }

void Sandbox::push_environment() const { lua_rawgeti(L_, LUA_REGISTRYINDEX, env_); }

bool Sandbox::call(int nargs, int nresults, std::string& error) {
  // A call made from inside another (game.grant running a power-up's start from a handler)
  // spends the outer call's budget; only the outermost arms and disarms it.
  if (depth_++ == 0) lua_sethook(L_, on_budget_spent, LUA_MASKCOUNT, instructions_);
  const int status = lua_pcall(L_, nargs, nresults, 0);
  if (--depth_ == 0) lua_sethook(L_, nullptr, 0, 0);
  if (status == 0) return true;
  const char* m = lua_tostring(L_, -1);
  error = m ? m : (status == LUA_ERRMEM ? "not enough memory" : "error object is not a string");
  lua_pop(L_, 1);
  return false;
}

void Sandbox::run_file(const std::string& file) {
  if (!std::filesystem::exists(file)) throw ScriptError(file + ": no such file");
  files_.push_back(file);
  const int status = luaL_loadfilex(L_, file.c_str(), "t");
  if (status != 0) {
    std::string m = lua_tostring(L_, -1) ? lua_tostring(L_, -1) : "not enough memory";
    lua_pop(L_, 1);
    if (m.find("wrong mode") != std::string::npos)
      m = file + ": binary chunk (precompiled bytecode) refused: scripts must be Lua text";
    throw ScriptError(m.rfind(file, 0) == 0 ? m : file + ": " + m);
  }
  lua_rawgeti(L_, LUA_REGISTRYINDEX, env_);
  lua_setfenv(L_, -2);
  std::string error;
  if (!call(0, 1, error)) throw ScriptError(error.rfind(file, 0) == 0 ? error : file + ": " + error);
}

}  // namespace quantum::lua

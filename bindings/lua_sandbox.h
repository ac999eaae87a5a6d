// A Lua state for designer scripts: text only, a memory cap, an instruction budget per call, and
// only the libraries a rule needs. Field files and sports both run in one.
#pragma once

#include <lua.hpp>

#include <cstddef>
#include <stdexcept>
#include <string>

namespace quantum::lua {

struct ScriptError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Sandbox {
 public:
  // `libraries`: which of Lua's own go into the scripts' environment besides the base
  // functions: "math" always; "string" and "table" when `rules` is true (sports need them,
  // field files are data), and os.clock. No io, the rest of os, debug, package, ffi, jit,
  // require, load, loadstring, dofile or collectgarbage.
  Sandbox(size_t memory_budget, int instruction_budget, bool rules);
  ~Sandbox();
  Sandbox(const Sandbox&) = delete;
  Sandbox& operator=(const Sandbox&) = delete;

  lua_State* L() const { return L_; }

  // Loads `file` as Lua text with the sandbox as its environment and runs it; leaves its one
  // result on the stack. Throws ScriptError "file:line: message" (or "file: message").
  void run_file(const std::string& file);

  // lua_pcall with the instruction budget armed; on failure returns the message and pops it.
  bool call(int nargs, int nresults, std::string& error);

 private:
  struct Budget {
    size_t used = 0, limit = 0;
  };
  static void* alloc(void* ud, void* ptr, size_t old_size, size_t new_size);
  static void on_budget_spent(lua_State* L, lua_Debug*);

  Budget budget_;
  lua_State* L_ = nullptr;
  int env_ = LUA_NOREF;
  int instructions_;
  int depth_ = 0;  // calls in progress (a handler's game.grant calls into the script again)
};

}  // namespace quantum::lua

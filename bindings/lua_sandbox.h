// A Lua state for designer scripts: text only, a memory cap, an instruction budget per call, and
// only the libraries a rule needs. Field files and sports both run in one.
#pragma once

#include <lua.hpp>

#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace quantum::lua {

struct ScriptError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The first of `folders` holding `relative` (a file), or an empty path when none does. `looked`
// gets every place tried, for an error message.
std::filesystem::path find_in(const std::vector<std::filesystem::path>& folders, const std::filesystem::path& relative,
                              std::string& looked);

class Sandbox {
 public:
  // Of Lua's own libraries the scripts get the base functions, math, string, table and
  // os.clock: no io, the rest of os, debug, package, ffi, jit, load, loadstring, dofile or
  // collectgarbage. With `rules` (sports, not field files), `require` loads the script's own
  // Lua modules, as text, from `module_folders` only (see require_module).
  Sandbox(size_t memory_budget, int instruction_budget, bool rules,
          std::vector<std::filesystem::path> module_folders = {});
  ~Sandbox();
  Sandbox(const Sandbox&) = delete;
  Sandbox& operator=(const Sandbox&) = delete;

  lua_State* L() const { return L_; }
  // Pushes the scripts' environment table (to add a global of the caller's, like `param`).
  void push_environment() const;

  // Loads `file` as Lua text with the sandbox as its environment and runs it; leaves its one
  // result on the stack. Throws ScriptError "file:line: message" (or "file: message").
  void run_file(const std::string& file);

  // lua_pcall with the instruction budget armed; on failure returns the message and pops it.
  bool call(int nargs, int nresults, std::string& error);

  // require(name) for scripts: "util" or "lib.util" is util.lua or lib/util.lua in the first
  // module folder that has it, loaded once (as text, in the sandbox) and its result kept.
  // Pushes the result. Throws ScriptError for a bad name, a module that is not there (saying
  // that the sandbox looks only in its folders) or one that fails.
  void require_module(const std::string& name);

  // Every Lua allocation, freeing and resizing so far: the tests' measure of the garbage a frame
  // makes.
  size_t allocations() const { return budget_.calls; }

  // Every file run so far (run_file, and the modules require loaded), in order.
  const std::vector<std::string>& files() const { return files_; }

 private:
  struct Budget {
    size_t used = 0, limit = 0, calls = 0;
  };
  static void* alloc(void* ud, void* ptr, size_t old_size, size_t new_size);
  static void on_budget_spent(lua_State* L, lua_Debug*);

  Budget budget_;
  lua_State* L_ = nullptr;
  int env_ = LUA_NOREF;
  int instructions_;
  int depth_ = 0;  // calls in progress (a handler's game.grant calls into the script again)
  std::vector<std::filesystem::path> module_folders_;
  int modules_ = LUA_NOREF;  // name -> result of every module loaded
  std::vector<std::string> files_;
};

}  // namespace quantum::lua

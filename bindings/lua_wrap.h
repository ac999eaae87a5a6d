// The one way C++ is exposed to Lua (after LÖVE's luax_* helpers). Two kinds of API, one style:
//
//  - a module is a table of functions called with a dot: `game.say("goal")`, `quantum.scenario(...)`;
//  - an object made by a module function is a userdata whose methods are called with a colon:
//    `s:run(1.0)`.
//
// Every function goes through guard<F>: a C++ exception thrown by F (bad arguments included, see
// the arg helpers) becomes a Lua error at the calling script's file and line, naming the
// function: "rules/x/sport.lua:12: game.respawn: no spot or team 'bleu' in this field". A dot
// used for a colon, or the other way round, is the same kind of error, saying which to use. In a
// sandbox, a call once the budget is spent is the budget's error: the call does not run.
#pragma once

#include <lua.hpp>

#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace quantum::lua {

// A script called a function the wrong way; the guard names the function and the line.
struct ArgError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

class Sandbox;

namespace wrap_detail {
// False, with the error message pushed, when the function was called in the wrong style.
bool style_ok(lua_State* L);
// Pushes "where: name: message", the error the guard raises.
void push_error(lua_State* L, const char* message);
// A call from a script into the engine. In a sandbox it checks the budget first (a spent budget
// is the error, before the function runs), then tells the sandbox that its scripts wait for the
// engine until the call returns or raises (Sandbox::enter_engine).
class EngineCall {
 public:
  explicit EngineCall(lua_State* L);
  ~EngineCall();
  EngineCall(const EngineCall&) = delete;
  EngineCall& operator=(const EngineCall&) = delete;

 private:
  Sandbox* sandbox_;
};
}  // namespace wrap_detail

// Calls F with the guard described above. F returns its number of results, like a lua_CFunction.
// lua_error is raised only once no C++ object of this frame is alive.
template <int (*F)(lua_State*)>
int guard(lua_State* L) {
  if (!wrap_detail::style_ok(L)) return lua_error(L);
  int results = -1;
  {
    const wrap_detail::EngineCall engine(L);
    try {
      results = F(L);
    } catch (const std::exception& e) {
      wrap_detail::push_error(L, e.what());
    }
  }
  return results >= 0 ? results : lua_error(L);
}

struct Function {
  const char* name;
  lua_CFunction call;  // guard<f>
};

// Pushes a module table: `prefix.name` for each function, each seeing `self` (upvalue_self). The
// table is read-only to scripts (an assignment is an error naming the module).
void push_module(lua_State* L, const char* prefix, std::initializer_list<Function> functions, void* self);
// Makes the empty table at `proxy` a read-only view of the table at `contents`: reads go
// through, an assignment is an error naming `name`, and its metatable is protected. Scripts that
// share a Lua state share these tables (`game`, the libraries), so none may change them for the
// others; the contents stay reachable only to C++.
void seal(lua_State* L, int proxy, int contents, const char* name);
// Whether the table at `index` is sealed (the sandbox's rawset refuses those).
bool is_read_only(lua_State* L, int index);
// Registers the metatable of a userdata type whose methods are called as `object:name(...)`;
// `gc` (may be null) runs when the object is collected.
void register_type(lua_State* L, const char* type, std::initializer_list<Function> methods, lua_CFunction gc);

// Inside a module function: the `self` its module was made with.
template <class T>
T& upvalue_self(lua_State* L) {
  return *static_cast<T*>(lua_touserdata(L, lua_upvalueindex(3)));
}
// Inside a method: the object (argument 1), a T* boxed in the userdata (null once collected).
template <class T>
T* object(lua_State* L) {
  return *static_cast<T**>(lua_touserdata(L, 1));
}

// Argument readers: each throws ArgError naming the argument ("argument 2: expected a number,
// got string"). Indices are the script's own (1 is the first argument it wrote).
std::string check_string(lua_State* L, int arg);
// The same without a copy: valid while the argument is on the stack.
std::string_view check_view(lua_State* L, int arg);
double check_number(lua_State* L, int arg);
double opt_number(lua_State* L, int arg, double fallback);
std::optional<std::string> opt_string(lua_State* L, int arg);
void check_table(lua_State* L, int arg);
// The argument's position as the script counts it: for a method, `self` is not counted.
int script_arg(lua_State* L, int arg);

}  // namespace quantum::lua

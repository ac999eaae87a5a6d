#include "lua_wrap.h"

#include "lua_sandbox.h"

#include <string_view>

namespace quantum::lua {

// Upvalues of every wrapped function: 1 its display name ("game.say", "scenario:run"); 2 the
// module table for a module function, or the type's metatable name for a method; 3 the module's
// `self` (modules only).

namespace wrap_detail {

void push_error(lua_State* L, const char* message) {
  // The match names its own calls for C++ callers ("award: ..."): after "game.award: " that
  // would say the name twice.
  const std::string_view name = lua_tostring(L, lua_upvalueindex(1)), text = message;
  const std::string_view own = name.substr(name.find_last_of(".:") + 1);
  if (text.size() > own.size() + 2 && text.starts_with(own) && text.substr(own.size(), 2) == ": ")
    message += own.size() + 2;
  luaL_where(L, 1);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_pushstring(L, ": ");
  lua_pushstring(L, message);
  lua_concat(L, 4);
}

bool style_ok(lua_State* L) {
  const int how = lua_upvalueindex(2);
  if (lua_istable(L, how) ? !lua_rawequal(L, 1, how) : luaL_testudata(L, 1, lua_tostring(L, how)) != nullptr)
    return true;
  const std::string name = lua_tostring(L, lua_upvalueindex(1));
  const std::string advice = lua_istable(L, how)
                                 ? "call it with a dot, " + name + "(...), not a colon"
                                 : "a method: call it with a colon on the object, e.g. s:" +
                                       name.substr(name.find(':') + 1) + "(...)";
  push_error(L, advice.c_str());
  return false;
}

EngineCall::EngineCall(lua_State* L) : sandbox_(Sandbox::enter_engine(L)) {}
EngineCall::~EngineCall() {
  if (sandbox_) sandbox_->leave_engine();
}

}  // namespace wrap_detail

namespace {

// __newindex of a module: every key of the proxy is absent, so every assignment lands here.
int refuse_write(lua_State* L) {
  luaL_where(L, 1);
  lua_pushfstring(L, "%s is read-only: scripts share it, so none may change it for the others (assigning '%s')",
                  lua_tostring(L, lua_upvalueindex(1)), lua_tostring(L, 2) ? lua_tostring(L, 2) : luaL_typename(L, 2));
  lua_concat(L, 2);
  return lua_error(L);
}

}  // namespace

void seal(lua_State* L, int proxy, int contents, const char* name) {
  const auto absolute = [L](int index) { return index > 0 ? index : lua_gettop(L) + index + 1; };
  proxy = absolute(proxy), contents = absolute(contents);
  lua_createtable(L, 0, 3);
  lua_pushvalue(L, contents);
  lua_setfield(L, -2, "__index");
  lua_pushstring(L, name);
  lua_pushcclosure(L, refuse_write, 1);
  lua_setfield(L, -2, "__newindex");
  lua_pushstring(L, "read-only");
  lua_setfield(L, -2, "__metatable");
  lua_setmetatable(L, proxy);
}

void push_module(lua_State* L, const char* prefix, std::initializer_list<Function> functions, void* self) {
  // The functions live in a hidden table behind the empty proxy scripts see (seal).
  lua_newtable(L);
  const int proxy = lua_gettop(L);
  lua_createtable(L, 0, int(functions.size()));
  const int module = lua_gettop(L);
  for (const Function& f : functions) {
    lua_pushstring(L, (*prefix ? std::string(prefix) + "." + f.name : std::string(f.name)).c_str());
    lua_pushvalue(L, proxy);  // what a colon call passes first: style_ok compares with it
    lua_pushlightuserdata(L, self);
    lua_pushcclosure(L, f.call, 3);
    lua_setfield(L, module, f.name);
  }
  seal(L, proxy, module, *prefix ? prefix : "this module");
  lua_pop(L, 1);
}

bool is_read_only(lua_State* L, int index) {
  if (!lua_getmetatable(L, index)) return false;
  lua_getfield(L, -1, "__newindex");
  const bool read_only = lua_tocfunction(L, -1) == refuse_write;
  lua_pop(L, 2);
  return read_only;
}

void register_type(lua_State* L, const char* type, std::initializer_list<Function> methods, lua_CFunction gc) {
  luaL_newmetatable(L, type);
  if (gc) {
    lua_pushcfunction(L, gc);
    lua_setfield(L, -2, "__gc");
  }
  lua_createtable(L, 0, int(methods.size()));
  for (const Function& m : methods) {
    lua_pushstring(L, (std::string(type) + ":" + m.name).c_str());
    lua_pushstring(L, type);
    lua_pushcclosure(L, m.call, 2);
    lua_setfield(L, -2, m.name);
  }
  lua_setfield(L, -2, "__index");
  lua_pop(L, 1);
}

int script_arg(lua_State* L, int arg) { return lua_isstring(L, lua_upvalueindex(2)) ? arg - 1 : arg; }

namespace {

[[noreturn]] void wrong(lua_State* L, int arg, const char* expected) {
  throw ArgError("argument " + std::to_string(script_arg(L, arg)) + ": expected " + expected + ", got " +
                 luaL_typename(L, arg));
}

}  // namespace

std::string_view check_view(lua_State* L, int arg) {
  size_t n = 0;
  const char* s = lua_type(L, arg) == LUA_TSTRING || lua_type(L, arg) == LUA_TNUMBER ? lua_tolstring(L, arg, &n) : nullptr;
  if (!s) wrong(L, arg, "a string");
  return {s, n};
}

std::string check_string(lua_State* L, int arg) { return std::string(check_view(L, arg)); }

double check_number(lua_State* L, int arg) {
  if (lua_type(L, arg) != LUA_TNUMBER) wrong(L, arg, "a number");
  return lua_tonumber(L, arg);
}

double opt_number(lua_State* L, int arg, double fallback) {
  return lua_isnoneornil(L, arg) ? fallback : check_number(L, arg);
}

std::optional<std::string> opt_string(lua_State* L, int arg) {
  if (lua_isnoneornil(L, arg)) return std::nullopt;
  return check_string(L, arg);
}

void check_table(lua_State* L, int arg) {
  if (!lua_istable(L, arg)) wrong(L, arg, "a table");
}

}  // namespace quantum::lua

#include "carry_over.h"

#include "lua_push.h"
#include "lua_sandbox.h"

namespace quantum::lua {
namespace {

// Copies sport.state from the old version's Lua state into the new one's. Recursive in C, so the
// nesting is bounded (a chain of tables 10^5 deep would overflow the C and Lua stacks); a state
// past a limit is refused whole rather than carried over in part.
struct PlainCopy {
  static constexpr int kMaxValues = 100000;
  static constexpr int kMaxDepth = 100;
  lua_State* from;
  lua_State* to;
  int seen;  // index in `to` of a table: from's table pointer -> its copy
  int values = 0;
  int depth = 0;

  // Raised in `to`, which runs this under lua_cpcall: `from` never raises (lua_next and the
  // pushes below cannot, and lua_checkstack reports rather than raises).
  void copy(int index) {
    index = index < 0 ? lua_gettop(from) + index + 1 : index;
    Sandbox::check_budget(to);
    if (++values > kMaxValues)
      luaL_error(to, "sport.state holds more than %d values", kMaxValues);
    switch (lua_type(from, index)) {
      case LUA_TBOOLEAN: lua_pushboolean(to, lua_toboolean(from, index)); return;
      case LUA_TNUMBER: lua_pushnumber(to, lua_tonumber(from, index)); return;
      case LUA_TSTRING: {
        size_t n = 0;
        const char* text = lua_tolstring(from, index, &n);
        lua_pushlstring(to, text, n);
        return;
      }
      case LUA_TTABLE: break;
      default: lua_pushnil(to); return;  // functions and the like belong to the old script
    }
    lua_pushlightuserdata(to, const_cast<void*>(lua_topointer(from, index)));
    lua_rawget(to, seen);
    if (!lua_isnil(to, -1)) return;
    if (depth == kMaxDepth) luaL_error(to, "sport.state nests tables more than %d deep", kMaxDepth);
    if (!lua_checkstack(from, 4) || !lua_checkstack(to, 6)) luaL_error(to, "not enough memory");
    ++depth;
    lua_pop(to, 1);
    lua_newtable(to);
    lua_pushlightuserdata(to, const_cast<void*>(lua_topointer(from, index)));
    lua_pushvalue(to, -2);
    lua_rawset(to, seen);
    lua_pushnil(from);
    while (lua_next(from, index)) {
      const int key = lua_type(from, -2);
      if (key == LUA_TSTRING || key == LUA_TNUMBER) {
        copy(-2);
        copy(-1);
        if (lua_isnil(to, -2)) lua_pop(to, 2);
        else lua_rawset(to, -3);
      }
      lua_pop(from, 1);
    }
    --depth;
  }

  // Under lua_cpcall on `to`: running out of the new sandbox's memory is an error, not a panic.
  static int run(lua_State* L) {
    auto* c = static_cast<PlainCopy*>(lua_touserdata(L, 1));
    lua_settop(L, 0);
    lua_newtable(L);
    c->seen = lua_gettop(L);
    c->copy(-1);
    lua_remove(L, c->seen);
    lua_setfield(L, LUA_REGISTRYINDEX, "quantum.reload_state");  // out of the protected call
    return 0;
  }
};

}  // namespace

std::string copy_state(lua_State* from, int sport, lua_State* to) {
  const int from_top = lua_gettop(from);
  lua_rawgeti(from, LUA_REGISTRYINDEX, sport);
  raw_field(from, lua_gettop(from), "state");
  PlainCopy copy{from, to, 0};
  std::string error;
  if (lua_cpcall(to, PlainCopy::run, &copy) != 0) {
    error = lua_tostring(to, -1) ? lua_tostring(to, -1) : "error";
    lua_pop(to, 1);
    lua_pushnil(to);
  } else {
    lua_getfield(to, LUA_REGISTRYINDEX, "quantum.reload_state");
    lua_pushnil(to);
    lua_setfield(to, LUA_REGISTRYINDEX, "quantum.reload_state");
  }
  lua_settop(from, from_top);
  return error;
}

}  // namespace quantum::lua

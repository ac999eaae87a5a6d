#include "lua_random.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <new>
#include <optional>
#include <system_error>
#include <type_traits>

#include "lua_sandbox.h"
#include "lua_wrap.h"
#include "quantum/noise.h"

namespace quantum::lua {
namespace {

// One environment's generator: a full userdata, the upvalue its random and randomseed share.
struct Stream {
  uint64_t name;                      // FNV-1a of the environment's name
  std::optional<DecisionRng> rng;     // none until the first draw
  std::optional<uint64_t> from;       // the match seed it started from (none: before a match)
  bool own = false;                   // started by the script's math.randomseed
};
static_assert(std::is_trivially_destructible_v<Stream>, "a Lua userdata without __gc");

Stream& stream_of(lua_State* L) { return *static_cast<Stream*>(lua_touserdata(L, lua_upvalueindex(1))); }

// A number in [0, 1), the stream (re)started first when the match's seed is not the one it
// started from.
double draw(lua_State* L) {
  Stream& s = stream_of(L);
  const std::optional<uint64_t>& seed = Sandbox::of(L).seed();
  if (!s.own && (!s.rng || s.from != seed)) {
    s.rng.emplace(seed.value_or(0) * 0x9E3779B97F4A7C15ull + s.name);
    s.from = seed;
  }
  return s.rng->uniform();
}

// Lua 5.1's math.random: random() in [0, 1), random(m) a whole number in [1, m], random(m, n) one
// in [m, n].
int random(lua_State* L) {
  const double r = draw(L);
  switch (lua_gettop(L)) {
    case 0: lua_pushnumber(L, r); return 1;
    case 1: {
      const double high = std::floor(luaL_checknumber(L, 1));
      luaL_argcheck(L, 1 <= high, 1, "interval is empty");
      lua_pushnumber(L, std::floor(r * high) + 1);
      return 1;
    }
    case 2: {
      const double low = std::floor(luaL_checknumber(L, 1)), high = std::floor(luaL_checknumber(L, 2));
      luaL_argcheck(L, low <= high, 2, "interval is empty");
      lua_pushnumber(L, std::floor(r * (high - low + 1)) + low);
      return 1;
    }
    default: return luaL_error(L, "wrong number of arguments");
  }
}

// math.randomseed(x): this script's stream starts again from x alone (every bit of it).
int randomseed(lua_State* L) {
  const double x = luaL_checknumber(L, 1);
  uint64_t bits = 0;
  std::memcpy(&bits, &x, sizeof bits);
  Stream& s = stream_of(L);
  s.rng.emplace(bits);
  s.own = true;
  return 0;
}

}  // namespace

std::string stream_name(const std::string& file) {
  std::error_code error;
  const std::filesystem::path p = std::filesystem::absolute(file, error).lexically_normal();
  return (p.parent_path().filename() / p.filename()).generic_string();
}

void set_own_math(lua_State* L, int env, const std::string& name) {
  env = env > 0 ? env : lua_gettop(L) + env + 1;
  lua_newtable(L);  // the proxy scripts see
  lua_createtable(L, 0, 32);
  const int contents = lua_gettop(L);
  lua_getglobal(L, "math");  // Lua's own: no script reaches the state's globals
  for (lua_pushnil(L); lua_next(L, -2);) {
    lua_pushvalue(L, -2);
    lua_insert(L, -2);
    lua_rawset(L, contents);
  }
  lua_pop(L, 1);
  auto* s = new (lua_newuserdata(L, sizeof(Stream))) Stream{};
  s->name = 1469598103934665603ull;
  for (const char c : name) s->name = (s->name ^ uint8_t(c)) * 1099511628211ull;
  lua_pushvalue(L, -1);
  lua_pushcclosure(L, random, 1);
  lua_setfield(L, contents, "random");
  lua_pushcclosure(L, randomseed, 1);
  lua_setfield(L, contents, "randomseed");
  seal(L, -2, -1, "math");
  lua_pop(L, 1);
  lua_setfield(L, env, "math");
}

}  // namespace quantum::lua

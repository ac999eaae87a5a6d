#include "field_loader.h"

#include "lua_sandbox.h"

#include <filesystem>
#include <set>
#include <string>

namespace quantum::lua {
namespace {

// A field file is data: a runaway loop or a memory bomb in it is a mistake to report, not a hang.
constexpr int kInstructionBudget = 10'000'000;
constexpr size_t kMemoryBudget = 64u << 20;

// Walks the returned table, naming every place it looks at.
class Reader {
 public:
  Reader(lua_State* L) : L(L) {}

  [[noreturn]] void fail(const std::string& place, const std::string& message) { throw FieldError(place, message); }

  std::string type_at(int idx) { return luaL_typename(L, idx); }

  // Reports keys of the table at idx that are not in `known` (a typo would otherwise be ignored).
  void only_keys(int idx, const std::string& place, std::initializer_list<const char*> known) {
    std::set<std::string> allowed(known.begin(), known.end());
    lua_pushnil(L);
    while (lua_next(L, idx)) {
      lua_pop(L, 1);
      if (lua_type(L, -1) != LUA_TSTRING) continue;  // array parts are checked by their readers
      const std::string key = lua_tostring(L, -1);
      if (!allowed.count(key)) {
        std::string list;
        for (const char* k : known) {
          if (!list.empty()) list += ", ";
          list += k;
        }
        lua_pop(L, 1);
        fail(place, "unknown key '" + key + "' (known: " + list + ")");
      }
    }
  }

  // Pushes t[key]; returns false (and pushes nothing) when it is nil.
  bool field(int idx, const char* key) {
    lua_getfield(L, idx, key);
    if (lua_isnil(L, -1)) {
      lua_pop(L, 1);
      return false;
    }
    return true;
  }

  float number(int idx, const char* key, const std::string& place, float fallback, bool required) {
    if (!field(idx, key)) {
      if (required) fail(place, std::string("missing '") + key + "'");
      return fallback;
    }
    if (lua_type(L, -1) != LUA_TNUMBER) fail(place + "." + key, "expected a number, got " + type_at(-1));
    const float v = float(lua_tonumber(L, -1));
    lua_pop(L, 1);
    return v;
  }

  std::string string(int idx, const char* key, const std::string& place, const std::string& fallback, bool required) {
    if (!field(idx, key)) {
      if (required) fail(place, std::string("missing '") + key + "'");
      return fallback;
    }
    if (lua_type(L, -1) != LUA_TSTRING) fail(place + "." + key, "expected a string, got " + type_at(-1));
    std::string v = lua_tostring(L, -1);
    lua_pop(L, 1);
    return v;
  }

  // A point is {x, y} (or {x = .., y = ..}) at the top of the stack; pops it.
  Vec2 point(const std::string& place) {
    if (!lua_istable(L, -1)) fail(place, "expected a point {x, y}, got " + type_at(-1));
    const int t = lua_gettop(L);
    Vec2 p;
    const char* names[2] = {"x", "y"};
    for (int k = 0; k < 2; ++k) {
      lua_rawgeti(L, t, k + 1);
      if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        lua_getfield(L, t, names[k]);
      }
      if (lua_type(L, -1) != LUA_TNUMBER)
        fail(place, std::string("expected a number for ") + names[k] + ", got " + type_at(-1));
      (k == 0 ? p.x : p.y) = float(lua_tonumber(L, -1));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    return p;
  }

  Vec2 point_at(int idx, const char* key, const std::string& place) {
    if (!field(idx, key)) fail(place, std::string("missing '") + key + "'");
    return point(place + "." + key);
  }

  // Calls each(i, place) with entry i of the array t[key] on top of the stack; the entry must be a table.
  template <class Each>
  void array(int idx, const char* key, const std::string& place, Each each) {
    if (!field(idx, key)) return;
    if (!lua_istable(L, -1)) fail(place + key, "expected a list, got " + type_at(-1));
    const int list = lua_gettop(L);
    const size_t n = lua_objlen(L, list);
    for (size_t i = 1; i <= n; ++i) {
      lua_rawgeti(L, list, int(i));
      const std::string here = place + key + "[" + std::to_string(i) + "]";
      if (!lua_istable(L, -1)) fail(here, "expected a table, got " + type_at(-1));
      each(lua_gettop(L), here);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }

  lua_State* L;
};

Field read_field(Reader& r, int top) {
  lua_State* L = r.L;
  Field f;
  r.only_keys(top, "field", {"name", "ball", "brownian", "max_body_speed", "walls", "goals", "spots", "bodies", "bounds"});
  f.name = r.string(top, "name", "field", "unnamed field", false);
  f.brownian = r.number(top, "brownian", "field", f.brownian, false);
  f.max_body_speed = r.number(top, "max_body_speed", "field", f.max_body_speed, false);
  if (r.field(top, "ball")) {
    if (!lua_istable(L, -1)) r.fail("ball", "expected a table, got " + r.type_at(-1));
    const int b = lua_gettop(L);
    r.only_keys(b, "ball", {"radius", "wall_restitution", "body_restitution", "audible_bounce"});
    f.ball_radius = r.number(b, "radius", "ball", f.ball_radius, false);
    f.wall_restitution = r.number(b, "wall_restitution", "ball", f.wall_restitution, false);
    f.body_restitution = r.number(b, "body_restitution", "ball", f.body_restitution, false);
    f.audible_bounce = r.number(b, "audible_bounce", "ball", f.audible_bounce, false);
    lua_pop(L, 1);
  }
  r.array(top, "walls", "", [&](int w, const std::string& place) {
    r.only_keys(w, place, {"name", "points"});
    const std::string name = r.string(w, "name", place, "wall " + place.substr(5), false);
    int id = 0;
    while (id < int(f.wall_names.size()) && f.wall_names[id] != name) ++id;
    if (id == int(f.wall_names.size())) f.wall_names.push_back(name);
    if (!r.field(w, "points")) r.fail(place, "missing 'points'");
    if (!lua_istable(L, -1)) r.fail(place + ".points", "expected a list of points, got " + r.type_at(-1));
    const int pts = lua_gettop(L);
    const size_t n = lua_objlen(L, pts);
    if (n < 2) r.fail(place + ".points", "a wall needs at least 2 points, got " + std::to_string(n));
    Vec2 prev;
    for (size_t i = 1; i <= n; ++i) {
      lua_rawgeti(L, pts, int(i));
      const Vec2 p = r.point(place + ".points[" + std::to_string(i) + "]");
      if (i > 1) f.segments.push_back({prev, p, id});
      prev = p;
    }
    lua_pop(L, 1);
  });
  r.array(top, "goals", "", [&](int g, const std::string& place) {
    r.only_keys(g, place, {"name", "team", "from", "to"});
    Goal goal;
    goal.team = r.string(g, "team", place, "", true);
    goal.name = r.string(g, "name", place, goal.team + " goal", false);
    goal.a = r.point_at(g, "from", place);
    goal.b = r.point_at(g, "to", place);
    f.goals.push_back(goal);
  });
  r.array(top, "spots", "", [&](int s, const std::string& place) {
    r.only_keys(s, place, {"name", "team", "at"});
    Spot spot;
    spot.team = r.string(s, "team", place, "", false);
    spot.name = r.string(s, "name", place, "spot " + place.substr(5), false);
    spot.at = r.point_at(s, "at", place);
    f.spots.push_back(spot);
  });
  r.array(top, "bodies", "", [&](int b, const std::string& place) {
    r.only_keys(b, place, {"name", "team", "radius", "at"});
    BodySpec body;
    body.team = r.string(b, "team", place, "", true);
    body.name = r.string(b, "name", place, body.team + " body", false);
    body.radius = r.number(b, "radius", place, 0, true);
    body.start = r.point_at(b, "at", place);
    f.bodies.push_back(body);
  });
  if (r.field(top, "bounds")) {
    if (!lua_istable(L, -1) || lua_objlen(L, -1) != 2) r.fail("bounds", "expected two corners { {x0, y0}, {x1, y1} }");
    const int b = lua_gettop(L);
    lua_rawgeti(L, b, 1);
    f.bounds_min = r.point("bounds[1]");
    lua_rawgeti(L, b, 2);
    f.bounds_max = r.point("bounds[2]");
    f.has_bounds = true;
    lua_pop(L, 1);
  }
  return f;
}

}  // namespace

std::string field_file(const std::string& path) {
  return std::filesystem::is_directory(path) ? (std::filesystem::path(path) / "field.lua").string() : path;
}

Field load_field(const std::string& path) {
  const std::string file = field_file(path);
  if (!std::filesystem::exists(file)) throw FieldError(file, "no such field file");
  Sandbox sandbox(kMemoryBudget, kInstructionBudget, false);
  lua_State* L = sandbox.L();
  try {
    sandbox.run_file(file);
  } catch (const ScriptError& e) {
    // Lua's own messages start with "file:line:".
    throw FieldError("", e.what());
  }
  if (!lua_istable(L, -1)) throw FieldError(file, std::string("must return a table, returned ") + luaL_typename(L, -1));
  Reader reader(L);
  try {
    Field f = read_field(reader, lua_gettop(L));
    finish_field(f);
    return f;
  } catch (const FieldError& e) {
    throw FieldError(e.place.empty() ? file : file + ": " + e.place, e.message);
  }
}

}  // namespace quantum::lua

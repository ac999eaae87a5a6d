#include "lua_push.h"

#include <algorithm>
#include <cmath>

#include "lua_sandbox.h"

namespace quantum::lua {

void raw_field(lua_State* L, int index, const char* key) {
  if (index < 0 && index > LUA_REGISTRYINDEX) index = lua_gettop(L) + index + 1;
  lua_pushstring(L, key);
  lua_rawget(L, index);
}

void raw_set(lua_State* L, const char* key) {
  lua_pushstring(L, key);
  lua_insert(L, -2);
  lua_rawset(L, -3);
}

namespace {

void set(lua_State* L, const char* key, std::string_view value) {
  lua_pushlstring(L, value.data(), value.size());
  raw_set(L, key);
}

void set(lua_State* L, const char* key, double value) {
  lua_pushnumber(L, value);
  raw_set(L, key);
}

// Pushes t[key] of the table on top, a new empty table put there first when it has none.
void subtable(lua_State* L, const char* key) {
  raw_field(L, -1, key);
  if (lua_istable(L, -1)) return;
  lua_pop(L, 1);
  lua_newtable(L);
  lua_pushstring(L, key);
  lua_pushvalue(L, -2);
  lua_rawset(L, -4);
}

// Makes the list on top hold exactly `n` entries, set by put(i) (which pushes entry i, 0-based).
template <class Put>
void refill_list(lua_State* L, size_t n, Put put) {
  const size_t old = lua_objlen(L, -1);
  for (size_t i = 0; i < n; ++i) {
    put(i);
    lua_rawseti(L, -2, int(i + 1));
  }
  for (size_t i = old; i > n; --i) {
    lua_pushnil(L);
    lua_rawseti(L, -2, int(i));
  }
}

}  // namespace

void push_strings(lua_State* L, std::span<const std::string> list) {
  lua_createtable(L, int(list.size()), 0);
  for (size_t i = 0; i < list.size(); ++i) {
    lua_pushlstring(L, list[i].data(), list[i].size());
    lua_rawseti(L, -2, int(i + 1));
  }
}

void push_score(lua_State* L, const std::map<std::string, int>& score) {
  lua_createtable(L, 0, int(score.size()));
  for (const auto& [team, goals] : score) {
    lua_pushinteger(L, goals);
    raw_set(L, team.c_str());
  }
}

void push_event(lua_State* L, const game::GameEvent& e) {
  lua_createtable(L, 0, 18);
  set(L, "type", game::to_string(e.type)), set(L, "actor", e.actor), set(L, "team", e.team);
  set(L, "by", e.by), set(L, "by_team", e.by_team);
  set(L, "previous", e.previous), set(L, "previous_team", e.previous_team), set(L, "holder", e.holder);
  set(L, "t", e.t), set(L, "p", e.p), set(L, "p_newtonian", e.p_newtonian), set(L, "particles", double(e.particles));
  set(L, "x", e.at.x), set(L, "y", e.at.y), set(L, "vx", e.velocity.x), set(L, "vy", e.velocity.y);
  set(L, "speed", std::hypot(e.velocity.x, e.velocity.y));
  if (!e.powerup.empty()) set(L, "powerup", e.powerup);
}

namespace {

void push_point(lua_State* L, Vec2 p) {
  lua_createtable(L, 2, 0);
  lua_pushnumber(L, p.x);
  lua_rawseti(L, -2, 1);
  lua_pushnumber(L, p.y);
  lua_rawseti(L, -2, 2);
}

void set_point(lua_State* L, const char* key, Vec2 p) {
  push_point(L, p);
  raw_set(L, key);
}

// A list of `items`, each a table filled by fill(item).
template <class Items, class Fill>
void set_list(lua_State* L, const char* key, const Items& items, Fill fill) {
  lua_createtable(L, int(items.size()), 0);
  for (size_t i = 0; i < items.size(); ++i) {
    lua_newtable(L);
    fill(items[i]);
    lua_rawseti(L, -2, int(i + 1));
  }
  raw_set(L, key);
}

// { {x0, y0}, {x1, y1} }: a rectangle as field files give it.
void push_corners(lua_State* L, Vec2 low, Vec2 high) {
  lua_createtable(L, 2, 0);
  push_point(L, low);
  lua_rawseti(L, -2, 1);
  push_point(L, high);
  lua_rawseti(L, -2, 2);
}

}  // namespace

void push_field(lua_State* L, const Field& f) {
  lua_newtable(L);
  set(L, "name", f.name);
  push_corners(L, f.bounds_min, f.bounds_max);
  raw_set(L, "bounds");
  set(L, "ball_radius", f.ball_radius), set(L, "friction", f.friction);
  set_list(L, "goals", f.goals, [&](const Goal& g) {
    set(L, "name", g.name), set(L, "team", g.team), set_point(L, "from", g.a), set_point(L, "to", g.b);
  });
  set_list(L, "spots", f.spots, [&](const Spot& s) { set(L, "name", s.name), set(L, "team", s.team), set_point(L, "at", s.at); });
  set_list(L, "areas", f.areas, [&](const Area& a) {
    set(L, "name", a.name), set(L, "team", a.team), set_point(L, "from", a.a), set_point(L, "to", a.b);
    set(L, "radius", a.radius);
    lua_pushboolean(L, a.box);  // from and to are a rectangle's corners
    raw_set(L, "box");
  });
  set_list(L, "players", f.bodies, [&](const BodySpec& b) {
    set(L, "name", b.name), set(L, "team", b.team), set(L, "role", b.role), set(L, "reach", b.radius);
    set_point(L, "at", b.start);  // where it starts: a formation's place
    // `reach` is the radius (how far the hands get); with height, how high they get standing.
    if (f.has_height()) set(L, "reach_height", f.reach_of(int(&b - f.bodies.data())));
    lua_pushboolean(L, b.catches);
    raw_set(L, "catches");
    lua_pushboolean(L, b.hits);
    raw_set(L, "hits");
    lua_pushboolean(L, b.kicks);
    raw_set(L, "kicks");
    if (b.zoned) {
      push_corners(L, b.zone_min, b.zone_max);
      raw_set(L, "zone");
    }
  });
  push_strings(L, f.wall_names);
  raw_set(L, "walls");
}

void TablePool::push(lua_State* L, size_t k) {
  if (ref_ == LUA_NOREF) {
    lua_newtable(L);
    ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
  }
  lua_rawgeti(L, LUA_REGISTRYINDEX, ref_);
  lua_rawgeti(L, -1, int(k + 1));
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    lua_newtable(L);
    lua_pushvalue(L, -1);
    lua_rawseti(L, -3, int(k + 1));
  }
  lua_remove(L, -2);
  // The sport's modifiers and every power-up's factor are handed the same tables: a metatable one
  // of them set must not run when the engine fills the table, or when the next script reads it.
  lua_pushnil(L);
  lua_setmetatable(L, -2);
}

void fill_fate(lua_State* L, const game::FateView& f, const Field& field) {
  set(L, "kind", f.kind()), set(L, "actor", f.actor), set(L, "team", f.team), set(L, "favours", f.favours);
  // Built on the stack: Lua interns the text, and a text seen before costs nothing.
  char via[256];
  set(L, "via", std::string_view(via, write_via(f.fate, field, via, sizeof via)));
  set(L, "mass", f.mass), set(L, "tweaked", f.tweaked), set(L, "count", double(f.count));
  // A pooled table may hold another fate's player: one that ends at no player has none.
  if (at_body(f.fate.kind)) lua_pushlstring(L, f.actor.data(), f.actor.size());
  else lua_pushnil(L);
  raw_set(L, "player");
  lua_pushboolean(L, f.contact);
  raw_set(L, "contact");
  subtable(L, "path");
  refill_list(L, f.fate.path_len, [&](size_t i) {
    const std::string& wall = field.wall_names[f.fate.path[i]];
    lua_pushlstring(L, wall.data(), wall.size());
  });
  lua_pop(L, 1);
}

void fill_player(lua_State* L, const game::Match& match, size_t k) {
  const game::Player& p = match.players()[k];
  set(L, "name", p.name), set(L, "team", p.team);
  set(L, "x", p.position.x), set(L, "y", p.position.y), set(L, "vx", p.velocity.x), set(L, "vy", p.velocity.y);
  set(L, "speed", std::hypot(p.velocity.x, p.velocity.y));
  set(L, "handicap", match.handicap_now(int(k)));
  // A pooled table may hold another player's: what this player lacks is cleared, not left.
  if (p.skill) lua_pushnumber(L, *p.skill);
  else lua_pushnil(L);
  raw_set(L, "skill");
  if (match.field().has_height()) lua_pushnumber(L, match.world().reach(int(k)));
  else lua_pushnil(L);
  raw_set(L, "reach_height");
  lua_pushboolean(L, p.turn);
  raw_set(L, "turn");
  // Numbers, not a table: a pooled frame's players allocate nothing.
  if (p.place) lua_pushnumber(L, p.place->x);
  else lua_pushnil(L);
  raw_set(L, "place_x");
  if (p.place) lua_pushnumber(L, p.place->y);
  else lua_pushnil(L);
  raw_set(L, "place_y");
  const BodySpec& body = match.field().bodies[k];
  set(L, "role", body.role);
  const int area = match.field().area_at(p.position);
  set(L, "area", area < 0 ? std::string_view() : std::string_view(match.field().areas[size_t(area)].name));
  lua_pushboolean(L, match.holder() == int(k));
  raw_set(L, "holds");
  subtable(L, "powerups");
  size_t held = 0;
  for (const game::ActivePowerup& a : match.powerups()) held += a.player == int(k);
  size_t next = 0;
  refill_list(L, held, [&](size_t) {
    while (match.powerups()[next].player != int(k)) ++next;
    const std::string& name = match.powerups()[next++].name;
    lua_pushlstring(L, name.data(), name.size());
  });
  lua_pop(L, 1);
}

void push_players(lua_State* L, const game::Match& match) {
  lua_createtable(L, int(match.players().size()), 0);
  for (size_t i = 0; i < match.players().size(); ++i) {
    lua_newtable(L);
    fill_player(L, match, i);
    lua_rawseti(L, -2, int(i + 1));
  }
}

void fill_powerup(lua_State* L, const game::Match& match, const game::ActivePowerup& p) {
  // A pooled table may have held another power-up's numbers: none of them may linger. (Setting
  // a field to nil while traversing is allowed, and the key's slot stays for the next fill.)
  lua_pushnil(L);
  while (lua_next(L, -2)) {
    lua_pop(L, 1);
    lua_pushvalue(L, -1);
    lua_pushnil(L);
    lua_rawset(L, -4);
  }
  for (const auto& [key, value] : p.params) set(L, key.c_str(), value);
  set(L, "name", p.name);
  set(L, "player", match.players()[size_t(p.player)].name);
  set(L, "remaining", std::max(0.0, p.until - match.time()));
}

std::optional<PhraseValue> phrase_value(lua_State* L, int vars, std::string_view name) {
  if (!lua_istable(L, vars)) return std::nullopt;
  lua_pushlstring(L, name.data(), name.size());
  lua_rawget(L, vars);
  std::optional<PhraseValue> v;
  if (lua_type(L, -1) == LUA_TNUMBER) {
    v = PhraseValue{{}, lua_tonumber(L, -1)};
  } else if (lua_type(L, -1) == LUA_TSTRING) {
    size_t n = 0;
    const char* s = lua_tolstring(L, -1, &n);
    v = PhraseValue{std::string_view(s, n), std::nullopt};
  } else if (lua_type(L, -1) == LUA_TBOOLEAN) {
    v = PhraseValue{lua_toboolean(L, -1) ? "true" : "false", std::nullopt};
  }
  lua_pop(L, 1);
  return v;
}

std::map<std::string, double> numbers_of(lua_State* L, int index) {
  std::map<std::string, double> out;
  if (!lua_istable(L, index)) return out;
  lua_pushnil(L);
  while (lua_next(L, index)) {
    Sandbox::check_budget(L);
    if (lua_type(L, -2) == LUA_TSTRING && lua_type(L, -1) == LUA_TNUMBER) out[lua_tostring(L, -2)] = lua_tonumber(L, -1);
    lua_pop(L, 1);
  }
  return out;
}

}  // namespace quantum::lua


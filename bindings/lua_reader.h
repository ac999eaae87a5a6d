// Reads the tables a script returns (field.lua, sport.lua, power-ups, a spec's options) strictly:
// every place it looks at is named in its errors, an unknown key is named with the nearest known
// one (a typo is never silently ignored), and values are read raw, so a table's metamethods
// never run outside a protected call. The tables a designer also keeps data in (the sport's, its
// match, a power-up's) take any key but a near miss of the engine's.
#pragma once

#include <lua.hpp>

#include <initializer_list>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "lua_sandbox.h"
#include "quantum/field.h"
#include "quantum/limits.h"

namespace quantum::lua {

// A value where it does not belong. `place` is the path to it ("walls[2].points[3]"), `message`
// what is wrong; readers' callers prefix the file.
struct ReadError : std::runtime_error {
  ReadError(std::string place, std::string message);
  std::string place, message;
};

// The closest of `known` to `key` ("phrase" -> "phrases") when at most a third of the key is
// wrong, else "": looser than near_miss, to suggest in a message, never to refuse a key.
std::string nearest(std::string_view key, std::span<const std::string> known);
// The one of `known` that `key` is a slip of, "" when none: ignoring case, at most one slip (a
// letter added, dropped or changed, or two neighbours swapped) per four letters of the known key,
// and at most two. "On" is a near miss of "on", "phrase" of "phrases", "modifer" of "modifiers";
// "hp" and "turn_factor" are no near miss of anything.
std::string near_miss(std::string_view key, std::span<const std::string> known);
// "unknown key 'phrase' (did you mean 'phrases'? known: a, b, c)"
std::string unknown_key(std::string_view key, std::span<const std::string> known, std::string_view what = "key");

class Reader {
 public:
  explicit Reader(lua_State* L) : L(L) {}

  [[noreturn]] void fail(const std::string& place, const std::string& message) const;
  // Fails naming `place` unless `range` holds `v`: "throws.speed: must be in (0, 1000] m/s, got 2000".
  void within(const std::string& place, const limits::Range& range, double v) const {
    if (!range.contains(v)) fail(place, limits::must_be_in(range, v));
  }
  std::string type_at(int idx) const { return luaL_typename(L, idx); }

  // Fails on a string key of the table at idx that is not in `known` ("unknown key 'x'", or
  // "unknown event 'x'" with what = "event"). Array entries are left to their readers.
  void only_keys(int idx, const std::string& place, std::initializer_list<const char*> known) const;
  void only_keys(int idx, const std::string& place, std::span<const std::string> known,
                 std::string_view what = "key") const;
  // Fails on a string key of the table at idx that is a near miss of one in `known`; any other
  // key is the script's own, kept for its functions to read.
  void no_near_misses(int idx, const std::string& place, std::span<const std::string> known) const;

  // Pushes t[key] (raw); false, and nothing pushed, when it is nil.
  bool field(int idx, const char* key) const;
  // The value at the top must be of `type` (LUA_TTABLE, ...); fails naming `place` otherwise.
  void expect(int type, const std::string& place, const char* what = nullptr) const;

  double number(int idx, const char* key, const std::string& place, double fallback, bool required) const;
  // A whole number from lo to hi at t[key] (fallback when nil), or the one at the top of the stack
  // (left there): a script's 1e300 or 2.5 fails here, naming the range, instead of reaching an int.
  int whole(int idx, const char* key, const std::string& place, int fallback, int lo, int hi) const;
  int whole_at_top(const std::string& place, int lo, int hi) const;
  std::string string(int idx, const char* key, const std::string& place, const std::string& fallback,
                     bool required) const;
  bool boolean(int idx, const char* key, const std::string& place, bool fallback) const;
  // A point is {x, y} (or {x = .., y = ..}) at the top of the stack; pops it.
  Vec2 point(const std::string& place) const;
  Vec2 point_at(int idx, const char* key, const std::string& place) const;

  // Calls each(i, place) with entry i of the list t[key] on top of the stack; each entry must be
  // a table. A list of more than `most` entries fails before any entry is read.
  template <class Each>
  void array(int idx, const char* key, const std::string& place, size_t most, Each each) const {
    if (!field(idx, key)) return;
    const std::string here = place.empty() ? key : place + "." + key;
    expect(LUA_TTABLE, here, "a list");
    const int list = lua_gettop(L);
    const size_t n = lua_objlen(L, list);
    if (n > most) fail(here, std::to_string(n) + " entries, more than the " + std::to_string(most) + " allowed");
    for (size_t i = 1; i <= n; ++i) {
      lua_rawgeti(L, list, int(i));
      const std::string entry = here + "[" + std::to_string(i) + "]";
      expect(LUA_TTABLE, entry);
      each(lua_gettop(L), entry);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }

  // Fails when the table at idx has more than `most` entries: checked before any is read.
  void at_most(int idx, const std::string& place, size_t most) const;

  // Calls each(key, place) with t[key] on top of the stack for every string key of the map at
  // idx (in no particular order); a key that is not a string fails.
  template <class Each>
  void map(int idx, const std::string& place, Each each) const {
    idx = absolute(idx);
    lua_pushnil(L);
    while (lua_next(L, idx)) {
      Sandbox::check_budget(L);
      if (lua_type(L, -2) != LUA_TSTRING) fail(place, "expected names as keys, got a " + type_at(-2));
      const std::string key = lua_tostring(L, -2);
      each(key, place + "." + key);
      lua_pop(L, 1);
    }
  }

  lua_State* const L;

 private:
  void check_keys(int idx, const std::string& place, std::span<const std::string> known, std::string_view what,
                  bool own_keys) const;
  int absolute(int idx) const { return idx > 0 || idx <= LUA_REGISTRYINDEX ? idx : lua_gettop(L) + idx + 1; }
};

}  // namespace quantum::lua

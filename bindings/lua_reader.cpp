#include "lua_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "quantum/narrow.h"

namespace quantum::lua {

ReadError::ReadError(std::string p, std::string m)
    : std::runtime_error(p.empty() ? m : p + ": " + m), place(std::move(p)), message(std::move(m)) {}

namespace {

// Optimal string alignment distance, ignoring case: how many letters added, dropped or changed,
// or neighbours swapped, turn one into the other. A swap is one slip of the fingers, not two.
size_t slips(std::string_view a, std::string_view b) {
  const auto same = [](char x, char y) { return std::tolower((unsigned char)x) == std::tolower((unsigned char)y); };
  std::vector<size_t> before(b.size() + 1), row(b.size() + 1), next(b.size() + 1);
  std::iota(row.begin(), row.end(), size_t(0));
  for (size_t i = 1; i <= a.size(); ++i) {
    next[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      next[j] = std::min({row[j] + 1, next[j - 1] + 1, row[j - 1] + (same(a[i - 1], b[j - 1]) ? 0 : 1)});
      if (i > 1 && j > 1 && same(a[i - 1], b[j - 2]) && same(a[i - 2], b[j - 1]))
        next[j] = std::min(next[j], before[j - 2] + 1);
    }
    std::swap(before, row);
    std::swap(row, next);
  }
  return row[b.size()];
}

}  // namespace

std::string nearest(std::string_view key, std::span<const std::string> known) {
  std::string best;
  size_t best_distance = 0;
  for (const std::string& k : known) {
    const size_t d = slips(key, k);
    if (best.empty() || d < best_distance) best = k, best_distance = d;
  }
  // Worth suggesting: at most a third of the key wrong.
  return best_distance <= std::max<size_t>(2, key.size() / 3) ? best : std::string();
}

std::string near_miss(std::string_view key, std::span<const std::string> known) {
  std::string best;
  size_t best_slips = 0;
  for (const std::string& k : known) {
    // A typist slips per letter typed. In two or three letters one change makes another word (ox
    // beside on), so only case counts; from four letters one slip (phrase), from eight two (modifer).
    const size_t allowed = std::min<size_t>(2, k.size() / 4);
    // A slip changes the length by one at most: a key further off is no near miss, unmeasured.
    if (key.size() > k.size() + allowed || k.size() > key.size() + allowed) continue;
    const size_t d = slips(key, k);
    if (d <= allowed && (best.empty() || d < best_slips)) best = k, best_slips = d;
  }
  return best;
}

std::string unknown_key(std::string_view key, std::span<const std::string> known, std::string_view what) {
  std::string list;
  for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
  // A key refused as a slip names the key it is a slip of.
  std::string near = near_miss(key, known);
  if (near.empty()) near = nearest(key, known);
  return "unknown " + std::string(what) + " '" + std::string(key) + "' (" +
         (near.empty() ? "" : "did you mean '" + near + "'? ") + "known: " + (list.empty() ? "none" : list) + ")";
}

void Reader::fail(const std::string& place, const std::string& message) const { throw ReadError(place, message); }

void Reader::only_keys(int idx, const std::string& place, std::initializer_list<const char*> known) const {
  const std::vector<std::string> names(known.begin(), known.end());
  only_keys(idx, place, names);
}

void Reader::only_keys(int idx, const std::string& place, std::span<const std::string> known,
                       std::string_view what) const {
  check_keys(idx, place, known, what, false);
}

void Reader::no_near_misses(int idx, const std::string& place, std::span<const std::string> known) const {
  check_keys(idx, place, known, "key", true);
}

void Reader::check_keys(int idx, const std::string& place, std::span<const std::string> known, std::string_view what,
                        bool own_keys) const {
  idx = absolute(idx);
  lua_pushnil(L);
  while (lua_next(L, idx)) {
    Sandbox::check_budget(L);
    lua_pop(L, 1);
    if (lua_type(L, -1) != LUA_TSTRING) continue;  // array parts are checked by their readers
    const std::string key = lua_tostring(L, -1);
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    if (own_keys && near_miss(key, known).empty()) continue;
    lua_pop(L, 1);
    fail(place, unknown_key(key, known, what) +
                    (own_keys ? "; keys of your own are welcome here, but this one looks like a typo" : ""));
  }
}

void Reader::at_most(int idx, const std::string& place, size_t most) const {
  idx = absolute(idx);
  size_t n = 0;
  lua_pushnil(L);
  while (lua_next(L, idx)) {
    Sandbox::check_budget(L);
    lua_pop(L, 1);
    if (++n > most) {
      lua_pop(L, 1);
      fail(place, "more than the " + std::to_string(most) + " entries allowed");
    }
  }
}

bool Reader::field(int idx, const char* key) const {
  idx = absolute(idx);
  lua_pushstring(L, key);
  lua_rawget(L, idx);
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    return false;
  }
  return true;
}

void Reader::expect(int type, const std::string& place, const char* what) const {
  if (lua_type(L, -1) == type) return;
  fail(place, std::string("expected ") + (what ? what : std::string("a ") + lua_typename(L, type)) + ", got " + type_at(-1));
}

double Reader::number(int idx, const char* key, const std::string& place, double fallback, bool required) const {
  if (!field(idx, key)) {
    if (required) fail(place, std::string("missing '") + key + "'");
    return fallback;
  }
  expect(LUA_TNUMBER, place.empty() ? key : place + "." + key);
  const double v = lua_tonumber(L, -1);
  lua_pop(L, 1);
  return v;
}

int Reader::whole(int idx, const char* key, const std::string& place, int fallback, int lo, int hi) const {
  if (!field(idx, key)) return fallback;
  const int v = whole_at_top(place.empty() ? key : place + "." + key, lo, hi);
  lua_pop(L, 1);
  return v;
}

int Reader::whole_at_top(const std::string& place, int lo, int hi) const {
  expect(LUA_TNUMBER, place);
  const double v = lua_tonumber(L, -1);
  if (!(v >= lo && v <= hi && v == std::floor(v))) {
    char message[96];
    std::snprintf(message, sizeof message, "expected a whole number from %d to %d, got %.14g", lo, hi, v);
    fail(place, message);
  }
  return int(v);
}

std::string Reader::string(int idx, const char* key, const std::string& place, const std::string& fallback,
                           bool required) const {
  if (!field(idx, key)) {
    if (required) fail(place, std::string("missing '") + key + "'");
    return fallback;
  }
  expect(LUA_TSTRING, place.empty() ? key : place + "." + key);
  std::string v = lua_tostring(L, -1);
  lua_pop(L, 1);
  return v;
}

bool Reader::boolean(int idx, const char* key, const std::string& place, bool fallback) const {
  if (!field(idx, key)) return fallback;
  expect(LUA_TBOOLEAN, place.empty() ? key : place + "." + key);
  const bool v = lua_toboolean(L, -1);
  lua_pop(L, 1);
  return v;
}

Vec2 Reader::point(const std::string& place) const {
  if (!lua_istable(L, -1)) fail(place, "expected a point {x, y}, got " + type_at(-1));
  const int t = lua_gettop(L);
  Vec2 p;
  const char* names[2] = {"x", "y"};
  for (int k = 0; k < 2; ++k) {
    lua_rawgeti(L, t, k + 1);
    if (lua_isnil(L, -1)) {
      lua_pop(L, 1);
      lua_pushstring(L, names[k]);
      lua_rawget(L, t);
    }
    if (lua_type(L, -1) != LUA_TNUMBER)
      fail(place, std::string("expected a number for ") + names[k] + ", got " + type_at(-1));
    (k == 0 ? p.x : p.y) = to_float(lua_tonumber(L, -1));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  return p;
}

Vec2 Reader::point_at(int idx, const char* key, const std::string& place) const {
  if (!field(idx, key)) fail(place, std::string("missing '") + key + "'");
  return point(place + "." + key);
}

}  // namespace quantum::lua

#include "lua_bounded.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <string_view>

#include "lua_sandbox.h"

namespace quantum::lua {
namespace {

// Hand-written on purpose (see the header): the same patterns as Lua 5.1's manual, section 5.4.1,
// with a step counter. Nothing here allocates but Lua's own buffer.
constexpr int kMaxCaptures = 32;
constexpr int kMaxDepth = 200;          // the matcher's own recursion (captures, '?', '-', '*')
constexpr int64_t kChargeEvery = 4096;  // steps between two looks at the budget
constexpr ptrdiff_t kUnfinished = -1, kPosition = -2;
constexpr int64_t kBytesPerInstruction = 32;  // a plain search's bytes cost one instruction's time
// A whole-string function's byte costs 0.4 to 1.4 ns (LuaJIT's, measured on 30 MB), an
// instruction 1 to 2 ns: charged a byte an instruction, one call takes at most ~14 ms.
constexpr double kScannedBytesPerInstruction = 1;

struct Matcher {
  lua_State* L;
  Sandbox* sandbox;
  const char *src_init, *src_end, *p_end;
  int level = 0, depth = 0;
  int64_t steps = 0;
  struct {
    const char* init;
    ptrdiff_t len;
  } capture[kMaxCaptures];

  // A step is a character compared, or a byte of a set or a replacement scanned.
  void step(int64_t n = 1) {
    steps += n;
    if (steps >= kChargeEvery) sandbox->charge(L, steps), steps = 0;
  }
  // Charges what is left when a search ends, so short searches count too.
  void settle() { sandbox->charge(L, steps), steps = 0; }

  char at(const char* p) const { return p < p_end ? *p : '\0'; }

  const char* class_end(const char* p) const {
    if (*p++ == '%') {
      if (p >= p_end) luaL_error(L, "malformed pattern (ends with '%%')");
      return p + 1;
    }
    if (p[-1] == '[') {
      if (at(p) == '^') ++p;
      do {  // the first ']' of a set is a character of it
        if (p >= p_end) luaL_error(L, "malformed pattern (missing ']')");
        if (*p++ == '%' && p < p_end) ++p;
      } while (at(p) != ']');
      return p + 1;
    }
    return p;
  }

  static bool in_class(int c, int cl) {
    bool yes;
    switch (std::tolower(cl)) {
      case 'a': yes = std::isalpha(c); break;
      case 'c': yes = std::iscntrl(c); break;
      case 'd': yes = std::isdigit(c); break;
      case 'l': yes = std::islower(c); break;
      case 'p': yes = std::ispunct(c); break;
      case 's': yes = std::isspace(c); break;
      case 'u': yes = std::isupper(c); break;
      case 'w': yes = std::isalnum(c); break;
      case 'x': yes = std::isxdigit(c); break;
      case 'z': yes = c == 0; break;
      default: return cl == c;
    }
    return std::isupper(cl) ? !yes : yes;
  }

  // p at '[', end at its ']'.
  static bool in_set(int c, const char* p, const char* end) {
    bool sign = true;
    if (p[1] == '^') sign = false, ++p;
    while (++p < end) {
      if (*p == '%') {
        ++p;
        if (in_class(c, static_cast<unsigned char>(*p))) return sign;
      } else if (p[1] == '-' && p + 2 < end) {
        p += 2;
        if (static_cast<unsigned char>(p[-2]) <= c && c <= static_cast<unsigned char>(*p)) return sign;
      } else if (static_cast<unsigned char>(*p) == c) {
        return sign;
      }
    }
    return !sign;
  }

  bool single(const char* s, const char* p, const char* ep) {
    if (s >= src_end) return false;
    if (*p == '[') step(ep - p);  // a set is scanned whole
    const int c = static_cast<unsigned char>(*s);
    switch (*p) {
      case '.': return true;
      case '%': return in_class(c, static_cast<unsigned char>(p[1]));
      case '[': return in_set(c, p, ep - 1);
      default: return static_cast<unsigned char>(*p) == c;
    }
  }

  const char* match(const char* s, const char* p) {
    if (++depth > kMaxDepth) luaL_error(L, "pattern too complex (nested more than %d deep)", kMaxDepth);
    const char* r = match_here(s, p);
    --depth;
    return r;
  }

  const char* match_here(const char* s, const char* p) {
    for (;;) {
      step();
      if (p >= p_end) return s;
      switch (*p) {
        case '(':
          return at(p + 1) == ')' ? start_capture(s, p + 2, kPosition) : start_capture(s, p + 1, kUnfinished);
        case ')': return end_capture(s, p + 1);
        case '$':
          if (p + 1 == p_end) return s == src_end ? s : nullptr;
          break;
        case '%':
          if (at(p + 1) == 'b') {
            s = balanced(s, p + 2);
            if (!s) return nullptr;
            p += 4;
            continue;
          }
          if (at(p + 1) == 'f') {
            p += 2;
            if (at(p) != '[') luaL_error(L, "missing '[' after '%%f' in pattern");
            const char* ep = class_end(p);
            const int before = s == src_init ? 0 : static_cast<unsigned char>(s[-1]);
            const int here = s < src_end ? static_cast<unsigned char>(*s) : 0;
            if (in_set(before, p, ep - 1) || !in_set(here, p, ep - 1)) return nullptr;
            p = ep;
            continue;
          }
          if (std::isdigit(static_cast<unsigned char>(at(p + 1)))) {
            s = back_reference(s, at(p + 1));
            if (!s) return nullptr;
            p += 2;
            continue;
          }
          break;
        default: break;
      }
      const char* ep = class_end(p);
      const bool m = single(s, p, ep);
      switch (at(ep)) {
        case '?': {
          if (m) {
            if (const char* r = match(s + 1, ep + 1)) return r;
          }
          p = ep + 1;
          continue;
        }
        case '*': return longest(s, p, ep);
        case '+': return m ? longest(s + 1, p, ep) : nullptr;
        case '-': return shortest(s, p, ep);
        default:
          if (!m) return nullptr;
          ++s;
          p = ep;
      }
    }
  }

  const char* longest(const char* s, const char* p, const char* ep) {
    ptrdiff_t i = 0;
    while (single(s + i, p, ep)) ++i, step();
    for (; i >= 0; --i)
      if (const char* r = match(s + i, ep + 1)) return r;
    return nullptr;
  }

  const char* shortest(const char* s, const char* p, const char* ep) {
    for (;;) {
      if (const char* r = match(s, ep + 1)) return r;
      if (!single(s, p, ep)) return nullptr;
      ++s;
    }
  }

  const char* start_capture(const char* s, const char* p, ptrdiff_t what) {
    if (level >= kMaxCaptures) luaL_error(L, "too many captures");
    capture[level] = {s, what};
    ++level;
    const char* r = match(s, p);
    if (!r) --level;
    return r;
  }

  const char* end_capture(const char* s, const char* p) {
    int open = level - 1;
    while (open >= 0 && capture[open].len != kUnfinished) --open;
    if (open < 0) luaL_error(L, "invalid pattern capture");
    capture[open].len = s - capture[open].init;
    const char* r = match(s, p);
    if (!r) capture[open].len = kUnfinished;
    return r;
  }

  const char* balanced(const char* s, const char* p) {
    if (p + 1 >= p_end) luaL_error(L, "missing arguments to '%%b'");
    if (s >= src_end || *s != *p) return nullptr;
    int open = 1;
    while (++s < src_end) {
      step();
      if (*s == p[1]) {
        if (--open == 0) return s + 1;
      } else if (*s == *p) {
        ++open;
      }
    }
    return nullptr;
  }

  const char* back_reference(const char* s, char digit) {
    const int k = digit - '1';
    if (k < 0 || k >= level || capture[k].len == kUnfinished) luaL_error(L, "invalid capture index");
    const size_t n = size_t(capture[k].len);
    step(int64_t(n));
    if (size_t(src_end - s) >= n && std::memcmp(capture[k].init, s, n) == 0) return s + n;
    return nullptr;
  }

  void push_capture(int i, const char* s, const char* e) {
    if (i >= level) {
      if (i != 0) luaL_error(L, "invalid capture index");
      lua_pushlstring(L, s, size_t(e - s));
      return;
    }
    if (capture[i].len == kUnfinished) luaL_error(L, "unfinished capture");
    if (capture[i].len == kPosition) lua_pushinteger(L, capture[i].init - src_init + 1);
    else lua_pushlstring(L, capture[i].init, size_t(capture[i].len));
  }

  // The captures, or the whole match (s..e) when the pattern has none; s null: captures only.
  int push_captures(const char* s, const char* e) {
    const int n = level == 0 && s ? 1 : level;
    luaL_checkstack(L, n, "too many captures");
    for (int i = 0; i < n; ++i) push_capture(i, s, e);
    return n;
  }
};

Matcher matcher_for(lua_State* L, std::string_view s, std::string_view p) {
  Matcher m{L, &Sandbox::of(L), s.data(), s.data() + s.size(), p.data() + p.size(), 0, 0, 0, {}};
  return m;
}

std::string_view arg_view(lua_State* L, int arg) {
  size_t n = 0;
  const char* s = luaL_checklstring(L, arg, &n);
  return {s, n};
}

// Where a search starts: Lua's init argument (negative counts from the end), clamped.
size_t start_of(lua_State* L, int arg, size_t length) {
  ptrdiff_t init = ptrdiff_t(luaL_optinteger(L, arg, 1));
  if (init < 0) init += ptrdiff_t(length) + 1;
  return init <= 1 ? 0 : std::min(size_t(init - 1), length);
}

int find_or_match(lua_State* L, bool find) {
  const std::string_view s = arg_view(L, 1), p = arg_view(L, 2);
  const size_t init = start_of(L, 3, s.size());
  if (find && (lua_toboolean(L, 4) || p.find_first_of("^$*+?.([%-") == std::string_view::npos)) {
    Sandbox::of(L).charge(L, int64_t(s.size() - init) / kBytesPerInstruction);
    // glibc's memmem is linear (two-way); std::string_view::find may not be.
    const void* hit = p.empty() ? s.data() + init : memmem(s.data() + init, s.size() - init, p.data(), p.size());
    const size_t at = hit ? size_t(static_cast<const char*>(hit) - s.data()) : std::string_view::npos;
    if (at == std::string_view::npos) {
      lua_pushnil(L);
      return 1;
    }
    lua_pushinteger(L, lua_Integer(at + 1));
    lua_pushinteger(L, lua_Integer(at + p.size()));
    return 2;
  }
  Matcher m = matcher_for(L, s, p);
  const bool anchor = !p.empty() && p[0] == '^';
  const char* pattern = p.data() + (anchor ? 1 : 0);
  const char* from = s.data() + init;
  do {
    m.level = 0;
    if (const char* e = m.match(from, pattern)) {
      m.settle();
      if (!find) return m.push_captures(from, e);
      lua_pushinteger(L, from - s.data() + 1);
      lua_pushinteger(L, e - s.data());
      return m.push_captures(nullptr, nullptr) + 2;
    }
  } while (from++ < m.src_end && !anchor);
  m.settle();
  lua_pushnil(L);
  return 1;
}

int find(lua_State* L) { return find_or_match(L, true); }
int match(lua_State* L) { return find_or_match(L, false); }

// gmatch's iterator: upvalues are the string, the pattern and where the next search starts.
int gmatch_next(lua_State* L) {
  const std::string_view s = arg_view(L, lua_upvalueindex(1)), p = arg_view(L, lua_upvalueindex(2));
  Matcher m = matcher_for(L, s, p);
  for (const char* from = s.data() + size_t(lua_tointeger(L, lua_upvalueindex(3))); from <= m.src_end; ++from) {
    m.level = 0;
    if (const char* e = m.match(from, p.data())) {
      m.settle();
      // An empty match moves on by one, or the loop would find it forever.
      lua_pushinteger(L, (e == from ? e + 1 : e) - s.data());
      lua_replace(L, lua_upvalueindex(3));
      return m.push_captures(from, e);
    }
  }
  m.settle();
  return 0;
}

int gmatch(lua_State* L) {
  luaL_checkstring(L, 1);
  luaL_checkstring(L, 2);
  lua_settop(L, 2);
  lua_pushinteger(L, 0);
  lua_pushcclosure(L, gmatch_next, 3);
  return 1;
}

void add_replacement(Matcher& m, luaL_Buffer& b, const char* s, const char* e) {
  lua_State* L = m.L;
  switch (lua_type(L, 3)) {
    case LUA_TFUNCTION: {
      const Sandbox::Nested nested(L, *m.sandbox, "string.gsub");
      lua_pushvalue(L, 3);
      lua_call(L, m.push_captures(s, e), 1);
      break;
    }
    case LUA_TTABLE: {  // its __index may be a function that calls gsub again
      const Sandbox::Nested nested(L, *m.sandbox, "string.gsub");
      m.push_capture(0, s, e);
      lua_gettable(L, 3);
      break;
    }
    default: {  // a string: %0 the match, %1-%9 its captures, %% a percent sign
      const std::string_view r = arg_view(L, 3);
      m.step(int64_t(r.size()));
      for (size_t i = 0; i < r.size(); ++i) {
        if (r[i] != '%' || i + 1 == r.size()) {
          luaL_addchar(&b, r[i]);
          continue;
        }
        const char c = r[++i];
        if (!std::isdigit(static_cast<unsigned char>(c))) {
          luaL_addchar(&b, c);
        } else if (c == '0') {
          luaL_addlstring(&b, s, size_t(e - s));
        } else {
          m.push_capture(c - '1', s, e);
          luaL_addvalue(&b);
        }
      }
      return;
    }
  }
  if (!lua_toboolean(L, -1)) {  // nil or false keeps what matched
    lua_pop(L, 1);
    lua_pushlstring(L, s, size_t(e - s));
  } else if (!lua_isstring(L, -1)) {
    luaL_error(L, "invalid replacement value (a %s)", luaL_typename(L, -1));
  }
  luaL_addvalue(&b);
}

int gsub(lua_State* L) {
  const std::string_view s = arg_view(L, 1), p = arg_view(L, 2);
  const int kind = lua_type(L, 3);
  luaL_argcheck(L, kind == LUA_TNUMBER || kind == LUA_TSTRING || kind == LUA_TFUNCTION || kind == LUA_TTABLE, 3,
                "string/function/table expected");
  const lua_Integer most = luaL_optinteger(L, 4, lua_Integer(s.size()) + 1);
  Matcher m = matcher_for(L, s, p);
  const bool anchor = !p.empty() && p[0] == '^';
  const char* pattern = p.data() + (anchor ? 1 : 0);
  const char* src = s.data();
  luaL_Buffer b;
  luaL_buffinit(L, &b);
  lua_Integer n = 0;
  while (n < most) {
    m.level = 0;
    const char* e = m.match(src, pattern);
    if (e) ++n, add_replacement(m, b, src, e);
    if (e && e > src) src = e;
    else if (src < m.src_end) luaL_addchar(&b, *src++);
    else break;
    if (anchor) break;
  }
  m.settle();
  luaL_addlstring(&b, src, size_t(m.src_end - src));
  luaL_pushresult(&b);
  lua_pushinteger(L, n);
  return 2;
}

// table.sort and table.concat: charged for their length, then Lua's own (upvalue 1) runs.
constexpr size_t kMostSorted = 50'000;
constexpr int64_t kSortPerCompare = 9, kConcatPerEntry = 25;  // instructions' worth, as measured

int sort(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  // A comparator in C (string.reverse, say) runs no Lua instruction a hook could count.
  if (lua_iscfunction(L, 2)) luaL_error(L, "table.sort: the comparator must be a Lua function");
  const size_t n = lua_objlen(L, 1);
  if (n > kMostSorted) luaL_error(L, "table.sort: %d entries, more than the sandbox sorts (%d)", int(n), int(kMostSorted));
  // Strings compare byte by byte: long ones cost their length at every comparison.
  double bytes = 0;
  for (size_t i = 1; i <= n; ++i) {
    lua_rawgeti(L, 1, int(i));
    if (lua_type(L, -1) == LUA_TSTRING) bytes += double(lua_objlen(L, -1));
    lua_pop(L, 1);
  }
  const double log_n = std::log2(double(n) + 1);
  Sandbox& sandbox = Sandbox::of(L);
  sandbox.charge(L, int64_t(double(n) * log_n * kSortPerCompare + bytes * log_n / kBytesPerInstruction));
  const Sandbox::Nested nested(L, sandbox, "table.sort");
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, 0);
  return 0;
}

// string.format's %s calls __tostring from C: a __tostring that formats itself would recurse on
// the C stack. It runs as Lua's own (upvalue 1), counted as a nested callback.
template <const char* kName>
int nested_call(lua_State* L) {
  const Sandbox::Nested nested(L, Sandbox::of(L), kName);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
  return lua_gettop(L);
}
constexpr char kFormat[] = "string.format";

// Lua's print, but to the sandbox's print_line (stderr: stdout carries `--events -` and
// `quantum track`'s JSON). Arguments go through the global tostring, whose __tostring may
// recurse through print, hence the nesting count. The line is cut at a fixed size in a buffer
// of its own: a script printing a 30 MB string must not cost 30 MB more.
int print(lua_State* L) {
  Sandbox& sandbox = Sandbox::of(L);
  const Sandbox::Nested nested(L, sandbox, "print");
  char line[Sandbox::kPrintedLine + 1];
  size_t used = 0, whole = 0;
  const int n = lua_gettop(L);
  lua_getglobal(L, "tostring");
  for (int i = 1; i <= n; ++i) {
    lua_pushvalue(L, n + 1);
    lua_pushvalue(L, i);
    lua_call(L, 1, 1);
    size_t length = 0;
    const char* text = lua_tolstring(L, -1, &length);
    if (!text) return luaL_error(L, "'tostring' must return a string to 'print'");
    const char* separator = i > 1 ? "\t" : "";
    for (const auto& [piece, size] : {std::pair{separator, std::strlen(separator)}, std::pair{text, length}}) {
      const size_t room = Sandbox::kPrintedLine - used, taken = std::min(size, room);
      std::memcpy(line + used, piece, taken);
      used += taken;
      whole += size;
    }
    lua_pop(L, 1);
  }
  line[used] = '\0';
  sandbox.print_line(L, std::string_view(line, used), whole);
  return 0;
}

// Functions that read or write whole strings in C (tonumber, string.upper, lower, reverse, rep)
// take about a nanosecond a byte and no instruction a hook could count: charged for their bytes
// before they run, so one on a 30 MB string spends the budget at once instead of running 20 ms
// or more past it.
int charged_by_bytes(lua_State* L, double bytes) {
  Sandbox::of(L).charge(L, int64_t(std::min(bytes / kScannedBytesPerInstruction, 1e15)));
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
  return lua_gettop(L);
}

int by_string_arguments(lua_State* L) {
  double bytes = 0;
  for (int i = 1; i <= lua_gettop(L); ++i)
    if (lua_type(L, i) == LUA_TSTRING) bytes += double(lua_objlen(L, i));
  return charged_by_bytes(L, bytes);
}

int rep(lua_State* L) {
  const double times = std::max(0.0, double(luaL_optnumber(L, 2, 0)));
  const double each = double(lua_type(L, 1) == LUA_TSTRING ? lua_objlen(L, 1) : 0) +
                      double(lua_type(L, 3) == LUA_TSTRING ? lua_objlen(L, 3) : 0);
  return charged_by_bytes(L, each * times);
}

int concat(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  const lua_Integer first = luaL_optinteger(L, 3, 1), last = luaL_optinteger(L, 4, lua_Integer(lua_objlen(L, 1)));
  // In doubles: a range of 2^59 entries would overflow the charge and refund the budget.
  if (last >= first)
    Sandbox::of(L).charge(L, int64_t(std::min((double(last) - double(first) + 1) * kConcatPerEntry, 1e15)));
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, 1);
  return 1;
}

// xpcall's message handler, guarded: LuaJIT calls a handler that fails again and again, so a
// handler that loops once the budget is spent would never end. Once it is spent the error goes
// through as it is; before, the script's handler runs protected.
int guarded_handler(lua_State* L) {
  if (Sandbox::of(L).spent()) return 1;
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  if (lua_pcall(L, lua_gettop(L) - 1, 1, 0) != 0 && lua_type(L, -1) == LUA_TSTRING) {
    lua_pushfstring(L, "error in error handling: %s", lua_tostring(L, -1));
  }
  return 1;
}

int xpcall(lua_State* L) {
  luaL_checkany(L, 2);
  const Sandbox::Nested nested(L, Sandbox::of(L), "xpcall");
  lua_settop(L, 2);
  lua_pushvalue(L, 2);
  lua_pushcclosure(L, guarded_handler, 1);
  lua_pushvalue(L, 1);
  if (lua_pcall(L, 0, LUA_MULTRET, 3) != 0) {
    lua_pushboolean(L, 0);
    lua_insert(L, -2);
    return 2;
  }
  lua_pushboolean(L, 1);
  lua_replace(L, 3);
  return lua_gettop(L) - 2;
}

void replace(lua_State* L, const char* library, const char* name, lua_CFunction f, bool wraps) {
  if (!library) {
    if (wraps) {
      lua_getglobal(L, name);
      lua_pushcclosure(L, f, 1);
    } else {
      lua_pushcfunction(L, f);
    }
    lua_setglobal(L, name);
    return;
  }
  lua_getglobal(L, library);
  if (wraps) {
    lua_getfield(L, -1, name);
    lua_pushcclosure(L, f, 1);
  } else {
    lua_pushcfunction(L, f);
  }
  lua_setfield(L, -2, name);
  lua_pop(L, 1);
}

}  // namespace

void install_bounded(lua_State* L) {
  replace(L, "string", "find", find, false);
  replace(L, "string", "match", match, false);
  replace(L, "string", "gmatch", gmatch, false);
  replace(L, "string", "gsub", gsub, false);
  replace(L, "table", "sort", sort, true);
  replace(L, "table", "concat", concat, true);
  replace(L, nullptr, "tonumber", by_string_arguments, true);
  for (const char* name : {"upper", "lower", "reverse"}) replace(L, "string", name, by_string_arguments, true);
  replace(L, "string", "rep", rep, true);
  replace(L, nullptr, "xpcall", xpcall, false);
  replace(L, "string", "format", nested_call<kFormat>, true);
  replace(L, nullptr, "print", print, false);
}

}  // namespace quantum::lua

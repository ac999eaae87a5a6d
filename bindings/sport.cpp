#include "sport.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "field_loader.h"
#include "lua_push.h"

namespace quantum::lua {
namespace {

constexpr size_t kMemoryBudget = 64u << 20;
constexpr int kInstructionBudget = 10'000'000;  // per call: a rule that loops forever is skipped

const char* const kHandlers[] = {"drop",     "shot", "intercept", "retouch", "bounce",    "goal",
                                 "own_goal", "out",  "time_up",   "match_end", "powerup", "powerup_end"};

}  // namespace

Sport::Sport(const std::string& folder)
    : folder_(folder),
      file_((std::filesystem::path(folder) / "sport.lua").string()),
      sandbox_(kMemoryBudget, kInstructionBudget, true) {
  if (!std::filesystem::is_directory(folder)) throw ScriptError(folder + ": no such sport folder");
  lua_State* L = sandbox_.L();
  sandbox_.run_file(file_);
  auto fail = [&](const std::string& place, const std::string& message) -> ScriptError {
    return ScriptError(file_ + ": " + place + ": " + message);
  };
  if (!lua_istable(L, -1)) throw ScriptError(file_ + ": must return a table, returned " + luaL_typename(L, -1));
  const int t = lua_gettop(L);
  auto typed = [&](int table, const char* key, int type, const std::string& place) {
    lua_getfield(L, table, key);
    if (lua_isnil(L, -1)) return false;
    if (lua_type(L, -1) != type)
      throw fail(place.empty() ? key : place + "." + key,
                 std::string("expected a ") + lua_typename(L, type) + ", got " + luaL_typename(L, -1));
    return true;
  };
  name_ = folder;
  if (typed(t, "name", LUA_TSTRING, "")) name_ = lua_tostring(L, -1);
  lua_pop(L, 1);
  std::string field_name = "field.lua";
  if (typed(t, "field", LUA_TSTRING, "")) field_name = lua_tostring(L, -1);
  lua_pop(L, 1);
  field_ = load_field((std::filesystem::path(folder) / field_name).string());
  if (typed(t, "particles", LUA_TNUMBER, "")) {
    const double n = lua_tonumber(L, -1);
    if (!(n >= 1 && n <= 10'000'000)) throw fail("particles", "must be between 1 and 10,000,000");
    particles_ = uint32_t(n);
  }
  lua_pop(L, 1);
  if (typed(t, "match", LUA_TTABLE, "")) {
    const int m = lua_gettop(L);
    if (typed(m, "seconds", LUA_TNUMBER, "match")) {
      seconds_ = lua_tonumber(L, -1);
      if (!(seconds_ > 0 && seconds_ <= 24 * 3600)) throw fail("match.seconds", "must be in (0, 86400]");
    }
    lua_pop(L, 1);
    if (typed(m, "start", LUA_TSTRING, "match")) {
      const std::string where = lua_tostring(L, -1);
      first_spot_ = -1;
      for (size_t s = 0; s < field_.spots.size() && first_spot_ < 0; ++s)
        if (field_.spots[s].name == where) first_spot_ = int(s);
      if (first_spot_ < 0) first_spot_ = field_.spot_of_team(where);
      if (first_spot_ < 0) throw fail("match.start", "no spot or team '" + where + "' in the field");
    }
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  handicaps_.assign(field_.bodies.size(), 1.0);
  if (typed(t, "handicaps", LUA_TTABLE, "")) {
    for (size_t k = 0; k < field_.bodies.size(); ++k) {
      if (typed(lua_gettop(L), field_.bodies[k].name.c_str(), LUA_TNUMBER, "handicaps")) {
        handicaps_[k] = lua_tonumber(L, -1);
        if (!(handicaps_[k] > 0 && std::isfinite(handicaps_[k]))) throw fail("handicaps." + field_.bodies[k].name, "must be > 0");
      }
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  if (typed(t, "balance", LUA_TTABLE, "")) {
    const int b = lua_gettop(L);
    if (typed(b, "per_goal", LUA_TNUMBER, "balance")) {
      balance_per_goal_ = lua_tonumber(L, -1);
      if (!(balance_per_goal_ >= 0 && balance_per_goal_ <= 10)) throw fail("balance.per_goal", "must be in [0, 10]");
    }
    lua_pop(L, 1);
    if (typed(b, "most", LUA_TNUMBER, "balance")) {
      balance_most_ = lua_tonumber(L, -1);
      if (!(balance_most_ >= 1 && std::isfinite(balance_most_))) throw fail("balance.most", "must be >= 1");
    }
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  if (typed(t, "factors", LUA_TTABLE, "")) {
    for (const char* kind : {"goal", "own_goal", "body", "out", "field"}) {
      if (typed(lua_gettop(L), kind, LUA_TNUMBER, "factors") && !(lua_tonumber(L, -1) >= 0))
        throw fail(std::string("factors.") + kind, "must be >= 0");
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  if (typed(t, "phrases", LUA_TTABLE, "")) {
    lua_pushnil(L);
    while (lua_next(L, -2)) {
      if (lua_type(L, -2) != LUA_TSTRING || lua_type(L, -1) != LUA_TSTRING)
        throw fail("phrases", "expected text for every key, e.g. shot = \"{team} shoots\"");
      phrases_[lua_tostring(L, -2)] = lua_tostring(L, -1);
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  if (typed(t, "on", LUA_TTABLE, "")) {
    lua_pushnil(L);
    while (lua_next(L, -2)) {
      const std::string key = lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : "?";
      if (std::find(std::begin(kHandlers), std::end(kHandlers), key) == std::end(kHandlers))
        throw fail("on." + key, "unknown event (known: drop, shot, intercept, retouch, bounce, goal, own_goal, out, "
                                "time_up, match_end, powerup, powerup_end)");
      if (!lua_isfunction(L, -1)) throw fail("on." + key, std::string("expected a function, got ") + luaL_typename(L, -1));
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  if (typed(t, "modifiers", LUA_TTABLE, "")) {
    for (size_t i = 1; i <= lua_objlen(L, -1); ++i) {
      lua_rawgeti(L, -1, int(i));
      if (!lua_isfunction(L, -1))
        throw fail("modifiers[" + std::to_string(i) + "]", std::string("expected a function, got ") + luaL_typename(L, -1));
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  read_audio(t);
  sport_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
  push_game_api(L, this);
  game_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
}

Sport::~Sport() = default;

void Sport::read_audio(int t) {
  namespace fs = std::filesystem;
  lua_State* L = sandbox_.L();
  auto fail = [&](const std::string& place, const std::string& message) {
    return ScriptError(file_ + ": audio." + place + ": " + message);
  };
  // A sound file: in the sport's folder, else among the engine's own (sounds/).
  const fs::path shared = QUANTUM_SOUNDS_DIR;
  auto resolve = [&](const std::string& name) {
    const fs::path own = fs::path(folder_) / name;
    return (fs::exists(own) ? own : shared / name).lexically_normal().string();
  };
  for (const char* e : {"shot", "intercept", "retouch"}) audio_.sounds[e] = resolve("hit.wav");
  for (const char* e : {"goal", "own_goal"}) audio_.sounds[e] = resolve("goal.wav");
  audio_.sounds["drop"] = resolve("whistle.wav");
  audio_.sounds["bounce"] = resolve("wall.wav");
  audio_.priorities = {{"goal", 3}, {"own_goal", 3}, {"match_end", 3}, {"time_up", 3}, {"drop", 2},
                       {"out", 2},  {"shot", 1},     {"intercept", 1}, {"retouch", 0}, {"bounce", 0}};
  lua_getfield(L, t, "audio");
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    return;
  }
  if (!lua_istable(L, -1)) throw ScriptError(file_ + ": audio: expected a table");
  const int a = lua_gettop(L);
  lua_getfield(L, a, "voice");
  if (lua_isstring(L, -1)) audio_.voice = lua_tostring(L, -1);
  lua_pop(L, 1);
  for (auto [key, out] : {std::pair{"rate", &audio_.rate}, {"volume", &audio_.volume}}) {
    lua_getfield(L, a, key);
    if (lua_isnumber(L, -1)) *out = int(lua_tonumber(L, -1));
    else if (!lua_isnil(L, -1)) throw fail(key, "expected a number");
    lua_pop(L, 1);
  }
  for (auto [key, out] : {std::pair{"listener", &audio_.listener}, {"facing", &audio_.facing}}) {
    lua_getfield(L, a, key);
    if (lua_istable(L, -1)) {
      lua_rawgeti(L, -1, 1);
      lua_rawgeti(L, -2, 2);
      if (!lua_isnumber(L, -2) || !lua_isnumber(L, -1)) throw fail(key, "expected a point {x, y}");
      *out = {float(lua_tonumber(L, -2)), float(lua_tonumber(L, -1))};
      lua_pop(L, 2);
    } else if (!lua_isnil(L, -1)) {
      throw fail(key, "expected a point {x, y}");
    }
    lua_pop(L, 1);
  }
  // sounds = {event = "file"}, recorded = {phrase key = "file"}, priorities = {event = n}
  for (const char* key : {"sounds", "recorded", "priorities"}) {
    lua_getfield(L, a, key);
    if (lua_istable(L, -1)) {
      lua_pushnil(L);
      while (lua_next(L, -2)) {
        const std::string k = lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : "?";
        if (std::string(key) == "priorities") {
          if (!lua_isnumber(L, -1)) throw fail(std::string(key) + "." + k, "expected a number");
          audio_.priorities[k] = int(lua_tonumber(L, -1));
        } else {
          if (lua_type(L, -1) != LUA_TSTRING) throw fail(std::string(key) + "." + k, "expected a file name");
          (std::string(key) == "sounds" ? audio_.sounds : audio_.recorded)[k] = resolve(lua_tostring(L, -1));
        }
        lua_pop(L, 1);
      }
    } else if (!lua_isnil(L, -1)) {
      throw fail(key, "expected a table");
    }
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
}

std::string Sport::phrase(const std::string& key, const std::map<std::string, std::string>& vars) const {
  const auto it = phrases_.find(key);
  const std::string& text = it == phrases_.end() ? key : it->second;
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    const size_t close = text[i] == '{' ? text.find('}', i) : std::string::npos;
    const auto var = close == std::string::npos ? vars.end() : vars.find(text.substr(i + 1, close - i - 1));
    if (var == vars.end()) {
      out += text[i];
      continue;
    }
    out += var->second;
    i = close;
  }
  return out;
}

void Sport::set_factor(const std::string& kind, double value) {
  const char* kinds[] = {"goal", "own_goal", "body", "out", "field"};
  if (std::find(std::begin(kinds), std::end(kinds), kind) == std::end(kinds))
    throw std::invalid_argument("no fate kind '" + kind + "' (known: goal, own_goal, body, out, field)");
  if (!(std::isfinite(value) && value >= 0)) throw std::invalid_argument("factor for " + kind + " must be a number >= 0");
  lua_State* L = sandbox_.L();
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  lua_getfield(L, -1, "factors");
  if (!lua_istable(L, -1)) {
    lua_pop(L, 1);
    lua_newtable(L);
    lua_pushvalue(L, -1);
    lua_setfield(L, -3, "factors");
  }
  lua_pushnumber(L, value);
  lua_setfield(L, -2, kind.c_str());
  lua_pop(L, 2);
}

std::vector<double> Sport::factors(std::span<const game::FateView> fates, game::Match& match) {
  lua_State* L = sandbox_.L();
  reading_ = &match;
  std::vector<double> out;
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  const int sport = lua_gettop(L);
  lua_getfield(L, sport, "factors");
  const int kinds = lua_gettop(L);
  lua_getfield(L, sport, "modifiers");
  const int modifiers = lua_gettop(L);
  const size_t n_modifiers = lua_istable(L, modifiers) ? lua_objlen(L, modifiers) : 0;
  for (const game::FateView& f : fates) {
    double factor = 1;
    if (lua_istable(L, kinds)) {
      lua_getfield(L, kinds, f.kind.c_str());
      if (lua_isnumber(L, -1)) factor = lua_tonumber(L, -1);
      lua_pop(L, 1);
    }
    for (size_t i = 1; i <= n_modifiers; ++i) {
      lua_rawgeti(L, modifiers, int(i));
      push_fate(L, f);
      lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
      std::string error;
      if (!sandbox_.call(2, 1, error)) {
        match.report_error(error + " (modifiers[" + std::to_string(i) + "] skipped)");
        continue;
      }
      const double m = lua_tonumber(L, -1);
      if (lua_isnumber(L, -1) && std::isfinite(m) && m >= 0) factor *= m;
      else if (!lua_isnil(L, -1))
        match.report_error(file_ + ": modifiers[" + std::to_string(i) +
                                                     "] returned " + luaL_typename(L, -1) + ", not a number >= 0 (skipped)");
      lua_pop(L, 1);
    }
    out.push_back(factor * powerup_factors(f, match));
  }
  lua_settop(L, sport - 1);
  reading_ = nullptr;
  return out;
}

void Sport::on_event(const game::GameEvent& e, game::Match& match) {
  lua_State* L = sandbox_.L();
  game::Match* outer = match_;
  const game::Match* outer_reading = reading_;
  match_ = &match, reading_ = &match;
  if (e.type == "powerup" || e.type == "powerup_end") announce_powerup(e, match);
  const int top = lua_gettop(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  lua_getfield(L, -1, "on");
  if (lua_istable(L, -1)) {
    lua_getfield(L, -1, e.type.c_str());
    if (lua_isfunction(L, -1)) {
      lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
      push_event(L, e);
      std::string error;
      if (!sandbox_.call(2, 0, error)) match.report_error(error + " (on." + e.type + " skipped)");
    }
  }
  lua_settop(L, top);
  match_ = outer, reading_ = outer_reading;
}

int Sport::powerup(const std::string& name) {
  if (const auto it = powerups_.find(name); it != powerups_.end()) return it->second;
  namespace fs = std::filesystem;
  if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos)
    throw std::invalid_argument("power-up '" + name + "': names are lower-case letters, digits and _");
  fs::path sport = fs::path(folder_).lexically_normal();
  if (sport.filename().empty()) sport = sport.parent_path();  // "rules/practice/"
  const fs::path own = sport / "powerups" / (name + ".lua");
  const fs::path shared = sport.parent_path() / "powerups" / (name + ".lua");
  const fs::path file = fs::exists(own) ? own : shared;
  if (!fs::exists(file))
    throw ScriptError("no power-up '" + name + "' (looked for " + own.string() + " and " + shared.string() + ")");
  lua_State* L = sandbox_.L();
  sandbox_.run_file(file.string());
  const std::string where = file.string() + ": ";
  if (!lua_istable(L, -1)) {
    lua_pop(L, 1);
    throw ScriptError(where + "must return a table");
  }
  lua_getfield(L, -1, "factor");
  const bool has_factor = lua_isfunction(L, -1);
  lua_getfield(L, -2, "duration");
  const bool has_duration = lua_isnumber(L, -1) && lua_tonumber(L, -1) > 0;
  lua_pop(L, 2);
  if (!has_factor || !has_duration) {
    lua_pop(L, 1);
    throw ScriptError(where + "needs factor = function(fate, holder, game, p) and duration = seconds > 0");
  }
  return powerups_[name] = luaL_ref(L, LUA_REGISTRYINDEX);
}

void Sport::grant(game::Match& match, int player, const std::string& name, std::map<std::string, double> opts) {
  lua_State* L = sandbox_.L();
  const int script = powerup(name);
  const int top = lua_gettop(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, script);
  const int t = lua_gettop(L);
  // The script's defaults, then the grant's own numbers.
  lua_getfield(L, t, "defaults");
  std::map<std::string, double> params = numbers_of(L, lua_gettop(L));
  lua_pop(L, 1);
  for (const auto& [key, value] : opts) params[key] = value;
  lua_getfield(L, t, "duration");
  double seconds = lua_tonumber(L, -1);
  lua_pop(L, 1);
  if (const auto it = params.find("seconds"); it != params.end()) seconds = it->second, params.erase(it);
  // start(holder, game, p) may note what the power-up needs later (black ice: the velocity to keep).
  lua_getfield(L, t, "start");
  if (lua_isfunction(L, -1)) {
    game::Match* outer = match_;
    const game::Match* outer_reading = reading_;
    match_ = &match, reading_ = &match;
    push_player(L, match, size_t(player));
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    lua_createtable(L, 0, int(params.size()));
    for (const auto& [key, value] : params) {
      lua_pushnumber(L, value);
      lua_setfield(L, -2, key.c_str());
    }
    lua_pushvalue(L, -1);
    lua_insert(L, -5);  // a reference to the params table below the function, for after the call
    std::string error;
    const bool ok = sandbox_.call(3, 0, error);
    match_ = outer, reading_ = outer_reading;
    if (!ok) {
      lua_settop(L, top);
      throw ScriptError(error + " (start of power-up " + name + ")");
    }
    params = numbers_of(L, lua_gettop(L));
  }
  lua_settop(L, top);
  match.grant(player, name, seconds, std::move(params));
}

double Sport::powerup_factors(const game::FateView& fate, game::Match& match) {
  lua_State* L = sandbox_.L();
  double factor = 1;
  for (const game::ActivePowerup& a : match.powerups()) {
    int script = LUA_NOREF;
    try {
      script = powerup(a.name);  // granted before this sport was reloaded: its script loads here
    } catch (const std::exception& e) {
      match.report_error(std::string(e.what()) + " (power-up " + a.name + " skipped)");
      continue;
    }
    const int top = lua_gettop(L);
    lua_rawgeti(L, LUA_REGISTRYINDEX, script);
    lua_getfield(L, -1, "factor");
    push_fate(L, fate);
    push_player(L, match, size_t(a.player));
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    push_powerup(L, match, a);
    std::string error;
    if (!sandbox_.call(4, 1, error)) {
      match.report_error(error + " (power-up " + a.name + " skipped)");
    } else if (lua_isnumber(L, -1) && std::isfinite(lua_tonumber(L, -1)) && lua_tonumber(L, -1) >= 0) {
      factor *= lua_tonumber(L, -1);
    } else if (!lua_isnil(L, -1)) {
      match.report_error("power-up " + a.name + ": factor returned " + luaL_typename(L, -1) +
                         ", not a number >= 0 (skipped)");
    }
    lua_settop(L, top);
  }
  return factor;
}

void Sport::reload_powerup(const std::string& name) {
  const auto it = powerups_.find(name);
  if (it == powerups_.end()) return;  // never used: it loads fresh when granted
  const int old = it->second;
  powerups_.erase(it);
  try {
    powerup(name);
  } catch (...) {
    powerups_[name] = old;
    throw;
  }
  luaL_unref(sandbox_.L(), LUA_REGISTRYINDEX, old);
}

namespace {

// Copies the plain data at `index` of `from` onto the top of `to`: what survives a reload. A
// table met again (shared, or a cycle) is the same table in the copy, and at most kMaxNodes
// values are copied: a designer's state must not hang a reload.
struct PlainCopy {
  static constexpr int kMaxNodes = 100000;
  lua_State* from;
  lua_State* to;
  int seen;  // index in `to` of a table: from's table pointer -> its copy
  int nodes = 0;

  void copy(int index) {
    index = index < 0 ? lua_gettop(from) + index + 1 : index;
    if (++nodes > kMaxNodes) {
      lua_pushnil(to);
      return;
    }
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

void Sport::take_over(Sport& old, game::Match& match) {
  lua_State* from = old.sandbox_.L();
  lua_State* L = sandbox_.L();
  const int old_top = lua_gettop(from), top = lua_gettop(L);
  lua_rawgeti(from, LUA_REGISTRYINDEX, old.sport_ref_);
  lua_getfield(from, -1, "state");
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  const int t = lua_gettop(L);
  PlainCopy copy{from, L, 0};
  if (lua_cpcall(L, PlainCopy::run, &copy) != 0) {
    match.report_error(std::string("reload: the old state could not be carried over: ") +
                       (lua_tostring(L, -1) ? lua_tostring(L, -1) : "error"));
    lua_pop(L, 1);
    lua_pushnil(L);
  } else {
    lua_getfield(L, LUA_REGISTRYINDEX, "quantum.reload_state");
    lua_pushnil(L);
    lua_setfield(L, LUA_REGISTRYINDEX, "quantum.reload_state");
  }
  lua_settop(from, old_top);
  lua_getfield(L, t, "on_reload");
  if (lua_isfunction(L, -1)) {
    lua_insert(L, -2);  // on_reload, state
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    lua_insert(L, -2);  // on_reload, game, state
    game::Match* outer = match_;
    const game::Match* outer_reading = reading_;
    match_ = &match, reading_ = &match;
    std::string error;
    if (!sandbox_.call(2, 0, error)) match.report_error(error + " (on_reload skipped)");
    match_ = outer, reading_ = outer_reading;
  } else {
    lua_pop(L, 1);
    lua_setfield(L, t, "state");
  }
  lua_settop(L, top);
}

void Sport::announce_powerup(const game::GameEvent& e, game::Match& match) {
  const auto script = powerups_.find(e.powerup);
  if (script == powerups_.end()) return;
  lua_State* L = sandbox_.L();
  const int top = lua_gettop(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, script->second);
  lua_getfield(L, -1, "phrases");
  if (lua_istable(L, -1)) {
    lua_getfield(L, -1, e.type == "powerup" ? "start" : "over");
    if (lua_isstring(L, -1)) {
      // The script's phrase, with the sport's own phrase of the same key in its place if it has one.
      const std::string key = e.powerup + (e.type == "powerup" ? "_start" : "_over");
      const std::map<std::string, std::string> vars{{"player", e.actor}, {"team", e.team}};
      const std::string own = phrase(key, vars);
      match.say(own != key ? own : phrase(lua_tostring(L, -1), vars));
    }
  }
  lua_settop(L, top);
  // stop(holder, game): undoes what start did to the field (the wormhole closes).
  if (e.type != "powerup_end" || e.actor_index < 0) return;
  lua_rawgeti(L, LUA_REGISTRYINDEX, script->second);
  lua_getfield(L, -1, "stop");
  if (lua_isfunction(L, -1)) {
    push_player(L, match, size_t(e.actor_index));
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    std::string error;
    if (!sandbox_.call(2, 0, error)) match.report_error(error + " (stop of power-up " + e.powerup + " skipped)");
  }
  lua_settop(L, top);
}

}  // namespace quantum::lua

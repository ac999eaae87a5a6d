#include "powerups.h"

#include "confined_path.h"
#include "lua_reader.h"
#include "quantum/limits.h"
#include "scripted_rules.h"

namespace quantum::lua {
namespace fs = std::filesystem;
namespace {

const std::vector<std::string> kPowerupKeys = {"name", "duration", "defaults", "phrases", "factor", "start", "stop"};

}  // namespace

bool plain_powerup_name(const std::string& name) {
  return !name.empty() && name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") == std::string::npos;
}

fs::path powerup_file(const std::vector<fs::path>& folders, const std::string& name, std::string& looked) {
  return confined_path(folders, name + ".lua", "power-up '" + name + "'", looked);
}

void check_engine_phrase(const std::string& place, const PhraseTemplate& phrase, std::span<const std::string> allowed) {
  for (const std::string& name : phrase.placeholders()) {
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw ReadError(place, unknown_key(name, allowed, "placeholder") + ": the engine says this phrase");
    if (phrase.numeric(name)) throw ReadError(place, "{" + name + "} is text: it takes no number format");
  }
}

void Powerups::load_held(const game::Match& match) {
  for (const game::ActivePowerup& a : match.powerups()) {
    try {
      rules_.sandbox_->protect([&] { script(a.name); });
    } catch (const std::exception&) {
    }
  }
}

std::string Powerups::named_by(const std::string& file) const {
  for (const auto& [name, f] : files_)
    if (f == file) return name;
  return "";
}

int Powerups::script(const std::string& name) {
  if (const auto it = scripts_.find(name); it != scripts_.end()) return it->second;
  if (!plain_powerup_name(name))
    throw std::invalid_argument("power-up '" + name + "': names are lower-case letters, digits and _");
  std::string looked;
  const fs::path file = powerup_file(rules_.folders_.powerups, name, looked);
  if (file.empty()) throw ScriptError("no power-up '" + name + "' (looked for " + looked + ")");
  lua_State* L = rules_.sandbox_->L();
  const int base = lua_gettop(L);
  rules_.sandbox_->run_file(file.string());
  const std::string where = file.string() + ": ";
  const Reader r(L);
  try {
    r.expect(LUA_TTABLE, "", "a table");
    const int t = lua_gettop(L);
    r.no_near_misses(t, "", kPowerupKeys);
    if (!r.field(t, "factor")) r.fail("", "needs factor = function(fate, holder, game, p)");
    r.expect(LUA_TFUNCTION, "factor");
    lua_pop(L, 1);
    if (!(r.number(t, "duration", "", 0, true) > 0)) r.fail("duration", "must be seconds > 0");
    for (const char* optional : {"start", "stop"}) {
      if (!r.field(t, optional)) continue;
      r.expect(LUA_TFUNCTION, optional);
      lua_pop(L, 1);
    }
    if (r.field(t, "defaults")) {
      r.expect(LUA_TTABLE, "defaults");
      r.map(-1, "defaults", [&](const std::string&, const std::string& place) { r.expect(LUA_TNUMBER, place); });
      lua_pop(L, 1);
    }
    if (r.field(t, "phrases")) {
      r.expect(LUA_TTABLE, "phrases");
      r.only_keys(-1, "phrases", {"start", "over"});
      r.map(-1, "phrases", [&](const std::string&, const std::string& place) {
        r.expect(LUA_TSTRING, place);
        try {
          check_engine_phrase(place, PhraseTemplate(lua_tostring(L, -1)), kPowerupVars);
        } catch (const std::invalid_argument& e) {
          r.fail(place, e.what());
        }
      });
      lua_pop(L, 1);
    }
  } catch (const ReadError& e) {
    lua_settop(L, base);
    throw ScriptError(where + e.what());
  }
  files_[name] = file.string();
  return scripts_[name] = luaL_ref(L, LUA_REGISTRYINDEX);
}

void Powerups::grant(game::Match& match, int player, const std::string& name, std::map<std::string, double> opts) {
  lua_State* L = rules_.sandbox_->L();
  const int script = this->script(name);
  const int top = lua_gettop(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, script);
  const int t = lua_gettop(L);
  // The script's defaults, then the grant's own numbers.
  raw_field(L, t, "defaults");
  std::map<std::string, double> params = numbers_of(L, lua_gettop(L));
  lua_pop(L, 1);
  for (const auto& [key, value] : opts) params[key] = value;
  raw_field(L, t, "duration");
  double seconds = lua_tonumber(L, -1);
  lua_pop(L, 1);
  if (const auto it = params.find("seconds"); it != params.end()) seconds = it->second, params.erase(it);
  if (!limits::kPowerupSeconds.contains(seconds)) {
    lua_settop(L, top);
    throw std::invalid_argument("power-up " + name + ": seconds " + limits::must_be_in(limits::kPowerupSeconds, seconds));
  }
  // start(holder, game, p) may note what the power-up needs later (black ice: the velocity to keep).
  raw_field(L, t, "start");
  if (lua_isfunction(L, -1)) {
    const ScriptedRules::Acting acting(rules_, match, true);
    lua_newtable(L);
    fill_player(L, match, size_t(player));
    lua_rawgeti(L, LUA_REGISTRYINDEX, rules_.game_ref_);
    lua_createtable(L, 0, int(params.size()));
    for (const auto& [key, value] : params) {
      lua_pushnumber(L, value);
      raw_set(L, key.c_str());
    }
    lua_pushvalue(L, -1);
    lua_insert(L, -5);  // a reference to the params table below the function, for after the call
    std::string error;
    if (!rules_.call(3, 0, error)) {
      lua_settop(L, top);
      throw ScriptError(error + " (start of power-up " + name + ")");
    }
    params = numbers_of(L, lua_gettop(L));
  }
  lua_settop(L, top);
  match.grant(player, name, seconds, std::move(params));
}

void Powerups::factors(size_t fate, game::Match& match, double& factor, game::FactorTerms& terms) {
  lua_State* L = rules_.sandbox_->L();
  int& zeroed_by = rules_.zeroed_by_[fate];
  for (size_t j = 0; j < match.powerups().size(); ++j) {
    const game::ActivePowerup& a = match.powerups()[j];
    if (disabled_.count(a.name) || rules_.sandbox_->spent()) continue;
    int script = LUA_NOREF;
    try {
      script = this->script(a.name);  // granted before this sport was reloaded: its script loads here
    } catch (const std::exception& e) {
      match.report_error(std::string(e.what()) + " (power-up " + a.name + " skipped)");
      continue;
    }
    const int top = lua_gettop(L);
    lua_rawgeti(L, LUA_REGISTRYINDEX, script);
    raw_field(L, -1, "factor");
    rules_.fate_tables_.push(L, fate);
    rules_.player_tables_.push(L, size_t(a.player));
    lua_rawgeti(L, LUA_REGISTRYINDEX, rules_.game_ref_);
    rules_.powerup_tables_.push(L, j);
    std::string error;
    if (!rules_.call(4, 1, error)) {
      match.report_error(error + " (power-up " + a.name + " skipped)");
    } else if (!lua_isnil(L, -1)) {
      const double f = checked_term(L, match, [&] {
        raw_field(L, top + 1, "factor");
        const std::string at = defined_at(L, -1, files_[a.name]);
        lua_pop(L, 1);
        return at + "power-up " + a.name + ": factor returned ";
      });
      factor = times(factor, f);
      const auto strength = a.params.find("strength");
      terms.add(fate, {game::FactorTerm::Source::Powerup, a.name_id, a.player, {},
                       strength == a.params.end() ? 0 : strength->second, strength != a.params.end(), f});
      if (f == 0 && zeroed_by == ScriptedRules::kNotZeroed) zeroed_by = ScriptedRules::powerup_code(j);
    }
    lua_settop(L, top);
  }
}

std::vector<std::string> Powerups::reload(const std::vector<std::string>& names, game::Match& match) {
  rules_.begin_frame(match);
  std::vector<std::string> errors;
  for (const std::string& name : names) {
    errors.emplace_back();
    const auto it = scripts_.find(name);
    if (it == scripts_.end()) continue;  // never used: it loads fresh when granted
    const int old = it->second;
    const std::string old_file = files_[name];
    scripts_.erase(it);
    try {
      rules_.sandbox_->protect([&] { script(name); });
      disabled_.erase(name), rules_.overruns_.erase(name);  // a new version gets a fresh start
      luaL_unref(rules_.sandbox_->L(), LUA_REGISTRYINDEX, old);
    } catch (const std::exception& e) {
      scripts_[name] = old;
      files_[name] = old_file;
      errors.back() = e.what();
    }
  }
  rules_.sandbox_->new_period();
  return errors;
}

void Powerups::announce(const game::GameEvent& e, game::Match& match) {
  const auto script = scripts_.find(e.powerup);
  if (script == scripts_.end()) return;
  lua_State* L = rules_.sandbox_->L();
  const int top = lua_gettop(L);
  const bool starting = e.type == game::EventKind::Powerup;
  const std::string team = rules_.spec_.team_name(e.team);
  auto vars = [&](std::string_view name) -> std::optional<PhraseValue> {
    if (name == "player") return PhraseValue{e.actor, std::nullopt};
    if (name == "team") return PhraseValue{team, std::nullopt};
    return std::nullopt;
  };
  // The sport's own phrase `<name>_start` (or `_over`) takes the script's place.
  const std::string own = e.powerup + (starting ? "_start" : "_over");
  lua_rawgeti(L, LUA_REGISTRYINDEX, script->second);
  raw_field(L, -1, "phrases");
  if (rules_.phrases_.find(own)) {
    rules_.say(match, own, vars);
  } else if (lua_istable(L, -1)) {
    raw_field(L, -1, starting ? "start" : "over");
    if (lua_isstring(L, -1)) {
      rules_.said_.clear();
      PhraseTemplate(lua_tostring(L, -1)).fill(rules_.said_, vars);
      match.say(rules_.said_);
    }
  }
  lua_settop(L, top);
  // stop(holder, game): undoes what start did to the field (the wormhole closes).
  if (starting || e.actor_index < 0) return;
  lua_rawgeti(L, LUA_REGISTRYINDEX, script->second);
  raw_field(L, -1, "stop");
  if (lua_isfunction(L, -1)) {
    lua_newtable(L);
    fill_player(L, match, size_t(e.actor_index));
    lua_rawgeti(L, LUA_REGISTRYINDEX, rules_.game_ref_);
    std::string error;
    if (!rules_.call(2, 0, error)) match.report_error(error + " (stop of power-up " + e.powerup + " skipped)");
  }
  lua_settop(L, top);
}

}  // namespace quantum::lua

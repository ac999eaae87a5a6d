#include "scripted_rules.h"

#include <algorithm>
#include <cmath>

#include "carry_over.h"
#include "game/plain_rules.h"
#include "lua_reader.h"
#include "quantum/limits.h"

namespace quantum::lua {
namespace fs = std::filesystem;

std::string defined_at(lua_State* L, int index, const std::string& fallback) {
  lua_Debug ar;
  lua_pushvalue(L, index);
  lua_getinfo(L, ">S", &ar);
  if (ar.source[0] != '@' || ar.linedefined <= 0) return fallback + ": ";
  return std::string(ar.source + 1) + ":" + std::to_string(ar.linedefined) + ": ";
}


ScriptedRules::ScriptedRules(const std::string& folder, const fs::path& engine, Params params, const Limits& load)
    : ScriptedRules(folder, engine, std::move(params), load, nullptr) {}

std::unique_ptr<ScriptedRules> ScriptedRules::reload(const ScriptedRules& current) {
  return std::unique_ptr<ScriptedRules>(
      new ScriptedRules(current.folders_.folder, current.folders_.engine, current.params_, Limits{}, &current.spec_.field));
}

ScriptedRules::ScriptedRules(const std::string& folder, const fs::path& engine, Params params, const Limits& load,
                             const Field* playing)
    : folders_(folder, engine),
      file_((fs::path(folders_.folder) / "sport.lua").string()),
      params_(std::move(params)),
      sandbox_(Sandbox::make(Limits{}, true, folders_.modules)),
      powerups_(*this) {
  std::fill(std::begin(by_kind_), std::end(by_kind_), 1.0);
  sandbox_->set_budget(load);
  sport_ref_ = load_sport(*sandbox_, params_, folders_, playing, spec_);
  for (const auto& [key, text] : spec_.phrases) phrases_.add(key, text);
  lua_State* L = sandbox_->L();
  sandbox_->protect([&] {
    push_game_api(L, this);
    game_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
  });
  timers_.reserve(16);
  if (playing) return;  // a reload: take_over spends the rest of its frame's budget
  // Loading is not a frame: what it spent must not leave the first frame (or a grant before it)
  // without a budget, as it did on a slow machine.
  sandbox_->set_budget(Limits{});
  sandbox_->new_period();
}

ScriptedRules::~ScriptedRules() = default;

void ScriptedRules::unknown_phrase(std::string_view key) const {
  throw std::invalid_argument("no phrase '" + std::string(key) + "' in " + file_ + ": " +
                              unknown_key(key, phrases_.keys(), "phrase key") +
                              " (text to speak as it is starts with a capital or has a space)");
}

double ScriptedRules::factor(const std::string& kind) const {
  lua_State* L = sandbox_->L();
  double value = 1;
  sandbox_->protect([&] {
    lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
    raw_field(L, -1, "factors");
    if (lua_istable(L, -1)) {
      raw_field(L, -1, kind.c_str());
      if (lua_type(L, -1) == LUA_TNUMBER) value = lua_tonumber(L, -1);
    }
  });
  return value;
}

void ScriptedRules::set_factor(const std::string& kind, double value) {
  const std::vector<std::string> kinds = fate_kind_names();
  if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end())
    throw std::invalid_argument(unknown_key(kind, kinds, "fate kind"));
  if (game::bounded_factor(value).problem)
    throw std::invalid_argument("factor for " + kind + " must be a number in [0, 1e6]");
  lua_State* L = sandbox_->L();
  sandbox_->protect([&] {
    lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
    raw_field(L, -1, "factors");
    if (!lua_istable(L, -1)) {
      lua_pop(L, 1);
      lua_newtable(L);
      lua_pushstring(L, "factors");
      lua_pushvalue(L, -2);
      lua_rawset(L, -4);
    }
    lua_pushstring(L, kind.c_str());
    lua_pushnumber(L, value);
    lua_rawset(L, -3);
  });
  spec_.factors[std::find(kinds.begin(), kinds.end(), kind) - kinds.begin()] = value;
}

void ScriptedRules::factors(std::span<const game::FateView> fates, game::Match& match, std::span<double> out,
                    game::FactorTerms& terms) {
  zeroed_by_.reserve(std::max(kBusyFateGroups, fates.size()));  // as Match's fate buffers: room for a busy moment
  zeroed_by_.assign(fates.size(), kNotZeroed);
  bool scripted = false;
  if (!disabled_ && !sandbox_->spent()) {
    try {
      sandbox_->protect([&] { script_factors(fates, match, out, terms); });
      scripted = true;
    } catch (const ScriptError& e) {
      if (!stuck(match)) match.report_error(std::string(e.what()) + " (this frame's modifiers skipped)");
    }
  }
  if (!scripted) {  // the scripts could not run: the factors by kind as last read
    terms.clear();
    for (size_t k = 0; k < fates.size(); ++k) {
      out[k] = by_kind_[int(fates[k].fate.kind)];
      terms.add(k, {game::FactorTerm::Source::Sport, 0, -1, {}, 0, false, out[k]});
    }
  }
  for (size_t k = 0; k < fates.size(); ++k)
    if (out[k] == 0 && zeroed_by_[k] == kNotZeroed && by_kind_[int(fates[k].fate.kind)] == 0) zeroed_by_[k] = kKindFactor;
  double kept = 0, mass = 0;
  for (size_t k = 0; k < fates.size(); ++k) kept += fates[k].mass * out[k], mass += fates[k].mass;
  // Particles' fates share the ball, which must go somewhere; tackles are chances of their own,
  // and none at all is a frame like any other.
  const bool tackles = !fates.empty() && fates[0].fate.kind == FateKind::Tackle;
  // Contacts (mass 0) keep their factors: a player given 0 never gets the ball, whatever the fates.
  if (mass > 0 && kept == 0 && !tackles) {
    report_zeroing(fates, match);
    for (size_t k = 0; k < fates.size(); ++k)
      if (!fates[k].contact) out[k] = 1;
    terms.skip();
  }
}

void ScriptedRules::script_factors(std::span<const game::FateView> fates, game::Match& match, std::span<double> out,
                           game::FactorTerms& terms) {
  lua_State* L = sandbox_->L();
  const Acting reading(*this, match, false);
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  const int sport = lua_gettop(L);
  raw_field(L, sport, "factors");
  if (lua_istable(L, -1))  // checked when loaded, but a handler may have changed it since
    for (FateKind k : kFateKinds) {
      raw_field(L, -1, to_string(k));
      const auto culprit = [&] { return file_ + ": factors." + to_string(k) + " is "; };
      by_kind_[int(k)] = lua_isnil(L, -1) ? 1.0 : checked_term(L, match, culprit);
      lua_pop(L, 1);
    }
  raw_field(L, sport, "modifiers");
  const int modifiers = lua_gettop(L);
  const size_t n_modifiers = lua_istable(L, modifiers) ? lua_objlen(L, modifiers) : 0;
  // What a script put there since the sport loaded, told once a frame (the same words each
  // frame: told once and counted) naming the function after which it was so.
  const auto not_usable = [&](const std::string& what, int index) {
    match.report_error((modifiers_broken_by_.empty() ? file_ + ": " : modifiers_broken_by_ + "since this function ran, ") +
                       what + " is a " + luaL_typename(L, index) + ", not " +
                       (what == "modifiers" ? "a list of functions" : "a function") + " (skipped)");
  };
  bool told = !lua_isnil(L, modifiers) && !lua_istable(L, modifiers);
  if (told) not_usable("modifiers", modifiers);
  // The players and power-ups a power-up's factor sees, filled once for all fates.
  for (size_t k = 0; k < match.players().size() && !match.powerups().empty(); ++k) {
    player_tables_.push(L, k);
    fill_player(L, match, k);
    lua_pop(L, 1);
  }
  for (size_t j = 0; j < match.powerups().size(); ++j) {
    powerup_tables_.push(L, j);
    fill_powerup(L, match, match.powerups()[j]);
    lua_pop(L, 1);
  }
  for (size_t k = 0; k < fates.size(); ++k) {
    const game::FateView& f = fates[k];
    double factor = by_kind_[int(f.fate.kind)];
    terms.add(k, {game::FactorTerm::Source::Sport, 0, -1, {}, 0, false, factor});
    if (factor == 0) zeroed_by_[k] = kKindFactor;
    if (n_modifiers > 0 || !match.powerups().empty()) {
      fate_tables_.push(L, k);
      fill_fate(L, f, match.field());
      lua_pop(L, 1);
    }
    for (size_t i = 1; i <= n_modifiers && !sandbox_->spent(); ++i) {  // spent: the rest keep their factor
      lua_rawgeti(L, modifiers, int(i));
      if (!lua_isfunction(L, -1)) {
        if (!told) not_usable("modifiers[" + std::to_string(i) + "]", -1), told = true;
        lua_pop(L, 1);
        continue;
      }
      fate_tables_.push(L, k);
      lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
      std::string error;
      if (!call(2, 1, error)) {
        match.report_error(error + " (modifiers[" + std::to_string(i) + "] skipped)");
        continue;
      }
      if (!lua_isnil(L, -1)) {
        const double m = checked_term(L, match, [&] {
          lua_rawgeti(L, modifiers, int(i));
          const std::string at = defined_at(L, -1, file_);
          lua_pop(L, 1);
          return at + "modifiers[" + std::to_string(i) + "] returned ";
        });
        factor = times(factor, m);
        terms.add(k, {game::FactorTerm::Source::Modifier, int(i), -1, {}, 0, false, m});
        if (m == 0 && zeroed_by_[k] == kNotZeroed) zeroed_by_[k] = modifier_code(i);
      }
      lua_pop(L, 1);
    }
    powerups_.factors(k, match, factor, terms);
    out[k] = factor;
  }
}

bool ScriptedRules::call(int nargs, int nresults, std::string& error) {
  lua_State* L = sandbox_->L();
  lua_pushvalue(L, -nargs - 1);  // the function, kept below it for its place
  lua_insert(L, -nargs - 2);
  const bool ok = sandbox_->call(nargs, nresults, error);
  const int function = lua_gettop(L) - (ok ? nresults : 0);
  if (modifiers_usable(L)) modifiers_broken_by_.clear();
  else if (modifiers_broken_by_.empty()) modifiers_broken_by_ = defined_at(L, function, file_);
  lua_remove(L, function);
  return ok;
}

// Whether the sport's modifiers are none or a list of functions, as loading checked. A list a
// script made as long as memory allows is looked at until the frame's budget is spent (the
// watchdog's flag), not past it; what is not looked at counts as usable.
bool ScriptedRules::modifiers_usable(lua_State* L) {
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  raw_field(L, -1, "modifiers");
  bool usable = lua_isnil(L, -1) || lua_istable(L, -1);
  if (lua_istable(L, -1))
    for (size_t i = 1, n = lua_objlen(L, -1); i <= n && usable && !sandbox_->spent(); ++i) {
      lua_rawgeti(L, -1, int(i));
      usable = lua_isfunction(L, -1);
      lua_pop(L, 1);
    }
  lua_pop(L, 2);
  return usable;
}

// Every fate zeroed: the draw would have nothing left to choose from. The match goes on with
// this frame's factors skipped, and the error names what zeroed them.
void ScriptedRules::report_zeroing(std::span<const game::FateView> fates, game::Match& match) {
  std::vector<int> culprits;
  for (size_t k = 0; k < fates.size(); ++k)
    if (fates[k].mass > 0 && std::find(culprits.begin(), culprits.end(), zeroed_by_[k]) == culprits.end())
      culprits.push_back(zeroed_by_[k]);
  std::sort(culprits.begin(), culprits.end(), std::greater<>());
  std::string who;
  for (int c : culprits) {
    std::string name;
    if (c == kNotZeroed) {
      name = file_ + ": factors too small to tell from 0 (their product underflows)";
    } else if (c == kKindFactor) {
      name = file_ + ": factors";
      std::string kinds;
      for (const game::FateView& f : fates)
        if (f.mass > 0 && kinds.find(f.kind()) == std::string::npos) kinds += std::string(kinds.empty() ? "" : "/") + f.kind();
      name += " (" + kinds + ")";
    } else if (c > 0) {
      name = file_ + ": modifiers[" + std::to_string(c) + "]";
    } else {
      const std::string& p = match.powerups()[size_t(-2 - c)].name;
      name = "power-up " + p + " (" + powerups_.file(p) + ")";
    }
    who += (who.empty() ? "" : ", ") + name;
  }
  match.report_error(who + (culprits.size() > 1 ? " together give" : " gives") +
                     " every fate a factor of 0, which would leave the ball nowhere to be; this frame's factors are "
                     "skipped");
}

void ScriptedRules::on_event(const game::GameEvent& e, game::Match& match) {
  if (disabled_ || sandbox_->spent()) return game::plain_event(e, match);
  try {
    sandbox_->protect([&] { run_handler(e, match); });
  } catch (const ScriptError& x) {
    if (stuck(match)) return game::plain_event(e, match);  // so that no goal goes uncounted
    match.report_error(std::string(x.what()) + " (on." + game::to_string(e.type) + " skipped)");
  }
}

void ScriptedRules::run_handler(const game::GameEvent& e, game::Match& match) {
  lua_State* L = sandbox_->L();
  const Acting acting(*this, match, true);
  if (e.type == game::EventKind::Powerup || e.type == game::EventKind::PowerupEnd) {
    const int before = lua_gettop(L);
    try {
      powerups_.announce(e, match);
    } catch (const std::exception& x) {
      lua_settop(L, before);
      match.report_error(std::string(x.what()) + " (announcing power-up " + e.powerup + ")");
    }
  }
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  raw_field(L, -1, "on");
  if (!lua_istable(L, -1)) return;
  raw_field(L, -1, game::to_string(e.type));
  if (!lua_isfunction(L, -1)) return;
  lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
  push_event(L, e);
  std::string error;
  if (!call(2, 0, error)) match.report_error(error + " (on." + game::to_string(e.type) + " skipped)");
}

void ScriptedRules::begin_frame(game::Match& match) {
  if (stuck(match)) return;
  if (sandbox_->spent()) note_overrun(match);
  sandbox_->new_period();
}

bool ScriptedRules::stuck(game::Match& match) {
  if (!sandbox_->abandoned()) return false;
  if (!disabled_) {
    disabled_ = true;
    match.report_error(sandbox_->stuck() + "; " + spec_.name +
                       " disabled: the match goes on with the engine's plain rules (a goal counts for the other team)");
  }
  return true;
}

// The script that ran when the budget ran out: a power-up's file, else the sport's own.
void ScriptedRules::note_overrun(game::Match& match) {
  const std::string& file = sandbox_->spent_in();
  const std::string powerup = powerups_.named_by(file);
  if (++overruns_[powerup] < kOverrunsToDisable) return;
  const std::string times = " ran out of a frame's Lua budget " + std::to_string(kOverrunsToDisable) + " times";
  if (!powerup.empty()) {
    if (powerups_.disable(powerup))
      match.report_error(file + ": power-up " + powerup + " disabled: it" + times + "; the match goes on without it");
  } else if (!disabled_) {
    disabled_ = true;
    match.report_error((file.empty() ? file_ : file) + ": " + spec_.name + " disabled: its scripts" + times +
                       "; the match goes on with the engine's plain rules (a goal counts for the other team)");
  }
}

int ScriptedRules::add_timer(game::Match& match, double seconds) {
  lua_State* L = sandbox_->L();
  limits::check(limits::kPowerupSeconds, seconds, "seconds");
  if (timers_.size() >= 1000) throw std::invalid_argument("1000 timers are pending already");
  const int function = luaL_ref(L, LUA_REGISTRYINDEX);
  timers_.push_back({match.time() + seconds, next_timer_, function});
  return next_timer_++;
}

void ScriptedRules::cancel_timer(int id) {
  const auto it = std::find_if(timers_.begin(), timers_.end(), [&](const Timer& t) { return t.id == id; });
  if (it == timers_.end()) return;
  luaL_unref(sandbox_->L(), LUA_REGISTRYINDEX, it->function);
  timers_.erase(it);
}

void ScriptedRules::tick(game::Match& match) {
  if (disabled_ || sandbox_->spent()) return;  // due timers wait for a frame with budget
  // Most frames have no timer due: the trip to the sandbox's thread is spared them.
  if (std::none_of(timers_.begin(), timers_.end(), [&](const Timer& t) { return t.is_due(match.time()); })) return;
  try {
    sandbox_->protect([&] { run_timers(match); });
  } catch (const ScriptError& x) {
    if (!stuck(match)) match.report_error(std::string(x.what()) + " (timer skipped)");
  }
}

void ScriptedRules::run_timers(game::Match& match) {
  lua_State* L = sandbox_->L();
  // Timers set while these run wait for the next frame, however short their delay.
  const int before = next_timer_;
  for (;;) {
    auto next = timers_.end();
    for (auto it = timers_.begin(); it != timers_.end(); ++it)
      if (it->id < before && it->is_due(match.time()) &&
          (next == timers_.end() || it->due < next->due || (it->due == next->due && it->id < next->id)))
        next = it;
    if (next == timers_.end() || sandbox_->spent()) return;
    const Timer timer = *next;
    timers_.erase(next);
    const Acting acting(*this, match, true);
    match.set_cause("timer");
    lua_rawgeti(L, LUA_REGISTRYINDEX, timer.function);
    luaL_unref(L, LUA_REGISTRYINDEX, timer.function);
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    std::string error;
    if (!call(1, 0, error)) match.report_error(error + " (timer skipped)");
  }
}

void ScriptedRules::grant(game::Match& match, int player, const std::string& name, std::map<std::string, double> opts) {
  if (disabled_ || powerups_.disabled(name))
    throw std::invalid_argument("power-up " + name + ": disabled in this match (its scripts overran their budget)");
  sandbox_->protect([&] { powerups_.grant(match, player, name, std::move(opts)); });
}

std::vector<std::string> ScriptedRules::reload_powerups(const std::vector<std::string>& names, game::Match& match) {
  return powerups_.reload(names, match);
}

void ScriptedRules::take_over(ScriptedRules& old, game::Match& match) {
  // The power-ups the match holds load with the new version, not in its first frame: loading is
  // the engine's work, and under the address sanitizer a few scripts' loading spent a frame's
  // whole budget, so their factors were skipped (seen in the soak). One that fails to load is
  // reported when the frame asks for it.
  powerups_.load_held(match);
  if (old.sandbox_->abandoned()) return;  // its state cannot be read: the new version starts afresh
  old.sandbox_->new_period();  // reading its state is the engine's work, whatever the old scripts spent
  try {
    old.sandbox_->protect([&] { sandbox_->protect([&] { carry_state(old, match); }); });
  } catch (const ScriptError& e) {
    if (!stuck(match)) match.report_error(std::string(e.what()) + " (on_reload skipped)");
  }
}

void ScriptedRules::carry_state(ScriptedRules& old, game::Match& match) {
  lua_State* from = old.sandbox_->L();
  lua_State* L = sandbox_->L();
  const int top = lua_gettop(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  const int t = lua_gettop(L);
  if (const std::string error = copy_state(from, old.sport_ref_, L); !error.empty())
    match.report_error("reload: the old state could not be carried over: " + error);
  raw_field(L, t, "on_reload");
  if (lua_isfunction(L, -1)) {
    lua_insert(L, -2);  // on_reload, state
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    lua_insert(L, -2);  // on_reload, game, state
    const Acting acting(*this, match, true);
    std::string error;
    if (!call(2, 0, error)) match.report_error(error + " (on_reload skipped)");
  } else if (!lua_isnil(L, -2)) {  // nothing to carry: the new version's own state stays
    lua_pop(L, 1);
    lua_pushstring(L, "state");
    lua_insert(L, -2);
    lua_rawset(L, t);
  }
  lua_settop(L, top);
}

}  // namespace quantum::lua

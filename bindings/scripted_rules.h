// A sport's behaviour, written in Lua (rules/<sport>/sport.lua): its fate factors and modifier
// hooks, event handlers and timers, behind the game engine's Rules interface. What it is as data
// (field, settings, phrases, sound) is the game::SportSpec its loader read (sport_loader.h); its
// power-ups are powerups.h's, and what a reload carries over carry_over.h's. The Lua API it sees
// is documented in docs/lua-api.md.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "engine_paths.h"
#include "game/game.h"
#include "game/sport_spec.h"
#include "lua_push.h"
#include "lua_sandbox.h"
#include "params.h"
#include "phrases.h"
#include "powerups.h"
#include "sport_loader.h"

namespace quantum::lua {

class ScriptedRules final : public game::Rules {
 public:
  // Loads the sport (load_sport): `folder` holds sport.lua, or is a sport's name (find_sport);
  // `engine` is where the engine's own power-ups and helpers are (a replay uses the copy it
  // recorded); `params` are what its field and sport read with param() (params.h). Throws as
  // load_sport does, and std::invalid_argument for a sport not found. Loading spends at most
  // `load`; the match's frames then get Limits{} each.
  explicit ScriptedRules(const std::string& folder, const std::filesystem::path& engine = engine_rules_folder(),
                         Params params = {}, const Limits& load = kLoadLimits);
  ~ScriptedRules() override;

  // `current`'s sport.lua loaded again while its match runs (a reload): all of it, and the
  // take_over that must follow, within one frame's budget (Limits{}), on the field `current`
  // plays on and with its parameters. The field file does not run again: a match keeps its
  // field, and a changed one takes effect at the next match. Throws as the constructor does.
  static std::unique_ptr<ScriptedRules> reload(const ScriptedRules& current);

  // The sport as data, as it loaded (its factors as set_factor left them).
  const game::SportSpec& spec() const { return spec_; }
  const Params& params() const { return params_; }
  const SportFolders& folders() const { return folders_; }

  // Replaces the sport's factor for a fate kind (fate_kind_names(): goal, own_goal, body, out,
  // field, catch, pass, intercept), e.g. to
  // compare a sport's factors with none. Throws std::invalid_argument for an unknown kind or a
  // value that is not a number >= 0.
  void set_factor(const std::string& kind, double value);
  // The factor sport.lua (or set_factor) gives a fate kind: 1 when it gives none.
  double factor(const std::string& kind) const;

  // Every call into the scripts runs protected and within one budget per frame for all of the
  // sport's Lua (lua_sandbox.h). A script that spends it kOverrunsToDisable times in a match is
  // disabled: the sport's own (handlers, timers, modifiers) gives way to game::plain_event and its
  // factors by kind, a power-up's to nothing. Events whose handler cannot run because the frame's
  // budget is spent get the plain rules too, so no goal goes uncounted. (Power-ups share the
  // sport's state: a disabled sport's power-ups stop too.) A script stuck in one instruction
  // (the sandbox abandoned) disables the sport at once.
  static constexpr int kOverrunsToDisable = 3;
  void factors(std::span<const game::FateView> fates, game::Match& match, std::span<double> out,
               game::FactorTerms& terms) override;
  void on_event(const game::GameEvent& event, game::Match& match) override;
  void tick(game::Match& match) override;
  void begin_frame(game::Match& match) override;
  bool disabled() const { return disabled_; }
  bool powerup_disabled(const std::string& name) const { return powerups_.disabled(name); }

  // Says phrase `key` (or literal text) on the match; lookup(name) gives placeholder values.
  // Throws std::invalid_argument for a key the sport has no phrase for, or a placeholder
  // without a value.
  template <class Lookup>
  void say(game::Match& match, std::string_view key_or_text, Lookup&& lookup) {
    const PhraseTemplate* phrase = phrases_.find(key_or_text);
    if (!phrase && Phrases::looks_like_key(key_or_text)) unknown_phrase(key_or_text);
    const auto recorded = spec_.audio.recorded.find(key_or_text);
    said_.clear();
    try {
      if (phrase) phrase->fill(said_, lookup);
      else PhraseTemplate(key_or_text).fill(said_, lookup);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument((phrase ? "phrase '" + std::string(key_or_text) + "': " : std::string()) + e.what());
    }
    match.say(said_, recorded == spec_.audio.recorded.end() ? std::string_view() : std::string_view(recorded->second));
  }
  // The sport's phrase `key` when it has one, else the text `fallback` (the engine's own words).
  template <class Lookup>
  void say_or(game::Match& match, std::string_view key, std::string_view fallback, Lookup&& lookup) {
    say(match, phrases_.find(key) ? key : fallback, lookup);
  }

  // Gives player `player` (a body index) the power-up `name` (Powerups::grant), protected.
  void grant(game::Match& match, int player, const std::string& name, std::map<std::string, double> opts);
  // Loads the power-ups `names` again from their files (Powerups::reload).
  std::vector<std::string> reload_powerups(const std::vector<std::string>& names, game::Match& match);
  bool has_powerup(const std::string& name) const { return powerups_.has(name); }

  // After a reload: this (new) sport takes over from `old`, in what is left of reload()'s budget:
  // the power-ups the match holds load, then its `on_reload(game, state)` gets a copy of the old
  // sport table's `state` (plain data: numbers, strings, booleans, tables; carry_over.h); without
  // one, the copy becomes its `state`. The old version's timers are not carried.
  void take_over(ScriptedRules& old, game::Match& match);

  // game.after(seconds, fn): fn (on top of the stack, popped) runs once, `seconds` from now, as
  // a handler does. Returns its id for cancel_timer.
  int add_timer(game::Match& match, double seconds);
  void cancel_timer(int id);

  // For wrap_game.cpp: the match the current call acts on (handlers and timers), or reads
  // (modifiers and power-up factors too).
  game::Match* match() const { return match_; }
  const game::Match* reading() const { return reading_; }
  lua_State* L() const { return sandbox_->L(); }
  const Sandbox& sandbox() const { return *sandbox_; }

 private:
  friend class Powerups;
  // Loads sport.lua within `load`; `playing` is the field of the match a reload joins (kept, with
  // the parameters its file read), null to load the one sport.lua names.
  ScriptedRules(const std::string& folder, const std::filesystem::path& engine, Params params, const Limits& load,
                const Field* playing);
  struct Timer {
    double due;
    int id;
    int function;  // registry reference
    bool is_due(double now) const { return due <= now + 1e-9; }
  };
  class Acting;

  [[noreturn]] void unknown_phrase(std::string_view key) const;
  // Which factor made a fate 0: none, the sport's factors by kind, modifiers[i], or the j-th
  // active power-up.
  static constexpr int kNotZeroed = -1, kKindFactor = 0;
  static int modifier_code(size_t i) { return int(i); }           // 1-based, as Lua counts
  static int powerup_code(size_t j) { return -2 - int(j); }
  void script_factors(std::span<const game::FateView> fates, game::Match& match, std::span<double> out,
                      game::FactorTerms& terms);
  void run_handler(const game::GameEvent& e, game::Match& match);
  // Every call into the sport's scripts: sandbox_->call, then a look at the modifiers the call
  // may have replaced (a handler's `sport.modifiers = {{}}`). The first call after which they
  // are not a list of functions is remembered (modifiers_broken_by_: where that function starts),
  // for script_factors' error to name; a call after which they are one again forgets it.
  bool call(int nargs, int nresults, std::string& error);
  bool modifiers_usable(lua_State* L);
  void run_timers(game::Match& match);
  void carry_state(ScriptedRules& old, game::Match& match);
  void note_overrun(game::Match& match);
  // The sandbox was abandoned (lua_sandbox.h): the sport is disabled, said once. Nothing may
  // touch its Lua state after that.
  bool stuck(game::Match& match);
  void report_zeroing(std::span<const game::FateView> fates, game::Match& match);

  SportFolders folders_;
  std::string file_;  // sport.lua
  Params params_;  // before the sandbox: its `param` function points here
  Sandbox::Ptr sandbox_;
  game::SportSpec spec_;
  int sport_ref_ = LUA_NOREF, game_ref_ = LUA_NOREF;
  Phrases phrases_;  // spec_.phrases, parsed to be filled
  Powerups powerups_;
  std::vector<Timer> timers_;
  int next_timer_ = 1;
  TablePool fate_tables_, player_tables_, powerup_tables_;
  std::vector<int> zeroed_by_;           // per fate: which factor made it 0 (codes above)
  double by_kind_[kFateKindCount];       // the sport's factors by kind, as last read (used while Lua cannot run)
  std::map<std::string, int> overruns_;  // per script ("" the sport's own, else a power-up): budgets spent
  bool disabled_ = false;
  std::string said_;                     // the phrase being filled (its room is kept)
  std::string modifiers_broken_by_;      // "file:line: " (see call), "" while the modifiers are usable
  game::Match* match_ = nullptr;
  const game::Match* reading_ = nullptr;
};

// While a handler, a timer or a power-up's start or stop runs, the rules may act on the match;
// while factors are computed they may only read it. Nested calls restore what was before. The
// scripts' random numbers are the match's (Sandbox::set_seed).
class ScriptedRules::Acting {
 public:
  Acting(ScriptedRules& sport, game::Match& match, bool may_act)
      : sport_(sport), outer_(sport.match_), outer_reading_(sport.reading_) {
    sport.match_ = may_act ? &match : nullptr;
    sport.reading_ = &match;
    sport.sandbox_->set_seed(match.config().seed);
  }
  ~Acting() { sport_.match_ = outer_, sport_.reading_ = outer_reading_; }
  Acting(const Acting&) = delete;
  Acting& operator=(const Acting&) = delete;

 private:
  ScriptedRules& sport_;
  game::Match* outer_;
  const game::Match* outer_reading_;
};

// Builds the `game` table the handlers receive (wrap_game.cpp).
void push_game_api(lua_State* L, ScriptedRules* sport);

// The player (body index) of that name; throws ArgError naming the nearest one otherwise.
int player_index(const game::Match& match, const std::string& name);

// "rules/x/sport.lua:12: ", where the Lua function at `index` is defined; `fallback` + ": " when
// that is unknown.
std::string defined_at(lua_State* L, int index, const std::string& fallback);

// A factor's term never takes the product past game::kMostFactor, so no number of them
// overflows.
inline double times(double factor, double term) { return std::min(factor * term, game::kMostFactor); }

// A term of a factor at the top of the stack (a number, not nil), in bounds; what is out of them
// is reported, the error starting with what `culprit()` names (made only then: this runs for
// every fate every frame). The text names no value, so that a term out of bounds every frame is
// one message, shown once.
template <class Culprit>
double checked_term(lua_State* L, game::Match& match, Culprit&& culprit) {
  if (lua_type(L, -1) != LUA_TNUMBER) {
    match.report_error(culprit() + "a " + luaL_typename(L, -1) + ", not a factor in [0, 1e6] (skipped)");
    return 1;
  }
  const game::BoundedFactor f = game::bounded_factor(lua_tonumber(L, -1));
  if (f.problem) match.report_error(culprit() + f.problem);
  return f.value;
}

}  // namespace quantum::lua

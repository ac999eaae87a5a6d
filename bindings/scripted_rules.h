// A sport written in Lua (rules/<sport>/sport.lua): its field, match settings, fate factors,
// handicaps, modifier hooks, event handlers, timers and announcer phrases, behind the game
// engine's Rules interface. The Lua API it sees is documented in docs/lua-api.md.
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
#include "lua_push.h"
#include "lua_sandbox.h"
#include "params.h"
#include "phrases.h"

namespace quantum::lua {

// A sport's sound, from sport.lua's `audio` table (docs/lua-api.md). Paths are resolved.
struct SportAudio {
  std::string voice = "en-us";
  int rate = 175, volume = 100;
  Vec2 listener{0, 0}, facing{1, 0};
  std::map<std::string, std::string, std::less<>> sounds;    // event type -> sound file
  std::map<std::string, std::string, std::less<>> recorded;  // phrase key -> sound file spoken instead
  std::map<std::string, int, std::less<>> priorities;        // event type (or "timer") -> announcer priority
  // Event types (or "timer") whose phrases, while still waiting, give way to newer ones.
  std::map<std::string, bool, std::less<>> supersede;
  float duck = 0.1f;       // game sounds' gain while the announcer speaks
  double repeat_gap = 2;   // seconds within which the same words are not said again
  int keep = 3;            // phrases of this priority or more wait as long as it takes (never stale)
  double wait_for = 1;     // a more urgent phrase lets one ending within this many seconds finish
};

// What loading sport.lua and the modules it requires may spend before a match: a second of CPU,
// as a field file gets (on a slow machine, or under the sanitizers, loading alone passed a
// frame's 20 ms). A reload loads between two frames of a running match: Limits{}, a frame's
// (Sport::reload).
inline constexpr Limits kLoadLimits{64u << 20, 100'000'000, 1.0};

class Sport final : public game::Rules {
 public:
  // `folder` holds sport.lua, or is a sport's name (find_sport); `engine` is where the engine's
  // own power-ups and helpers are (a replay uses the copy it recorded); `params` are what its
  // field and sport read with param() (params.h). Throws ScriptError naming the file (and line,
  // or the place in the returned table) for a script that does not load, FieldError for a bad
  // field, and std::invalid_argument for a parameter neither reads or a sport not found. Loading spends at most `load`; the
  // match's frames then get Limits{} each.
  explicit Sport(const std::string& folder, const std::filesystem::path& engine = engine_rules_folder(),
                 Params params = {}, const Limits& load = kLoadLimits);
  ~Sport() override;

  // `current`'s sport.lua loaded again while its match runs (a reload): all of it, and the
  // take_over that must follow, within one frame's budget (Limits{}), on the field `current`
  // plays on and with its parameters. The field file does not run again: a match keeps its
  // field, and a changed one takes effect at the next match. Throws as the constructor does.
  static std::unique_ptr<Sport> reload(const Sport& current);

  const std::string& name() const { return name_; }
  const std::string& folder() const { return folder_; }
  const std::filesystem::path& engine() const { return engine_; }
  const Params& params() const { return params_; }
  const Field& field() const { return field_; }
  // The field file sport.lua names, the one its next match loads (lexically normal).
  const std::filesystem::path& field_file() const { return field_file_; }
  uint32_t particles() const { return particles_; }
  double seconds() const { return seconds_; }
  double stall() const { return stall_; }  // match.stall: see game::MatchConfig::stall
  int first_spot() const { return first_spot_; }  // match.start: where the first ball drops...
  int first_holder() const { return first_holder_; }  // ...or who holds it (-1: nobody)
  // The sport's handicap for every body of the field (1 where it names none).
  const std::vector<double>& handicaps() const { return handicaps_; }
  // Automatic balance (sport.lua's `balance`): see game::MatchConfig.
  double balance_per_goal() const { return balance_per_goal_; }
  double balance_most() const { return balance_most_; }
  // How players throw (sport.lua's `throws`): a throw's speed when none is given, and its spread.
  double throw_speed() const { return throw_speed_; }
  double tackle_rate() const { return tackle_rate_; }  // tackles.rate: see game::MatchConfig::tackle_rate
  ThrowSpread throw_spread() const { return throw_spread_; }
  const SportAudio& audio() const { return audio_; }
  // Where power-up scripts are looked for, in order: the sport's own powerups/, the one beside
  // the sport's folder, the engine's.
  const std::vector<std::filesystem::path>& powerup_folders() const { return powerup_folders_; }
  // Where require() looks for the sport's Lua modules: the sport's folder, the engine's helpers.
  const std::vector<std::filesystem::path>& module_folders() const { return module_folders_; }

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
  bool powerup_disabled(const std::string& name) const { return disabled_powerups_.count(name) > 0; }

  // Says phrase `key` (or literal text) on the match; lookup(name) gives placeholder values.
  // Throws std::invalid_argument for a key the sport has no phrase for, or a placeholder
  // without a value.
  template <class Lookup>
  void say(game::Match& match, std::string_view key_or_text, Lookup&& lookup) {
    const PhraseTemplate* phrase = phrases_.find(key_or_text);
    if (!phrase && Phrases::looks_like_key(key_or_text)) unknown_phrase(key_or_text);
    const auto recorded = audio_.recorded.find(key_or_text);
    said_.clear();
    try {
      if (phrase) phrase->fill(said_, lookup);
      else PhraseTemplate(key_or_text).fill(said_, lookup);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument((phrase ? "phrase '" + std::string(key_or_text) + "': " : std::string()) + e.what());
    }
    match.say(said_, recorded == audio_.recorded.end() ? std::string_view() : std::string_view(recorded->second));
  }
  // The sport's phrase `key` when it has one, else the text `fallback` (the engine's own words).
  template <class Lookup>
  void say_or(game::Match& match, std::string_view key, std::string_view fallback, Lookup&& lookup) {
    say(match, phrases_.find(key) ? key : fallback, lookup);
  }
  // The host's own announcements (the match paused or resumed): say_or without placeholders.
  void say_host(game::Match& match, const std::string& key, const std::string& fallback);

  // Gives player `player` (a body index) the power-up `name`: its script (name.lua in the first
  // of powerup_folders() that has it) is loaded once, its start runs, and the match holds it
  // for opts.seconds (default the script's duration). `opts` are its numbers (strength, ...),
  // over the script's defaults. Throws ScriptError for a script that does not load,
  // std::invalid_argument for a bad name or value.
  void grant(game::Match& match, int player, const std::string& name, std::map<std::string, double> opts);

  // Loads the power-ups `names` again from their files (they changed), between two frames: all of
  // them within one frame's budget, a period of their own (begin_frame's: the frame before keeps
  // its overrun counted; the next frame starts whole, as what a failed version spent is no
  // script's that plays on). Returns each one's error (a ScriptError's, naming the file and line,
  // or a ReadError's), "" when it loaded; one that does not load keeps the version loaded before.
  // Names not loaded yet are skipped: they load fresh when granted.
  std::vector<std::string> reload_powerups(const std::vector<std::string>& names, game::Match& match);
  bool has_powerup(const std::string& name) const { return powerups_.count(name) > 0; }

  // After a reload: this (new) sport takes over from `old`, in what is left of reload()'s budget:
  // the power-ups the match holds load, then its `on_reload(game, state)` gets a copy of the old
  // sport table's `state` (plain data: numbers, strings, booleans, tables); without one, the copy
  // becomes its `state`. The old version's timers are not carried.
  void take_over(Sport& old, game::Match& match);

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
  // A team's display name (sport.lua's `teams`), else the team's own name.
  std::string team_name(const std::string& team) const;

 private:
  struct Script;
  // Loads sport.lua within `load`; `playing` is the field of the match a reload joins (kept, with
  // the parameters its file read), null to load the one sport.lua names.
  Sport(const std::string& folder, const std::filesystem::path& engine, Params params, const Limits& load,
        const Field* playing);
  struct Timer {
    double due;
    int id;
    int function;  // registry reference
    bool is_due(double now) const { return due <= now + 1e-9; }
  };
  // While a handler, timer or power-up callback runs, the match it may act on.
  class Acting;

  void read_sport(int table);
  void read_match(const class Reader& r, int table);
  void read_audio(const class Reader& r, int table);
  void check_phrases() const;
  void check_said_keys() const;
  [[noreturn]] void unknown_phrase(std::string_view key) const;
  int powerup(const std::string& name);  // loads it on first use; its table's registry reference
  // The script of the power-up of that (plain) name in powerup_folders(), or an empty path
  // (`looked`: where it was looked for). Throws ReadError for one that is not a regular file or
  // leads out of the folders.
  std::filesystem::path powerup_file(const std::string& name, std::string& looked) const;
  // Which factor made a fate 0: none, the sport's factors by kind, modifiers[i], or the j-th
  // active power-up.
  static constexpr int kNotZeroed = -1, kKindFactor = 0;
  static int modifier_code(size_t i) { return int(i); }           // 1-based, as Lua counts
  static int powerup_code(size_t j) { return -2 - int(j); }
  // Multiplies the active power-ups' factors for fates[fate] into `factor`, each a term.
  void powerup_factors(size_t fate, game::Match& match, double& factor, game::FactorTerms& terms);
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
  void grant_protected(game::Match& match, int player, const std::string& name, std::map<std::string, double> opts);
  void carry_state(Sport& old, game::Match& match);
  void note_overrun(game::Match& match);
  // The sandbox was abandoned (lua_sandbox.h): the sport is disabled, said once. Nothing may
  // touch its Lua state after that.
  bool stuck(game::Match& match);
  void announce_powerup(const game::GameEvent& e, game::Match& match);
  void report_zeroing(std::span<const game::FateView> fates, game::Match& match);

  std::string folder_, file_, name_;
  std::filesystem::path engine_;
  std::vector<std::filesystem::path> powerup_folders_, module_folders_;
  Params params_;  // before the sandbox: its `param` function points here
  Sandbox::Ptr sandbox_;
  int sport_ref_ = LUA_NOREF, game_ref_ = LUA_NOREF;
  std::filesystem::path field_file_;
  Field field_;
  uint32_t particles_ = 1000;
  double seconds_ = 180;
  double stall_ = game::MatchConfig{}.stall;
  int first_spot_ = 0;
  int first_holder_ = -1;
  std::vector<double> handicaps_;
  double balance_per_goal_ = 0, balance_most_ = 2;
  double throw_speed_ = 10;
  double tackle_rate_ = 0;
  ThrowSpread throw_spread_;
  Phrases phrases_;
  std::map<std::string, std::string> team_names_;
  std::map<std::string, int> powerups_;       // loaded power-up scripts: name -> their table in the registry
  std::map<std::string, std::string> powerup_files_;
  SportAudio audio_;
  std::vector<Timer> timers_;
  int next_timer_ = 1;
  TablePool fate_tables_, player_tables_, powerup_tables_;
  std::vector<int> zeroed_by_;           // per fate: which factor made it 0 (codes above)
  double by_kind_[kFateKindCount];       // the sport's factors by kind, as last read (used while Lua cannot run)
  std::map<std::string, int> overruns_;  // per script ("" the sport's own, else a power-up): budgets spent
  bool disabled_ = false;
  std::set<std::string> disabled_powerups_;
  std::string said_;                     // the phrase being filled (its room is kept)
  std::string modifiers_broken_by_;      // "file:line: " (see call), "" while the modifiers are usable
  game::Match* match_ = nullptr;
  const game::Match* reading_ = nullptr;
};

// Builds the `game` table the handlers receive (wrap_game.cpp).
void push_game_api(lua_State* L, Sport* sport);

// The player (body index) of that name; throws ArgError naming the nearest one otherwise.
int player_index(const game::Match& match, const std::string& name);

}  // namespace quantum::lua

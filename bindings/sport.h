// A sport written in Lua (rules/<sport>/sport.lua): its field, match settings, fate factors,
// handicaps, modifier hooks, event handlers and announcer phrases, behind the game engine's
// Rules interface. The Lua API it sees is documented in docs/lua-api.md.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "game/game.h"
#include "lua_sandbox.h"

namespace quantum::lua {

// A sport's sound, from sport.lua's `audio` table (docs/lua-api.md). Paths are resolved.
struct SportAudio {
  std::string voice = "en";
  int rate = 175, volume = 100;
  Vec2 listener{0, 0}, facing{1, 0};
  std::map<std::string, std::string> sounds;      // event type -> sound file
  std::map<std::string, std::string> recorded;    // phrase key -> sound file spoken instead
  std::map<std::string, int> priorities;          // event type -> announcer priority
};

class Sport final : public game::Rules {
 public:
  // `folder` holds sport.lua. Throws ScriptError naming the file (and line) for a script that
  // does not load, and FieldError for a bad field.
  explicit Sport(const std::string& folder);
  ~Sport() override;

  const std::string& name() const { return name_; }
  const std::string& folder() const { return folder_; }
  const Field& field() const { return field_; }
  uint32_t particles() const { return particles_; }
  double seconds() const { return seconds_; }
  int first_spot() const { return first_spot_; }  // match.start: where the first ball drops
  // The sport's handicap for every body of the field (1 where it names none).
  const std::vector<double>& handicaps() const { return handicaps_; }
  // Automatic balance (sport.lua's `balance`): see game::MatchConfig.
  double balance_per_goal() const { return balance_per_goal_; }
  double balance_most() const { return balance_most_; }
  const SportAudio& audio() const { return audio_; }

  // Replaces the sport's factor for a fate kind (goal, own_goal, body, out, field), e.g. to
  // compare a sport's factors with none. Throws std::invalid_argument for an unknown kind or a
  // value that is not a number >= 0.
  void set_factor(const std::string& kind, double value);

  std::vector<double> factors(std::span<const game::FateView> fates, game::Match& match) override;
  void on_event(const game::GameEvent& event, game::Match& match) override;

  void read_audio(int table);

  // "{team} shoots" with {team = "Blue"}: a phrase of the sport by key, or the text itself.
  std::string phrase(const std::string& key_or_text, const std::map<std::string, std::string>& vars) const;

  // Gives player `player` (a body index) the power-up `name`: its script (powerups/<name>.lua in
  // the sport's folder, else in the folder beside it, rules/powerups/) is loaded once, its start
  // runs, and the match holds it for opts.seconds (default the script's duration). `opts` are its
  // numbers (strength, ...), over the script's defaults. Throws ScriptError for a script that
  // does not load, std::invalid_argument for a bad name or value.
  void grant(game::Match& match, int player, const std::string& name, std::map<std::string, double> opts);

  // Loads power-up `name` again from its file (it changed). Throws ScriptError, naming the file
  // and line, when it does not load; the version loaded before stays.
  void reload_powerup(const std::string& name);
  bool has_powerup(const std::string& name) const { return powerups_.count(name) > 0; }

  // After a reload: this (new) sport takes over from `old`. Its `on_reload(game, state)` gets a
  // copy of the old sport table's `state` (plain data: numbers, strings, booleans, tables);
  // without one, the copy becomes its `state`.
  void take_over(Sport& old, game::Match& match);

  // For wrap_game.cpp: the match the current call acts on.
  game::Match* match() const { return match_; }
  const game::Match* reading() const { return reading_; }
  lua_State* L() const { return sandbox_.L(); }

 private:
  std::string folder_, file_, name_;
  Sandbox sandbox_;
  int sport_ref_ = LUA_NOREF, game_ref_ = LUA_NOREF;
  Field field_;
  uint32_t particles_ = 1000;
  double seconds_ = 180;
  int first_spot_ = 0;
  std::vector<double> handicaps_;
  double balance_per_goal_ = 0, balance_most_ = 2;
  std::map<std::string, std::string> phrases_;
  std::map<std::string, int> powerups_;  // loaded power-up scripts: name -> their table in the registry
  int powerup(const std::string& name);  // loads it on first use
  double powerup_factors(const game::FateView& fate, game::Match& match);
  void announce_powerup(const game::GameEvent& e, game::Match& match);
  SportAudio audio_;
  game::Match* match_ = nullptr;
  const game::Match* reading_ = nullptr;
};

// Builds the `game` table the handlers receive (wrap_game.cpp).
void push_game_api(lua_State* L, Sport* sport);

}  // namespace quantum::lua

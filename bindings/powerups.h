// Power-ups: scripts a player holds for a while (rules/powerups/<name>.lua, or a sport's own),
// each a factor on the fates and, at its start and end, what it does to the match and what the
// announcer says. They run in their sport's sandbox, with its budget (scripted_rules.h), and are
// loaded when first granted. The Lua API is in docs/lua-api.md, "Power-ups".
#pragma once

#include <filesystem>
#include <map>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "game/game.h"
#include "phrases.h"

namespace quantum::lua {

class ScriptedRules;

// The placeholders the engine fills in a power-up's phrases.
inline const std::vector<std::string> kPowerupVars = {"player", "team"};

// A power-up's name is its script's file name, without the folder: no path reaches out of them.
bool plain_powerup_name(const std::string& name);
// The script of the power-up of that (plain) name in `folders`, or an empty path (`looked`: where
// it was looked for). Throws ReadError for one that is not a regular file or leads out of them.
std::filesystem::path powerup_file(const std::vector<std::filesystem::path>& folders, const std::string& name,
                                   std::string& looked);
// Checks a phrase the engine says itself: every placeholder is one of `allowed` (what the
// engine fills in, always text), none with a number format. Throws ReadError naming `place`.
void check_engine_phrase(const std::string& place, const PhraseTemplate& phrase, std::span<const std::string> allowed);

// The power-ups of one loaded sport: their scripts, loaded once, and those disabled for overrunning.
class Powerups {
 public:
  explicit Powerups(ScriptedRules& rules) : rules_(rules) {}
  Powerups(const Powerups&) = delete;
  Powerups& operator=(const Powerups&) = delete;

  // Gives player `player` (a body index) the power-up `name`: its script (name.lua in the first
  // of the sport's power-up folders that has it) is loaded once, its start runs, and the match
  // holds it for opts.seconds (default the script's duration). `opts` are its numbers (strength,
  // ...), over the script's defaults. Runs inside the sandbox's protect. Throws ScriptError for a
  // script that does not load, std::invalid_argument for a bad name or value.
  void grant(game::Match& match, int player, const std::string& name, std::map<std::string, double> opts);
  // Multiplies the active power-ups' factors for fates[fate] into `factor`, each a term.
  void factors(size_t fate, game::Match& match, double& factor, game::FactorTerms& terms);
  // A power-up starts or ends (its event): its phrase is said, and at its end its stop runs.
  void announce(const game::GameEvent& e, game::Match& match);
  // The power-ups the match holds load now (a new version of the sport: loading is the engine's
  // work, not its first frame's). One that fails to load is reported when a frame asks for it.
  void load_held(const game::Match& match);

  // Loads the power-ups `names` again from their files (they changed), between two frames: all of
  // them within one frame's budget, a period of their own (begin_frame's: the frame before keeps
  // its overrun counted; the next frame starts whole, as what a failed version spent is no
  // script's that plays on). Returns each one's error (a ScriptError's, naming the file and line,
  // or a ReadError's), "" when it loaded; one that does not load keeps the version loaded before.
  // Names not loaded yet are skipped: they load fresh when granted.
  std::vector<std::string> reload(const std::vector<std::string>& names, game::Match& match);

  bool has(const std::string& name) const { return scripts_.count(name) > 0; }
  bool disabled(const std::string& name) const { return disabled_.count(name) > 0; }
  // Disables `name` for the rest of the match; false when it was already.
  bool disable(const std::string& name) { return disabled_.insert(name).second; }
  // The power-up whose script is `file`, "" for none.
  std::string named_by(const std::string& file) const;
  // The script of a loaded power-up.
  const std::string& file(const std::string& name) { return files_[name]; }

 private:
  int script(const std::string& name);  // loads it on first use; its table's registry reference

  ScriptedRules& rules_;
  std::map<std::string, int> scripts_;  // loaded power-up scripts: name -> their table in the registry
  std::map<std::string, std::string> files_;
  std::set<std::string> disabled_;
};

}  // namespace quantum::lua

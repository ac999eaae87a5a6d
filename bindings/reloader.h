// Hot reload while a match runs: the sport's folder, its power-up folders and the engine's Lua
// helpers are watched (inotify); a changed sport.lua (or a module it requires) or power-up
// script in use is loaded again between two frames, within a frame's budget, and the match
// plays on with it. A script that fails to load is reported and the old one keeps running. Only
// what changed is loaded: the field stays the match's, and a changed one waits for the next
// match.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "game/game.h"
#include "scripted_rules.h"

namespace quantum::lua {

class Reloader {
 public:
  // Watches what `sport` loads from. `factors`: overrides of the sport's factors, applied to
  // every reloaded version too. Without `watch_files` only changed() counts (a replay applies
  // the changes it recorded, nothing else). Throws std::runtime_error when the folders cannot be
  // watched.
  Reloader(const ScriptedRules& sport, std::map<std::string, double> factors = {}, bool watch_files = true);
  ~Reloader();
  Reloader(const Reloader&) = delete;
  Reloader& operator=(const Reloader&) = delete;

  // Takes `file` as changed, as if it had been saved (the next poll reloads it).
  void changed(const std::filesystem::path& file);

  // Reloads whatever changed since the last call, all within one frame's budget
  // (ScriptedRules::reload, ScriptedRules::reload_powerups). A new sport takes over from `sport`
  // (state carried, see ScriptedRules::take_over) and becomes the match's rules; `sport` then
  // owns it. Each reload is one
  // line on `errors`: "quantum: reloaded FILE" (or "power-up NAME"), or "quantum: reload failed:
  // FILE:LINE: ...". A changed field file (or sport.lua naming another) is not loaded: the
  // first is one line, "quantum: FILE changed: the new field takes effect at the next match", and
  // the rest say nothing. Returns the number of files reloaded.
  // `acted_on`, when given, gets every changed file the poll saw, loaded or not: what a recording
  // keeps.
  int poll(std::unique_ptr<ScriptedRules>& sport, game::Match& match, std::ostream& errors,
           std::vector<std::filesystem::path>* acted_on = nullptr);
  // The reloads that failed and have not loaded since: script ("sport.lua", a power-up's name)
  // -> what failed ("FILE:LINE: ..."), for a view's error screen.
  const std::map<std::string, std::string>& failures() const { return failures_; }

 private:
  std::filesystem::path folder_;
  std::map<std::string, double> factors_;
  int fd_ = -1;
  std::map<int, std::filesystem::path> watches_;  // watch descriptor -> folder
  std::set<std::filesystem::path> powerup_folders_, module_folders_;
  std::set<std::filesystem::path> changed_;
  std::map<std::string, std::string> failures_;
  bool field_told_ = false;

  void field_waits(const std::filesystem::path& file, std::ostream& errors);
};

}  // namespace quantum::lua

// Hot reload while a match runs: the sport's folder and the power-ups beside it are watched
// (inotify); a changed sport.lua or power-up script is loaded again between two frames, and the
// match plays on with it. A script that fails to load is reported and the old one keeps running.
#pragma once

#include <iosfwd>
#include <map>
#include <memory>
#include <string>

#include "game/game.h"
#include "sport.h"

namespace quantum::tools {

class RulesReloader {
 public:
  // `factors`: overrides of the sport's factors, applied to every reloaded version too.
  // Throws std::runtime_error when the folders cannot be watched.
  RulesReloader(const std::string& sport_folder, std::map<std::string, double> factors = {});
  ~RulesReloader();
  RulesReloader(const RulesReloader&) = delete;
  RulesReloader& operator=(const RulesReloader&) = delete;

  // Reloads whatever changed since the last call. A new sport takes over from `sport` (state
  // carried, see Sport::take_over) and becomes the match's rules; `sport` then owns it. Each
  // failure is one line on `errors`, "quantum: reload failed: FILE:LINE: ...". Returns the
  // number of files reloaded.
  int poll(std::unique_ptr<lua::Sport>& sport, game::Match& match, std::ostream& errors);

 private:
  std::string folder_;
  std::map<std::string, double> factors_;
  int fd_ = -1;
  std::map<int, std::string> watches_;  // watch descriptor -> folder
};

}  // namespace quantum::tools

// Where a session's sport comes from: its data (game::SportSpec) and the rules that play it, and,
// between frames, new versions of them when their files change. The runtime declares what it
// asks and knows no scripting language; the program layer hands it a loader (tools/lua_sport.h:
// the sports written in Lua), and a test may hand it plain rules.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "game/game.h"
#include "game/sport_spec.h"

namespace quantum::runtime {

// What a session asks its loader for.
struct SportRequest {
  std::string sport;             // a sport's folder or name
  std::filesystem::path engine;  // the engine's own rules to use (a replay's copy); empty: the installed ones
  std::vector<std::string> params;        // NAME=VALUE for the sport's files
  std::map<std::string, double> factors;  // overrides of the sport's factors by fate kind, on every version
  // Reloads: none, the files that change while the match runs (--watch), or only those a
  // recording says changed (changed()).
  enum class Reloads { None, Watched, Told } reloads = Reloads::None;
};

class SportSource {
 public:
  virtual ~SportSource() = default;
  // The version playing now: a reload replaces both, so hold neither across frames.
  virtual const game::SportSpec& spec() const = 0;
  virtual game::Rules& rules() = 0;
  // Takes `file` as changed, as if it had been saved (the next reload() loads it).
  virtual void changed(const std::filesystem::path& file) = 0;
  // Between two frames: loads whatever changed, within one frame's budget, and makes the new
  // rules the match's (Match::set_rules). One line per reload on `errors` ("quantum: reloaded
  // FILE", "quantum: reload failed: FILE:LINE: ..."). Returns how many files were reloaded;
  // `acted_on`, when given, gets every changed file seen, loaded or not (what a recording keeps).
  virtual int reload(game::Match& match, std::ostream& errors, std::vector<std::filesystem::path>* acted_on) = 0;
  // The reloads that failed and have not loaded since: script -> what failed ("FILE:LINE: ...").
  virtual const std::map<std::string, std::string>& failures() const = 0;
};

// Loads a sport. Throws, naming the file and place, for a sport that does not load.
using SportLoader = std::function<std::unique_ptr<SportSource>(const SportRequest&)>;

}  // namespace quantum::runtime

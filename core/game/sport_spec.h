// A sport as data: its field, the settings of its matches, its handicaps, its phrases and its
// sound, and where its files are. A loader makes it (bindings/sport_loader.h reads sport.lua),
// and the rules that play it come beside it (game::Rules: the sport's scripts, or PlainRules).
// A session builds its match from this alone, whatever language the rules are written in.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "game/game.h"

namespace quantum::game {

// A sport's sound, from sport.lua's `audio` table (docs/lua-api.md); paths are resolved. The
// game engine only carries it: the runtime's sound (runtime/match_audio.h) plays it.
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

struct SportSpec {
  std::string name;
  std::string folder;            // the sport's folder, lexically normal
  std::filesystem::path engine;  // where the engine's power-ups and helpers come from (a replay: its copy)
  std::filesystem::path field_file;  // the field file the next match loads (lexically normal)
  Field field;
  // The sport's match settings (particles, time limit, stall, where the ball starts, balance,
  // throws, tackles); the seed, the threads and the frame rate are the session's to set.
  MatchConfig match;
  std::vector<double> handicaps;  // one per body of the field (1 where the sport names none)
  // Each fate kind's factor as the sport loaded (overrides given to the loader included); its
  // rules may change them during a match.
  double factors[kFateKindCount];
  std::map<std::string, std::string, std::less<>> phrases;     // key -> template ("{team} shoots")
  std::map<std::string, std::string, std::less<>> team_names;  // team -> its name as the announcer says it
  SportAudio audio;
  std::vector<std::string> params;  // "name=value", what the sport was loaded with (the command line's)

  SportSpec() { std::fill(std::begin(factors), std::end(factors), 1.0); }
  // A team's display name (sport.lua's `teams`), else the team's own name.
  std::string team_name(std::string_view team) const;
};

// The host's own announcements (the match paused or resumed): the sport's phrase `key` when it
// has one (a phrase the engine says has no placeholders: the loader checks), else `fallback`.
void say_host(const SportSpec& sport, Match& match, std::string_view key, std::string_view fallback);

}  // namespace quantum::game

// `quantum play`: a match of a sport (rules/<sport>) between simulated players or tracked ones,
// told by the announcer as a transcript and written out as JSON-lines events.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "game/game.h"

namespace quantum::tools {

struct PlayOptions {
  std::string sport = "rules/airhockey";
  std::string input = "bots";   // or a tracking source: fakenect:DIR, kinect, video:FILE, camera:N, tuio:PORT
  uint64_t seed = 1;
  double seconds = 0;           // 0: the sport's own time limit
  uint32_t particles = 0;       // 0: the sport's own
  std::string events;           // JSON-lines file, "-" for stdout, empty for none
  std::vector<double> skills;   // per player, 0..1; empty: 0.6 each
  std::vector<double> handicaps;  // per player; empty: the sport's
  double auto_balance = -1;       // handicap boost per goal behind; < 0: the sport's (docs/lua-api.md)
  std::map<std::string, double> factors;  // overrides of the sport's factors by fate kind
  std::string audio = "none";             // "" the sound card, "none", "wav:FILE" (see MatchAudio)
  bool transcript = true;
  bool watch = true;                      // reload the sport's and power-ups' scripts when they change
};

struct PlayResult {
  std::map<std::string, int> score;
  std::string winner;  // "" for a draw
  game::RallyStats stats;
  int rule_errors = 0;
};

// Plays one match. The transcript and the closing summary go to `out`, rule errors to `errors`.
// Throws on bad options, a sport that does not load or a bad field.
PlayResult play(const PlayOptions& options, std::ostream& out, std::ostream& errors);

struct BalanceResult {
  int matches = 0, draws = 0;
  std::map<std::string, int> wins;  // by team
  double contacts_per_rally = 0;    // over all rallies of all matches
  double goals_per_minute = 0;      // over all time played
};

// Plays `matches` matches with seeds options.seed, options.seed + 1, ... on every core, without
// transcripts. The result depends only on the options, not on the number of cores.
BalanceResult balance(const PlayOptions& options, int matches);

// "0.3,0.9" -> {0.3, 0.9}; throws naming the option for anything else.
std::vector<double> parse_list(const std::string& text, const std::string& option);

}  // namespace quantum::tools

// `quantum play` and `quantum balance`: matches of a sport (rules/<sport>) run through a
// runtime::Session, told as a transcript and JSON-lines events, with a closing summary.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "game/game.h"
#include "session.h"

namespace quantum::tools {

struct PlayResult {
  std::map<std::string, int> score;
  std::string winner;  // "" for a draw
  game::RallyStats stats;
  int rule_errors = 0;
};

struct DeskOptions;

// Plays one match, at the desk when `desk` asks for a view, a video, a snapshot or the mouse
// (desk.h). The transcript and the closing summary go to `out` (none when `transcript` is
// false), rule errors and warnings to `errors`. Throws on bad options, a sport that does not
// load or a bad field.
PlayResult play(const runtime::SessionOptions& options, std::ostream& out, std::ostream& errors, bool transcript = true,
                const DeskOptions* desk = nullptr);

struct BalanceResult {
  int matches = 0, draws = 0;
  std::map<std::string, int> wins;  // by team
  double contacts_per_rally = 0;    // over all rallies of all matches
  double goals_per_minute = 0;      // over all time played
  int possessions = 0;              // sports of catching: times a team gained the ball...
  double passes_per_possession = 0;  // ...and the passes it made, on average, before losing it
};

// Plays `matches` matches with seeds options.seed, options.seed + 1, ... on every core, without
// transcripts, sound or logs. The result depends only on the options, not on the number of cores.
BalanceResult balance(const runtime::SessionOptions& options, int matches);

// "realtime" or "fast", as --pace says it.
runtime::SessionOptions::Pacing pacing(const std::string& pace);

// "0.3,0.9" -> {0.3, 0.9}; throws naming the option for anything else.
std::vector<double> parse_list(const std::string& text, const std::string& option);

}  // namespace quantum::tools

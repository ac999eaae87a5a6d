// `quantum balance`: many seeded matches between simulated players, their win rates and gameflow,
// every match as a CSV row, and with --plot a sweep of handicaps and fate factors drawn by
// gnuplot with a one-page summary (docs/gameflow.md).
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "play.h"
#include "session.h"

namespace quantum::tools {

struct BalanceResult {
  int matches = 0, draws = 0;
  std::map<std::string, int> wins;  // by team
  Counted counted;                  // what the sport counts (its field's kind of play)...
  Figures totals;                   // ...over all matches: its figures are describe(counted, totals)
  int stalls = 0, stalled_matches = 0;  // stalled events (the sport's bound without play), and matches with any
  std::vector<uint64_t> seeds;      // one per match, in order
  std::vector<PlayResult> results;
};

// Plays `matches` matches with seeds options.seed, options.seed + 1, ... on every core, without
// transcripts, sound or logs; `progress(done)` is called (from any thread, one at a time) as each
// ends. The result depends only on the options, not on the number of cores.
BalanceResult balance(const runtime::SessionOptions& options, int matches,
                      const std::function<void(int done)>& progress = {});

// One row per match: seed, winner, each team's score, rallies, contacts, goals, passes,
// possessions, seconds, stalls, then `extra` columns (a sweep's value) named in `extra_names`; the
// header first when `header` (a sweep's later points append to its first's).
void write_csv(std::ostream& out, const BalanceResult& r, const std::vector<std::string>& extra_names = {},
               const std::vector<double>& extra = {}, bool header = true);

// The points of a --plot sweep: five handicaps of the first team, four strengths of the fate
// factors. A study with --plot plays matches + kSweepPoints * sweep_matches matches.
inline constexpr int kSweepPoints = 9;

// --plot DIR: the study's CSV, a sweep of the first team's handicap and one of the fate factors'
// strength (each point `sweep_matches` matches), their PNG plots (gnuplot) and summary.md. Each
// sweep's point is named on `log` as it starts; `progress` (if any) counts the study's matches,
// the sweeps' after the study's own. Returns what DIR holds, for its confirmation line. Throws
// when DIR cannot be written or gnuplot fails.
runtime::Written plot_study(const runtime::SessionOptions& options, const BalanceResult& study, int sweep_matches,
                            const std::string& dir, runtime::ProgressLine* progress, std::ostream& log);

}  // namespace quantum::tools

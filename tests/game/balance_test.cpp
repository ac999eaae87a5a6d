// Handicaps, measured as the issue asks: a weak simulated player (skill 0, Red) against a strong
// one (skill 1, Blue) over 200 seeded matches, without and with a handicap of 2 for the weak
// one (since bounces are heard, skill counts for much more: docs/gameflow.md). Fixed seeds; 300
// particles keep the 400 matches within a minute on two cores. And the automatic balance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <map>

#include <unistd.h>

#include "balance.h"
#include "field_loader.h"
#include "scripted_rules.h"

namespace quantum {
namespace {

constexpr int kMatches = 200;
int progress_calls = 0;

double red_win_rate(double red_handicap) {
  runtime::SessionOptions o;
  o.particles = 300;
  o.skills = {1.0, 0.0};
  o.handicaps = {1.0, red_handicap};
  const tools::BalanceResult r = tools::balance(o, kMatches);
  EXPECT_EQ(r.matches, kMatches);
  return double(r.wins.at("red")) / kMatches;
}

TEST(Balance, HandicapBringsTheWeakPlayerCloserToEven) {
  const double without = red_win_rate(1.0), with = red_win_rate(2.0);
  std::cout << "weak player's win rate: " << without << " without a handicap, " << with << " with 2\n";
  // The weak player loses more than half: one-sided z-test against 50 %, rejected at p < 0.01.
  const double z_weak = (without - 0.5) / std::sqrt(0.25 / kMatches);
  EXPECT_LT(z_weak, -2.33) << "skill makes no difference: " << without;
  // The handicap raises its win rate: two-proportion z-test, rejected at p < 0.001 (one-sided).
  const double pooled = (without + with) / 2;
  const double z_gain = (with - without) / std::sqrt(pooled * (1 - pooled) * 2.0 / kMatches);
  EXPECT_GT(z_gain, 3.09) << without << " -> " << with;
  // ...and brings it closer to even.
  EXPECT_LT(std::fabs(with - 0.5), std::fabs(without - 0.5));
}

// Matches are spread over threads; the totals must be those of the same seeds played one by one.
TEST(Balance, ResultsDoNotDependOnHowMatchesAreSpread) {
  runtime::SessionOptions o;
  o.particles = 200;
  o.seconds = 20;
  o.seed = 11;
  const tools::BalanceResult all = tools::balance(o, 6);
  std::map<std::string, int> wins;
  int draws = 0;
  for (int k = 0; k < 6; ++k) {
    runtime::SessionOptions one = o;
    one.seed = o.seed + uint64_t(k);
    const tools::BalanceResult r = tools::balance(one, 1);
    draws += r.draws;
    for (const auto& [team, n] : r.wins) wins[team] += n;
  }
  EXPECT_EQ(wins, all.wins);
  EXPECT_EQ(draws, all.draws);
  EXPECT_THROW(tools::balance(o, 0), std::invalid_argument);
}

// The automatic balance: each goal behind multiplies the trailing team's handicaps by 1 + per
// goal, up to `most` times their own; the leaders keep theirs.
TEST(Balance, AutoBalanceBoostsTheTrailingTeamPerGoalUpToItsMost) {
  lua::ScriptedRules sport(QUANTUM_SOURCE_DIR "/rules/airhockey");
  game::MatchConfig config;
  config.particles = 100;
  config.balance_per_goal = 0.5;
  config.balance_most = 2;
  game::Match match(sport.spec().field, config, sport, {1.0, 1.2});
  EXPECT_DOUBLE_EQ(match.handicap_now(0), 1.0);
  EXPECT_DOUBLE_EQ(match.handicap_now(1), 1.2);
  match.award("red", 1);
  EXPECT_DOUBLE_EQ(match.handicap_now(0), 1.5);  // Blue trails by one
  EXPECT_DOUBLE_EQ(match.handicap_now(1), 1.2);
  match.award("red", 2);
  EXPECT_DOUBLE_EQ(match.handicap_now(0), 2.0);  // 1.5^3 = 3.375, held at twice its own
  match.award("blue", 4);
  EXPECT_DOUBLE_EQ(match.handicap_now(0), 1.0);
  EXPECT_DOUBLE_EQ(match.handicap_now(1), 1.2 * 1.5);
  config.balance_per_goal = -1;
  EXPECT_THROW(game::Match(sport.spec().field, config, sport), std::invalid_argument);
}

std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

bool is_png(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return std::string(magic + 1, 3) == "PNG" && std::filesystem::file_size(file) > 5000;
}

// --plot: every match a CSV row, the sweeps' PNG plots (gnuplot) and a summary that shows them;
// one progress line counts the study's matches and the sweeps' after them (a clock of the test's
// own, a second a call, draws it at every call), and the folder is confirmed with what it holds.
TEST(Balance, APlottedStudyWritesEveryMatchItsPlotsAndASummary) {
  runtime::SessionOptions o;
  o.particles = 200;
  o.seconds = 15;
  progress_calls = 0;
  const tools::BalanceResult study = tools::balance(o, 4, [](int done) { progress_calls = std::max(progress_calls, done); });
  EXPECT_EQ(progress_calls, 4);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "quantum_balance_plot";
  std::filesystem::remove_all(dir);
  std::ostringstream log, told;
  double now = 0;
  runtime::ProgressLine progress(told, true, "balance", 4 + tools::kSweepPoints * 2, "matches", 0, [&] { return now += 1; });
  const runtime::Written written = tools::plot_study(o, study, 2, dir.string(), &progress, log);
  EXPECT_NE(told.str().find("\rbalance: 6 of 22 matches (27 %), 0:"), std::string::npos) << told.str();
  EXPECT_NE(told.str().find("\rbalance: 22 of 22 matches (100 %)"), std::string::npos) << told.str();
  EXPECT_EQ(written.path, dir.string());
  EXPECT_EQ(written.what, "summary.md, 3 PNG plots and 5 CSV files, 22 matches in all");
  const std::vector<std::string> matches = lines_of(dir / "matches.csv");
  ASSERT_EQ(matches.size(), 5u);  // a header and four matches
  EXPECT_EQ(matches[0], "seed,winner,score_blue,score_red,rallies,contacts,goals,passes,possessions,seconds,stalls");
  EXPECT_EQ(matches[1].rfind("1,", 0), 0u) << matches[1];
  EXPECT_EQ(lines_of(dir / "handicap_sweep.csv").size(), 6u);   // five handicaps
  EXPECT_EQ(lines_of(dir / "handicap_matches.csv").size(), 11u);  // two matches each
  EXPECT_EQ(lines_of(dir / "factor_sweep.csv").size(), 5u);     // four strengths
  EXPECT_EQ(lines_of(dir / "factor_matches.csv").size(), 9u);
  for (const char* png : {"win_rate_vs_handicap.png", "contacts_vs_factors.png", "goals_vs_factors.png"}) {
    EXPECT_TRUE(is_png(dir / png)) << png;
    EXPECT_NE(lines_of(dir / "summary.md").size(), 0u);
  }
  std::string summary;
  for (const std::string& line : lines_of(dir / "summary.md")) summary += line + "\n";
  // Air hockey counts contacts and goals; its score is its goals, so no points besides.
  for (const char* part : {"![win rate](win_rate_vs_handicap.png)", "| Blue |", "Contacts per rally", "goals per minute"})
    EXPECT_NE(summary.find(part), std::string::npos) << part << "\n" << summary;
  EXPECT_EQ(summary.find("points per minute"), std::string::npos) << summary;
}

// Basketball's score is points (2 or 3 a basket): the study reads the sport's own score.
TEST(Balance, ASportsOwnScoreIsSummarisedNotItsGoals) {
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/basketball";
  o.seconds = 60;
  const tools::BalanceResult r = tools::balance(o, 2);
  int goals = 0, points = 0;
  for (const tools::PlayResult& p : r.results) {
    goals += p.stats.goals;
    for (const auto& [team, n] : p.score) points += n;
  }
  ASSERT_GT(goals, 0);
  EXPECT_GE(points, 2 * goals);
  EXPECT_EQ(r.totals.goals, goals);
  EXPECT_EQ(r.totals.points, points);
  // A sport of holding whose score is not its goals says passes, goals and its own points.
  const std::string told = tools::describe(r.counted, r.totals);
  for (const char* part : {"passes per possession", "goals per minute", "points per minute"})
    EXPECT_NE(told.find(part), std::string::npos) << part << ": " << told;
}

// `quantum balance --csv FILE` confirms the file on stderr once it is whole; the summary on stdout
// is as it was.
TEST(Balance, TheCsvIsConfirmedOnceWritten) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("quantum_balance_csv_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string csv = (dir / "matches.csv").string(), err = (dir / "stderr.txt").string();
  const int status = std::system((QUANTUM_BINARY " balance " QUANTUM_SOURCE_DIR "/rules/airhockey --matches 2 --seconds 3 "
                                  "--particles 200 --csv " + csv + " >/dev/null 2>" + err).c_str());
  EXPECT_EQ(status, 0);
  const std::vector<std::string> said = lines_of(err);
  ASSERT_EQ(said.size(), 1u);
  EXPECT_EQ(said[0].rfind("quantum: wrote " + csv + ": 2 matches, ", 0), 0u) << said[0];
  std::filesystem::remove_all(dir);
}

}  // namespace
// A court of hits without goals counts touches per rally and the points it scores, no goals.
TEST(Balance, ASportOfHitsCountsTouchesAndPointsNotGoals) {
  const tools::Counted court = tools::counted(lua::load_field(QUANTUM_SOURCE_DIR "/tests/sports/rally/field.lua"));
  EXPECT_EQ(court.play, tools::Counted::Play::Hits);
  EXPECT_FALSE(court.goals);
  const std::string told = tools::describe(court, {.rallies = 4, .contacts = 38, .points = 4, .seconds = 120});
  EXPECT_EQ(told, "touches per rally 9.50, points per minute 2.00 (the sport's score)");
  EXPECT_EQ(tools::counted(lua::load_field(QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua")).play, tools::Counted::Play::Strikes);
}

}  // namespace quantum

#include "balance.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "output_files.h"
#include "quantum/fate.h"
#include "scripted_rules.h"

namespace quantum::tools {
namespace {

namespace fs = std::filesystem;

// A 95 % Wilson interval for k successes in n: honest near 0 and 1, where a normal one is not.
std::pair<double, double> wilson(int k, int n) {
  if (n == 0) return {0, 1};
  const double z = 1.96, p = double(k) / n, z2n = z * z / n;
  const double centre = (p + z2n / 2) / (1 + z2n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2n / (4 * n)) / (1 + z2n);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

// Mean and standard error of a per-match figure.
template <class Figure>
std::pair<double, double> mean_and_error(const BalanceResult& r, Figure figure) {
  std::vector<double> v;
  for (const PlayResult& p : r.results)
    if (const double x = figure(p); std::isfinite(x)) v.push_back(x);
  if (v.empty()) return {0, 0};
  double mean = 0, var = 0;
  for (double x : v) mean += x;
  mean /= double(v.size());
  for (double x : v) var += (x - mean) * (x - mean);
  const double error = v.size() > 1 ? std::sqrt(var / double(v.size() - 1) / double(v.size())) : 0;
  return {mean, error};
}

}  // namespace

BalanceResult balance(const runtime::SessionOptions& options, int matches, const std::function<void(int done)>& progress) {
  if (matches < 1 || matches > 100'000) throw std::invalid_argument("--matches must be in [1, 100000]");
  runtime::SessionOptions quiet = options;
  quiet.watch = false;
  quiet.events.clear();
  quiet.audio = "none";
  quiet.pacing = runtime::SessionOptions::Pacing::Fast;
  std::vector<PlayResult> results(static_cast<size_t>(matches));
  std::atomic<int> next{0};
  int done = 0;
  std::exception_ptr failure;
  std::mutex lock;
  auto worker = [&] {
    for (int m; (m = next++) < matches;) {
      runtime::SessionOptions o = quiet;
      o.seed = options.seed + uint64_t(m);
      std::ostringstream out, errors;
      try {
        results[size_t(m)] = play(o, out, errors, false);
        const std::lock_guard<std::mutex> told(lock);
        if (progress) progress(++done);
      } catch (...) {
        const std::lock_guard<std::mutex> failed(lock);
        if (!failure) failure = std::current_exception();
        next = matches;
      }
    }
  };
  std::vector<std::thread> threads;
  const unsigned cores = std::max(1u, std::min(std::thread::hardware_concurrency(), unsigned(matches)));
  for (unsigned t = 0; t < cores; ++t) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);

  BalanceResult r;
  r.matches = matches;
  for (int m = 0; m < matches; ++m) {
    const PlayResult& p = results[size_t(m)];
    r.seeds.push_back(options.seed + uint64_t(m));
    if (p.winner.empty()) ++r.draws;
    else ++r.wins[p.winner];
    for (const auto& [team, n] : p.score) r.wins.try_emplace(team, 0);
    r.totals += p.figures();
    r.stalls += p.stats.stalls, r.stalled_matches += p.stats.stalls > 0;
  }
  r.counted = results.front().counted;
  r.results = std::move(results);
  return r;
}

void write_csv(std::ostream& out, const BalanceResult& r, const std::vector<std::string>& extra_names,
               const std::vector<double>& extra, bool header) {
  if (header) {
    out << "seed,winner";
    for (const auto& [team, n] : r.wins) out << ",score_" << team;
    out << ",rallies,contacts,goals,passes,possessions,seconds,stalls";
    for (const std::string& name : extra_names) out << ',' << name;
    out << '\n';
  }
  for (size_t m = 0; m < r.results.size(); ++m) {
    const PlayResult& p = r.results[m];
    out << r.seeds[m] << ',' << (p.winner.empty() ? "draw" : p.winner);
    for (const auto& [team, n] : r.wins) {
      const auto it = p.score.find(team);
      out << ',' << (it == p.score.end() ? 0 : it->second);
    }
    out << ',' << p.stats.rallies << ',' << p.stats.contacts << ',' << p.stats.goals << ',' << p.stats.passes << ','
        << p.stats.possessions << ',' << p.stats.seconds << ',' << p.stats.stalls;
    for (double x : extra) out << ',' << x;
    out << '\n';
  }
}

runtime::Written plot_study(const runtime::SessionOptions& options, const BalanceResult& study, int sweep_matches,
                            const std::string& dir, runtime::ProgressLine* progress, std::ostream& log) {
  runtime::make_output_folder("--plot", dir);
  auto open = [&](const std::string& name) {
    std::ofstream f(fs::path(dir) / name);
    if (!f) throw std::runtime_error("--plot " + dir + ": cannot write " + name);
    return f;
  };
  std::ofstream matches = open("matches.csv");
  write_csv(matches, study);
  matches.close();

  const lua::ScriptedRules sport(options.sport, lua::engine_rules_folder(), lua::Params(options.params));
  const std::vector<BodySpec>& bodies = sport.spec().field.bodies;
  const std::string first_team = bodies.empty() ? "" : bodies.front().team;
  const std::string first_name = sport.spec().team_name(first_team);
  int played = study.matches;  // so far, the sweeps' points before this one's
  auto run = [&](runtime::SessionOptions o, const char* what) {
    if (progress) progress->clear();  // a terminal's progress line, off the line below
    log << what << std::endl;  // a study takes minutes: say where it is as it goes
    BalanceResult r = balance(o, sweep_matches, [&](int done) {
      if (progress) (*progress)(played + done);
    });
    played += sweep_matches;
    return r;
  };

  // Win rate of the first team against its players' handicap, the others' as they are.
  const std::vector<double> given = options.handicaps.empty() ? sport.spec().handicaps : options.handicaps;
  std::ofstream handicap_data = open("handicap_sweep.csv");
  handicap_data << "handicap,win_rate,low,high,matches\n";
  std::ofstream handicap_rows = open("handicap_matches.csv");
  bool header = true;
  constexpr double kHandicaps[] = {0.5, 0.71, 1.0, 1.41, 2.0};
  constexpr double kStrengths[] = {0.0, 0.5, 1.0, 1.5};
  static_assert(std::size(kHandicaps) + std::size(kStrengths) == kSweepPoints);
  for (double h : kHandicaps) {
    runtime::SessionOptions o = options;
    o.handicaps = given;
    for (size_t b = 0; b < bodies.size(); ++b)
      if (bodies[b].team == first_team) o.handicaps[b] *= h;
    char what[96];
    std::snprintf(what, sizeof what, "sweep: %s's handicap x%.2f", first_name.c_str(), h);
    const BalanceResult r = run(o, what);
    const auto it = r.wins.find(first_team);
    const int wins = it == r.wins.end() ? 0 : it->second;
    const auto [low, high] = wilson(wins, r.matches);
    handicap_data << h << ',' << double(wins) / r.matches << ',' << low << ',' << high << ',' << r.matches << '\n';
    write_csv(handicap_rows, r, {"handicap"}, {h}, header);
    header = false;
  }

  // Gameflow against the fate factors' strength: each factor f becomes f^s, from flat (s = 0)
  // through the sport's own (s = 1) to beyond.
  std::ofstream factor_data = open("factor_sweep.csv");
  factor_data << "strength,contacts_per_rally,contacts_error,goals_per_minute,goals_error,points_per_minute,points_error\n";
  std::ofstream factor_rows = open("factor_matches.csv");
  header = true;
  for (double strength : kStrengths) {
    runtime::SessionOptions o = options;
    for (const std::string& kind : fate_kind_names()) {
      const auto set = options.factors.find(kind);
      o.factors[kind] = std::pow(set != options.factors.end() ? set->second : sport.factor(kind), strength);
    }
    char what[96];
    std::snprintf(what, sizeof what, "sweep: fate factors to the power %.1f", strength);
    const BalanceResult r = run(o, what);
    const auto contacts = mean_and_error(r, [](const PlayResult& p) {
      return p.stats.rallies ? double(p.stats.contacts) / p.stats.rallies : NAN;
    });
    const auto goals = mean_and_error(r, [](const PlayResult& p) { return p.stats.goals * 60 / p.stats.seconds; });
    const auto scored = mean_and_error(r, [](const PlayResult& p) { return p.figures().points * 60 / p.stats.seconds; });
    factor_data << strength << ',' << contacts.first << ',' << contacts.second << ',' << goals.first << ','
                << goals.second << ',' << scored.first << ',' << scored.second << '\n';
    write_csv(factor_rows, r, {"factor_strength"}, {strength}, header);
    header = false;
  }
  handicap_data.close(), factor_data.close(), handicap_rows.close(), factor_rows.close();

  const std::string d = fs::absolute(dir).string();
  std::ofstream script = open("plots.gp");
  script << "set datafile separator ','\nset terminal pngcairo size 800,500 font ',11'\nset key top left\nset grid\n"
         << "set output '" << d << "/win_rate_vs_handicap.png'\n"
         << "set title \"" << sport.spec().name << ": " << first_name << " against its handicap (" << sweep_matches
         << " matches a point, 95 % Wilson interval)\"\n"
         << "set xlabel \"" << first_name << "'s handicap (x the sport's)\"\nset ylabel 'win rate'\n"
         << "set logscale x 2\nset xtics (0.5, 0.71, 1, 1.41, 2)\nset yrange [0:1]\n"
         << "plot '" << d << "/handicap_sweep.csv' every ::1 using 1:2:3:4 with yerrorlines lw 2 title '"
         << first_name << " wins', 0.5 with lines dt 2 title 'even'\n"
         << "unset logscale x\nset xtics autofreq\nset autoscale y\nset yrange [0:*]\n"
         << "set xlabel \"fate factor strength s (each factor f becomes f^s: 0 flat, 1 the sport's)\"\n"
         << "set output '" << d << "/contacts_vs_factors.png'\n"
         << "set title \"" << sport.spec().name << ": contacts per rally (" << sweep_matches
         << " matches a point, mean and standard error)\"\nset ylabel 'contacts per rally'\n"
         << "plot '" << d << "/factor_sweep.csv' every ::1 using 1:2:3 with yerrorlines lw 2 title 'contacts per rally'\n"
         << "set output '" << d << "/goals_vs_factors.png'\n"
         << "set title \"" << sport.spec().name << ": scoring (" << sweep_matches
         << " matches a point, mean and standard error)\"\nset ylabel 'per minute'\n"
         << "plot '" << d << "/factor_sweep.csv' every ::1 using 1:4:5 with yerrorlines lw 2 title 'goals per minute', "
         << "'' every ::1 using 1:6:7 with yerrorlines lw 2 title 'points per minute (the sport''s score)'\n";
  script.close();
  const std::string command = "gnuplot '" + d + "/plots.gp' 2>'" + d + "/gnuplot.log'";
  if (std::system(command.c_str()) != 0)
    throw std::runtime_error("--plot: gnuplot failed (Debian: gnuplot-nox); see " + d + "/gnuplot.log");

  std::ofstream summary = open("summary.md");
  char line[256];
  summary << "# " << sport.spec().name << ": balance study\n\n"
          << study.matches << " matches (seeds " << options.seed << " to " << options.seed + uint64_t(study.matches) - 1
          << ") between simulated players; every match in [matches.csv](matches.csv).\n\n"
          << "| team | wins | share | 95 % interval |\n| --- | --- | --- | --- |\n";
  for (const auto& [team, n] : study.wins) {
    const auto [low, high] = wilson(n, study.matches);
    std::snprintf(line, sizeof line, "| %s | %d | %.0f %% | %.0f-%.0f %% |\n", sport.spec().team_name(team).c_str(), n,
                  100.0 * n / study.matches, 100 * low, 100 * high);
    summary << line;
  }
  std::snprintf(line, sizeof line, "| draws | %d | %.0f %% | |\n\n", study.draws, 100.0 * study.draws / study.matches);
  summary << line;
  std::string figures = describe(study.counted, study.totals);
  figures[0] = char(std::toupper(figures[0]));
  summary << figures;
  std::snprintf(line, sizeof line, "; stalls %d, in %d of %d matches", study.stalls, study.stalled_matches, study.matches);
  summary << line;
  summary << ".\n\n## " << first_name << " against its handicap\n\n![win rate](win_rate_vs_handicap.png)\n\n"
          << "Data: [handicap_sweep.csv](handicap_sweep.csv), every match in [handicap_matches.csv](handicap_matches.csv).\n\n"
          << "## Gameflow against the fate factors\n\n![contacts per rally](contacts_vs_factors.png)\n\n"
          << "![goals per minute](goals_vs_factors.png)\n\nData: [factor_sweep.csv](factor_sweep.csv), every match in "
          << "[factor_matches.csv](factor_matches.csv).\n";
  if (!summary) throw std::runtime_error("--plot " + dir + ": cannot write summary.md");
  if (progress) progress->clear();
  log << "plots and summary in " << dir << "/summary.md\n";
  return {dir, "summary.md, 3 PNG plots and 5 CSV files, " + std::to_string(played) + " matches in all"};
}

}  // namespace quantum::tools

#include "play.h"

#include "desk.h"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <ostream>
#include <sstream>
#include <thread>

namespace quantum::tools {

runtime::SessionOptions::Pacing pacing(const std::string& pace) {
  if (pace == "realtime") return runtime::SessionOptions::Pacing::RealTime;
  if (pace == "fast") return runtime::SessionOptions::Pacing::Fast;
  throw std::invalid_argument("--pace must be realtime or fast, not '" + pace + "'");
}

std::vector<double> parse_list(const std::string& text, const std::string& option) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v))
      throw std::invalid_argument(option + ": '" + item + "' is not a number (expected e.g. 0.3,0.9)");
    out.push_back(v);
  }
  return out;
}

PlayResult play(const runtime::SessionOptions& options, std::ostream& out, std::ostream& errors, bool transcript,
                const DeskOptions* desk) {
  PlayResult result;
  if (desk && desk->wanted()) {
    result = play_at_desk(options, *desk, out, errors, transcript);
  } else {
    runtime::Session session(options, transcript ? &out : nullptr, errors);
    session.run();
    const game::Match& match = session.match();
    result = {match.score(), match.winner(), match.stats(), session.rule_errors()};
  }
  if (transcript) {
    const game::RallyStats& s = result.stats;
    out << "final score:";
    for (const auto& [team, goals] : result.score) out << ' ' << team << ' ' << goals;
    out << (result.winner.empty() ? " (draw)" : " (" + result.winner + " wins)") << '\n';
    char buf[200];
    std::snprintf(buf, sizeof buf, "rallies %d, contacts per rally %.2f, goals per minute %.2f, %.0f s played\n",
                  s.rallies, s.rallies ? double(s.contacts) / s.rallies : 0.0, s.seconds > 0 ? s.goals * 60 / s.seconds : 0.0,
                  s.seconds);
    out << buf;
  }
  return result;
}

BalanceResult balance(const runtime::SessionOptions& options, int matches) {
  if (matches < 1 || matches > 100'000) throw std::invalid_argument("--matches must be in [1, 100000]");
  runtime::SessionOptions quiet = options;
  quiet.watch = false;
  quiet.events.clear();
  quiet.audio = "none";
  quiet.pacing = runtime::SessionOptions::Pacing::Fast;
  std::vector<PlayResult> results(static_cast<size_t>(matches));
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_lock;
  auto worker = [&] {
    for (int m; (m = next++) < matches;) {
      runtime::SessionOptions o = quiet;
      o.seed = options.seed + uint64_t(m);
      std::ostringstream out, errors;
      try {
        results[size_t(m)] = play(o, out, errors, false);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_lock);
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
  int rallies = 0, contacts = 0, goals = 0, passes = 0;
  double seconds = 0;
  for (const PlayResult& p : results) {
    if (p.winner.empty()) ++r.draws;
    else ++r.wins[p.winner];
    for (const auto& [team, n] : p.score) r.wins.try_emplace(team, 0);
    rallies += p.stats.rallies, contacts += p.stats.contacts, goals += p.stats.goals, seconds += p.stats.seconds;
    passes += p.stats.passes, r.possessions += p.stats.possessions;
  }
  r.contacts_per_rally = rallies ? double(contacts) / rallies : 0;
  r.passes_per_possession = r.possessions ? double(passes) / r.possessions : 0;
  r.goals_per_minute = seconds > 0 ? goals * 60 / seconds : 0;
  return r;
}

}  // namespace quantum::tools

#include "play.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <atomic>
#include <chrono>
#include <mutex>
#include <sstream>
#include <thread>

#include "event_log.h"
#include "match_audio.h"
#include "game/bots.h"
#include "sport.h"

namespace quantum::tools {
namespace {

std::string event_json(const game::GameEvent& e, const std::vector<game::Said>& said) {
  nlohmann::ordered_json j;
  j["t"] = rounded(e.t);
  j["type"] = e.type;
  j["actor"] = e.actor;
  if (!e.team.empty()) j["team"] = e.team;
  if (!e.by.empty()) j["by"] = e.by;
  j["p"] = rounded(e.p);
  j["p_newtonian"] = rounded(e.p_newtonian);
  j["particles"] = e.particles;
  j["x"] = rounded(e.at.x);
  j["y"] = rounded(e.at.y);
  if (!said.empty()) {
    j["said"] = nlohmann::json::array();
    for (const game::Said& s : said) j["said"].push_back(s.text);
  }
  return j.dump();
}

std::string stamp(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%4d:%05.2f", int(t / 60), std::fmod(t, 60.0));
  return buf;
}

}  // namespace

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

PlayResult play(const PlayOptions& o, std::ostream& out, std::ostream& errors) {
  if (o.input != "bots")
    throw std::invalid_argument("--input " + o.input + ": only 'bots' (simulated players) is available so far");
  lua::Sport sport(o.sport);
  for (const auto& [kind, value] : o.factors) sport.set_factor(kind, value);
  const size_t n_players = sport.field().bodies.size();
  std::vector<double> skills = o.skills.empty() ? std::vector<double>(n_players, 0.6) : o.skills;
  if (skills.size() != n_players)
    throw std::invalid_argument("--skill: " + sport.name() + " has " + std::to_string(n_players) + " players, got " +
                                std::to_string(skills.size()) + " skills");
  std::vector<double> handicaps = o.handicaps.empty() ? sport.handicaps() : o.handicaps;
  if (handicaps.size() != n_players)
    throw std::invalid_argument("--handicap: " + sport.name() + " has " + std::to_string(n_players) +
                                " players, got " + std::to_string(handicaps.size()) + " handicaps");
  if (!(o.seconds >= 0 && o.seconds <= 24 * 3600)) throw std::invalid_argument("--seconds must be in (0, 86400]");

  game::MatchConfig config;
  config.particles = o.particles ? o.particles : sport.particles();
  config.seed = o.seed;
  config.seconds = o.seconds > 0 ? o.seconds : sport.seconds();
  config.first_spot = sport.first_spot();
  game::Match match(sport.field(), config, sport, handicaps);
  game::Bots bots(match.field(), skills, o.seed);

  std::ofstream file;
  std::ostream* log = open_event_log(o.events, file);

  MatchAudio sound(o.audio, sport.audio(), errors);
  const auto wall_start = std::chrono::steady_clock::now();
  PlayResult result;
  const double dt = 1.0 / config.fps;
  if (o.transcript) out << sport.name() << ": " << match.field().name << ", seed " << o.seed << '\n';
  while (!match.finished()) {
    match.step(bots.move(match.time() + dt, dt));
    const std::vector<game::GameEvent> events = match.take_events();
    const std::vector<game::Said> said = match.take_said();
    for (const std::string& e : match.take_errors()) {
      errors << "quantum: rules error: " << e << '\n';
      ++result.rule_errors;
    }
    for (const game::GameEvent& e : events) bots.hear(e), sound.event(e);
    for (const game::Said& s : said) sound.said(s);
    sound.frame(match.time());
    // On a sound card the match runs in real time: people are listening.
    if (sound.on_device())
      std::this_thread::sleep_until(wall_start + std::chrono::duration<double>(match.time()));
    if (o.transcript)
      for (const game::Said& s : said) out << stamp(s.t) << "  " << s.text << '\n';
    if (log)
      for (size_t k = 0; k < events.size(); ++k)
        *log << event_json(events[k], k + 1 == events.size() ? said : std::vector<game::Said>{}) << '\n';
  }
  if (log) log->flush();
  sound.finish(match.time());
  result.score = match.score();
  result.winner = match.winner();
  result.stats = match.stats();
  const game::RallyStats& s = result.stats;
  if (o.transcript) {
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

}  // namespace quantum::tools

namespace quantum::tools {

BalanceResult balance(const PlayOptions& options, int matches) {
  if (matches < 1 || matches > 100'000) throw std::invalid_argument("--matches must be in [1, 100000]");
  PlayOptions quiet = options;
  quiet.transcript = false;
  quiet.events.clear();
  std::vector<PlayResult> results(static_cast<size_t>(matches));
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_lock;
  auto worker = [&] {
    for (int m; (m = next++) < matches;) {
      PlayOptions o = quiet;
      o.seed = options.seed + uint64_t(m);
      std::ostringstream out, errors;
      try {
        results[size_t(m)] = play(o, out, errors);
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
  int rallies = 0, contacts = 0, goals = 0;
  double seconds = 0;
  for (const PlayResult& p : results) {
    if (p.winner.empty()) ++r.draws;
    else ++r.wins[p.winner];
    for (const auto& [team, n] : p.score) r.wins.try_emplace(team, 0);
    rallies += p.stats.rallies, contacts += p.stats.contacts, goals += p.stats.goals, seconds += p.stats.seconds;
  }
  r.contacts_per_rally = rallies ? double(contacts) / rallies : 0;
  r.goals_per_minute = seconds > 0 ? goals * 60 / seconds : 0;
  return r;
}

}  // namespace quantum::tools

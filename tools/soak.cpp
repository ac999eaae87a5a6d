// `quantum-soak`: an hour of matches (by default) between simulated players at full speed, with
// power-ups granted at random and the scripts reloaded as they play, watched for what only a long
// run shows: memory that grows, a value that is not a number in any log, a cloud that grows past
// its bound, a ball that nothing happens to. Prints its figures; exits 1 when one is out of bounds
// (docs/reliability.md).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <regex>
#include <sstream>

#include "session.h"
#include "system/sanitizers.h"
#include "lua_sport.h"

namespace fs = std::filesystem;
using namespace quantum;

namespace {

struct SoakOptions {
  std::string sport = "airhockey";
  double seconds = 3600;       // simulated match time, over as many matches as it takes
  uint32_t particles = 0;      // 0: the sport's
  uint64_t seed = 1;
  double grant_every = 10;     // seconds between random power-ups
  double reload_every = 60;    // seconds between reloads of the sport and a power-up
  double warm = 300;           // memory is measured from this match time on
  double most_growth = 16;     // MiB the resident memory may grow after warming up
  double longest_gap = 60;     // seconds the ball may go without an event of its own
};

struct Figures {
  double played = 0;
  int matches = 0, grants = 0, refused = 0, reloads = 0, rule_errors = 0;
  size_t frames = 0, events = 0, phrases = 0, not_numbers = 0, log_lines = 0;
  size_t most_particles = 0, particle_bound = 0;  // the cloud's most, and twice its target (it passes
                                                  // the target right after a realized contact)
  double next_sample = 60;
  double longest_gap = 0, gap_at = 0;  // the longest time without a ball event, and when it ended
  double warm_mib = 0, most_mib = 0;   // resident memory once warm, and its most after
  std::vector<std::string> problems;
};

// Under the address sanitizer resident memory is mostly its quarantine of freed blocks (up to
// 256 MiB, filling over the run), so growth would measure that; LeakSanitizer checks for leaks
// there instead, at exit.
constexpr bool kMemoryMeasured = !quantum::system::kAddressSanitized;

double resident_mib() {
  std::ifstream statm("/proc/self/statm");
  size_t pages = 0, resident = 0;
  statm >> pages >> resident;
  return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

// Events of the ball itself: power-ups, pauses and the clock happen whether or not it moves.
bool ball_event(game::EventKind k) {
  using enum game::EventKind;
  return k != Powerup && k != PowerupEnd && k != Paused && k != Resumed && k != TimeUp && k != MatchEnd;
}

bool finite(Vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }

// A JSON log holds a value that was not a number as null (runtime/json_lines.h).
size_t nulls_in(const nlohmann::json& j) {
  if (j.is_null()) return 1;
  size_t n = 0;
  if (j.is_structured())
    for (const auto& v : j) n += nulls_in(v);
  return n;
}

void scan_log(const fs::path& file, Figures& f) {
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    ++f.log_lines;
    const auto j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded()) f.problems.push_back(file.string() + ": a line that is not JSON: " + line.substr(0, 120));
    else if (const size_t n = nulls_in(j)) f.not_numbers += n, f.problems.push_back(file.string() + ": " + line.substr(0, 200));
  }
}

std::vector<fs::path> powerup_scripts(const lua::ScriptedRules& sport) {
  std::vector<fs::path> out;
  for (const fs::path& folder : sport.folders().powerups)
    if (fs::is_directory(folder))
      for (const auto& entry : fs::directory_iterator(folder))
        if (entry.path().extension() == ".lua") out.push_back(entry.path());
  std::sort(out.begin(), out.end());  // the same order on every machine: the run is the seed's
  return out;
}

void play_match(const SoakOptions& so, const fs::path& logs, Figures& f) {
  runtime::SessionOptions o;
  o.sport = so.sport;
  o.seed = so.seed + uint64_t(f.matches);
  o.seconds = std::min(so.seconds - f.played, 86400.0);
  o.particles = so.particles;
  o.watch = true;
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  o.events = (logs / "events.jsonl").string();
  o.decisions = (logs / "decisions.jsonl").string();
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  const std::vector<fs::path> powerups = powerup_scripts(tools::scripted_rules(session));
  std::mt19937_64 random(o.seed);
  const std::regex not_a_number(R"(\b-?(nan|inf)\b)", std::regex::icase);
  double last_ball = 0;
  session.watch([&](const runtime::News& news) {
    for (const game::GameEvent& e : news.events) {
      ++f.events;
      if (!std::isfinite(e.t) || !std::isfinite(e.p) || !finite(e.at) || !finite(e.velocity)) ++f.not_numbers;
      if (!ball_event(e.type)) continue;
      if (e.t - last_ball > f.longest_gap) f.longest_gap = e.t - last_ball, f.gap_at = f.played + e.t;
      last_ball = e.t;
    }
    for (const game::Said& s : news.said) {
      ++f.phrases;
      if (std::regex_search(s.text, not_a_number)) ++f.not_numbers, f.problems.push_back("said: " + s.text);
    }
  });
  double next_grant = so.grant_every, next_reload = so.reload_every;
  f.particle_bound = std::max(f.particle_bound, 2 * size_t(session.match().config().particles));
  const int players = int(session.match().players().size());
  while (session.frame()) {
    ++f.frames;
    const double t = session.match().time();
    f.most_particles = std::max(f.most_particles, session.match().world().cloud().size());
    if (t >= next_grant && !powerups.empty()) {
      next_grant += so.grant_every;
      const std::string name = powerups[random() % powerups.size()].stem();
      try {
        tools::scripted_rules(session).grant(session.match(), int(random() % uint64_t(players)), name, {});
        session.tell();
        ++f.grants;
      } catch (const std::exception& e) {
        ++f.refused;  // a power-up that needs options of its own
      }
    }
    if (t >= next_reload) {
      next_reload += so.reload_every;
      session.reload((fs::path(so.sport) / "sport.lua").string());
      if (!powerups.empty()) session.reload(powerups[random() % powerups.size()].string());
      ++f.reloads;
    }
    if (f.played + t >= f.next_sample) {  // once a minute of play
      f.next_sample += 60;
      const double mib = resident_mib();
      if (f.played + t >= so.warm) {
        if (f.warm_mib == 0) f.warm_mib = mib;
        f.most_mib = std::max(f.most_mib, mib);
      }
    }
  }
  session.finish();
  const double t = session.match().time();
  if (t - last_ball > f.longest_gap) f.longest_gap = t - last_ball, f.gap_at = f.played + t;
  f.played += t;
  ++f.matches;
  f.rule_errors += session.rule_errors();
  // The reloads' own notices are what was asked for; anything else said there is a problem.
  std::istringstream said(errors.str());
  for (std::string line; std::getline(said, line);)
    if (line.rfind("quantum: reloaded ", 0) != 0) f.problems.push_back("match " + std::to_string(f.matches) + ": " + line);
  scan_log(logs / "events.jsonl", f);
  scan_log(logs / "decisions.jsonl", f);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Play matches between simulated players at full speed for a long time, with random power-ups and "
               "reloads, and check that memory stays flat, no log holds a value that is not a number, the cloud "
               "stays bounded and the ball is never stuck"};
  SoakOptions so;
  app.add_option("SPORT", so.sport, "the sport's folder")->capture_default_str();
  app.add_option("--seconds", so.seconds, "simulated match time, over as many matches as it takes")
      ->capture_default_str()->check(CLI::Range(1.0, 1e6));
  app.add_option("--particles", so.particles, "particles (0: the sport's)")->capture_default_str();
  app.add_option("--seed", so.seed, "the first match's seed (the next ones count up)")->capture_default_str();
  app.add_option("--grant-every", so.grant_every, "seconds between random power-ups")->capture_default_str()
      ->check(CLI::Range(0.1, 1e6));
  app.add_option("--reload-every", so.reload_every, "seconds between reloads of the sport and a power-up")
      ->capture_default_str()->check(CLI::Range(0.1, 1e6));
  app.add_option("--warm", so.warm, "match time after which memory must stay flat, s")->capture_default_str()
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--most-growth", so.most_growth, "MiB resident memory may grow once warm")->capture_default_str();
  app.add_option("--longest-gap", so.longest_gap, "seconds the ball may go without an event")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const fs::path logs = fs::temp_directory_path() / ("quantum_soak_" + std::to_string(getpid()));
  fs::create_directories(logs);
  Figures f;
  try {
    while (f.played < so.seconds - 1e-9) play_match(so, logs, f);
  } catch (const std::exception& e) {
    std::cerr << "quantum-soak: " << e.what() << '\n';
    fs::remove_all(logs);
    return 1;
  }
  fs::remove_all(logs);

  const double growth = f.most_mib - f.warm_mib;
  std::cout << "soak: " << f.played << " s of " << so.sport << " in " << f.matches << " matches, " << f.frames
            << " frames, " << f.events << " events, " << f.phrases << " phrases, " << f.log_lines << " log lines\n"
            << "soak: " << f.grants << " power-ups granted (" << f.refused << " refused), " << f.reloads
            << " reloads, " << f.rule_errors << " rule errors\n"
            << "soak: resident memory " << f.warm_mib << " MiB at " << so.warm << " s, at most " << f.most_mib
            << " MiB after (growth " << growth << " MiB, bound " << so.most_growth
            << (kMemoryMeasured ? ")\n" : "; not checked: the address sanitizer's quarantine)\n")
            << "soak: most particles " << f.most_particles << " (bound " << f.particle_bound << "), values not a number "
            << f.not_numbers << '\n'
            << "soak: longest time without a ball event " << f.longest_gap << " s (ending at " << f.gap_at
            << " s; bound " << so.longest_gap << ")\n";
  for (const std::string& p : f.problems) std::cout << "soak: problem: " << p << '\n';
  const bool ok = (growth <= so.most_growth || !kMemoryMeasured) && f.not_numbers == 0 && f.longest_gap <= so.longest_gap &&
                  f.most_particles <= f.particle_bound &&
                  f.problems.empty() && f.rule_errors == 0;
  std::cout << (ok ? "soak: passed\n" : "soak: FAILED\n");
  return ok ? 0 : 1;
}

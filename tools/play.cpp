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
#include "reloader.h"
#include "tracked_input.h"

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

// Players from a tracking source: each tracked id moves the body of that name. Recordings are
// replayed in match time; live sources as their frames come.
class TrackedBodies {
 public:
  TrackedBodies(const std::string& spec, const Field& field)
      : field_(field), input_(spec, tracking::tracked_field(field), SourceOptions{}) {
    for (const BodySpec& b : field.bodies) bodies_.push_back({b.start, {0, 0}});
  }

  bool live() const { return input_.live(); }

  // Brings the bodies up to match time t. Lost or Ended when the source is; else Frame (and the
  // bodies are as of the latest frame due, or as they were when nothing new came).
  TrackingInput::Status advance(double t, double timeout) {
    // A live source is asked at most once a frame of the match: a Kinect blocks until its next
    // frame, and asking every step would hold the match to the camera's 30 Hz.
    if (live() && seen_ && t < next_ask_) return TrackingInput::Status::Frame;
    for (;;) {
      if (!pending_) {
        tracking::TrackedFrame f;
        const TrackingInput::Status s = input_.next(f, timeout);
        if (s == TrackingInput::Status::Calibrating) continue;  // the match waits for the source
        // Nothing new: the bodies stay as they are; before the first frame the match waits.
        if (s == TrackingInput::Status::Waiting)
          return seen_ ? TrackingInput::Status::Frame : TrackingInput::Status::Lost;
        if (s != TrackingInput::Status::Frame) return s;
        if (t0_ < 0) t0_ = f.t - t;
        f.t -= t0_;
        pending_ = std::move(f);
      }
      if (pending_->t > t + 1e-9 && !live()) return TrackingInput::Status::Frame;  // not due yet
      apply(*pending_);
      seen_ = true;
      next_ask_ = pending_->t + 1.0 / 60;
      pending_.reset();
      if (live()) return TrackingInput::Status::Frame;
    }
  }

  // After a pause the source's clock went on without the match's.
  void resync() { t0_ = -1, next_ask_ = 0; }

  const std::vector<BodyInput>& bodies() const { return bodies_; }

 private:
  // Tracking glitches must not stop a match: positions stay within a field's size of the bounds
  // and speeds under the field's limit, as the core requires.
  void apply(const tracking::TrackedFrame& f) {
    for (BodyInput& b : bodies_) b.velocity = {0, 0};  // no input: the body holds still
    for (const tracking::TrackedPlayer& p : f.players) {
      for (size_t k = 0; k < field_.bodies.size(); ++k) {
        if (field_.bodies[k].name != p.id) continue;
        const float slack = 0.5f * std::max(field_.bounds_max.x - field_.bounds_min.x, field_.bounds_max.y - field_.bounds_min.y);
        bodies_[k].position = {std::clamp(float(p.x), field_.bounds_min.x - slack, field_.bounds_max.x + slack),
                               std::clamp(float(p.y), field_.bounds_min.y - slack, field_.bounds_max.y + slack)};
        const double speed = std::hypot(p.vx, p.vy), most = 0.99 * field_.max_body_speed;
        const double scale = speed > most ? most / speed : 1.0;
        bodies_[k].velocity = {float(p.vx * scale), float(p.vy * scale)};
      }
    }
  }

  Field field_;
  TrackingInput input_;
  std::vector<BodyInput> bodies_;
  std::optional<tracking::TrackedFrame> pending_;
  double t0_ = -1;        // source time at match time 0
  bool seen_ = false;     // a frame has come
  double next_ask_ = 0;   // match time from which a live source is asked again
};

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
  // A reload replaces the sport between two frames: it is always reached through this pointer.
  auto sport = std::make_unique<lua::Sport>(o.sport);
  for (const auto& [kind, value] : o.factors) sport->set_factor(kind, value);
  const size_t n_players = sport->field().bodies.size();
  std::vector<double> skills = o.skills.empty() ? std::vector<double>(n_players, 0.6) : o.skills;
  if (skills.size() != n_players)
    throw std::invalid_argument("--skill: " + sport->name() + " has " + std::to_string(n_players) + " players, got " +
                                std::to_string(skills.size()) + " skills");
  std::vector<double> handicaps = o.handicaps.empty() ? sport->handicaps() : o.handicaps;
  if (handicaps.size() != n_players)
    throw std::invalid_argument("--handicap: " + sport->name() + " has " + std::to_string(n_players) +
                                " players, got " + std::to_string(handicaps.size()) + " handicaps");
  if (!(o.seconds >= 0 && o.seconds <= 24 * 3600)) throw std::invalid_argument("--seconds must be in (0, 86400]");

  game::MatchConfig config;
  config.particles = o.particles ? o.particles : sport->particles();
  config.seed = o.seed;
  config.seconds = o.seconds > 0 ? o.seconds : sport->seconds();
  config.first_spot = sport->first_spot();
  config.balance_per_goal = o.auto_balance >= 0 ? o.auto_balance : sport->balance_per_goal();
  config.balance_most = sport->balance_most();
  game::Match match(sport->field(), config, *sport, handicaps);
  game::Bots bots(match.field(), skills, o.seed);
  std::optional<TrackedBodies> tracked;
  if (o.input != "bots") tracked.emplace(o.input, match.field());
  std::optional<RulesReloader> reloader;
  if (o.watch) reloader.emplace(o.sport, o.factors);

  std::ofstream file;
  std::ostream* log = open_event_log(o.events, file);

  MatchAudio sound(o.audio, sport->audio(), errors);
  auto wall_start = std::chrono::steady_clock::now();
  PlayResult result;
  const double dt = 1.0 / config.fps;
  if (o.transcript) out << sport->name() << ": " << match.field().name << ", seed " << o.seed << '\n';
  // People are listening, or playing: on a sound card or with live players the match runs in
  // real time.
  const bool real_time = sound.on_device() || (tracked && tracked->live());
  bool paused = false;
  while (!match.finished()) {
    // Between two frames: the scripts that changed are loaded again.
    if (reloader) reloader->poll(sport, match, errors);
    std::vector<game::GameEvent> host_events;  // the host's own: the input paused or resumed
    if (tracked) {
      const TrackingInput::Status status = tracked->advance(match.time() + dt, paused ? 0.1 : 0.0);
      if (status == TrackingInput::Status::Ended) {
        if (o.transcript) out << stamp(match.time()) << "  (the recording is over)\n";
        break;
      }
      const bool lost = status == TrackingInput::Status::Lost;
      if (lost != paused) {
        // A camera that went away pauses the match, with an announcement, until it is back.
        paused = lost;
        const char* key = lost ? "paused" : "resumed";
        const std::string text = sport->phrase(key, {});
        match.say(text != key ? text : lost ? "The players cannot be seen. The match is paused" : "Play on");
        game::GameEvent e;
        e.t = match.time();
        e.type = key;
        host_events.push_back(e);
        if (!lost) {
          tracked->resync();
          wall_start = std::chrono::steady_clock::now() - std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                              std::chrono::duration<double>(match.time()));
        }
      }
    }
    if (paused) std::this_thread::sleep_for(std::chrono::milliseconds(20));  // a camera is asked again, not spun on
    else match.step(tracked ? tracked->bodies() : bots.move(match.time() + dt, dt));
    std::vector<game::GameEvent> events = match.take_events();
    events.insert(events.begin(), host_events.begin(), host_events.end());
    const std::vector<game::Said> said = match.take_said();
    for (const std::string& e : match.take_errors()) {
      errors << "quantum: rules error: " << e << '\n';
      ++result.rule_errors;
    }
    for (const game::GameEvent& e : events) bots.hear(e), sound.event(e);
    for (const game::Said& s : said) sound.said(s);
    sound.frame(match.time());
    if (real_time && !paused) std::this_thread::sleep_until(wall_start + std::chrono::duration<double>(match.time()));
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
  quiet.watch = false;
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

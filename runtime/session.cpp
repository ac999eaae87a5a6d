#include "session.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <exception>
#include <iomanip>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

#include "event_log.h"
#include "interrupts.h"
#include "match_audio.h"
#include "quantum/limits.h"
#include "recording.h"

namespace quantum::runtime {
namespace {

// In its own stream: the shared error stream's format stays as it was.
std::string one_decimal(double v) { return (std::ostringstream() << std::fixed << std::setprecision(1) << v).str(); }

// "1.2 s", "16.7 ms": a duration as a person reads it.
std::string seconds(double s) { return s < 1 ? one_decimal(1000 * s) + " ms" : one_decimal(s) + " s"; }

// n values, one per player of `sport`: the given ones, or `fallback` for each.
std::vector<double> per_player(const std::vector<double>& given, const std::vector<double>& fallback,
                               const game::SportSpec& sport, const char* option, const char* what) {
  const size_t n = sport.field.bodies.size();
  const std::vector<double>& v = given.empty() ? fallback : given;
  if (v.size() != n)
    throw std::invalid_argument(std::string(option) + ": " + sport.name + " has " + std::to_string(n) +
                                " players, got " + std::to_string(v.size()) + " " + what);
  return v;
}

constexpr const char* kPlayersLost = "the players cannot be seen: the match is paused until they are back";

const char* signal_name(int signal) { return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal"; }

}  // namespace

std::vector<Output> outputs_of(const SessionOptions& o) {
  return {{"--events", o.events},
          {"--decisions", o.decisions},
          {"--audio", o.audio.rfind("wav:", 0) == 0 ? o.audio.substr(4) : ""},
          {"--record", o.record, true}};
}

Session::Session(const SessionOptions& o, const SportLoader& sports, std::ostream* transcript, std::ostream& errors,
                 std::unique_ptr<PlayerSource> players)
    : transcript_(transcript), errors_(errors), players_(std::move(players)), until_(o.until) {
  // 0 is no --seconds: the sport's own time limit.
  if (o.seconds != 0 && !limits::kMatchSeconds.contains(o.seconds))
    throw std::invalid_argument("--seconds " + limits::must_be_in(limits::kMatchSeconds, o.seconds));
  check_distinct(outputs_of(o));
  // A replay plays what was recorded: its copy of the sport, its seed and settings.
  SessionOptions settings = o;
  std::optional<Replay> replay;
  if (!o.replay.empty()) {
    replay = open_replay(o.replay);
    for (const std::string& d : replay->differences) errors_ << "quantum: replay: " << d << '\n';
    settings.sport = replay->sport.string();
    settings.seed = replay->seed, settings.seconds = replay->seconds, settings.particles = replay->particles;
    settings.handicaps = replay->handicaps, settings.auto_balance = replay->auto_balance, settings.factors = replay->factors;
    settings.params = replay->params;
  }
  // A replay reloads what its recording reloaded, when it did, and nothing else.
  using Reloads = SportRequest::Reloads;
  reloads_ = o.watch || replay;
  sport_ = sports({settings.sport, replay ? replay->engine : std::filesystem::path(), settings.params, settings.factors,
                   replay ? Reloads::Told : o.watch ? Reloads::Watched : Reloads::None});
  const game::SportSpec& sport = sport_->spec();
  const std::vector<double> handicaps = per_player(settings.handicaps, sport.handicaps, sport, "--handicap", "handicaps");
  for (size_t k = 0; k < handicaps.size(); ++k)
    limits::check(limits::kHandicap, handicaps[k], "--handicap: " + sport.field.bodies[k].name + "'s handicap");
  // The sport's settings, and the session's over them.
  game::MatchConfig config = sport.match;
  config.seed = settings.seed;
  config.threads = settings.threads;
  if (settings.particles) config.particles = settings.particles;
  if (settings.seconds > 0) config.seconds = settings.seconds;
  if (settings.auto_balance >= 0) config.balance_per_goal = settings.auto_balance;
  match_ = std::make_unique<game::Match>(sport.field, config, sport_->rules(), handicaps);
  if (!players_ && replay)
    players_ = std::make_unique<RecordedPlayers>(o.replay, std::move(replay->work), match_->field(), &errors_, replay->frames);
  planned_end_ = {config.seconds, replay ? "the recording's time limit" : o.seconds > 0 ? "--seconds" : "the sport's time limit"};
  if (replay && replay->frames && double(*replay->frames) / match_->fps() < planned_end_.seconds)
    planned_end_ = {double(*replay->frames) / match_->fps(), "the recording's end"};
  if (until_ > 0 && until_ < planned_end_.seconds) planned_end_ = {until_, "--until"};
  if (o.must_reach > planned_end_.seconds + 1e-9)
    throw std::invalid_argument("--snapshot-at " + (std::ostringstream() << o.must_reach).str() + ": the match ends at " +
                                seconds(planned_end_.seconds) + " (" + planned_end_.by + "), before that moment");
  if (!players_) {
    if (o.input == "bots") {
      const std::vector<double> skills(sport.field.bodies.size(), 0.6);
      players_ = std::make_unique<BotPlayers>(match_->field(), per_player(o.skills, skills, sport, "--skill", "skills"),
                                              o.seed, config.throw_speed);
    } else {
      players_ = tracked_players(o.input, match_->field(), {o.accel, o.fov}, &errors_, o.field_size, o.setup);
    }
  }
  // A replay's rules read the skills its recording's did (none in a recording made before rules
  // could read them, which is what those rules got).
  for (size_t k = 0; k < match_->players().size(); ++k)
    match_->set_skill(int(k), !replay ? players_->skill(k) : k < replay->skills.size() ? replay->skills[k] : std::nullopt);
  log_ = std::make_unique<LineFile>("--events", o.events);
  decisions_ = std::make_unique<LineFile>("--decisions", o.decisions);
  if (decisions_->stream()) write_decision_header(*decisions_->stream(), settings, sport, *match_);
  decisions_->commit();
  audio_ = std::make_unique<MatchAudio>(o.audio, sport.audio, errors_);
  // People are listening, playing or watching: then the match runs in real time.
  real_time_ = o.pacing == SessionOptions::Pacing::RealTime ||
               (o.pacing == SessionOptions::Pacing::Automatic && (audio_->on_device() || players_->live() || o.watched));
  // Last: a recording is made only once everything else has opened.
  if (!o.record.empty()) recorder_ = std::make_unique<Recorder>(o.record, settings, sport, match_->players());
  kept_from_ = wall_start_ = clock_seconds();
  if (transcript_) *transcript_ << sport.name << ": " << match_->field().name << ", seed " << config.seed << '\n';
  commit_outputs();
}

Session::~Session() = default;

void Session::reload(const std::string& file) {
  if (!reloads_) throw std::logic_error("this session does not reload its scripts (SessionOptions::watch)");
  sport_->changed(file);
}

void Session::tell() {
  game::Match& m = *match_;
  const News news{m.events(), m.said(), m.errors(), ledger_.next_id()};
  players_->hear(news.events);
  const double sound_from = clock_seconds();
  for (const game::GameEvent& e : news.events) audio_->event(e);
  for (size_t i = 0; i < news.said.size(); ++i) audio_->said(news.said[i], news.first_phrase + i);
  costs_.sound += clock_seconds() - sound_from;
  ledger_.hold(news.events, news.said);
  // A rule that fails every frame is one line, not thousands: each error once, counted.
  for (const std::string& e : news.errors)
    if (++errors_seen_[e] == 1) {
      errors_ << "quantum: rules error: " << e << '\n';
      rule_problems_.push_back(e);
    }
  rule_errors_ += int(news.errors.size());
  write_settled();
  if (watcher_) watcher_(news);
  m.clear_news();
}

// A camera that went away pauses the match, with an announcement, until it is back.
void Session::pause_or_resume(bool lost) {
  paused_ = lost;
  match_->note(lost ? game::EventKind::Paused : game::EventKind::Resumed);
  game::say_host(sport_->spec(), *match_, lost ? "paused" : "resumed",
                 lost ? "The players cannot be seen. The match is paused" : "Play on");
  match_->set_cause("");
  if (!lost) {
    players_->resync();
    resync();
  }
}

bool Session::frame() {
  if (over_) return false;
  const double began = clock_seconds();
  costs_.drawing += std::exchange(drawn_, 0.0);
  game::Match& m = *match_;
  audio_->clear_fates();
  tell();  // what happened between frames (a spec's grant, a scene set up)
  if (reloads_) {
    for (const std::filesystem::path& file : players_->files_to_reload()) sport_->changed(file);
    std::vector<std::filesystem::path> reloaded;
    if (sport_->reload(m, errors_, recorder_ ? &reloaded : nullptr) > 0) {
      audio_->set_sport(sport_->spec().audio);
      // The new version starts with a clean slate: an error it still makes is shown again.
      report_repeated_errors();
      errors_seen_.clear();
      rule_problems_.clear();
    }
    if (recorder_ && !reloaded.empty()) recorder_->reloaded(reloaded);
  }
  const double dt = 1.0 / m.fps();
  const PlayerSource::Status status = players_->advance(m.time() + dt, m, paused_);
  if (recorder_) recorder_->frame(status, players_->bodies(), players_->throws());
  if (status == PlayerSource::Status::Ended) {
    over_ = recording_over_ = true;
  } else {
    const bool lost = status == PlayerSource::Status::Lost;
    if (lost != paused_) pause_or_resume(lost);
    forget_fixed_problems();
    if (!paused_) {
      const double engine_from = clock_seconds();
      for (const game::Throw& t : players_->throws()) m.let_go(t);
      m.step(players_->bodies());
      costs_.engine += clock_seconds() - engine_from;
      if (decisions_->stream() && m.decision())
        write_decision(*decisions_->stream(), *m.decision(), {m.decision_terms(), m.decision_contacts_from(), m.powerup_names()},
                       m.field());
    }
  }
  tell();
  const double sound_from = clock_seconds();
  audio_->frame(m.time());
  costs_.sound += clock_seconds() - sound_from;
  write_settled();
  commit_outputs();
  if (!m.finished() && !over_) interrupted_ = interrupting_signal();
  over_ = over_ || m.finished() || (until_ > 0 && m.time() >= until_ - 1e-9) || interrupted_;
  costs_.frames += clock_seconds() - began;
  ++costs_.count;
  // A camera is asked again while paused, not spun on.
  if (paused_ && players_->live()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  else if (real_time_) keep_time();
  return !over_;
}

bool Session::run_to(double t) {
  const bool real_time = std::exchange(real_time_, false);
  bool going = !over_;
  while (going && match_->time() + 1e-9 < t) going = frame();
  real_time_ = real_time;
  resync();
  return going;
}

std::vector<Session::Problem> Session::problems() const {
  std::vector<Problem> standing;
  for (const std::string& e : rule_problems_) standing.push_back({"rules error", e});
  if (reloads_)
    for (const auto& [script, failure] : sport_->failures())
      if (!dismissed_.count(failure)) standing.push_back({"reload failed", failure});
  if (paused_ && !dismissed_.count(kPlayersLost)) standing.push_back({"players lost", kPlayersLost});
  return standing;
}

void Session::dismiss_problems() {
  for (const Problem& p : problems())
    if (p.kind != "rules error") dismissed_.insert(p.text);
  rule_problems_.clear();
}

void Session::forget_fixed_problems() {
  std::erase_if(dismissed_, [this](const std::string& text) {
    if (text == kPlayersLost) return !paused_;
    if (reloads_)
      for (const auto& [script, failure] : sport_->failures())
        if (failure == text) return false;
    return true;
  });
}

void Session::keep_time() {
  const double late = clock_seconds() - (wall_start_ + match_->time() / speed_);
  if (late < 0) std::this_thread::sleep_for(std::chrono::duration<double>(-late));
  const double now = clock_seconds();
  if (!paused_) wall_played_ += now - kept_from_;
  kept_from_ = now;
  if (late < 0) return;
  // Players hear the ball and see the view late: whoever runs the match is told, once (a slow
  // match is late every frame). A second's grace rides out a reload or a slow disk; a pause
  // (a recording's) holds the match time, so it is no lateness.
  if (late_said_ || paused_ || late < kLateToSay) return;
  late_said_ = true;
  const game::Match& m = *match_;
  errors_ << "quantum: the match runs " << seconds(late) << " behind real time after " << seconds(m.time())
          << " of play: " << late_because() << '\n';
}

// Which of the engine, the drawing and the sound took a late frame's time, and what keeps the
// match in time then: fewer particles are offered only when the engine is the cost.
std::string Session::late_because() const {
  const double n = double(std::max<uint64_t>(1, costs_.count));
  const std::string cloud = " with a cloud of " + std::to_string(match_->config().particles) + " particles";
  struct Part {
    std::string name;  // as the warning names it
    double each;       // s a frame
    std::string what, remedy;
  };
  const Part parts[] = {
      {"the engine", costs_.engine / n, cloud, "; fewer particles (--particles) keep it in time"},
      {"the drawing", costs_.drawing / n, "", "; a video (--video FILE) is drawn without the clock"},
      {"the sound", costs_.sound / n, "", "; --audio none keeps it in time"},
      {"the rest of the frame", (costs_.frames - costs_.engine - costs_.sound) / n,
       ", for the players' input, the logs, watchers and reloads", ""},
  };
  const Part& most = *std::max_element(std::begin(parts), std::end(parts),
                                       [](const Part& a, const Part& b) { return a.each < b.each; });
  std::string others;
  for (const Part& p : parts)
    if (&p != &most) others += (others.empty() ? "" : ", ") + p.name + " " + seconds(p.each);
  return "its frames take " + seconds((costs_.frames + costs_.drawing) / n) + ", longer than the " +
         seconds(1 / (match_->fps() * speed_)) + " they may, and " + most.name + " takes most of it: " + seconds(most.each) +
         " a frame" + most.what + " (" + others + ")" + most.remedy;
}

std::span<const audio::PhraseFate> Session::fates() const { return audio_->fates(); }

std::vector<Written> Session::written() const {
  std::vector<Written> files;
  for (const LineFile* log : {log_.get(), decisions_.get()})
    if (const std::optional<Written> w = log->written()) files.push_back(*w);
  if (const std::optional<Written> wav = audio_->written()) files.push_back(*wav);
  if (recorder_ && recorder_->whole())
    files.push_back({recorder_->dir().string(), std::to_string(recorder_->frames()) + " frames (" +
                                                    seconds(double(recorder_->frames()) / match_->fps()) + ")"});
  return files;
}

void Session::write_settled(bool all) {
  ledger_.settle(audio_->fates());
  ledger_.write(log_->stream(), transcript_, all);
}

void Session::commit_outputs() {
  log_->commit();
  decisions_->commit();
  log_->say_failure(errors_);
  decisions_->say_failure(errors_);
  if (recorder_) recorder_->say_failure(errors_);
  // Piped, the transcript would wait for a full buffer: a match killed after 12 s had none.
  if (transcript_ && !transcript_->flush() && !transcript_lost_) {
    transcript_lost_ = true;
    say_lost(errors_, "the transcript");
  }
}

void Session::report_repeated_errors() {
  for (const auto& [error, count] : errors_seen_)
    if (count > 1) errors_ << "quantum: rules error, " << count << " times in all: " << error << '\n';
}

void Session::set_speed(double speed) {
  if (!(speed > 0 && speed <= 100)) throw std::invalid_argument("speed must be in (0, 100]");
  speed_ = speed;
  resync();
}

void Session::resync() {
  drawn_ = 0;
  kept_from_ = clock_seconds();
  wall_start_ = kept_from_ - match_->time() / speed_;
}

void Session::run() {
  while (frame()) {
  }
  finish();
}

void Session::finish() {
  if (finished_) return;
  finished_ = true;
  // Taken before the last phrase rings out (on a sound card, up to seconds of waiting).
  const double played = match_->time(), took = wall_played_;
  tell();
  report_repeated_errors();
  players_->finish(played);
  // Every file is completed, also when another could not be written whole; the first that
  // could not is what finish() throws.
  std::exception_ptr lost;
  auto complete = [&lost](auto&& close) {
    try {
      close();
    } catch (const std::exception&) {
      if (!lost) lost = std::current_exception();
    }
  };
  complete([&] { audio_->finish(match_->time()); });
  write_settled(true);
  if ((recording_over_ || interrupted_) && transcript_) {
    const std::string why = interrupted_ ? std::string("(ended by ") + signal_name(interrupted_) + ")" : "(the recording is over)";
    const game::Said end{match_->time(), why, -1, "", ""};
    write_transcript(*transcript_, {&end, 1});
  }
  complete([&] { log_->close(); });
  complete([&] { decisions_->close(); });
  if (recorder_) complete([&] { recorder_->close(); });
  complete([&] {
    if (transcript_ && (!transcript_->flush() || transcript_lost_)) throw std::runtime_error("could not write the whole transcript");
  });
  if (late_said_)
    errors_ << "quantum: " << seconds(played) << " of play took " << seconds(took) << " of the clock ("
            << one_decimal(took / played) << " times real time)\n";
  if (lost) std::rethrow_exception(lost);
}

}  // namespace quantum::runtime

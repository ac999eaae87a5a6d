#include "playback.h"
#include "lua_sport.h"

#include <cstdlib>
#include <ostream>
#include <stdexcept>

namespace quantum::tools {
namespace {

// A look back replays the live match's recording from its start: what it would say again (the
// recording's differences, its rules' errors) was said the first time.
std::ostream& unheard() {
  static std::ostream none(nullptr);
  return none;
}

runtime::WorkFolder new_recording_folder() {
  std::string pattern = (std::filesystem::temp_directory_path() / "quantum-desk-XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw std::runtime_error("--view: cannot make a folder for looking back in " + pattern);
  return runtime::WorkFolder(pattern);
}

}  // namespace

Playback::Playback(runtime::SessionOptions options, std::ostream* transcript, std::ostream& errors, Players players,
                   bool look_back)
    : options_(std::move(options)), transcript_(transcript), errors_(errors), players_(std::move(players)) {
  if (look_back && !replay() && options_.record.empty()) {
    own_recording_ = new_recording_folder();
    options_.record = own_recording_.path().string();
  }
  live_ = open_live();
}

Playback::~Playback() = default;

std::unique_ptr<runtime::Session> Playback::open_live() {
  return std::make_unique<runtime::Session>(options_, tools::lua_sport, transcript_, errors_, players_ ? players_() : nullptr);
}

double Playback::length() const { return live_->match().config().seconds; }

double Playback::played() const { return replay() ? length() : live_->match().time(); }

bool Playback::at_live(double t) const {
  // Match times add up frames in floats: within half a frame is the same frame.
  return t >= live_->match().time() - 0.5 / live_->match().fps();
}

bool Playback::frame() {
  if (!past_) return live_->frame();
  if (past_->frame() && !at_live(past_->match().time())) return true;
  past_.reset();
  live_->resync();
  return !live_->over();
}

void Playback::seek(double t) {
  const double to = std::clamp(t, 0.0, played());
  if (to >= shown().match().time() - 1e-9) {
    if (past_ && at_live(to)) {
      past_.reset();
      live_->resync();
    } else {
      shown().run_to(to);
    }
    return;
  }
  if (replay()) {
    restart();  // its files are started again by the new session
    live_->run_to(to);
    return;
  }
  if (options_.record.empty()) return;  // no recording to look back at
  runtime::SessionOptions past;
  past.replay = options_.record;
  past.pacing = runtime::SessionOptions::Pacing::RealTime;
  past.watched = true;
  past_ = std::make_unique<runtime::Session>(past, tools::lua_sport, nullptr, unheard());
  past_->set_speed(speed_);
  past_->run_to(to);
}

void Playback::restart() {
  past_.reset();
  live_.reset();
  if (!own_recording_.path().empty()) {
    own_recording_ = new_recording_folder();
    options_.record = own_recording_.path().string();
  }
  live_ = open_live();
  live_->set_speed(speed_);
}

void Playback::set_speed(double speed) {
  speed_ = speed;
  live_->set_speed(speed);
  if (past_) past_->set_speed(speed);
}

}  // namespace quantum::tools

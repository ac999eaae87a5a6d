#include "match_audio.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <ostream>

namespace quantum::runtime {
namespace {

// espeak-ng keeps global state: one Speech per process, made on first use.
audio::Speech* speech(std::ostream& warnings, bool& failed) {
  static std::unique_ptr<audio::Speech> s;
  if (!s && !failed) {
    try {
      s = std::make_unique<audio::Speech>();
    } catch (const audio::AudioError& e) {
      failed = true;
      warnings << "quantum: " << e.what() << "; phrases are not spoken\n";
    }
  }
  return s.get();
}

bool speech_failed = false;

}  // namespace

MatchAudio::MatchAudio(const std::string& spec, const lua::SportAudio& sport, std::ostream& warnings)
    : sport_(sport), warnings_(warnings) {
  if (spec == "none") return;
  if (spec.rfind("wav:", 0) == 0) {
    if (spec.size() == 4) throw std::invalid_argument("--audio wav:FILE needs a file name");
    mixer_ = audio::Mixer::open_loopback(44100);
    wav_ = std::make_unique<audio::WavWriter>(spec.substr(4), mixer_->rate());
  } else if (spec.empty()) {
    mixer_ = audio::Mixer::open_device();
    if (!mixer_) {
      warnings_ << "quantum: no sound device could be opened; playing silently (--audio none for no sound, "
                   "--audio wav:FILE to record it)\n";
      return;
    }
  } else {
    throw std::invalid_argument("--audio " + spec + ": expected none or wav:FILE (or nothing, for the sound card)");
  }
  mixer_->set_listener({sport_.listener, sport_.facing});
  announcer_ = std::make_unique<audio::Announcer>(*mixer_);
}

MatchAudio::~MatchAudio() = default;

void MatchAudio::warn(const std::string& what) {
  if (warned_.insert(what).second) warnings_ << "quantum: " << what << '\n';
}

const audio::Clip* MatchAudio::clip(const std::string& path) {
  if (auto it = clips_.find(path); it != clips_.end()) return it->second.samples.empty() ? nullptr : &it->second;
  audio::Clip& c = clips_[path];
  try {
    c = audio::load_clip(path);
  } catch (const audio::AudioError& e) {
    warn(std::string(e.what()) + "; that sound stays silent");
  }
  return c.samples.empty() ? nullptr : &c;
}

void MatchAudio::event(const game::GameEvent& e) {
  if (!mixer_) return;
  const auto sound = sport_.sounds.find(std::string_view(game::to_string(e.type)));
  if (sound == sport_.sounds.end()) return;
  if (const audio::Clip* c = clip(sound->second)) mixer_->play(*c, e.at);
}

void MatchAudio::said(const game::Said& s) {
  if (!announcer_) return;
  const auto p = sport_.priorities.find(std::string_view(s.cause));
  const int priority = p == sport_.priorities.end() ? 1 : p->second;
  if (!s.recording.empty()) {
    if (const audio::Clip* c = clip(s.recording)) {
      announcer_->say(*c, priority, s.t, s.text);
      return;
    }  // a missing recording: the text is spoken instead
  }
  audio::Speech* voice = speech(warnings_, speech_failed);
  if (!voice) return;
  audio::Voice v{sport_.voice, sport_.rate, sport_.volume};
  try {
    announcer_->say(voice->say(s.text, v), priority, s.t, s.text);
  } catch (const audio::AudioError& e) {
    warn(std::string(e.what()) + "; speaking with the default voice");
    announcer_->say(voice->say(s.text, audio::Voice{}), priority, s.t, s.text);
  }
}

void MatchAudio::frame(double now) {
  if (!announcer_) return;
  announcer_->clear_fates();
  announcer_->update(now);
  if (!wav_) return;
  // Whole samples up to `now`; rounding both ends keeps the total exact over a match.
  const int frames = int(std::lround(now * mixer_->rate()) - std::lround(rendered_until_ * mixer_->rate()));
  rendered_until_ = std::max(rendered_until_, now);
  if (frames <= 0) return;
  mixer_->render(frames, chunk_);
  wav_->write(chunk_);
}

std::span<const std::string> MatchAudio::dropped() const {
  return announcer_ ? announcer_->dropped() : std::span<const std::string>();
}

std::span<const std::string> MatchAudio::cut() const {
  return announcer_ ? announcer_->cut() : std::span<const std::string>();
}

void MatchAudio::finish(double now) {
  if (!announcer_) return;
  // Let the last phrase and the horn ring out, at most three seconds: on the sound card by
  // waiting, into the file by rendering.
  double t = now;
  for (; t < now + 3.0 && !announcer_->speaking().empty(); t += 0.05) {
    if (!wav_) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    frame(t);
  }
  if (!wav_) return;
  frame(t + 0.5);
  wav_->close();
}

}  // namespace quantum::runtime

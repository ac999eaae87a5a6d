#include "match_audio.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <ostream>

#include "output_files.h"
#include "system/regular_file.h"

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

audio::AnnouncerRules rules(const game::SportAudio& sport) {
  audio::AnnouncerRules r;
  r.repeat_gap = sport.repeat_gap;
  r.wait_for = sport.wait_for;
  r.keep_from = sport.keep;
  return r;
}

}  // namespace

MatchAudio::MatchAudio(const std::string& spec, const game::SportAudio& sport, std::ostream& warnings)
    : sport_(sport), warnings_(warnings) {
  if (spec == "none") return;
  if (spec.rfind("wav:", 0) == 0) {
    if (spec.size() == 4) throw std::invalid_argument("--audio wav:FILE needs a file name");
    mixer_ = audio::Mixer::open_loopback(44100);
    wav_path_ = spec.substr(4);
    check_output_file("--audio", wav_path_);
    wav_ = std::make_unique<audio::WavWriter>(wav_path_, mixer_->rate());
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
  announcer_ = std::make_unique<audio::Announcer>(*mixer_, rules(sport_));
}

void MatchAudio::set_sport(const game::SportAudio& sport) {
  sport_ = sport;
  if (announcer_) announcer_->set_rules(rules(sport_));
}

MatchAudio::~MatchAudio() = default;

void MatchAudio::warn(const std::string& what) {
  if (warned_.insert(what).second) warnings_ << "quantum: " << what << '\n';
}

const audio::Clip* MatchAudio::clip(const std::string& path) {
  if (auto it = clips_.find(path); it != clips_.end()) return it->second.samples.empty() ? nullptr : &it->second;
  audio::Clip& c = clips_[path];
  try {
    // The sport's load checked it, but a sound loads when it first plays: a file that has become
    // a FIFO since would block the match on opening it.
    if (const std::string why = system::not_a_regular_file(path); !why.empty()) throw audio::AudioError(why);
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

void MatchAudio::silent(uint64_t id) {
  audio::PhraseFate f;
  f.id = id, f.kind = audio::PhraseFate::Kind::Silent;
  settled({&f, 1});
}

// Fates are copied into slots kept from frame to frame (a string's copy keeps its room): a
// running match allocates nothing.
void MatchAudio::settled(std::span<const audio::PhraseFate> fates) {
  for (const audio::PhraseFate& f : fates) {
    if (n_fates_ == fates_.size()) fates_.emplace_back();
    fates_[n_fates_++] = f;
  }
}

void MatchAudio::collect() {
  settled(announcer_->fates());
  announcer_->clear_fates();
}

void MatchAudio::said(const game::Said& s, uint64_t id) {
  if (!announcer_) return silent(id);
  say(s, id);
  collect();  // a repeat is skipped, and what it supersedes dropped, at once
}

void MatchAudio::say(const game::Said& s, uint64_t id) {
  const std::string_view cause(s.cause);
  const auto p = sport_.priorities.find(cause);
  const int priority = p == sport_.priorities.end() ? 1 : p->second;
  const auto supersede = sport_.supersede.find(cause);
  const bool supersedable = supersede != sport_.supersede.end() && supersede->second;
  if (!s.recording.empty()) {
    if (const audio::Clip* c = clip(s.recording)) {
      announcer_->say(*c, priority, s.t, s.text, id, supersedable);
      return;
    }  // a missing recording: the text is spoken instead
  }
  audio::Speech* voice = speech(warnings_, speech_failed);
  if (!voice) return silent(id);
  audio::Voice v{sport_.voice, sport_.rate, sport_.volume};
  try {
    announcer_->say(voice->say(s.text, v), priority, s.t, s.text, id, supersedable);
  } catch (const audio::AudioError& e) {
    warn(std::string(e.what()) + "; speaking with the default voice");
    announcer_->say(voice->say(s.text, audio::Voice{}), priority, s.t, s.text, id, supersedable);
  }
}

void MatchAudio::frame(double now) {
  if (!announcer_) return;
  // Into a file, what starts now sounds from the last sample written: the phrase's times in the
  // log are then where it is in the file.
  announcer_->update(wav_ ? rendered_until_ : now);
  collect();
  // Speech first: game sounds duck while the announcer speaks, so a horn or a rally of hits
  // never buries the words.
  mixer_->duck(announcer_->speaking().empty() ? 1.0f : sport_.duck);
  render(now);
}

void MatchAudio::render(double now) {
  if (!wav_) return;
  // Whole samples up to `now`; rounding both ends keeps the total exact over a match.
  const int frames = int(std::lround(now * mixer_->rate()) - std::lround(rendered_until_ * mixer_->rate()));
  rendered_until_ = std::max(rendered_until_, now);
  if (frames <= 0 || wav_lost_) return;
  mixer_->render(frames, chunk_);
  try {
    wav_->write(chunk_);
  } catch (const audio::AudioError&) {
    wav_lost_ = true;
    say_lost(warnings_, wav_path_);
  }
}

void MatchAudio::finish(double now) {
  if (!announcer_) return;
  // Let the last phrases and the horn ring out, at most ten seconds: on the sound card by
  // waiting, into the file by rendering. Nothing newer will come, so nothing waiting is stale.
  audio::AnnouncerRules last = rules(sport_);
  last.stale_after = 10;
  announcer_->set_rules(last);
  double t = now;
  for (; t < now + 10.0 && !announcer_->speaking().empty(); t += 0.05) {
    if (!wav_) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    frame(t);
  }
  announcer_->finish(t);
  collect();
  if (!wav_) return;
  mixer_->duck(1);
  render(t + 0.5);
  wav_->close();
  if (wav_lost_) throw audio::AudioError("--audio wav:" + wav_path_ + ": could not write every sample");
}

std::optional<Written> MatchAudio::written() const {
  if (!wav_ || wav_lost_) return std::nullopt;
  char what[64];
  std::snprintf(what, sizeof what, "%.1f s of sound", rendered_until_);
  return Written{wav_path_, what};
}

}  // namespace quantum::runtime

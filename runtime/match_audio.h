// A match's sound: each event's sound where it happened, each phrase through the announcer,
// to the sound card or rendered into a WAV file in step with match time. Any problem with
// sound (no device, a missing file, an unknown voice) is one warning and a fallback, never a
// failed match.
#pragma once

#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "audio/audio.h"
#include "game/game.h"
#include "game/sport_spec.h"
#include "output_files.h"

namespace quantum::runtime {

class MatchAudio {
 public:
  // spec: "" (the sound card, or silence with a warning when there is none), "none", or
  // "wav:FILE" (created at once: a bad path fails here, before anything plays). Throws
  // std::invalid_argument for any other spec, audio::AudioError for a WAV file that cannot be
  // written.
  MatchAudio(const std::string& spec, const game::SportAudio& sport, std::ostream& warnings);
  ~MatchAudio();

  // The sport's sound settings changed (a reloaded sport.lua).
  void set_sport(const game::SportAudio& sport);

  void event(const game::GameEvent& e);
  // `id` comes back with the phrase's fate.
  void said(const game::Said& s, uint64_t id);
  // Once per frame: starts due phrases and, for a WAV file, renders up to match time `now`.
  void frame(double now);
  // Lets the last phrases finish (at most 10 s), settles every phrase and completes the WAV file,
  // if any. A WAV file that could not be written whole (a full disk: told once, when it
  // happened, while the match went on) throws audio::AudioError here.
  void finish(double now);

  bool on_device() const { return mixer_ && !mixer_->loopback(); }  // the match runs in real time
  // After finish(): the WAV file, when there is one and every sample was written ("41.2 s of sound").
  std::optional<Written> written() const;
  // What became of phrases, settled since the last clear_fates(): spoken, cut off, dropped, or
  // silent when there is no sound to speak them with.
  std::span<const audio::PhraseFate> fates() const { return {fates_.data(), n_fates_}; }
  void clear_fates() { n_fates_ = 0; }

 private:
  const audio::Clip* clip(const std::string& path);
  void warn(const std::string& what);
  void render(double now);  // a WAV file's samples up to `now`
  void say(const game::Said& s, uint64_t id);
  void settled(std::span<const audio::PhraseFate> fates);
  void collect();  // the announcer's fates, into fates()
  void silent(uint64_t id);

  game::SportAudio sport_;
  std::ostream& warnings_;
  std::unique_ptr<audio::Mixer> mixer_;
  std::unique_ptr<audio::Announcer> announcer_;
  std::unique_ptr<audio::WavWriter> wav_;
  std::string wav_path_;
  bool wav_lost_ = false;  // a write failed: the rest of the match is not written
  std::map<std::string, audio::Clip> clips_;
  std::set<std::string> warned_;
  std::vector<int16_t> chunk_;
  std::vector<audio::PhraseFate> fates_;  // slots kept, as the announcer's
  size_t n_fates_ = 0;
  double rendered_until_ = 0;
};

}  // namespace quantum::runtime

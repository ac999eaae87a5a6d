// A match's sound: each event's sound where it happened, each phrase through the announcer,
// to the sound card or rendered into a WAV file in step with match time. Any problem with
// sound (no device, a missing file, an unknown voice) is one warning and a fallback, never a
// failed match.
#pragma once

#include <iosfwd>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "audio/audio.h"
#include "game/game.h"
#include "sport.h"

namespace quantum::runtime {

class MatchAudio {
 public:
  // spec: "" (the sound card, or silence with a warning when there is none), "none", or
  // "wav:FILE" (created at once: a bad path fails here, before anything plays). Throws
  // std::invalid_argument for any other spec, audio::AudioError for a WAV file that cannot be
  // written.
  MatchAudio(const std::string& spec, const lua::SportAudio& sport, std::ostream& warnings);
  ~MatchAudio();

  // The sport's sound settings changed (a reloaded sport.lua).
  void set_sport(const lua::SportAudio& sport) { sport_ = sport; }

  void event(const game::GameEvent& e);
  void said(const game::Said& s);
  // Once per frame: starts due phrases and, for a WAV file, renders up to match time `now`.
  void frame(double now);
  // Lets the last phrase finish and completes the WAV file, if any.
  void finish(double now);

  bool on_device() const { return mixer_ && !mixer_->loopback(); }  // the match runs in real time
  // The phrases the last frame() dropped (stale) or cut off (outranked).
  std::span<const std::string> dropped() const;
  std::span<const std::string> cut() const;

 private:
  const audio::Clip* clip(const std::string& path);
  void warn(const std::string& what);

  lua::SportAudio sport_;
  std::ostream& warnings_;
  std::unique_ptr<audio::Mixer> mixer_;
  std::unique_ptr<audio::Announcer> announcer_;
  std::unique_ptr<audio::WavWriter> wav_;
  std::map<std::string, audio::Clip> clips_;
  std::set<std::string> warned_;
  std::vector<int16_t> chunk_;
  double rendered_until_ = 0;
};

}  // namespace quantum::runtime

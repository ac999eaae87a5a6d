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

namespace quantum::tools {

class MatchAudio {
 public:
  // spec: "" (the sound card, or silence with a warning when there is none), "none", or
  // "wav:FILE". Throws std::invalid_argument for any other spec.
  MatchAudio(const std::string& spec, const lua::SportAudio& sport, std::ostream& warnings);
  ~MatchAudio();

  void event(const game::GameEvent& e);
  void said(const game::Said& s);
  // Once per frame: starts due phrases and, for a WAV file, renders up to match time `now`.
  void frame(double now);
  // Lets the last phrase finish and writes the WAV file, if any.
  void finish(double now);

  bool on_device() const { return mixer_ && !mixer_->loopback(); }  // the match runs in real time
  const std::string& wav() const { return wav_; }

 private:
  const audio::Clip* clip(const std::string& path);
  void warn(const std::string& what);

  lua::SportAudio sport_;
  std::ostream& warnings_;
  std::unique_ptr<audio::Mixer> mixer_;
  std::unique_ptr<audio::Announcer> announcer_;
  std::map<std::string, audio::Clip> clips_;
  std::set<std::string> warned_;
  std::string wav_;
  std::vector<int16_t> rendered_, chunk_;
  double rendered_until_ = 0;
};

}  // namespace quantum::tools

#include <espeak-ng/speak_lib.h>

#include <cstring>
#include <mutex>

#include "audio/audio.h"

namespace quantum::audio {
namespace {

// espeak-ng hands synthesized audio to a callback; user_data is the Clip being filled.
int collect(short* wav, int count, espeak_EVENT* events) {
  if (wav && count > 0 && events && events->user_data) {
    auto* clip = static_cast<Clip*>(events->user_data);
    clip->samples.insert(clip->samples.end(), wav, wav + count);
  }
  return 0;
}

// espeak-ng is one engine per process: initializing it twice and terminating both hangs in
// espeak_Terminate. Every Speech shares one initialization, ended with the last of them.
std::mutex engine_lock;
int engine_users = 0, engine_rate = 0;

}  // namespace

Speech::Speech() {
  std::lock_guard<std::mutex> lock(engine_lock);
  if (engine_users == 0) {
    engine_rate = espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 0, nullptr, espeakINITIALIZE_DONT_EXIT);
    if (engine_rate <= 0) throw AudioError("espeak-ng: cannot initialize (is espeak-ng-data installed?)");
    espeak_SetSynthCallback(collect);
  }
  ++engine_users;
  rate_ = engine_rate;
}

Speech::~Speech() {
  std::lock_guard<std::mutex> lock(engine_lock);
  if (--engine_users == 0) espeak_Terminate();
}

const Clip& Speech::say(const std::string& text, const Voice& v) {
  if (v.rate < espeakRATE_MINIMUM || v.rate > espeakRATE_MAXIMUM)
    throw AudioError("speech rate " + std::to_string(v.rate) + " is outside 80 to 450 words per minute");
  if (v.volume < 0 || v.volume > 200) throw AudioError("speech volume " + std::to_string(v.volume) + " is outside 0 to 200");
  const std::string key = v.name + '\x1f' + std::to_string(v.rate) + '\x1f' + std::to_string(v.volume) + '\x1f' + text;
  if (auto it = cache_.find(key); it != cache_.end()) return it->second;
  // The engine is shared, so the voice is set for every new phrase; cached ones cost nothing.
  if (espeak_SetVoiceByName(v.name.c_str()) != EE_OK) throw AudioError("unknown espeak-ng voice '" + v.name + "'");
  espeak_SetParameter(espeakRATE, v.rate, 0);
  espeak_SetParameter(espeakVOLUME, v.volume, 0);
  Clip clip;
  clip.rate = rate_;
  const espeak_ERROR e = espeak_Synth(text.c_str(), text.size() + 1, 0, POS_CHARACTER, 0, espeakCHARS_UTF8, nullptr, &clip);
  if (e != EE_OK) throw AudioError("espeak-ng could not speak '" + text + "'");
  return cache_.emplace(key, std::move(clip)).first->second;
}

}  // namespace quantum::audio

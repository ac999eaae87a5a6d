#include <espeak-ng/speak_lib.h>

#include <atomic>
#include <cstring>

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

// espeak-ng is one engine per process. It is initialized once and never terminated:
// espeak_Terminate (1.51, synchronous mode) can wait forever on a thread of its own, and the
// process's exit frees everything anyway.
int engine_rate() {
  static const int rate = [] {
    const int r = espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 0, nullptr, espeakINITIALIZE_DONT_EXIT);
    if (r > 0) espeak_SetSynthCallback(collect);
    return r;
  }();
  return rate;
}

}  // namespace

uint64_t new_clip_id() {
  static std::atomic<uint64_t> next{1};
  return next++;
}

Speech::Speech() : rate_(engine_rate()) {
  if (rate_ <= 0) throw AudioError("espeak-ng: cannot initialize (is espeak-ng-data installed?)");
}

Speech::~Speech() = default;

const Clip& Speech::say(std::string_view text, const Voice& v) {
  if (v.rate < espeakRATE_MINIMUM || v.rate > espeakRATE_MAXIMUM)
    throw AudioError("speech rate " + std::to_string(v.rate) + " is outside 80 to 450 words per minute");
  if (v.volume < 0 || v.volume > 200) throw AudioError("speech volume " + std::to_string(v.volume) + " is outside 0 to 200");
  // The phrases of the voice used last are at hand: a match speaks with one voice.
  if (!last_phrases_ || v.name != last_voice_.name || v.rate != last_voice_.rate || v.volume != last_voice_.volume) {
    last_phrases_ = &cache_[v.name + '\x1f' + std::to_string(v.rate) + '\x1f' + std::to_string(v.volume)];
    last_voice_ = v;
  }
  if (auto it = last_phrases_->find(text); it != last_phrases_->end()) return it->second;
  // The engine is shared, so the voice is set for every new phrase; cached ones cost nothing.
  if (espeak_SetVoiceByName(v.name.c_str()) != EE_OK) throw AudioError("unknown espeak-ng voice '" + v.name + "'");
  espeak_SetParameter(espeakRATE, v.rate, 0);
  espeak_SetParameter(espeakVOLUME, v.volume, 0);
  Clip clip;
  clip.rate = rate_;
  clip.id = new_clip_id();
  const std::string phrase(text);
  const espeak_ERROR e = espeak_Synth(phrase.c_str(), phrase.size() + 1, 0, POS_CHARACTER, 0, espeakCHARS_UTF8, nullptr, &clip);
  if (e != EE_OK) throw AudioError("espeak-ng could not speak '" + phrase + "'");
  return last_phrases_->emplace(phrase, std::move(clip)).first->second;
}

std::string Speech::ipa(const std::string& text, const std::string& voice) {
  if (espeak_SetVoiceByName(voice.c_str()) != EE_OK) throw AudioError("unknown espeak-ng voice '" + voice + "'");
  constexpr int kIpa = 0x02;  // espeak_TextToPhonemes' phoneme mode: IPA, in UTF-8
  std::string out;
  const void* rest = text.c_str();
  while (rest) {
    const char* phonemes = espeak_TextToPhonemes(&rest, espeakCHARS_UTF8, kIpa);
    if (!phonemes) break;
    out += phonemes;
  }
  return out;
}

}  // namespace quantum::audio

#define AL_ALEXT_PROTOTYPES
#include <al.h>
#include <alc.h>
#include <alext.h>

#include "audio/audio.h"
#include "system/quiet.h"

namespace quantum::audio {
namespace {

ALCdevice* dev(void* p) { return static_cast<ALCdevice*>(p); }

}  // namespace

// Opens the default device with stderr silenced: without a sound card ALSA and OpenAL each
// print several lines of their own, and the caller says it in one.
static ALCdevice* open_default_quietly() {
  const system::Quiet quiet({2});
  return alcOpenDevice(nullptr);
}

std::unique_ptr<Mixer> Mixer::open_device() {
  ALCdevice* d = open_default_quietly();
  if (!d) return nullptr;
  ALCcontext* c = alcCreateContext(d, nullptr);
  if (!c) {
    alcCloseDevice(d);
    return nullptr;
  }
  std::unique_ptr<Mixer> m(new Mixer);
  m->device_ = d, m->context_ = c;
  ALCint rate = 0;
  alcGetIntegerv(d, ALC_FREQUENCY, 1, &rate);
  m->rate_ = rate;
  m->set_listener({});
  return m;
}

std::unique_ptr<Mixer> Mixer::open_loopback(int rate) {
  if (!alcIsExtensionPresent(nullptr, "ALC_SOFT_loopback")) throw AudioError("OpenAL has no loopback device (ALC_SOFT_loopback)");
  ALCdevice* d = alcLoopbackOpenDeviceSOFT(nullptr);
  if (!d) throw AudioError("cannot open OpenAL's loopback device");
  if (!alcIsRenderFormatSupportedSOFT(d, rate, ALC_STEREO_SOFT, ALC_SHORT_SOFT)) {
    alcCloseDevice(d);
    throw AudioError("OpenAL's loopback device cannot render 16-bit stereo at " + std::to_string(rate) + " Hz");
  }
  const ALCint attrs[] = {ALC_FORMAT_CHANNELS_SOFT, ALC_STEREO_SOFT, ALC_FORMAT_TYPE_SOFT, ALC_SHORT_SOFT,
                          ALC_FREQUENCY, rate, ALC_HRTF_SOFT, ALC_FALSE, 0};
  ALCcontext* c = alcCreateContext(d, attrs);
  if (!c) {
    alcCloseDevice(d);
    throw AudioError("cannot create an OpenAL context on the loopback device");
  }
  std::unique_ptr<Mixer> m(new Mixer);
  m->device_ = d, m->context_ = c, m->loopback_ = true, m->rate_ = rate;
  m->set_listener({});
  return m;
}

Mixer::~Mixer() {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  for (auto& [handle, p] : playing_) {
    alDeleteSources(1, &p.source);
    alDeleteBuffers(1, &p.buffer);
  }
  alcMakeContextCurrent(nullptr);
  alcDestroyContext(static_cast<ALCcontext*>(context_));
  alcCloseDevice(dev(device_));
}

// Field (x, y) is OpenAL (x, 0, -y): the field lies flat, up is up, and a listener facing +x
// has +y on its left, as a player facing the other end does.
void Mixer::set_listener(const Listener& l) {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  listener_ = l;
  alListener3f(AL_POSITION, l.at.x, 0, -l.at.y);
  const ALfloat orientation[] = {l.facing.x, 0, -l.facing.y, 0, 1, 0};
  alListenerfv(AL_ORIENTATION, orientation);
  // Panning only: the field is small, and a far goal should not be quieter than a near one.
  alDistanceModel(AL_NONE);
}

int Mixer::start(const Clip& clip, float gain, bool relative, Vec2 at) {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  reclaim();
  if (clip.samples.empty() || clip.rate <= 0) return 0;
  Playing p{};
  alGenBuffers(1, &p.buffer);
  alBufferData(p.buffer, AL_FORMAT_MONO16, clip.samples.data(), ALsizei(clip.samples.size() * sizeof(int16_t)), clip.rate);
  alGenSources(1, &p.source);
  alSourcei(p.source, AL_BUFFER, ALint(p.buffer));
  alSourcef(p.source, AL_GAIN, gain);
  alSourcei(p.source, AL_SOURCE_RELATIVE, relative ? AL_TRUE : AL_FALSE);
  if (relative) alSource3f(p.source, AL_POSITION, 0, 0, 0);
  else alSource3f(p.source, AL_POSITION, at.x, 0, -at.y);
  alSourcePlay(p.source);
  if (alGetError() != AL_NO_ERROR) throw AudioError("OpenAL refused to play a sound");
  playing_[next_handle_] = p;
  return next_handle_++;
}

int Mixer::play(const Clip& clip, Vec2 at, float gain) { return start(clip, gain, false, at); }
int Mixer::play_at_listener(const Clip& clip, float gain) { return start(clip, gain, true, {}); }

void Mixer::stop(int handle) {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  if (auto it = playing_.find(handle); it != playing_.end()) alSourceStop(it->second.source);
}

bool Mixer::playing(int handle) const {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  const auto it = playing_.find(handle);
  if (it == playing_.end()) return false;
  ALint state = 0;
  alGetSourcei(it->second.source, AL_SOURCE_STATE, &state);
  return state == AL_PLAYING;
}

// Sources that have finished give their buffers back.
void Mixer::reclaim() {
  for (auto it = playing_.begin(); it != playing_.end();) {
    ALint state = 0;
    alGetSourcei(it->second.source, AL_SOURCE_STATE, &state);
    if (state == AL_PLAYING) {
      ++it;
      continue;
    }
    alDeleteSources(1, &it->second.source);
    alDeleteBuffers(1, &it->second.buffer);
    it = playing_.erase(it);
  }
}

void Mixer::render(int frames, std::vector<int16_t>& stereo) {
  if (!loopback_) throw AudioError("render() needs the loopback device");
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  stereo.resize(size_t(frames) * 2);
  alcRenderSamplesSOFT(dev(device_), stereo.data(), frames);
}

}  // namespace quantum::audio

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
  m->channels_.reserve(kSources);
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
  m->channels_.reserve(kSources);
  m->set_listener({});
  return m;
}

Mixer::~Mixer() {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  for (Channel& c : channels_) {
    alDeleteSources(1, &c.source);
    if (c.own_buffer) alDeleteBuffers(1, &c.own_buffer);
  }
  for (auto& [id, buffer] : buffers_) alDeleteBuffers(1, &buffer);
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

bool Mixer::busy(const Channel& c) const {
  ALint state = 0;
  alGetSourcei(c.source, AL_SOURCE_STATE, &state);
  return state == AL_PLAYING;
}

// A source for `clip`: one of its own that is free, else a new one, else the one that finished
// longest ago (or, all playing, the oldest), given the clip's buffer.
Mixer::Channel& Mixer::channel_for(const Clip& clip) {
  if (clip.id != 0)
    for (Channel& c : channels_)
      if (c.clip == clip.id && !busy(c)) return c;
  Channel* c = nullptr;
  if (channels_.size() < kSources) {
    c = &channels_.emplace_back();
    alGenSources(1, &c->source);
  } else {
    for (Channel& candidate : channels_)
      if (!c || (busy(*c) && !busy(candidate)) || (busy(*c) == busy(candidate) && candidate.handle < c->handle))
        c = &candidate;
    alSourceStop(c->source);
    alSourcei(c->source, AL_BUFFER, 0);  // a buffer still attached could not be deleted
    if (c->own_buffer) alDeleteBuffers(1, &c->own_buffer), c->own_buffer = 0;
  }
  unsigned buffer = 0;
  if (clip.id != 0) {
    auto [it, fresh] = buffers_.try_emplace(clip.id, 0u);
    if (fresh) {
      alGenBuffers(1, &it->second);
      alBufferData(it->second, AL_FORMAT_MONO16, clip.samples.data(), ALsizei(clip.samples.size() * sizeof(int16_t)),
                   clip.rate);
    }
    buffer = it->second;
  } else {
    alGenBuffers(1, &c->own_buffer);
    alBufferData(c->own_buffer, AL_FORMAT_MONO16, clip.samples.data(), ALsizei(clip.samples.size() * sizeof(int16_t)),
                 clip.rate);
    buffer = c->own_buffer;
  }
  alSourcei(c->source, AL_BUFFER, ALint(buffer));
  c->clip = clip.id;
  return *c;
}

void Mixer::prepare(const Clip& clip) {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  if (clip.id == 0 || clip.samples.empty() || clip.rate <= 0) return;
  for (const Channel& c : channels_)
    if (c.clip == clip.id) return;
  channel_for(clip);
}

int Mixer::start(const Clip& clip, float gain, bool relative, Vec2 at) {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  if (clip.samples.empty() || clip.rate <= 0) return 0;
  Channel& c = channel_for(clip);
  c.gain = gain, c.relative = relative;
  alSourcef(c.source, AL_GAIN, relative ? gain : gain * duck_);
  alSourcei(c.source, AL_SOURCE_RELATIVE, relative ? AL_TRUE : AL_FALSE);
  if (relative) alSource3f(c.source, AL_POSITION, 0, 0, 0);
  else alSource3f(c.source, AL_POSITION, at.x, 0, -at.y);
  alSourcePlay(c.source);
  if (alGetError() != AL_NO_ERROR) throw AudioError("OpenAL refused to play a sound");
  c.handle = next_handle_++;
  return c.handle;
}

int Mixer::play(const Clip& clip, Vec2 at, float gain) { return start(clip, gain, false, at); }
int Mixer::play_at_listener(const Clip& clip, float gain) { return start(clip, gain, true, {}); }

const Mixer::Channel* Mixer::find(int handle) const {
  for (const Channel& c : channels_)
    if (handle != 0 && c.handle == handle) return &c;
  return nullptr;
}

void Mixer::stop(int handle) {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  if (const Channel* c = find(handle)) alSourceStop(c->source);
}

bool Mixer::playing(int handle) const {
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  const Channel* c = find(handle);
  return c && busy(*c);
}

void Mixer::duck(float gain) {
  if (gain == duck_) return;
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  duck_ = gain;
  for (const Channel& c : channels_)
    if (!c.relative) alSourcef(c.source, AL_GAIN, c.gain * gain);
}

void Mixer::render(int frames, std::vector<int16_t>& stereo) {
  if (!loopback_) throw AudioError("render() needs the loopback device");
  alcMakeContextCurrent(static_cast<ALCcontext*>(context_));
  stereo.resize(size_t(frames) * 2);
  alcRenderSamplesSOFT(dev(device_), stereo.data(), frames);
}

}  // namespace quantum::audio

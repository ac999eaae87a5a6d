// Sound, the players' only view of the game: decoded clips (libsndfile), speech synthesized
// from the sports' phrases (espeak-ng, cached per phrase), and a mixer on OpenAL Soft that
// places each sound where it happened relative to a listener. The mixer renders to the sound
// card, or through OpenAL Soft's loopback device to memory (tests, WAV files).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "quantum/field.h"

namespace quantum::audio {

struct AudioError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Mono 16-bit samples.
struct Clip {
  std::vector<int16_t> samples;
  int rate = 0;
  double seconds() const { return rate > 0 ? double(samples.size()) / rate : 0; }
};

// Decodes a sound file (WAV, OGG, FLAC, ...); several channels are mixed down to one, since
// only mono sources can be placed. Throws AudioError naming the file.
Clip load_clip(const std::string& path);

// Writes interleaved 16-bit stereo samples as a WAV file. Throws AudioError naming the file.
void write_wav(const std::string& path, const std::vector<int16_t>& stereo, int rate);

struct Voice {
  std::string name = "en";
  int rate = 175;     // words per minute, 80 to 450
  int volume = 100;   // 0 to 200
};

// espeak-ng in synchronous mode. Synthesizing a short phrase takes milliseconds and setting a
// voice more, so each (voice, text) is synthesized once. espeak-ng has global state: all Speech
// objects share one engine for the life of the process, and only one thread may speak at a time.
class Speech {
 public:
  Speech();  // throws AudioError when espeak-ng or its data cannot be loaded
  ~Speech();
  Speech(const Speech&) = delete;
  Speech& operator=(const Speech&) = delete;

  // Throws AudioError for an unknown voice or a rate or volume out of range.
  const Clip& say(const std::string& text, const Voice& voice);

 private:
  std::map<std::string, Clip> cache_;
  int rate_ = 0;
};

// Where the listener stands on the field and which way it faces: sounds to its left play on the
// left channel.
struct Listener {
  Vec2 at{0, 0};
  Vec2 facing{1, 0};
};

class Mixer {
 public:
  // The default sound card; nullptr when there is none (or it cannot be opened).
  static std::unique_ptr<Mixer> open_device();
  // Renders to memory at `rate` samples per second, stereo, with no device and no waiting.
  static std::unique_ptr<Mixer> open_loopback(int rate = 44100);
  ~Mixer();
  Mixer(const Mixer&) = delete;
  Mixer& operator=(const Mixer&) = delete;

  void set_listener(const Listener& listener);
  // Starts a clip at a place on the field (positional) or at the listener's ears; returns a handle.
  int play(const Clip& clip, Vec2 at, float gain = 1);
  int play_at_listener(const Clip& clip, float gain = 1);
  void stop(int handle);
  bool playing(int handle) const;
  // Loopback only: renders the next `frames` frames (interleaved stereo), advancing every source.
  void render(int frames, std::vector<int16_t>& stereo);
  bool loopback() const { return loopback_; }
  int rate() const { return rate_; }

 private:
  Mixer() = default;
  int start(const Clip& clip, float gain, bool relative, Vec2 at);
  void reclaim();

  void* device_ = nullptr;   // ALCdevice*
  void* context_ = nullptr;  // ALCcontext*
  bool loopback_ = false;
  int rate_ = 0;
  Listener listener_;
  struct Playing {
    unsigned source, buffer;
  };
  std::map<int, Playing> playing_;
  int next_handle_ = 1;
};

// The announcer: one phrase at a time, most urgent first. A phrase of higher priority cuts off
// the one being spoken ("Goal!" over "Red shoots"); a phrase still waiting when it is older than
// `stale_after` seconds is dropped instead of piling up.
class Announcer {
 public:
  Announcer(Mixer& mixer, double stale_after = 1.5) : mixer_(mixer), stale_after_(stale_after) {}

  void say(const Clip& clip, int priority, double now, std::string text = {});
  // Starts the next phrase when the current one has ended or is outranked; call every frame.
  void update(double now);

  const std::string& speaking() const { return current_text_; }
  std::vector<std::string> dropped;  // stale phrases, for the log

 private:
  struct Waiting {
    Clip clip;
    int priority;
    double at;
    std::string text;
  };
  Mixer& mixer_;
  double stale_after_;
  std::vector<Waiting> queue_;
  int current_ = 0, current_priority_ = 0;
  std::string current_text_;
};

}  // namespace quantum::audio

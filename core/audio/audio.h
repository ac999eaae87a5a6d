// Sound, the players' only view of the game: decoded clips (libsndfile), speech synthesized
// from the sports' phrases (espeak-ng, cached per phrase), and a mixer on OpenAL Soft that
// places each sound where it happened relative to a listener. The mixer renders to the sound
// card, or through OpenAL Soft's loopback device to memory (tests, WAV files).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "quantum/field.h"

namespace quantum::audio {

struct AudioError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Mono 16-bit samples. A clip with an id (from load_clip or Speech) never changes, so a mixer
// uploads it once and plays it again from its own copy; one without (0) is uploaded per play.
struct Clip {
  std::vector<int16_t> samples;
  int rate = 0;
  uint64_t id = 0;
  double seconds() const { return rate > 0 ? double(samples.size()) / rate : 0; }
};
// A fresh id for a clip that will not change.
uint64_t new_clip_id();

// Decodes a sound file (WAV, OGG, FLAC, ...); several channels are mixed down to one, since
// only mono sources can be placed. Throws AudioError naming the file.
Clip load_clip(const std::string& path);

// A 16-bit stereo WAV file written as the samples come (a match's sound, frame by frame): the
// file is created at once, so a bad path is known before anything plays. Throws AudioError
// naming the file when it cannot be created or written.
class WavWriter {
 public:
  WavWriter(const std::string& path, int rate);
  ~WavWriter();
  WavWriter(const WavWriter&) = delete;
  WavWriter& operator=(const WavWriter&) = delete;
  void write(std::span<const int16_t> stereo);  // interleaved left, right
  void close();                                 // completes the header

 private:
  std::string path_;
  void* file_ = nullptr;  // SNDFILE*
};

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

  // Throws AudioError for an unknown voice or a rate or volume out of range. A phrase said
  // before costs a look-up and nothing else.
  const Clip& say(std::string_view text, const Voice& voice);

 private:
  using Phrases = std::map<std::string, Clip, std::less<>>;
  std::map<std::string, Phrases> cache_;  // voice -> text -> clip
  Voice last_voice_;
  Phrases* last_phrases_ = nullptr;
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
  // Starts a clip at a place on the field (positional) or at the listener's ears; returns a
  // handle. A clip with an id keeps its own sources, with its buffer attached for good (attaching
  // one costs OpenAL an allocation), so a sound heard before starts without one. At most
  // kSources sources are made; beyond that the longest-finished (or oldest) one is taken over.
  static constexpr size_t kSources = 128;
  int play(const Clip& clip, Vec2 at, float gain = 1);
  int play_at_listener(const Clip& clip, float gain = 1);
  // Uploads a clip with an id and gives it a source, so that its first play costs no more than
  // any other (a phrase queued for the announcer).
  void prepare(const Clip& clip);
  void stop(int handle);
  bool playing(int handle) const;
  // Loopback only: renders the next `frames` frames (interleaved stereo), advancing every source.
  void render(int frames, std::vector<int16_t>& stereo);
  bool loopback() const { return loopback_; }
  int rate() const { return rate_; }

 private:
  // A source, and the clip it plays. Buffers of clips with an id are made once per clip.
  struct Channel {
    unsigned source = 0;
    uint64_t clip = 0;        // the clip whose buffer is attached; 0 for none
    unsigned own_buffer = 0;  // a buffer made for one play (a clip without an id), 0 for none
    int handle = 0;           // the last play's handle
  };

  Mixer() = default;
  int start(const Clip& clip, float gain, bool relative, Vec2 at);
  Channel& channel_for(const Clip& clip);
  bool busy(const Channel& c) const;

  void* device_ = nullptr;   // ALCdevice*
  void* context_ = nullptr;  // ALCcontext*
  bool loopback_ = false;
  int rate_ = 0;
  Listener listener_;
  std::vector<Channel> channels_;  // room for kSources, made once
  std::map<uint64_t, unsigned> buffers_;
  int next_handle_ = 1;
  const Channel* find(int handle) const;
};

// The announcer: one phrase at a time, most urgent first. A phrase of higher priority cuts off
// the one being spoken ("Goal!" over "Red shoots"); a phrase still waiting when it is older than
// `stale_after` seconds is dropped instead of piling up.
class Announcer {
 public:
  Announcer(Mixer& mixer, double stale_after = 1.5);

  // `clip` must outlive its turn in the queue (clips from Speech or load_clip are kept for good).
  void say(const Clip& clip, int priority, double now, std::string_view text = {});
  // Starts the next phrase when the current one has ended or is outranked; call every frame.
  void update(double now);

  const std::string& speaking() const { return current_text_; }
  // Since the last clear_fates(): phrases dropped stale, never spoken, and phrases cut off by a
  // more urgent one, for whoever shows what became of them (the desk's ticker).
  std::span<const std::string> dropped() const { return {dropped_.data(), n_dropped_}; }
  std::span<const std::string> cut() const { return {cut_.data(), n_cut_}; }
  void clear_fates() { n_dropped_ = n_cut_ = 0; }

 private:
  struct Waiting {
    const Clip* clip;
    int priority;
    double at;
    std::string text;
  };
  Mixer& mixer_;
  double stale_after_;
  // The first n_waiting_ are queued; the others keep their text's room for the next phrases.
  std::vector<Waiting> queue_;
  size_t n_waiting_ = 0;
  std::vector<std::string> dropped_, cut_;
  size_t n_dropped_ = 0, n_cut_ = 0;
  int current_ = 0, current_priority_ = 0;
  std::string current_text_;
};

}  // namespace quantum::audio

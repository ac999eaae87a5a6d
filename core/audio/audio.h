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
#include "system/slots.h"

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
  // How `voice` pronounces `text`, in the IPA ("klˈɑːɹə"): for a listener that must know the
  // words as they were said (tools/listen.cpp). Throws AudioError for an unknown voice.
  std::string ipa(const std::string& text, const std::string& voice);

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
  // Sounds played at a place on the field at `gain` times their own (those playing and those to
  // come) until ducked again; the listener's own (the announcer) keep theirs. 1 undoes it.
  void duck(float gain);
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
    float gain = 1;           // the last play's own gain, before any duck
    bool relative = false;    // at the listener's ears (never ducked)
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
  float duck_ = 1;
  std::vector<Channel> channels_;  // room for kSources, made once
  std::map<uint64_t, unsigned> buffers_;
  int next_handle_ = 1;
  const Channel* find(int handle) const;
};

// What became of a phrase given to the announcer: spoken in full, cut off part way, or dropped
// without a sound. Players learn the game by ear, so whoever logs a match says which.
struct PhraseFate {
  // Silent: there was no sound to speak it with (no sound card, --audio none, no voice).
  enum class Kind : uint8_t { Spoken, Cut, Dropped, Silent };
  enum class Why : uint8_t {
    None,        // spoken in full
    Outranked,   // cut off by a more urgent phrase (`by`)
    Stale,       // waited longer than the announcer's stale_after
    Superseded,  // still waiting when newer news came (`by`)
    Repeat,      // the same words were just said, or are waiting (`by`)
    Ended,       // the match ended first (waiting, or cut off at the end)
  };
  uint64_t id = 0;  // the caller's, from say()
  Kind kind = Kind::Spoken;
  Why why = Why::None;
  double start = -1, end = -1;  // when it sounded, in the caller's time; -1 when it never did
  double length = 0;            // the whole phrase, seconds
  std::string by;
};
const char* to_string(PhraseFate::Kind kind);  // "spoken", "cut", "dropped", "silent"
const char* to_string(PhraseFate::Why why);    // "", "outranked", "stale", "superseded", "repeat", "ended"

// How the announcer keeps up with play; a sport sets them (docs/lua-api.md, Sound).
struct AnnouncerRules {
  // A phrase still waiting after this many seconds is dropped: old news. Phrases said together
  // (a goal call and the score) count from when the one before them starts.
  double stale_after = 1.5;
  int keep_from = 3;  // phrases of this priority or more (goal calls, the score) are never stale
  // The same words as the last phrase started, again within this many seconds of its start, are
  // skipped (and so are words already waiting): "Blue shoots" four times in a second is said once.
  double repeat_gap = 0;
  // A more urgent phrase lets the one being spoken finish when it ends within this many seconds,
  // rather than cutting it off into a fragment nobody understands.
  double wait_for = 0;
};

// The announcer: one phrase at a time, most urgent first. A phrase of higher priority cuts off
// the one being spoken ("Goal!" over "Red shoots") unless that one is nearly done; a phrase still
// waiting when it is stale is dropped instead of piling up, and play-by-play that newer news makes
// old (a supersedable phrase) gives way to it.
class Announcer {
 public:
  explicit Announcer(Mixer& mixer, AnnouncerRules rules = {});
  void set_rules(const AnnouncerRules& rules) { rules_ = rules; }

  // `clip` must outlive its turn in the queue (clips from Speech or load_clip are kept for good).
  // `id` comes back in the phrase's fate.
  void say(const Clip& clip, int priority, double now, std::string_view text = {}, uint64_t id = 0,
           bool supersedable = false);
  // Starts the next phrase when the current one has ended or is outranked; call every frame.
  void update(double now);
  // The match is over: what still waits is dropped, what still sounds is cut off.
  void finish(double now);

  const std::string& speaking() const { return current_text_; }
  // The fates settled since the last clear_fates(), in the order they were settled.
  std::span<const PhraseFate> fates() const { return fates_.used(); }
  void clear_fates() { fates_.clear(); }

 private:
  struct Waiting {
    const Clip* clip;
    int priority;
    double at;        // when it was said, or when the phrase it follows started: its news is as old as that
    uint64_t id;
    uint64_t follows;  // the phrase said just before it at the same moment ("0 to 2" after "Goal for Red!"), 0 for none
    bool supersedable;
    std::string text;
  };
  PhraseFate& settle(uint64_t id, PhraseFate::Kind kind, PhraseFate::Why why, double length, std::string_view by);
  void drop(size_t k, PhraseFate::Why why, std::string_view by);
  // The phrase being spoken has ended (spoken in full, or cut off at `end`).
  void end_current(PhraseFate::Kind kind, PhraseFate::Why why, std::string_view by, double end);

  Mixer& mixer_;
  AnnouncerRules rules_;
  system::Slots<Waiting> queue_;  // the phrases waiting; the slots behind keep their text's room
  system::Slots<PhraseFate> fates_;
  std::string last_started_;  // for repeat_gap: the last phrase started, and when
  double last_started_at_ = -1e300;
  uint64_t last_id_ = 0;  // the last phrase said, and when
  double last_at_ = -1;
  // The phrase being spoken.
  int current_ = 0, current_priority_ = 0;
  uint64_t current_id_ = 0;
  double current_start_ = 0, current_length_ = 0;
  std::string current_text_;
};

}  // namespace quantum::audio

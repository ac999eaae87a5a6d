// Record and replay: `quantum play --record DIR` keeps everything a match needs to happen again
// exactly, and `quantum replay DIR` plays it again from there (docs/desk.md).
//
// A recording is a folder:
//   recording.json   the engine's version, the command line, the options that shape the match (seed, particles,
//                    time limit, handicaps, balance, factors, parameters, each player's skill), the sport's path and a hash of
//                    every file copied below, and how many frames were played (null until the recording
//                    is closed: a recording whose process was killed replays up to its last whole frame)
//   sport/<name>/    the sport's folder as it was (Lua, field, sounds; not its specs)
//   sport/powerups/  the power-ups beside it, if any
//   engine/          the engine's own rules/powerups and rules/lib
//   frames.bin       every frame's players, as the match got them: the source's status, each
//                    body's position and velocity (floats, bit for bit), and the throws made
//   reloads/<frame>/ the files a reload loaded before that frame, as they were then
// The match draws from its seed, so the same players, files and options give the same events,
// byte for byte. A recording is data, whoever made it: a replay opens its files only if they are
// regular files inside it, of bounded size, and refuses a recording whose parts are missing,
// links, devices or FIFOs, or named outside it, naming the part (docs/desk.md).
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "game/sport_spec.h"
#include "output_files.h"
#include "players.h"

namespace quantum::runtime {

struct SessionOptions;

// The engine's version, as `git describe` gave it when it was built ("unknown" without git).
const char* engine_version();

// The most a recording's copies (its sport, the engine's scripts and its reloads) hold together.
// A replay copies them all before it plays, and a file at its original place is read to compare
// it only up to its copy's size: so a replay's work before its first frame is bounded by this,
// whatever a recording says. A sport with its sounds is a few megabytes; a recording of a sport
// larger than this is refused when it starts.
inline constexpr uint64_t kMostRecordedBytes = uint64_t(256) << 20;
// The most recording.json may hold: it is read whole. It lists every copied file, a few hundred
// bytes each: this is tens of thousands of files.
inline constexpr uint64_t kMostRecordingJsonBytes = uint64_t(16) << 20;

// FNV-1a (64 bits, hex) of a file's bytes (symlinks followed): enough to tell a changed file from
// a recorded one. Nothing when it is no regular file (a device, a FIFO: reading /dev/zero never
// ends) or holds more than `most` bytes, which are never read.
std::optional<std::string> fingerprint(const std::filesystem::path& file, uint64_t most = kMostRecordedBytes);

// The folders a match's scripts come from, each with its place in a recording: the sport's own,
// the power-ups beside it, and the engine's power-ups and rules/lib.
std::map<std::filesystem::path, std::filesystem::path> sport_trees(const game::SportSpec& sport);

// The decision log's format (docs/decisions.md): 2 has a header line; 1 (before it) had none.
inline constexpr int kDecisionLogVersion = 2;
// The decision log's first line: the engine, the sport's files and their hashes, and everything
// that shapes the match (seed, settings, factors, the players with their skills and handicaps).
void write_decision_header(std::ostream& out, const SessionOptions& options, const game::SportSpec& sport,
                           const game::Match& match);

class Recorder {
 public:
  // Creates `dir` (it must not exist, or be empty), copies the sport's files and writes
  // recording.json with the players' skills (what the rules read). Throws std::runtime_error
  // naming the folder when it cannot, or when the sport's files are more than kMostRecordedBytes.
  Recorder(const std::filesystem::path& dir, const SessionOptions& options, const game::SportSpec& sport,
           std::span<const game::Player> players);
  ~Recorder();
  // The players a frame was played with (nothing stepped when the source was lost).
  void frame(PlayerSource::Status status, std::span<const BodyInput> bodies, std::span<const game::Throw> throws);
  // The files a reload loaded before the frame to come.
  void reloaded(const std::vector<std::filesystem::path>& files);
  // Once, as soon as a write has failed (a full disk): a line to `errors` that says so.
  void say_failure(std::ostream& errors);
  // Completes recording.json (the frame count), replacing it whole: a kill at any moment leaves
  // the one written at the start or the completed one. Throws when anything could not be written.
  void close();
  // After close(): whether every file was written, and the frames recorded.
  bool whole() const { return closed_ && lost_.empty(); }
  uint64_t frames() const { return count_; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::map<std::filesystem::path, std::filesystem::path> places_;  // original folder -> its copy
  std::unique_ptr<DurableFile> frames_;
  std::string frame_;  // the frame being put together, reused
  uint64_t count_ = 0;
  bool closed_ = false;
  std::string lost_;  // the first file that could not be written whole
  bool told_ = false;
};

// A folder of the replay's own, removed with its owner whichever way the replay ends.
class WorkFolder {
 public:
  explicit WorkFolder(std::filesystem::path path = {}) : path_(std::move(path)) {}
  WorkFolder(WorkFolder&& other) noexcept : path_(std::exchange(other.path_, {})) {}
  WorkFolder& operator=(WorkFolder&& other) noexcept;
  ~WorkFolder() { remove(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  void remove() noexcept;
  std::filesystem::path path_;
};

// A recording opened for replay.
struct Replay {
  WorkFolder work;               // a copy of the recording's files, for this replay to change
  std::filesystem::path sport;   // the sport's folder in it
  std::filesystem::path engine;  // the engine's rules in it
  uint64_t seed = 1;
  double seconds = 0;
  uint32_t particles = 0;
  std::vector<double> handicaps;
  double auto_balance = -1;
  std::map<std::string, double> factors;
  std::vector<std::string> params;
  std::vector<std::optional<double>> skills;  // per player, none for a person (and in older recordings)
  std::string version;           // the engine that recorded it
  std::optional<uint64_t> frames;  // how many it recorded; none when it was never closed (a kill)
  // What differs now from when it was recorded: the engine, and the sport's files at their
  // original places ("rules/airhockey/sport.lua changed", "... is gone"); and a recording that
  // was never closed.
  std::vector<std::string> differences;
};

// Reads DIR's recording.json, copies the recording's files into a folder of the replay's own and
// compares the recorded files with the ones at their original places (only regular files are
// read, at most as many bytes as the copy has: anything else "changed"). Throws
// std::runtime_error naming what is missing, malformed or out of range (the key of
// recording.json), a recording's file that is not a regular file of its own (a symlink, a FIFO,
// a device), a path recording.json names outside the recording, or files past their bounds
// (kMostRecordedBytes, kMostRecordingJsonBytes); the copy removed.
Replay open_replay(const std::filesystem::path& dir);

// The players a recording played with, frame by frame; before a frame that had a reload, the
// files it loaded are put back into the replay's copy of the sport (`work`) for the session's
// reloader. A recording is data: a body's value the match would refuse (not a number, far
// outside the field, too fast) is dropped, the body staying where it was, and so is a throw the
// match would refuse, counted and told as tracking values are (DroppedValues). A damaged frame
// (cut short, an impossible status or count) ends the replay at the frame before, told once, and
// so do frames.bin's whole frames ending before the count recording.json has.
class RecordedPlayers final : public PlayerSource {
 public:
  // Owns `work` from now on: it goes when the replay is over. `frames`: Replay::frames. Throws
  // std::runtime_error naming frames.bin when it is not a regular file of the recording's own (a
  // FIFO, a symlink), or not a recording's frames.
  RecordedPlayers(const std::filesystem::path& dir, WorkFolder work, const Field& field,
                  std::ostream* warnings = nullptr, std::optional<uint64_t> frames = std::nullopt);
  Status advance(double t, const game::Match& match, bool waiting) override;
  std::span<const BodyInput> bodies() const override { return bodies_; }
  std::span<const game::Throw> throws() const override { return throws_; }
  std::vector<std::filesystem::path> files_to_reload() override;
  void finish(double t) override { dropped_.tell(t, 0, true); }

 private:
  // Reads the next frame into next_ and next_throws_: "" when it is whole, else what is wrong.
  std::string read_frame(uint8_t& code);
  bool read(void* to, size_t bytes) { return std::fread(to, 1, bytes, frames_.get()) == bytes; }
  // The replay ends after frame_ frames: `why` ("frame 150 is cut short"), told once.
  void end_early(const std::string& why);

  std::filesystem::path dir_;
  WorkFolder work_;
  Field field_;
  std::unique_ptr<FILE, int (*)(FILE*)> frames_{nullptr, &std::fclose};
  std::optional<uint64_t> recorded_frames_;
  std::ostream* warnings_;
  std::vector<BodyInput> bodies_, next_;
  std::vector<game::Throw> throws_, next_throws_;
  DroppedValues dropped_;
  bool over_ = false;
  uint64_t frame_ = 0;  // frames read so far
  int throw_floats_ = 3;  // per throw: vx, vy and up (2 in QGFRAMES2 recordings, made before height)
};

}  // namespace quantum::runtime

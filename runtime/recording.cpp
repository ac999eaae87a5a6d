#include "recording.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <ostream>
#include <set>
#include <stdexcept>
#include <unistd.h>

#include "output_files.h"
#include "session.h"
#include "system/regular_file.h"

namespace quantum::runtime {
namespace fs = std::filesystem;

const char* engine_version() { return QUANTUM_VERSION; }

namespace {

// QGFRAMES3: a throw has its upward speed (fields with height). QGFRAMES2 recordings replay
// with none; QGFRAMES1 (no throws at all) are refused.
constexpr char kMagic[] = "QGFRAMES3\n";
constexpr char kFlatThrows[] = "QGFRAMES2\n";

}  // namespace

namespace {

// FNV-1a, 64 bits, fed as bytes come.
struct Fnv1a {
  uint64_t h = 1469598103934665603ull;
  void add(const char* bytes, size_t n) {
    for (size_t k = 0; k < n; ++k) h = (h ^ uint8_t(bytes[k])) * 1099511628211ull;
  }
  std::string hex() const {
    char out[17];
    std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
    return out;
  }
};

enum class Read { Whole, TooLarge, Failed };

// Reads `fd` to its end, handing each piece to `take`: TooLarge, and no more read, as soon as it
// has given more than `most` bytes (a file may grow after its size was looked at).
template <typename Take>
Read read_all(int fd, uint64_t most, Take take) {
  static thread_local char buffer[1 << 16];
  for (uint64_t total = 0;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return Read::Failed;
    if (n == 0) return Read::Whole;
    total += uint64_t(n);
    if (total > most) return Read::TooLarge;
    take(buffer, size_t(n));
  }
}

}  // namespace

std::optional<std::string> fingerprint(const fs::path& file, uint64_t most) {
  std::string why;
  off_t size = 0;
  const system::FileDescriptor fd(system::open_regular(file, why, &size));
  if (fd.fd < 0 || uint64_t(size) > most) return std::nullopt;
  Fnv1a hash;
  if (read_all(fd.fd, most, [&](const char* bytes, size_t n) { hash.add(bytes, n); }) != Read::Whole) return std::nullopt;
  return hash.hex();
}

namespace {

// Whose folder a tree is: a sport's is read as the sport's load reads it (symlinks followed, and
// anything but a regular file left out); a recording holds its own files and folders only, so a
// symlink, a FIFO or a device in it is refused by name.
enum class Tree { Sport, Recording };

// The files under `from` but the specs.
std::vector<fs::path> files_under(const fs::path& from, Tree tree) {
  std::vector<fs::path> out;
  std::error_code error;
  const fs::file_status root = tree == Tree::Sport ? fs::status(from, error) : fs::symlink_status(from, error);
  if (root.type() == fs::file_type::not_found || (tree == Tree::Sport && !fs::is_directory(root))) return out;
  if (!fs::is_directory(root))
    throw std::runtime_error(from.string() + " is " + system::kind_of(root.type()) + ", not a folder of the recording's own");
  for (auto it = fs::recursive_directory_iterator(from); it != fs::recursive_directory_iterator(); ++it) {
    if (it->is_directory() && it->path().filename() == "spec") {
      it.disable_recursion_pending();
      continue;
    }
    const fs::file_type type = tree == Tree::Sport ? it->status().type() : it->symlink_status().type();
    if (type == fs::file_type::regular) out.push_back(it->path());
    else if (tree == Tree::Recording && type != fs::file_type::directory)
      throw std::runtime_error(it->path().string() + " is " + system::kind_of(type) +
                               ", not a regular file: a recording holds its own files, nothing else");
  }
  return out;
}

struct Copied {
  fs::path original, copy;
  std::string fnv1a;  // the original's, as copied
};

// Copies every file under `from` (but the specs) to `to`, with their fingerprints. `budget`: the
// bytes the copies may still take, less what these take; a file past it is refused (naming it)
// before it is read, and so is one that is not what `tree` allows.
std::vector<Copied> copy_tree(const fs::path& from, const fs::path& to, Tree tree, uint64_t& budget) {
  std::vector<Copied> out;
  for (const fs::path& file : files_under(from, tree)) {
    std::string why;
    off_t size = 0;
    const system::FileDescriptor fd(
        system::open_regular(file, why, &size, tree == Tree::Sport ? system::Links::Follow : system::Links::Refuse));
    if (fd.fd < 0) throw std::runtime_error(file.string() + " " + why);
    const std::string too_much = file.string() + ": more than " + std::to_string(kMostRecordedBytes >> 20) +
                                 " MiB of files in all, more than a recording holds";
    if (uint64_t(size) > budget) throw std::runtime_error(too_much);
    const fs::path copy = to / fs::relative(file, from);
    fs::create_directories(copy.parent_path());
    std::ofstream written(copy, std::ios::binary | std::ios::trunc);
    Fnv1a hash;
    uint64_t bytes = 0;
    const Read read = read_all(fd.fd, budget, [&](const char* piece, size_t n) {
      hash.add(piece, n);
      written.write(piece, std::streamsize(n));
      bytes += n;
    });
    if (read != Read::Whole) throw std::runtime_error(read == Read::TooLarge ? too_much : file.string() + " cannot be read");
    if (!written.flush()) throw std::runtime_error("cannot write " + copy.string());
    budget -= bytes;
    out.push_back({file, copy, hash.hex()});
  }
  return out;
}

// recording.json's `key`: a whole number from `lo` to `hi`, or a refusal naming the file and the key.
uint64_t whole(const nlohmann::json& j, const char* key, uint64_t lo, uint64_t hi, const fs::path& file,
               const std::string& note) {
  const nlohmann::json& v = j.at(key);
  const bool ok = (v.is_number_unsigned() || (v.is_number_integer() && v.get<int64_t>() >= 0)) &&
                  v.get<uint64_t>() >= lo && v.get<uint64_t>() <= hi;
  if (!ok)
    throw std::runtime_error(file.string() + ": \"" + key + "\" must be a whole number from " + std::to_string(lo) +
                             " to " + std::to_string(hi) + note + ", got " + v.dump());
  return v.get<uint64_t>();
}

// recording.json's `key`: a number in [lo, hi], or a refusal naming the file and the key.
double number(const nlohmann::json& j, const char* key, double lo, double hi, const fs::path& file,
              const std::string& note) {
  const nlohmann::json& v = j.at(key);
  if (!(v.is_number() && v.get<double>() >= lo && v.get<double>() <= hi))
    throw std::runtime_error(file.string() + ": \"" + key + "\" must be a number in [" + nlohmann::json(lo).dump() +
                             ", " + nlohmann::json(hi).dump() + "]" + note + ", got " + v.dump());
  return v.get<double>();
}

// Written beside it, then renamed over it: a kill leaves the old file or the new one, whole.
void write_json(const fs::path& file, const nlohmann::json& j) {
  const fs::path next = file.string() + ".next";
  {
    DurableFile out("--record", next.string());
    if (!out.write(j.dump(2) + '\n') || !out.close()) throw std::runtime_error("cannot write " + file.string());
  }
  std::error_code error;
  fs::rename(next, file, error);
  if (error) throw std::runtime_error("cannot write " + file.string() + ": " + error.message());
}

}  // namespace

std::map<fs::path, fs::path> sport_trees(const game::SportSpec& sport) {
  const fs::path folder = fs::absolute(sport.folder).lexically_normal();
  const fs::path engine = fs::absolute(sport.engine).lexically_normal();
  std::map<fs::path, fs::path> trees{{folder, fs::path("sport") / folder.filename()},
                                     {engine / "powerups", "engine/powerups"},
                                     {engine / "lib", "engine/lib"}};
  trees.emplace(folder.parent_path() / "powerups", "sport/powerups");  // unless the engine's own
  return trees;
}

void write_decision_header(std::ostream& out, const SessionOptions& o, const game::SportSpec& sport, const game::Match& match) {
  nlohmann::json files = nlohmann::json::array();
  std::map<std::string, nlohmann::json> hashes;  // by path, in an order a recording's replay keeps
  for (const auto& [original, place] : sport_trees(sport))
    for (const fs::path& file : files_under(original, Tree::Sport)) {
      const std::optional<std::string> hash = fingerprint(file);
      hashes[(place / fs::relative(file, original)).generic_string()] = hash ? nlohmann::json(*hash) : nlohmann::json();
    }
  for (const auto& [path, hash] : hashes) files.push_back({{"path", path}, {"fnv1a", hash}});
  nlohmann::json players = nlohmann::json::array();
  for (const game::Player& p : match.players())
    players.push_back({{"name", p.name}, {"team", p.team}, {"skill", p.skill ? nlohmann::json(*p.skill) : nlohmann::json()},
                       {"handicap", p.handicap}});
  nlohmann::json factors = nlohmann::json::object();
  for (FateKind k : kFateKinds) factors[to_string(k)] = sport.factors[int(k)];
  const game::MatchConfig& c = match.config();
  const nlohmann::json header = {{"format", "quantum decisions"},
                                 {"version", kDecisionLogVersion},
                                 {"engine", engine_version()},
                                 {"sport", fs::absolute(sport.folder).lexically_normal().filename().string()},
                                 {"files", files},
                                 {"seed", c.seed},
                                 {"seconds", c.seconds},
                                 {"fps", c.fps},
                                 {"particles", c.particles},
                                 {"tackle_rate", c.tackle_rate},
                                 {"balance", {{"per_goal", c.balance_per_goal}, {"most", c.balance_most}}},
                                 {"params", sport.params},
                                 {"factor_overrides", o.factors},
                                 {"factors", factors},
                                 {"players", players}};
  out << header.dump() << '\n';
}

Recorder::Recorder(const fs::path& dir, const SessionOptions& o, const game::SportSpec& sport,
                   std::span<const game::Player> players)
    : dir_(dir) {
  if (fs::exists(dir) && !(fs::is_directory(dir) && fs::is_empty(dir)))
    throw std::runtime_error("--record " + dir.string() + ": exists already (a recording goes into a new folder)");
  make_output_folder("--record", dir);
  const fs::path folder = fs::absolute(sport.folder).lexically_normal();
  for (const auto& [original, place] : sport_trees(sport)) places_[original] = dir / place;
  nlohmann::json files = nlohmann::json::array();
  uint64_t budget = kMostRecordedBytes;
  try {
    for (const auto& [original, copy] : places_)
      for (const Copied& c : copy_tree(original, copy, Tree::Sport, budget))
        files.push_back({{"copy", fs::relative(c.copy, dir).string()}, {"original", c.original.string()}, {"fnv1a", c.fnv1a}});
  } catch (const std::exception& e) {
    fs::remove_all(dir);  // no recording that a replay would refuse
    throw std::runtime_error("--record " + dir.string() + ": " + e.what());
  }
  nlohmann::json handicaps = o.handicaps, factors = o.factors, params = sport.params;
  nlohmann::json skills = nlohmann::json::array();
  for (const game::Player& p : players) skills.push_back(p.skill ? nlohmann::json(*p.skill) : nlohmann::json());
  write_json(dir / "recording.json",
             {{"engine", engine_version()},
              {"command", o.command},
              {"sport", folder.string()},
              {"sport_copy", fs::relative(places_[folder], dir).string()},
              {"seed", o.seed},
              {"seconds", o.seconds},
              {"particles", o.particles},
              {"handicaps", handicaps},
              {"auto_balance", o.auto_balance},
              {"factors", factors},
              {"params", params},
              {"skills", skills},
              {"files", files},
              {"frames", nullptr}});
  frames_ = std::make_unique<DurableFile>("--record", (dir / "frames.bin").string());
  if (!frames_->write({kMagic, sizeof kMagic - 1})) throw std::runtime_error("cannot write " + (dir / "frames.bin").string());
  frame_.reserve(1024);
}

Recorder::~Recorder() {
  try {
    // A session that failed to start leaves no half-made recording behind.
    if (count_ == 0 && !closed_) fs::remove_all(dir_);
    else close();
  } catch (...) {
  }
}

void Recorder::frame(PlayerSource::Status status, std::span<const BodyInput> bodies, std::span<const game::Throw> throws) {
  const uint8_t code = uint8_t(status);
  const uint32_t n = uint32_t(bodies.size()), n_throws = uint32_t(throws.size());
  auto put = [this](const auto& value) { frame_.append(reinterpret_cast<const char*>(&value), sizeof value); };
  frame_.clear();
  put(code);
  put(n);
  for (const BodyInput& b : bodies) put(std::array<float, 4>{b.position.x, b.position.y, b.velocity.x, b.velocity.y});
  put(n_throws);
  for (const game::Throw& t : throws) {
    put(int32_t(t.player));
    put(std::array<float, 3>{t.velocity.x, t.velocity.y, t.up});
  }
  // A frame goes to the file whole, in one write: a recording killed at any moment replays up
  // to its last frame.
  if (!frames_->write(frame_) && lost_.empty()) lost_ = frames_->path();
  ++count_;
}

void Recorder::reloaded(const std::vector<fs::path>& files) {
  const fs::path to = dir_ / "reloads" / std::to_string(count_);
  for (const fs::path& file : files) {
    const fs::path original = fs::absolute(file).lexically_normal();
    // The recorded folder it is in (a sport's own powerups/ is in the sport's folder).
    for (const auto& [folder, copy] : places_) {
      const fs::path inside = original.lexically_relative(folder);
      if (inside.empty() || *inside.begin() == "..") continue;
      const fs::path saved = to / fs::relative(copy / inside, dir_);
      std::error_code ec;
      fs::create_directories(saved.parent_path(), ec);
      if (!ec && fs::exists(original)) fs::copy_file(original, saved, fs::copy_options::overwrite_existing, ec);
      if (ec && lost_.empty()) lost_ = saved.string();
      break;
    }
  }
}

void Recorder::say_failure(std::ostream& errors) {
  if (lost_.empty() || told_) return;
  told_ = true;
  say_lost(errors, lost_);
}

void Recorder::close() {
  if (closed_) return;
  closed_ = true;
  if (!frames_->close() && lost_.empty()) lost_ = frames_->path();
  std::ifstream in(dir_ / "recording.json");
  nlohmann::json j = nlohmann::json::parse(in);
  j["frames"] = count_;
  write_json(dir_ / "recording.json", j);
  if (!lost_.empty()) throw std::runtime_error("--record " + dir_.string() + ": could not write every file of the recording (" + lost_ + ")");
}

namespace {

// DIR/recording.json, read whole (it is bounded) and parsed.
nlohmann::json read_recording_json(const fs::path& dir) {
  const fs::path file = dir / "recording.json";
  std::error_code error;
  if (!fs::exists(fs::symlink_status(file, error))) throw std::runtime_error(dir.string() + ": no recording here (no recording.json)");
  std::string why;
  off_t size = 0;
  const system::FileDescriptor fd(system::open_regular(file, why, &size, system::Links::Refuse));
  if (fd.fd < 0) throw std::runtime_error(file.string() + " " + why);
  const std::string too_large = file.string() + " holds more than " + std::to_string(kMostRecordingJsonBytes >> 20) +
                                " MiB, more than a recording's settings and list of files do";
  if (uint64_t(size) > kMostRecordingJsonBytes) throw std::runtime_error(too_large);
  std::string text;
  const Read read = read_all(fd.fd, kMostRecordingJsonBytes, [&](const char* piece, size_t n) { text.append(piece, n); });
  if (read != Read::Whole) throw std::runtime_error(read == Read::TooLarge ? too_large : file.string() + " cannot be read");
  try {
    return nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
}

// The place in the recording that recording.json's `key` names (`name`): a relative path without
// '..' below one of `parts`, which the replay's copy of the recording (`work`, nothing but its
// regular files and folders) holds as `type`. Refused by key otherwise: a recording runs no
// scripts and compares no files but its own.
fs::path recorded_place(const std::string& name, const std::string& key, const std::vector<std::string>& parts,
                        fs::file_type type, const fs::path& work, const fs::path& file) {
  const fs::path place(name);
  const bool inside = !place.empty() && place.is_relative() &&
                      std::find(parts.begin(), parts.end(), place.begin()->string()) != parts.end() &&
                      std::find(place.begin(), place.end(), "..") == place.end();
  if (!inside) {
    std::string folders;
    for (const std::string& part : parts) folders += (folders.empty() ? "" : " or ") + part + "/";
    throw std::runtime_error(file.string() + ": \"" + key + "\" must name a place in the recording's " + folders +
                             " (relative, without '..'), got " + nlohmann::json(name).dump());
  }
  std::error_code error;
  if (fs::symlink_status(work / place, error).type() != type)
    throw std::runtime_error(file.string() + ": \"" + key + "\" names " + place.string() +
                             ", which the recording does not hold (" +
                             (type == fs::file_type::directory ? "a folder" : "a file") + ")");
  return place;
}

}  // namespace

Replay open_replay(const fs::path& dir) {
  const nlohmann::json j = read_recording_json(dir);
  const fs::path file = dir / "recording.json";
  // Replays change their files as the recording's reloads come: they play in a copy of their own,
  // removed whichever way the replay ends.
  static std::atomic<int> replays{0};
  Replay r;
  r.work = WorkFolder(fs::temp_directory_path() /
                      ("quantum_replay_" + std::to_string(getpid()) + "_" + std::to_string(replays++)));
  const fs::path& work = r.work.path();
  fs::remove_all(work);
  try {
    uint64_t budget = kMostRecordedBytes;
    for (const char* part : {"sport", "engine", "reloads"}) copy_tree(dir / part, work / part, Tree::Recording, budget);
    r.sport = work / recorded_place(j.at("sport_copy").get<std::string>(), "sport_copy", {"sport"},
                                    fs::file_type::directory, work, file);
    r.engine = work / "engine";
    // The match's settings, within what `quantum play` accepts of their options.
    r.seed = whole(j, "seed", 0, UINT64_MAX, file, "");
    r.seconds = number(j, "seconds", 0, 24 * 3600, file, " (0: the sport's own time limit)");
    r.particles = uint32_t(whole(j, "particles", 0, 10'000'000, file, " (0: the sport's own)"));
    r.handicaps = j.at("handicaps").get<std::vector<double>>();
    r.auto_balance = number(j, "auto_balance", -1, 10, file, " (below 0: the sport's own)");
    r.factors = j.at("factors").get<std::map<std::string, double>>();
    r.params = j.value("params", std::vector<std::string>());
    for (const nlohmann::json& skill : j.value("skills", nlohmann::json::array())) {
      if (!skill.is_null() && !(skill.is_number() && skill.get<double>() >= 0 && skill.get<double>() <= 1))
        throw std::runtime_error(file.string() + ": \"skills\" must each be a number in [0, 1] (null: a person), got " +
                                 skill.dump());
      r.skills.push_back(skill.is_null() ? std::nullopt : std::optional<double>(skill.get<double>()));
    }
    r.version = j.at("engine");
    // Each original is read at most as far as its copy goes (a larger one has changed), and
    // each copy is listed once: the files compared cost no more than the recording's copies.
    std::set<fs::path> listed;
    for (const nlohmann::json& f : j.at("files")) {
      const fs::path copy = recorded_place(f.at("copy").get<std::string>(), "copy", {"sport", "engine"},
                                           fs::file_type::regular, work, file);
      if (!listed.insert(copy.lexically_normal()).second)
        throw std::runtime_error(file.string() + ": \"files\" lists " + copy.string() + " twice");
      const fs::path original = f.at("original").get<std::string>();
      std::error_code error;
      if (!fs::exists(fs::status(original, error))) r.differences.push_back(original.string() + " is gone since the recording");
      else if (fingerprint(original, fs::file_size(work / copy)) != f.at("fnv1a").get<std::string>())
        r.differences.push_back(original.string() + " changed since the recording");
    }
    // "frames" is null until the recording is closed (older engines wrote 0): its process was killed.
    if (const nlohmann::json frames = j.value("frames", nlohmann::json()); !frames.is_null() && frames != 0)
      r.frames = whole(j, "frames", 1, UINT64_MAX, file, " (null: a recording never closed)");
    else
      r.differences.push_back("the recording was never closed (its process was killed?): it replays up to its last "
                              "whole frame");
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
  if (r.version != engine_version())
    r.differences.insert(r.differences.begin(), std::string("recorded with engine ") + r.version + ", this is " + engine_version());
  return r;
}

WorkFolder& WorkFolder::operator=(WorkFolder&& other) noexcept {
  if (this != &other) {
    remove();
    path_ = std::exchange(other.path_, {});
  }
  return *this;
}

void WorkFolder::remove() noexcept {
  if (path_.empty()) return;
  std::error_code ignored;
  fs::remove_all(path_, ignored);
  path_.clear();
}

RecordedPlayers::RecordedPlayers(const fs::path& dir, WorkFolder work, const Field& field, std::ostream* warnings,
                                 std::optional<uint64_t> frames)
    : dir_(dir), work_(std::move(work)), field_(field), recorded_frames_(frames), warnings_(warnings),
      dropped_((dir / "frames.bin").string(), "recorded value",
               "not a number, far outside the field or faster than it allows, or a throw the match cannot make",
               warnings) {
  const fs::path file = dir / "frames.bin";
  std::string why;
  const int fd = system::open_regular(file, why, nullptr, system::Links::Refuse);
  if (fd < 0) throw std::runtime_error(file.string() + " " + why);
  frames_.reset(::fdopen(fd, "rb"));
  if (!frames_) {
    ::close(fd);
    throw std::runtime_error(file.string() + " cannot be read");
  }
  char magic[sizeof kMagic - 1] = {};
  const bool whole = read(magic, sizeof magic);
  if (whole && std::string(magic, sizeof magic) == kFlatThrows) throw_floats_ = 2;
  else if (!whole || std::string(magic, sizeof magic) != kMagic) {
    // Recordings before throws were recorded (QGFRAMES1) lack each frame's throws.
    const bool older = std::string(magic, 8) == std::string(kMagic, 8);
    throw std::runtime_error(file.string() +
                             (older ? ": recorded by an older engine (" + std::string(magic, sizeof magic - 1) +
                                          ", this one replays " + std::string(kMagic, sizeof kMagic - 2) + ")"
                                    : ": not a recording's frames"));
  }
  for (const BodySpec& b : field.bodies) bodies_.push_back({b.start, {0, 0}});
  next_ = bodies_;
}

void RecordedPlayers::end_early(const std::string& why) {
  // The frames before were whole: the replay ends there, as at the recording's end.
  over_ = true;
  if (warnings_)
    *warnings_ << "quantum: " << (dir_ / "frames.bin").string() << ": " << why << ": the replay ends after " << frame_
               << " whole frames, as if the recording were over\n";
}

std::string RecordedPlayers::read_frame(uint8_t& code) {
  const std::string cut = "is cut short";
  uint32_t n = 0;
  if (!read(&n, sizeof n)) return cut;
  if (code > uint8_t(Status::Ended))
    return "is damaged (its status is " + std::to_string(code) + ", not 0 to " + std::to_string(int(Status::Ended)) + ")";
  // Counts are checked before anything is read or made for them.
  if (n != next_.size())
    return "is damaged (it moves " + std::to_string(n) + " bodies, the field has " + std::to_string(next_.size()) + ")";
  for (BodyInput& b : next_) {
    float v[4];
    if (!read(v, sizeof v)) return cut;
    b = {{v[0], v[1]}, {v[2], v[3]}};
  }
  uint32_t n_throws = 0;
  if (!read(&n_throws, sizeof n_throws)) return cut;
  if (n_throws > 4 * next_.size())
    return "is damaged (" + std::to_string(n_throws) + " throws, at most " + std::to_string(4 * next_.size()) + ")";
  next_throws_.resize(n_throws);
  for (game::Throw& t : next_throws_) {
    int32_t player = 0;
    float v[3] = {0, 0, 0};
    if (!read(&player, sizeof player) || !read(v, size_t(throw_floats_) * sizeof(float))) return cut;
    if (player < 0 || size_t(player) >= next_.size())
      return "is damaged (a throw by player " + std::to_string(player) + ", the field has " + std::to_string(next_.size()) + ")";
    t = {player, {v[0], v[1]}, v[2]};
  }
  return "";
}

PlayerSource::Status RecordedPlayers::advance(double t, const game::Match&, bool) {
  throws_.clear();
  uint8_t code = 0;
  if (over_) return Status::Ended;
  if (!read(&code, 1)) {
    // A recording never closed said so when it opened (Replay::differences).
    if (recorded_frames_ && *recorded_frames_ != frame_)
      end_early("recording.json counts " + std::to_string(*recorded_frames_) + " frames");
    over_ = true;
    return Status::Ended;
  }
  if (const std::string damage = read_frame(code); !damage.empty()) {
    end_early("frame " + std::to_string(frame_) + " " + damage);
    return Status::Ended;
  }
  // What the match would refuse is dropped: the body stays where it was, still.
  for (size_t k = 0; k < next_.size(); ++k) {
    if (body_fault(field_, next_[k]) == BodyFault::None) {
      bodies_[k] = next_[k];
    } else {
      dropped_.count();
      bodies_[k].velocity = {0, 0};
    }
  }
  for (const game::Throw& th : next_throws_) {
    if (throw_fault({th.velocity.x, th.velocity.y, th.up}, field_.has_height()).empty()) throws_.push_back(th);
    else dropped_.count();
  }
  dropped_.tell(t);
  ++frame_;
  return Status(code);
}

std::vector<fs::path> RecordedPlayers::files_to_reload() {
  std::vector<fs::path> out;
  // open_replay copied the recording's reloads into the work folder, checked and bounded.
  const fs::path saved = work_.path() / "reloads" / std::to_string(frame_);
  if (!fs::is_directory(saved)) return out;
  uint64_t budget = kMostRecordedBytes;
  for (const Copied& c : copy_tree(saved, work_.path(), Tree::Recording, budget)) out.push_back(c.copy);
  return out;
}

}  // namespace quantum::runtime

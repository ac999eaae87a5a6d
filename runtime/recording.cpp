#include "recording.h"

#include <nlohmann/json.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <ostream>
#include <stdexcept>
#include <unistd.h>

#include "confined_path.h"
#include "output_files.h"
#include "session.h"
#include "sport.h"

namespace quantum::runtime {
namespace fs = std::filesystem;

const char* engine_version() { return QUANTUM_VERSION; }

namespace {

// QGFRAMES3: a throw has its upward speed (fields with height). QGFRAMES2 recordings replay
// with none; QGFRAMES1 (no throws at all) are refused.
constexpr char kMagic[] = "QGFRAMES3\n";
constexpr char kFlatThrows[] = "QGFRAMES2\n";

}  // namespace

std::string fingerprint(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  uint64_t h = 1469598103934665603ull;
  for (char c; in.get(c);) h = (h ^ uint8_t(c)) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

namespace {

// Copies every file under `from` (but the specs) to `to`; returns the copies, relative to `root`.
std::vector<std::pair<fs::path, fs::path>> copy_tree(const fs::path& from, const fs::path& to) {
  std::vector<std::pair<fs::path, fs::path>> out;  // original, copy
  if (!fs::is_directory(from)) return out;
  for (auto it = fs::recursive_directory_iterator(from); it != fs::recursive_directory_iterator(); ++it) {
    if (it->is_directory() && it->path().filename() == "spec") {
      it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file()) continue;
    const fs::path copy = to / fs::relative(it->path(), from);
    fs::create_directories(copy.parent_path());
    fs::copy_file(it->path(), copy, fs::copy_options::overwrite_existing);
    out.push_back({it->path(), copy});
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

// Written beside and renamed over: a process killed while writing leaves the old file whole.
void write_json(const fs::path& file, const nlohmann::json& j) {
  const fs::path beside = file.string() + ".new";
  {
    DurableFile out("--record", beside.string());
    if (!out.write(j.dump(2) + '\n') || !out.close()) throw std::runtime_error("cannot write " + file.string());
  }
  std::error_code ec;
  fs::rename(beside, file, ec);
  if (ec) throw std::runtime_error("cannot write " + file.string() + " (" + ec.message() + ")");
}

// Every file under `from` but the specs.
std::vector<fs::path> files_under(const fs::path& from) {
  std::vector<fs::path> out;
  if (!fs::is_directory(from)) return out;
  for (auto it = fs::recursive_directory_iterator(from); it != fs::recursive_directory_iterator(); ++it) {
    if (it->is_directory() && it->path().filename() == "spec") {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file()) out.push_back(it->path());
  }
  return out;
}

}  // namespace

std::map<fs::path, fs::path> sport_trees(const lua::Sport& sport) {
  const fs::path folder = fs::absolute(sport.folder()).lexically_normal();
  const fs::path engine = fs::absolute(sport.engine()).lexically_normal();
  std::map<fs::path, fs::path> trees{{folder, fs::path("sport") / folder.filename()},
                                     {engine / "powerups", "engine/powerups"},
                                     {engine / "lib", "engine/lib"}};
  trees.emplace(folder.parent_path() / "powerups", "sport/powerups");  // unless the engine's own
  return trees;
}

void write_decision_header(std::ostream& out, const SessionOptions& o, const lua::Sport& sport, const game::Match& match) {
  nlohmann::json files = nlohmann::json::array();
  std::map<std::string, std::string> hashes;  // by path, in an order a recording's replay keeps
  for (const auto& [original, place] : sport_trees(sport))
    for (const fs::path& file : files_under(original))
      hashes[(place / fs::relative(file, original)).generic_string()] = fingerprint(file);
  for (const auto& [path, hash] : hashes) files.push_back({{"path", path}, {"fnv1a", hash}});
  nlohmann::json players = nlohmann::json::array();
  for (const game::Player& p : match.players())
    players.push_back({{"name", p.name}, {"team", p.team}, {"skill", p.skill ? nlohmann::json(*p.skill) : nlohmann::json()},
                       {"handicap", p.handicap}});
  nlohmann::json factors = nlohmann::json::object();
  for (FateKind k : kFateKinds) factors[to_string(k)] = sport.factor(to_string(k));
  const game::MatchConfig& c = match.config();
  const nlohmann::json header = {{"format", "quantum decisions"},
                                 {"version", kDecisionLogVersion},
                                 {"engine", engine_version()},
                                 {"sport", fs::absolute(sport.folder()).lexically_normal().filename().string()},
                                 {"files", files},
                                 {"seed", c.seed},
                                 {"seconds", c.seconds},
                                 {"fps", c.fps},
                                 {"particles", c.particles},
                                 {"tackle_rate", c.tackle_rate},
                                 {"balance", {{"per_goal", c.balance_per_goal}, {"most", c.balance_most}}},
                                 {"params", sport.params().pairs()},
                                 {"factor_overrides", o.factors},
                                 {"factors", factors},
                                 {"players", players}};
  out << header.dump() << '\n';
}

Recorder::Recorder(const fs::path& dir, const SessionOptions& o, const lua::Sport& sport,
                   std::span<const game::Player> players)
    : dir_(dir) {
  if (fs::exists(dir) && !(fs::is_directory(dir) && fs::is_empty(dir)))
    throw std::runtime_error("--record " + dir.string() + ": exists already (a recording goes into a new folder)");
  make_output_folder("--record", dir);
  const fs::path folder = fs::absolute(sport.folder()).lexically_normal();
  for (const auto& [original, place] : sport_trees(sport)) places_[original] = dir / place;
  nlohmann::json files = nlohmann::json::array();
  for (const auto& [original, copy] : places_)
    for (const auto& [from, to] : copy_tree(original, copy))
      files.push_back({{"copy", fs::relative(to, dir).string()}, {"original", from.string()}, {"fnv1a", fingerprint(from)}});
  nlohmann::json handicaps = o.handicaps, factors = o.factors, params = sport.params().pairs();
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
              {"frames", 0}});
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

Replay open_replay(const fs::path& dir) {
  std::ifstream in(dir / "recording.json");
  if (!in) throw std::runtime_error(dir.string() + ": no recording here (no recording.json)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw std::runtime_error((dir / "recording.json").string() + ": " + e.what());
  }
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
    for (const char* part : {"sport", "engine"}) copy_tree(dir / part, work / part);
    r.sport = work / j.at("sport_copy").get<std::string>();
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
    for (const nlohmann::json& f : j.at("files")) {
      const fs::path original = f.at("original").get<std::string>();
      if (!fs::exists(original)) r.differences.push_back(original.string() + " is gone since the recording");
      // A device or a FIFO is no file of a sport's (and reading /dev/zero never ends).
      else if (!lua::not_a_regular_file(original).empty() || fingerprint(original) != f.at("fnv1a").get<std::string>())
        r.differences.push_back(original.string() + " changed since the recording");
    }
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

RecordedPlayers::RecordedPlayers(const fs::path& dir, WorkFolder work, const Field& field, std::ostream* warnings)
    : dir_(dir), work_(std::move(work)), field_(field), frames_(dir / "frames.bin", std::ios::binary),
      warnings_(warnings),
      dropped_((dir / "frames.bin").string(), "recorded value",
               "not a number, far outside the field or faster than it allows, or a throw the match cannot make",
               warnings) {
  char magic[sizeof kMagic - 1] = {};
  const bool read = bool(frames_.read(magic, sizeof magic));
  if (read && std::string(magic, sizeof magic) == kFlatThrows) throw_floats_ = 2;
  else if (!read || std::string(magic, sizeof magic) != kMagic) {
    // Recordings before throws were recorded (QGFRAMES1) lack each frame's throws.
    const bool older = std::string(magic, 8) == std::string(kMagic, 8);
    throw std::runtime_error((dir / "frames.bin").string() +
                             (older ? ": recorded by an older engine (" + std::string(magic, sizeof magic - 1) +
                                          ", this one replays " + std::string(kMagic, sizeof kMagic - 2) + ")"
                                    : ": not a recording's frames"));
  }
  for (const BodySpec& b : field.bodies) bodies_.push_back({b.start, {0, 0}});
  next_ = bodies_;
}

std::string RecordedPlayers::read_frame(uint8_t& code) {
  auto get = [&](void* to, size_t n) { return bool(frames_.read(static_cast<char*>(to), std::streamsize(n))); };
  const std::string cut = "is cut short";
  uint32_t n = 0;
  if (!get(&n, sizeof n)) return cut;
  if (code > uint8_t(Status::Ended))
    return "is damaged (its status is " + std::to_string(code) + ", not 0 to " + std::to_string(int(Status::Ended)) + ")";
  // Counts are checked before anything is read or made for them.
  if (n != next_.size())
    return "is damaged (it moves " + std::to_string(n) + " bodies, the field has " + std::to_string(next_.size()) + ")";
  for (BodyInput& b : next_) {
    float v[4];
    if (!get(v, sizeof v)) return cut;
    b = {{v[0], v[1]}, {v[2], v[3]}};
  }
  uint32_t n_throws = 0;
  if (!get(&n_throws, sizeof n_throws)) return cut;
  if (n_throws > 4 * next_.size())
    return "is damaged (" + std::to_string(n_throws) + " throws, at most " + std::to_string(4 * next_.size()) + ")";
  next_throws_.resize(n_throws);
  for (game::Throw& t : next_throws_) {
    int32_t player = 0;
    float v[3] = {0, 0, 0};
    if (!get(&player, sizeof player) || !get(v, size_t(throw_floats_) * sizeof(float))) return cut;
    if (player < 0 || size_t(player) >= next_.size())
      return "is damaged (a throw by player " + std::to_string(player) + ", the field has " + std::to_string(next_.size()) + ")";
    t = {player, {v[0], v[1]}, v[2]};
  }
  return "";
}

PlayerSource::Status RecordedPlayers::advance(double t, const game::Match&, bool) {
  throws_.clear();
  uint8_t code = 0;
  if (over_ || !frames_.read(reinterpret_cast<char*>(&code), 1)) return Status::Ended;
  if (const std::string damage = read_frame(code); !damage.empty()) {
    // The frames before it were whole: the replay ends there, as at the recording's end.
    over_ = true;
    if (warnings_)
      *warnings_ << "quantum: " << (dir_ / "frames.bin").string() << ": frame " << frame_ << ' ' << damage
                 << ": the replay ends after " << frame_ << " whole frames, as if the recording were over\n";
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
  const fs::path saved = dir_ / "reloads" / std::to_string(frame_);
  if (!fs::is_directory(saved)) return out;
  for (const auto& [from, to] : copy_tree(saved, work_.path())) out.push_back(to);
  return out;
}

}  // namespace quantum::runtime

// Record and replay: a match recorded with `--record` plays again from its folder to the same
// event log and decision log, byte for byte, whether its players were simulated, tracked from a
// Kinect recording or from a filmed handball rally with its throws, and with a script reloaded
// halfway; a replay says which files changed since.
#include <gtest/gtest.h>

#include <cstring>
#include <iterator>
#include <limits>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "field_loader.h"
#include "play.h"
#include "recording.h"
#include "session.h"
#if QUANTUM_WITH_TRACKING
#include "synthetic.h"
#endif
#include "lua_sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("quantum_recording_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Plays (options.record set) or replays (options.replay set) to the end; returns the event log
// and the decision log, and the warnings.
struct Logs {
  std::string events, decisions, warnings;
};
Logs run(runtime::SessionOptions o, const fs::path& out, const std::function<void(runtime::Session&, int)>& each_frame = {}) {
  o.events = (out / "events.jsonl").string();
  o.decisions = (out / "decisions.jsonl").string();
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  std::ostringstream warnings;
  {
    runtime::Session session(o, tools::lua_sport, nullptr, warnings);
    for (int frame = 0; session.frame(); ++frame)
      if (each_frame) each_frame(session, frame);
    session.finish();
  }
  return {read(o.events), read(o.decisions), warnings.str()};
}

// Replays `recording` to the end, its logs in `out` (made here).
Logs replay(const std::string& recording, const fs::path& out) {
  fs::create_directories(out);
  runtime::SessionOptions r;
  r.replay = recording;
  return run(r, out);
}

// No replay leaves its copy of the files behind, whichever way it ends.
void expect_no_work_folder_left() {
  for (const auto& entry : fs::directory_iterator(fs::temp_directory_path()))
    EXPECT_NE(entry.path().filename().string().rfind("quantum_replay_" + std::to_string(getpid()) + "_", 0), 0u)
        << entry.path();
}

// 20 s of `sport` between simulated players, recorded in dir/recording.
runtime::SessionOptions to_record(const std::string& sport, uint64_t seed, const fs::path& dir) {
  runtime::SessionOptions o;
  o.sport = sport;
  o.seconds = 20;
  o.seed = seed;
  o.record = (dir / "recording").string();
  return o;
}

TEST(Recording, ASimulatedMatchReplaysByteForByte) {
  const fs::path dir = scratch("bots");
  const runtime::SessionOptions o = to_record(QUANTUM_SOURCE_DIR "/rules/airhockey", 4, dir);
  fs::create_directories(dir / "played");
  const Logs played = run(o, dir / "played");
  const Logs replayed = replay(o.record, dir / "replayed");
  ASSERT_GT(std::count(played.events.begin(), played.events.end(), '\n'), 20);
  ASSERT_GT(std::count(played.decisions.begin(), played.decisions.end(), '\n'), 100);
  EXPECT_EQ(replayed.events, played.events);
  EXPECT_EQ(replayed.decisions, played.decisions);
  EXPECT_EQ(replayed.warnings, "");  // nothing changed since
  expect_no_work_folder_left();  // the replay's own copy of the files is gone with it
}

TEST(Recording, AReloadHalfwayIsReplayedWhereItHappened) {
  const fs::path dir = scratch("reload");
  fs::create_directories(dir / "sports");
  fs::copy(QUANTUM_SOURCE_DIR "/rules/airhockey", dir / "sports" / "airhockey", fs::copy_options::recursive);
  const fs::path sport = dir / "sports" / "airhockey" / "sport.lua";
  const std::string original = read(sport);
  runtime::SessionOptions o;
  o.sport = (dir / "sports" / "airhockey").string();
  o.seconds = 20;
  o.seed = 2;
  o.watch = true;
  o.record = (dir / "recording").string();
  fs::create_directories(dir / "played");
  const Logs played = run(o, dir / "played", [&](runtime::Session& s, int frame) {
    if (frame != 300) return;
    std::string edited = original;
    edited.replace(edited.find("factors = { goal = 5,"), 21, "factors = { goal = 50,");  // goals much likelier
    edited.replace(edited.find("\"{team} shoots\""), 15, "\"{team} has it\"");
    std::ofstream(sport) << edited;
    s.reload(sport.string());
  });
  EXPECT_NE(played.warnings.find("quantum: reloaded"), std::string::npos) << played.warnings;
  EXPECT_NE(played.events.find("has it"), std::string::npos);
  // The replay reloads at the same frame from its recorded copy, although the file is as it was.
  std::ofstream(sport) << original;
  const Logs replayed = replay(o.record, dir / "replayed");
  EXPECT_EQ(replayed.events, played.events);
  EXPECT_EQ(replayed.decisions, played.decisions);
}

// A power-up of the sport's own, edited while the match runs but before it is first granted:
// the match loads the edited script when it grants it, and so must the replay.
TEST(Recording, AScriptEditedBeforeItIsFirstUsedIsReplayedAsItWasUsed) {
  const fs::path dir = scratch("unused");
  const fs::path sport = dir / "sports" / "airhockey";
  fs::create_directories(sport / "powerups");
  fs::copy(QUANTUM_SOURCE_DIR "/rules/airhockey", sport, fs::copy_options::recursive);
  std::string text = read(sport / "sport.lua");
  text.replace(text.rfind("return sport"), 12,
               "local granted = false\n"
               "local drop = sport.on.drop\n"
               "sport.on.drop = function(game, e)\n"
               "  drop(game, e)\n"
               "  if not granted then\n"
               "    granted = true\n"
               "    game.after(8, function(game) game.grant(\"Red's mallet\", 'sticky') end)\n"
               "  end\n"
               "end\n"
               "return sport");
  std::ofstream(sport / "sport.lua") << text;
  const std::string sticky = "return { duration = 30, factor = function(fate, holder, game, p)\n"
                             "  if fate.kind == 'body' and fate.actor == holder.name then return STRENGTH end end }\n";
  auto with = [&](const std::string& strength) {
    std::string s = sticky;
    s.replace(s.find("STRENGTH"), 8, strength);
    return s;
  };
  std::ofstream(sport / "powerups" / "sticky.lua") << with("1");
  runtime::SessionOptions o;
  o.sport = sport.string();
  o.seconds = 20;
  o.seed = 6;
  o.watch = true;
  o.record = (dir / "recording").string();
  fs::create_directories(dir / "played");
  const Logs played = run(o, dir / "played", [&](runtime::Session& s, int frame) {
    if (frame != 200) return;
    std::ofstream(sport / "powerups" / "sticky.lua") << with("20");  // Red's mallet catches almost everything
    s.reload((sport / "powerups" / "sticky.lua").string());
  });
  std::ofstream(sport / "powerups" / "sticky.lua") << with("1");
  const Logs replayed = replay(o.record, dir / "replayed");
  EXPECT_NE(played.events.find("\"powerup\":\"sticky\""), std::string::npos);
  EXPECT_EQ(replayed.events, played.events);
  EXPECT_EQ(replayed.decisions, played.decisions);
}

TEST(Recording, AReplaySaysWhatChangedSinceTheRecording) {
  const fs::path dir = scratch("changed");
  fs::create_directories(dir / "sports");
  fs::copy(QUANTUM_SOURCE_DIR "/rules/practice", dir / "sports" / "practice", fs::copy_options::recursive);
  runtime::SessionOptions o;
  o.sport = (dir / "sports" / "practice").string();
  o.seconds = 5;
  o.record = (dir / "recording").string();
  fs::create_directories(dir / "played");
  const Logs played = run(o, dir / "played");
  std::ofstream(dir / "sports" / "practice" / "sport.lua", std::ios::app) << "-- edited after the recording\n";
  fs::remove(dir / "sports" / "practice" / "field.lua");
  const Logs replayed = replay(o.record, dir / "replayed");
  EXPECT_NE(replayed.warnings.find("practice/sport.lua changed since the recording"), std::string::npos) << replayed.warnings;
  EXPECT_NE(replayed.warnings.find("practice/field.lua is gone since the recording"), std::string::npos) << replayed.warnings;
  EXPECT_EQ(replayed.events, played.events);  // played from the recorded copy all the same
}

// Tracked matches: from a synthetic Kinect recording and a filmed handball rally.
#if QUANTUM_WITH_TRACKING
TEST(Recording, AMatchTrackedFromAKinectRecordingReplaysByteForByte) {
  const fs::path dir = scratch("kinect");
  tools::DepthSceneOptions scene;
  scene.frames = 240;  // 8 s of play at 30 Hz
  tools::write_depth_recording((dir / "kinect").string(), scene);
  // A sport on the synthetic table: air hockey's rules on a 0.9 x 0.45 m field.
  const fs::path sport = dir / "small";
  fs::create_directories(sport);
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/airhockey/sport.lua", sport / "sport.lua");
  std::ofstream(sport / "field.lua") << R"(local x, y, m = 0.45, 0.225, 0.06
return {
  name = "Small table",
  ball = { radius = 0.02 },
  brownian = 0.03,
  walls = {
    { name = "left wall", points = { { -x, y }, { x, y } } },
    { name = "right wall", points = { { -x, -y }, { x, -y } } },
    { name = "Blue's end", points = { { -x, y }, { -x, m } } },
    { name = "Blue's end", points = { { -x, -m }, { -x, -y } } },
    { name = "Red's end", points = { { x, y }, { x, m } } },
    { name = "Red's end", points = { { x, -m }, { x, -y } } },
  },
  goals = {
    { name = "Blue's goal", team = "blue", from = { -x, -m }, to = { -x, m } },
    { name = "Red's goal", team = "red", from = { x, -m }, to = { x, m } },
  },
  spots = {
    { name = "in front of Blue's goal", team = "blue", at = { -0.2, 0 } },
    { name = "in front of Red's goal", team = "red", at = { 0.2, 0 } },
  },
  bodies = {
    { name = "Blue's mallet", team = "blue", radius = 0.03, at = { -0.38, 0 } },
    { name = "Red's mallet", team = "red", radius = 0.03, at = { 0.38, 0 } },
  },
}
)";
  runtime::SessionOptions o;
  o.sport = sport.string();
  o.input = "fakenect:" + (dir / "kinect").string();
  o.record = (dir / "recording").string();
  fs::create_directories(dir / "played");
  const Logs played = run(o, dir / "played");
  ASSERT_GT(std::count(played.decisions.begin(), played.decisions.end(), '\n'), 5) << played.warnings;
  const Logs replayed = replay(o.record, dir / "replayed");
  EXPECT_EQ(replayed.events, played.events);
  EXPECT_EQ(replayed.decisions, played.decisions);
}

// Handball from a filmed rally and its accelerometers: the throws are part of each recorded
// frame, and the hall's --param's part of the recording.
// Rewrites a recording's frames as QGFRAMES2 did: each throw without its third number (its upward
// speed). False when the frames are not QGFRAMES3 or a throw has an upward speed.
bool as_flat_throws(const fs::path& frames) {
  std::ifstream in(frames, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string magic = "QGFRAMES3\n";
  if (bytes.compare(0, magic.size(), magic) != 0) return false;
  std::string out = "QGFRAMES2\n";
  size_t at = magic.size();
  auto take = [&](size_t n) { out.append(bytes, at, n), at += n; };
  auto u32 = [&]() { uint32_t v; std::memcpy(&v, bytes.data() + at, 4); return v; };
  while (at < bytes.size()) {
    take(1);  // status
    const uint32_t bodies = u32();
    take(4 + 16 * size_t(bodies));
    const uint32_t throws = u32();
    take(4);
    for (uint32_t k = 0; k < throws; ++k) {
      take(4 + 8);  // player, vx, vy
      float up;
      std::memcpy(&up, bytes.data() + at, 4);
      if (up != 0) return false;
      at += 4;
    }
  }
  std::ofstream(frames, std::ios::binary | std::ios::trunc) << out;
  return true;
}

TEST(Recording, AHandballRallyWithThrowsReplaysByteForByte) {
  const fs::path dir = scratch("rally");
  tools::HatSceneOptions scene;
  tools::write_rally_video((dir / "hall").string(), scene, lua::load_field(QUANTUM_SOURCE_DIR "/rules/handball"));
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/handball";
  o.input = "video:" + (dir / "hall" / "hats.avi").string();
  o.accel = (dir / "hall" / "accel.csv").string();
  o.fov = scene.horizontal_fov;
  o.params = {"minutes=1"};
  o.record = (dir / "recording").string();
  fs::create_directories(dir / "played");
  const Logs played = run(o, dir / "played");
  ASSERT_NE(played.events.find("\"type\":\"pass\""), std::string::npos) << played.warnings;
  ASSERT_NE(played.events.find("\"type\":\"goal\""), std::string::npos);
  const Logs replayed = replay(o.record, dir / "replayed");
  EXPECT_EQ(replayed.events, played.events);
  EXPECT_EQ(replayed.decisions, played.decisions);
  EXPECT_EQ(replayed.warnings, "");
  // The same recording as an engine before height wrote it (QGFRAMES2: a throw without its
  // upward speed, which a flat field's throws never have) replays the same match.
  ASSERT_TRUE(as_flat_throws(fs::path(o.record) / "frames.bin"));
  const Logs older = replay(o.record, dir / "older");
  EXPECT_EQ(older.events, played.events);
}
#endif

TEST(Recording, ARecordingGoesIntoANewFolder) {
  const fs::path dir = scratch("exists");
  std::ofstream(dir / "something") << "x";
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/practice";
  o.record = dir.string();
  std::ostringstream warnings;
  EXPECT_THROW(runtime::Session(o, tools::lua_sport, nullptr, warnings), std::runtime_error);
  EXPECT_THROW({
    runtime::SessionOptions r;
    r.replay = (dir / "nothing").string();
    runtime::Session(r, tools::lua_sport, nullptr, warnings);
  }, std::runtime_error);
}

// Damaged recordings: a handball match between simulated players (they throw), recorded once;
// each test damages a copy of it.
const fs::path& handball_recording() {
  static const fs::path recording = [] {
    // One per test process: CTest runs the tests that share it side by side.
    const fs::path dir = scratch("handball_" + std::to_string(getpid()));
    const runtime::SessionOptions o = to_record(QUANTUM_SOURCE_DIR "/rules/handball", 3, dir);
    run(o, dir);
    return fs::path(o.record);
  }();
  return recording;
}

fs::path copy_of_recording(const std::string& name) {
  const fs::path to = scratch(name) / "recording";
  fs::copy(handball_recording(), to, fs::copy_options::recursive);
  return to;
}

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Where each frame of QGFRAMES3 `bytes` starts, and where each throw's player is.
struct Frames {
  std::vector<size_t> starts, throws;
};
Frames frames_in(const std::string& bytes) {
  Frames f;
  auto u32 = [&](size_t at) { uint32_t v; std::memcpy(&v, bytes.data() + at, 4); return v; };
  for (size_t at = std::strlen("QGFRAMES3\n"); at < bytes.size();) {
    f.starts.push_back(at);
    at += 1 + 4 + 16 * size_t(u32(at + 1));
    const uint32_t n = u32(at);
    at += 4;
    for (uint32_t k = 0; k < n; ++k, at += 16) f.throws.push_back(at);
  }
  return f;
}

void put_floats(std::string& bytes, size_t at, std::initializer_list<float> values) {
  for (float v : values) std::memcpy(bytes.data() + at, &v, 4), at += 4;
}

size_t lines(const std::string& text) { return size_t(std::count(text.begin(), text.end(), '\n')); }

// Issue 17: a recording is data. A body's position that is not a number or far outside the field
// is dropped (the body stays where it was), counted and told, and the replay plays to its end.
TEST(Recording, ABodysBadValuesInTheFramesAreDroppedAndTheReplayGoesOn) {
  const fs::path recording = copy_of_recording("bad_bodies");
  std::string bytes = bytes_of(recording / "frames.bin");
  const Frames frames = frames_in(bytes);
  ASSERT_GT(frames.starts.size(), 600u);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t k = 100; k < 200; ++k) put_floats(bytes, frames.starts[k] + 5, {nan, nan});  // body 0's x, y
  for (size_t k = 300; k < 310; ++k) put_floats(bytes, frames.starts[k] + 5, {3.4e38f, 1e30f});
  // Body 1's velocity, well past the warning's 5 s from the first.
  put_floats(bytes, frames.starts[frames.starts.size() - 10] + 5 + 16, {0, 0, std::numeric_limits<float>::infinity(), 0});
  std::ofstream(recording / "frames.bin", std::ios::binary | std::ios::trunc) << bytes;
  Logs replayed;
  ASSERT_NO_THROW(replayed = replay(recording.string(), recording.parent_path() / "replayed"));
  EXPECT_NE(replayed.warnings.find("frames.bin: 1 recorded value dropped (not a number, far outside the field"),
            std::string::npos) << replayed.warnings;
  EXPECT_NE(replayed.warnings.find("; 111 in all), the match goes on"), std::string::npos) << replayed.warnings;
  EXPECT_LE(lines(replayed.warnings), 4u) << replayed.warnings;  // told at most every 5 s of the match
  EXPECT_NE(replayed.events.find("\"type\":\"time_up\""), std::string::npos);  // played to its end
}

// A throw the match cannot make (its speed not a number, infinite, above 1000 m/s or 0) is
// dropped and counted; the replay goes on.
TEST(Recording, AThrowTheMatchCannotMakeIsDroppedAndTheReplayGoesOn) {
  const fs::path recording = copy_of_recording("bad_throws");
  std::string bytes = bytes_of(recording / "frames.bin");
  const Frames frames = frames_in(bytes);
  ASSERT_GE(frames.throws.size(), 4u);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::vector<std::vector<float>> bad = {{nan, nan, nan}, {inf, 0, 0}, {1e38f, 1e38f, 0}, {0, 0, 0}};
  for (size_t k = 0; k < frames.throws.size(); ++k) {
    const std::vector<float>& v = bad[k % bad.size()];
    put_floats(bytes, frames.throws[k] + 4, {v[0], v[1], v[2]});
  }
  std::ofstream(recording / "frames.bin", std::ios::binary | std::ios::trunc) << bytes;
  Logs replayed;
  ASSERT_NO_THROW(replayed = replay(recording.string(), recording.parent_path() / "replayed"));
  EXPECT_NE(replayed.warnings.find("recorded value"), std::string::npos) << replayed.warnings;
  EXPECT_NE(replayed.events.find("\"type\":\"time_up\""), std::string::npos);
}

// A damaged frames.bin ends the replay at its last whole frame, told once, as a recording's end.
TEST(Recording, ADamagedFrameEndsTheReplayAtTheFrameBefore) {
  const std::string whole = bytes_of(handball_recording() / "frames.bin");
  const Frames frames = frames_in(whole);
  ASSERT_GE(frames.throws.size(), 1u);
  const uint32_t huge = 0xffffffff;
  const size_t throwing = std::upper_bound(frames.starts.begin(), frames.starts.end(), frames.throws[0]) - frames.starts.begin() - 1;
  struct Damage {
    std::string name, bytes, told;
  };
  std::vector<Damage> damages = {
      {"cut", whole.substr(0, frames.starts[150] + 7), "frame 150 is cut short: the replay ends after 150 whole frames"},
      {"status", whole, "frame 100 is damaged (its status is 200, not 0 to 2)"},
      {"bodies", whole, "frame 100 is damaged (it moves 4294967295 bodies"},
      {"throws", whole, "frame " + std::to_string(throwing) + " is damaged (4294967295 throws"},
  };
  damages[1].bytes[frames.starts[100]] = char(200);
  std::memcpy(damages[2].bytes.data() + frames.starts[100] + 1, &huge, 4);
  std::memcpy(damages[3].bytes.data() + frames.throws[0] - 4, &huge, 4);
  for (const Damage& d : damages) {
    const fs::path recording = copy_of_recording("damaged_" + d.name);
    std::ofstream(recording / "frames.bin", std::ios::binary | std::ios::trunc) << d.bytes;
    Logs replayed;
    ASSERT_NO_THROW(replayed = replay(recording.string(), recording.parent_path() / "replayed")) << d.name;
    EXPECT_NE(replayed.warnings.find(d.told), std::string::npos) << d.name << ": " << replayed.warnings;
    EXPECT_EQ(lines(replayed.warnings), 1u) << replayed.warnings;
  }
}

// recording.json's settings are checked as `quantum play` checks their options, by name.
TEST(Recording, ARecordingsSettingsOutOfRangeAreRefusedByName) {
  const fs::path recording = copy_of_recording("settings");
  const std::string original = read(recording / "recording.json");
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"particles", "-1"}, {"particles", "4000000000"}, {"particles", "1e300"}, {"particles", "30000000"},
      {"particles", "2.5"}, {"seed", "-1"}, {"seed", "1.5"}, {"seconds", "-3"}, {"seconds", "1e300"},
      {"auto_balance", "1e300"}};
  for (const auto& [key, value] : bad) {
    nlohmann::json j = nlohmann::json::parse(original);
    j[key] = nlohmann::json::parse(value);
    std::ofstream(recording / "recording.json", std::ios::trunc) << j.dump();
    runtime::SessionOptions r;
    r.replay = recording.string();
    std::ostringstream warnings;
    try {
      runtime::Session session(r, tools::lua_sport, nullptr, warnings);
      ADD_FAILURE() << key << " = " << value << " was taken";
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("recording.json: \"" + key + "\" must be"), std::string::npos) << message;
    }
  }
  expect_no_work_folder_left();
}

// Only regular files are fingerprinted: a device in "files" (reading /dev/zero never ends) differs.
TEST(Recording, ARecordedFileThatIsNoRegularFileDiffers) {
  const fs::path recording = copy_of_recording("device");
  nlohmann::json j = nlohmann::json::parse(read(recording / "recording.json"));
  j["files"] = nlohmann::json::array({{{"original", "/dev/zero"}, {"fnv1a", "0"}, {"copy", j["files"][0]["copy"]}}});
  std::ofstream(recording / "recording.json", std::ios::trunc) << j.dump();
  const Logs replayed = replay(recording.string(), recording.parent_path() / "replayed");
  EXPECT_NE(replayed.warnings.find("/dev/zero changed since the recording"), std::string::npos) << replayed.warnings;
}

// A replay that stops with an error, in recording.json or after it (a sport copy that does not
// load), removes its copy of the files all the same.
TEST(Recording, AReplayThatFailsLeavesNoCopyBehind) {
  const fs::path recording = copy_of_recording("fails");
  nlohmann::json j = nlohmann::json::parse(read(recording / "recording.json"));
  fs::remove(recording / j.at("sport_copy").get<std::string>() / "sport.lua");
  runtime::SessionOptions r;
  r.replay = recording.string();
  std::ostringstream warnings;
  EXPECT_ANY_THROW(runtime::Session(r, tools::lua_sport, nullptr, warnings));
  expect_no_work_folder_left();
}

// A replay whose recording ends before the match's time limit is not a draw: the summary says
// the match did not finish.
TEST(Recording, ARecordingThatEndsEarlyIsNoDraw) {
  const fs::path recording = copy_of_recording("early");
  const std::string whole = bytes_of(recording / "frames.bin");
  std::ofstream(recording / "frames.bin", std::ios::binary | std::ios::trunc) << whole.substr(0, frames_in(whole).starts[100]);
  runtime::SessionOptions r;
  r.replay = recording.string();
  r.pacing = runtime::SessionOptions::Pacing::Fast;
  r.audio = "none";
  std::ostringstream out, errors;
  tools::play(r, out, errors);
  EXPECT_NE(out.str().find("final score: blue 0 red 0 (not finished: level)"), std::string::npos) << out.str();
  EXPECT_EQ(out.str().find("(draw)"), std::string::npos);
}


// Issue 43, "Recordings are data": a recording's files are opened only if they are regular files
// of its own, bounded in size; the files it names are compared at a bounded cost; a recording
// whose parts are missing, links, FIFOs or out of place is refused, naming the part.

// A copy of the handball recording in a folder of this test's own.
fs::path fault_copy(const std::string& name) { return copy_of_recording("fault_" + name + "_" + std::to_string(getpid())); }

// What opening a replay of `recording` is refused with ("" when it opens).
std::string refusal(const fs::path& recording) {
  runtime::SessionOptions r;
  r.replay = recording.string();
  std::ostringstream warnings;
  try {
    runtime::Session session(r, tools::lua_sport, nullptr, warnings);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// What this process has read so far (every read(2) of every thread), in bytes.
uint64_t bytes_read() {
  std::ifstream io("/proc/self/io");
  for (std::string key; io >> key;) {
    uint64_t value = 0;
    io >> value;
    if (key == "rchar:") return value;
  }
  return 0;
}

void edit_json(const fs::path& recording, const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json j = nlohmann::json::parse(read(recording / "recording.json"));
  edit(j);
  std::ofstream(recording / "recording.json", std::ios::trunc) << j.dump();
}

// Opening a FIFO that nobody writes blocks: the replay would wait forever. It is refused at once.
void expect_a_fifo_refused(const std::string& part) {
  const fs::path recording = fault_copy("fifo_" + part);
  fs::remove(recording / part);
  ASSERT_EQ(::mkfifo((recording / part).c_str(), 0600), 0);
  EXPECT_EQ(refusal(recording), (recording / part).string() + " is a FIFO, not a regular file");
  expect_no_work_folder_left();
}

TEST(FaultRecordings, AFifoForRecordingJsonIsRefusedNamingIt) { expect_a_fifo_refused("recording.json"); }

TEST(FaultRecordings, AFifoForFramesBinIsRefusedNamingIt) { expect_a_fifo_refused("frames.bin"); }

// A link in a recording can only lead out of it: frames.bin, a script of the sport's copy, and
// the sport folder itself, each a symlink to whole, valid files elsewhere.
TEST(FaultRecordings, ASymlinkInARecordingIsRefusedNamingIt) {
  const fs::path recording = fault_copy("links");
  const fs::path elsewhere = recording.parent_path() / "elsewhere";
  fs::create_directories(elsewhere);
  fs::rename(recording / "frames.bin", elsewhere / "frames.bin");
  fs::create_symlink(elsewhere / "frames.bin", recording / "frames.bin");
  EXPECT_EQ(refusal(recording), (recording / "frames.bin").string() + " is a symbolic link, not a regular file");
  fs::remove(recording / "frames.bin");
  fs::rename(elsewhere / "frames.bin", recording / "frames.bin");
  ASSERT_EQ(refusal(recording), "");

  const fs::path script = recording / "sport" / "handball" / "sport.lua";
  fs::rename(script, elsewhere / "sport.lua");
  fs::create_symlink(elsewhere / "sport.lua", script);
  EXPECT_EQ(refusal(recording), script.string() + " is a symbolic link, not a regular file: a recording holds its own "
                                                  "files, nothing else");
  fs::remove(script);
  fs::rename(elsewhere / "sport.lua", script);

  fs::rename(recording / "sport", elsewhere / "sport");
  fs::create_directory_symlink(elsewhere / "sport", recording / "sport");
  EXPECT_EQ(refusal(recording), (recording / "sport").string() + " is a symbolic link, not a folder of the recording's own");
  expect_no_work_folder_left();
}

// recording.json's sport and the copies it lists are places in the recording: one outside it (by
// '..' or an absolute path: another sport's scripts would run) or one it does not hold is refused.
TEST(FaultRecordings, APlaceOutsideTheRecordingIsRefusedByKey) {
  const fs::path recording = fault_copy("places");
  const std::string original = read(recording / "recording.json");
  const fs::path other = recording.parent_path() / "other";
  fs::create_directories(other);
  fs::copy(QUANTUM_SOURCE_DIR "/rules/airhockey", other / "airhockey", fs::copy_options::recursive);
  struct Case {
    std::string key, value, refused;
  };
  const std::string airhockey = (other / "airhockey").string();
  const std::vector<Case> cases = {
      {"sport_copy", "../../other/airhockey", "\"sport_copy\" must name a place in the recording's sport/ (relative, "
                                              "without '..'), got \"../../other/airhockey\""},
      {"sport_copy", airhockey, "\"sport_copy\" must name a place in the recording's sport/ (relative, without '..'), "
                                "got \"" + airhockey + "\""},
      {"sport_copy", "sport/handball/../../../other/airhockey", "must name a place in the recording's sport/"},
      {"sport_copy", "sport/airhockey", "\"sport_copy\" names sport/airhockey, which the recording does not hold (a folder)"},
      {"copy", "../../other/airhockey/sport.lua", "\"copy\" must name a place in the recording's sport/ or engine/"},
      {"copy", "sport/handball/gone.lua", "\"copy\" names sport/handball/gone.lua, which the recording does not hold (a file)"},
  };
  for (const Case& c : cases) {
    std::ofstream(recording / "recording.json", std::ios::trunc) << original;
    edit_json(recording, [&](nlohmann::json& j) {
      if (c.key == "sport_copy") j["sport_copy"] = c.value;
      else j["files"][0]["copy"] = c.value;
    });
    const std::string message = refusal(recording);
    EXPECT_NE(message.find((recording / "recording.json").string() + ": "), std::string::npos) << c.value << ": " << message;
    EXPECT_NE(message.find(c.refused), std::string::npos) << c.value << ": " << message;
  }
  // A copy listed twice would have its original read twice.
  std::ofstream(recording / "recording.json", std::ios::trunc) << original;
  edit_json(recording, [](nlohmann::json& j) { j["files"].push_back(j["files"][0]); });
  const std::string twice = refusal(recording);
  EXPECT_NE(twice.find("\"files\" lists "), std::string::npos) << twice;
  EXPECT_NE(twice.find(" twice"), std::string::npos) << twice;
  expect_no_work_folder_left();
}

// A file the recording names at its original place is read no further than its copy goes: a
// 64 GiB file there (sparse: it takes no disk) has changed, and is not read. One inside the
// recording is refused before it is read.
TEST(FaultRecordings, AHugeFileIsNeverReadWhole) {
  const fs::path recording = fault_copy("huge");
  const fs::path huge = recording.parent_path() / "huge.lua";
  std::ofstream(huge).put('-');
  fs::resize_file(huge, uint64_t(64) << 30);
  edit_json(recording, [&](nlohmann::json& j) { j["files"][0]["original"] = huge.string(); });
  const uint64_t before = bytes_read();
  const runtime::Replay opened = runtime::open_replay(recording);
  EXPECT_LT(bytes_read() - before, runtime::kMostRecordedBytes);
  EXPECT_NE(std::find(opened.differences.begin(), opened.differences.end(), huge.string() + " changed since the recording"),
            opened.differences.end());

  fs::rename(huge, recording / "sport" / "handball" / "huge.lua");
  const uint64_t again = bytes_read();
  EXPECT_NE(refusal(recording).find((recording / "sport" / "handball" / "huge.lua").string() + ": more than 256 MiB of files "
                                    "in all, more than a recording holds"),
            std::string::npos);
  EXPECT_LT(bytes_read() - again, runtime::kMostRecordedBytes);
  fs::remove(recording / "sport" / "handball" / "huge.lua");
  std::ofstream(recording / "recording.json").put('{');
  fs::resize_file(recording / "recording.json", runtime::kMostRecordingJsonBytes + 1);
  EXPECT_EQ(refusal(recording), (recording / "recording.json").string() + " holds more than 16 MiB, more than a "
                                                                          "recording's settings and list of files do");
}

// Replays `recording` to its end; the frames it played and its warnings.
std::pair<int, std::string> replay_frames(const fs::path& recording) {
  runtime::SessionOptions r;
  r.replay = recording.string();
  r.pacing = runtime::SessionOptions::Pacing::Fast;
  r.audio = "none";
  std::ostringstream warnings;
  int frames = 0;
  runtime::Session session(r, tools::lua_sport, nullptr, warnings);
  while (session.frame()) ++frames;
  session.finish();
  return {frames, warnings.str()};
}

// A recording whose process was killed has recording.json as written at the start (no frame
// count) and frames.bin cut wherever its buffer was last written: it replays its whole frames,
// saying so. A closed recording whose frames.bin lost frames says so too.
TEST(FaultRecordings, AKilledRecordingReplaysUpToItsLastWholeFrame) {
  const fs::path recording = fault_copy("cut");
  const std::string whole = bytes_of(recording / "frames.bin");
  const Frames frames = frames_in(whole);
  ASSERT_GT(frames.starts.size(), 300u);
  edit_json(recording, [](nlohmann::json& j) { j["frames"] = nullptr; });
  std::ofstream(recording / "frames.bin", std::ios::binary | std::ios::trunc) << whole.substr(0, frames.starts[300] + 9);
  const auto [played, warnings] = replay_frames(recording);
  EXPECT_EQ(played, 300);
  EXPECT_NE(warnings.find("quantum: replay: the recording was never closed (its process was killed?): it replays up to "
                          "its last whole frame\n"),
            std::string::npos) << warnings;
  EXPECT_NE(warnings.find("frame 300 is cut short: the replay ends after 300 whole frames"), std::string::npos) << warnings;

  edit_json(recording, [&](nlohmann::json& j) { j["frames"] = frames.starts.size(); });
  std::ofstream(recording / "frames.bin", std::ios::binary | std::ios::trunc) << whole.substr(0, frames.starts[200]);
  const auto [closed_played, closed_warnings] = replay_frames(recording);
  EXPECT_EQ(closed_played, 200);
  EXPECT_NE(closed_warnings.find("frames.bin: recording.json counts " + std::to_string(frames.starts.size()) +
                                 " frames: the replay ends after 200 whole frames"),
            std::string::npos) << closed_warnings;
}

// The same with a real kill: `quantum play --record` killed by SIGKILL mid-match.
TEST(FaultRecordings, ARecordingKilledMidMatchReplays) {
  const fs::path dir = scratch("fault_killed_" + std::to_string(getpid()));
  const fs::path recording = dir / "recording";
  const std::string binary = QUANTUM_BINARY, record = recording.string();
  std::vector<std::string> args = {binary, "play", QUANTUM_SOURCE_DIR "/rules/handball", "--seconds", "3600", "--seed", "5",
                                   "--pace", "fast", "--audio", "none", "--quiet", "--record", record};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t quiet;
  posix_spawn_file_actions_init(&quiet);
  posix_spawn_file_actions_addopen(&quiet, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&quiet, 2, "/dev/null", O_WRONLY, 0);
  pid_t child = 0;
  ASSERT_EQ(posix_spawn(&child, binary.c_str(), &quiet, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&quiet);
  // Until it has recorded a few hundred frames (or has stopped by itself, which fails below).
  int status = 0;
  const auto recorded = [&] {
    std::error_code none_yet;
    const uintmax_t bytes = fs::file_size(recording / "frames.bin", none_yet);
    return none_yet ? 0 : bytes;
  };
  while (waitpid(child, &status, WNOHANG) == 0 && recorded() < 100'000) usleep(10'000);
  ASSERT_EQ(::kill(child, SIGKILL), 0) << "quantum play stopped by itself";
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  ASSERT_TRUE(nlohmann::json::parse(read(recording / "recording.json"))["frames"].is_null());
  const auto [played, warnings] = replay_frames(recording);
  EXPECT_GT(played, 300);
  EXPECT_NE(warnings.find("the recording was never closed"), std::string::npos) << warnings;
}

}  // namespace
}  // namespace quantum

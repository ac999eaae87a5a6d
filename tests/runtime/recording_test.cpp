// Record and replay: a match recorded with `--record` plays again from its folder to the same
// event log and decision log, byte for byte, whether its players were simulated, tracked from a
// Kinect recording or from a filmed handball rally with its throws, and with a script reloaded
// halfway; a replay says which files changed since.
#include <gtest/gtest.h>

#include <cstring>
#include <iterator>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "field_loader.h"
#include "session.h"
#include "synthetic.h"

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
    runtime::Session session(o, nullptr, warnings);
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

TEST(Recording, ASimulatedMatchReplaysByteForByte) {
  const fs::path dir = scratch("bots");
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/airhockey";
  o.seconds = 20;
  o.seed = 4;
  o.record = (dir / "recording").string();
  fs::create_directories(dir / "played");
  const Logs played = run(o, dir / "played");
  const Logs replayed = replay(o.record, dir / "replayed");
  ASSERT_GT(std::count(played.events.begin(), played.events.end(), '\n'), 20);
  ASSERT_GT(std::count(played.decisions.begin(), played.decisions.end(), '\n'), 100);
  EXPECT_EQ(replayed.events, played.events);
  EXPECT_EQ(replayed.decisions, played.decisions);
  EXPECT_EQ(replayed.warnings, "");  // nothing changed since
  // The replay's own copy of the files is gone with it.
  for (const auto& entry : fs::directory_iterator(fs::temp_directory_path()))
    EXPECT_NE(entry.path().filename().string().rfind("quantum_replay_" + std::to_string(getpid()) + "_", 0), 0u)
        << entry.path();
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

TEST(Recording, ARecordingGoesIntoANewFolder) {
  const fs::path dir = scratch("exists");
  std::ofstream(dir / "something") << "x";
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/practice";
  o.record = dir.string();
  std::ostringstream warnings;
  EXPECT_THROW(runtime::Session(o, nullptr, warnings), std::runtime_error);
  EXPECT_THROW({
    runtime::SessionOptions r;
    r.replay = (dir / "nothing").string();
    runtime::Session(r, nullptr, warnings);
  }, std::runtime_error);
}

}  // namespace
}  // namespace quantum

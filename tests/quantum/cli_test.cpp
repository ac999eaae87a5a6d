// `quantum simulate` as other tools use it: exit codes, JSON lines, the snapshot, errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <unistd.h>
#if QUANTUM_WITH_DESK
#include <opencv2/imgcodecs.hpp>
#endif

#include <array>
#include <cmath>
#include <map>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "field_loader.h"
#include "quantum/limits.h"
#include "recording.h"
#include "scenes.h"
#if QUANTUM_WITH_TRACKING
#include "synthetic.h"
#endif
#include "../shipped_sports.h"

namespace {

struct Outcome {
  int status;
  std::string out;  // stdout
  std::string err;  // stderr
};

// `shell` goes before the command, in the same shell: "ulimit -f 48;" caps the files it writes.
Outcome quantum(const std::string& args, const std::string& shell = "") {
  // One file per test process: CTest runs several at once.
  const std::string err_file =
      std::filesystem::temp_directory_path() / ("quantum_cli_stderr_" + std::to_string(getpid()) + ".txt");
  const std::string cmd = shell + std::string(QUANTUM_BINARY) + " " + args + " 2>" + err_file;
  FILE* pipe = popen(cmd.c_str(), "r");
  Outcome run{-1, "", ""};
  if (!pipe) return run;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) run.out.append(buf.data(), n);
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  run.err = ss.str();
  return run;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::string kTable = QUANTUM_SOURCE_DIR "/rules/airhockey";

TEST(Cli, SimulateWritesJsonLinesAndASummary) {
  const std::string events = std::filesystem::temp_directory_path() / "quantum_cli_events.jsonl";
  const Outcome r = quantum("simulate " + kTable + " --seconds 20 --seed 3 --events " + events);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("simulated 20 s of Quantum air hockey table"), std::string::npos) << r.out;
  std::istringstream lines(slurp(events));
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) {
    const nlohmann::json j = nlohmann::json::parse(line);
    for (const char* key : {"t", "type", "actor", "p", "particles"}) EXPECT_TRUE(j.contains(key)) << line;
    EXPECT_GE(j["p"].get<double>(), 0.0);
    EXPECT_LE(j["p"].get<double>(), 1.0);
    if (n == 0) {
      EXPECT_EQ(j["type"], "drop");
    }
    ++n;
  }
  EXPECT_GT(n, 3);
}

TEST(Cli, EventsToStdoutKeepStdoutPureJson) {
  const Outcome r = quantum("simulate " + kTable + " --seconds 10 --events -");
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  while (std::getline(lines, line)) EXPECT_NO_THROW(nlohmann::json::parse(line)) << line;
  EXPECT_NE(r.err.find("events:"), std::string::npos);
}

TEST(Cli, SameSeedSameLog) {
  const Outcome a = quantum("simulate " + kTable + " --seconds 15 --seed 9 --events -");
  const Outcome b = quantum("simulate " + kTable + " --seconds 15 --seed 9 --events -");
  ASSERT_EQ(a.status, 0);
  EXPECT_EQ(a.out, b.out);
  EXPECT_FALSE(a.out.empty());
}

// A cloud large enough that the prediction shares its chunks with a second thread: the same
// match, event for event, on one thread or two.
TEST(Cli, SameSeedSameLogWhateverTheThreads) {
  const std::string match = "play rules/airhockey --audio none --quiet --seconds 3 --seed 4 --particles 20000 --events - ";
  const Outcome one = quantum(match + "--threads 1");
  const Outcome two = quantum(match + "--threads 2");
  ASSERT_EQ(one.status, 0) << one.err;
  ASSERT_EQ(two.status, 0) << two.err;
  EXPECT_EQ(one.out, two.out);
  EXPECT_NE(one.out.find("\"type\":\"shot\""), std::string::npos) << "the players met the ball";
  EXPECT_NE(quantum(match + "--threads 3").status, 0);
}

// Every shipped sport: mallets strike, team players catch and throw on, a shooter shoots at
// the hoop. The match runs to its end, its events lie on the field, and a team sport's ball is
// played on after a catch (each catch is followed by a throw, bar one still in hand at the end).
TEST(Cli, SimulateRunsEveryShippedSport) {
  for (const char* sport : quantum::test::kShippedSports) {
    SCOPED_TRACE(sport);
    const std::string folder = std::string(QUANTUM_SOURCE_DIR "/rules/") + sport;
    quantum::Field field = quantum::lua::load_field(folder);
    quantum::finish_field(field);
    const std::string events = std::filesystem::temp_directory_path() / ("quantum_cli_simulate_" + std::string(sport));
    const Outcome r = quantum("simulate " + folder + " --seconds 30 --seed 5 --events " + events);
    ASSERT_EQ(r.status, 0) << r.err;
    // Nothing on stderr but the event log's confirmation.
    EXPECT_EQ(r.err.rfind("quantum: wrote " + events + ": ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.out.find("simulated 30 s of " + field.name), std::string::npos) << r.out;
    std::istringstream lines(slurp(events));
    std::string line;
    std::map<std::string, int> count;
    while (std::getline(lines, line)) {
      const nlohmann::json j = nlohmann::json::parse(line);
      ++count[j["type"].get<std::string>()];
      if (j["type"] == "out") continue;  // the ball left the bounds: that is where it was
      EXPECT_GE(j["x"].get<double>(), field.bounds_min.x) << line;
      EXPECT_LE(j["x"].get<double>(), field.bounds_max.x) << line;
      EXPECT_GE(j["y"].get<double>(), field.bounds_min.y) << line;
      EXPECT_LE(j["y"].get<double>(), field.bounds_max.y) << line;
    }
    EXPECT_GT(count["drop"] + count["throw"], 0) << "the ball was put in play";
    EXPECT_GT(count["hit"] + count["catch"], 0) << "the players met the ball";
    if (field.catching()) {
      EXPECT_NE(r.out.find(" catch " + std::to_string(count["catch"])), std::string::npos) << r.out;
      EXPECT_GE(count["throw"], count["catch"] - 1) << "a caught ball is thrown on";
    }
  }
}

// The scripted players of `quantum simulate` keep to the field and under its speed limit, with
// the velocity each reports the derivative of its path: checked every frame of a minute.
TEST(SimulateScene, ScriptedPlayersStayOnEveryShippedFieldAndWithinItsSpeed) {
  for (const char* sport : quantum::test::kShippedSports) {
    SCOPED_TRACE(sport);
    quantum::Field field = quantum::lua::load_field(std::string(QUANTUM_SOURCE_DIR "/rules/") + sport);
    quantum::finish_field(field);
    const double dt = 1.0 / 600;
    std::vector<quantum::BodyInput> before = quantum::tools::scripted_mallets(field, 0);
    for (double t = dt; t < 60; t += dt) {
      const std::vector<quantum::BodyInput> now = quantum::tools::scripted_mallets(field, t);
      for (size_t k = 0; k < now.size(); ++k) {
        const quantum::BodySpec& b = field.bodies[k];
        const quantum::BodyInput& in = now[k];
        ASSERT_GE(in.position.x - b.radius, field.bounds_min.x - 1e-4) << b.name << " at " << t;
        ASSERT_LE(in.position.x + b.radius, field.bounds_max.x + 1e-4) << b.name << " at " << t;
        ASSERT_GE(in.position.y - b.radius, field.bounds_min.y - 1e-4) << b.name << " at " << t;
        ASSERT_LE(in.position.y + b.radius, field.bounds_max.y + 1e-4) << b.name << " at " << t;
        ASSERT_LE(std::hypot(in.velocity.x, in.velocity.y), 0.5 * field.max_body_speed + 1e-4) << b.name << " at " << t;
        const double vx = (in.position.x - before[k].position.x) / dt, vy = (in.position.y - before[k].position.y) / dt;
        ASSERT_NEAR(vx, 0.5 * (in.velocity.x + before[k].velocity.x), 0.02) << b.name << " at " << t;
        ASSERT_NEAR(vy, 0.5 * (in.velocity.y + before[k].velocity.y), 0.02) << b.name << " at " << t;
      }
      before = now;
    }
  }
}

// simulate takes the field file's parameters: volleyball's indoor court has six a side, and a
// parameter the field does not read is refused with the ones it does.
TEST(Cli, SimulateTakesTheFieldsParameters) {
  const Outcome indoor = quantum("simulate rules/volleyball --seconds 1 --param players=6");
  ASSERT_EQ(indoor.status, 0) << indoor.err;
  EXPECT_NE(indoor.out.find("6 v 6"), std::string::npos) << indoor.out;
  const Outcome beach = quantum("simulate rules/volleyball --seconds 1");
  ASSERT_EQ(beach.status, 0) << beach.err;
  EXPECT_EQ(beach.out.find("6 v 6"), std::string::npos) << beach.out;
  const Outcome unread = quantum("simulate rules/volleyball --seconds 1 --param points=5");
  EXPECT_EQ(unread.status, 1);
  EXPECT_NE(unread.err.find("unknown parameter 'points' (known: net, players)"), std::string::npos) << unread.err;
}

#if QUANTUM_WITH_DESK
TEST(Cli, SnapshotIsAPicture) {
  const std::string png = std::filesystem::temp_directory_path() / "quantum_cli_snapshot.png";
  std::filesystem::remove(png);
  const Outcome r = quantum("simulate " + kTable + " --seconds 8 --particles 500 --snapshot " + png);
  ASSERT_EQ(r.status, 0) << r.err;
  const cv::Mat img = cv::imread(png);
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, 1100);  // the desk's picture (tests/runtime/desk_test.cpp checks what it shows)
  EXPECT_GT(img.rows, 500);
}
#endif

#if QUANTUM_WITH_REFERENCE
TEST(Cli, Box2DBackendRuns) {
  const Outcome r = quantum("simulate " + kTable + " --seconds 3 --particles 200 --backend box2d --events -");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"type\":\"drop\""), std::string::npos);
}
#endif

TEST(Cli, BadInputGivesAClearErrorAndExitCode) {
  Outcome r = quantum("simulate /nonexistent/field.lua");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("/nonexistent/field.lua: no such field file"), std::string::npos) << r.err;
  const std::string bad = std::filesystem::temp_directory_path() / "quantum_cli_bad.lua";
  std::ofstream(bad) << "return { spots = { { at = { 0, 'x' } } } }";
  r = quantum("simulate " + bad);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(bad + ": spots[1].at: expected a number for y"), std::string::npos) << r.err;
  r = quantum("simulate " + kTable + " --backend physx");
  EXPECT_NE(r.status, 0);
  r = quantum("simulate " + kTable + " --particles 0");
  EXPECT_NE(r.status, 0);
#if QUANTUM_WITH_DESK
  r = quantum("simulate " + kTable + " --snapshot /nonexistent/dir/x.png --seconds 2");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("/nonexistent/dir/x.png"), std::string::npos) << r.err;
#endif
}

// Values the engine cannot honour are refused before anything runs, naming the option.
TEST(Cli, ValuesItCannotHonourAreRefusedByName) {
  const std::pair<const char*, const char*> refused[] = {
      {"--auto-balance nan", "--auto-balance"},
      {"--auto-balance inf", "--auto-balance"},
      {"--seed -1", "--seed"},
      {"--seed 18446744073709551616", "--seed"},
      {"--seed 1e3", "--seed"},
      {"--seconds nan", "--seconds"},
      {"--handicap 1e308,1", "--handicap"},
      {"--handicap 0,1", "--handicap"},
      {"--fov nan", "--fov"},
      {"--skill 2,0.5", "--skill"},
      {"--skill nan,0.5", "--skill"},
  };
  for (const auto& [option, name] : refused) {
    const Outcome r = quantum(std::string("play rules/airhockey --audio none --quiet --seconds 1 ") + option);
    EXPECT_EQ(r.status, 1) << option;
    EXPECT_NE(r.err.find(name), std::string::npos) << option << ": " << r.err;
  }
  const Outcome highest = quantum("play rules/airhockey --audio none --quiet --seconds 1 --seed 18446744073709551615");
  EXPECT_EQ(highest.status, 0) << highest.err;
}

// The command line takes a range's end (quantum/limits.h) and refuses just beyond it, naming the
// range: in CLI11's checks (--fps) and in the session's (--handicap).
TEST(LimitsCommandLine, AnOptionTakesItsRangesEndAndRefusesBeyondNamingTheRange) {
  const std::string simulate = "simulate " + kTable + " --seconds 0.1 --fps ";
  EXPECT_EQ(quantum(simulate + "1000").status, 0);
  const Outcome fast = quantum(simulate + "1000.5");
  EXPECT_NE(fast.status, 0);
  EXPECT_NE(fast.err.find("--fps: expected a number in " + quantum::limits::interval(quantum::limits::kFps) + ", got '1000.5'"),
            std::string::npos)
      << fast.err;
  const std::string play = "play rules/airhockey --audio none --quiet --seconds 0.1 --handicap ";
  const Outcome most = quantum(play + "1000,1");
  EXPECT_EQ(most.status, 0) << most.err;
  const Outcome more = quantum(play + "1000.5,1");
  EXPECT_EQ(more.status, 1);
  EXPECT_NE(more.err.find("handicap " + quantum::limits::must_be_in(quantum::limits::kHandicap, 1000.5)), std::string::npos)
      << more.err;
}

// A log that cannot be written (a full disk, made here with the shell's file size limit) is told
// once, as soon as a write fails, the match plays to its end, and the exit code says something was
// lost.
TEST(Cli, ALogOnAFullDiskIsToldAtOnceAndTheExitCodeSaysSo) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("quantum_cli_log_" + std::to_string(getpid()));
  for (const char* option : {"--events", "--decisions"}) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string log = (dir / "log.jsonl").string();
    // 4 KiB (8 blocks of 512 bytes): 20 s of air hockey logs more, with either option.
    const Outcome r = quantum(std::string("play rules/airhockey --audio none --seconds 20 ") + option + " " + log, "ulimit -f 8; ");
    EXPECT_EQ(r.status, 1) << option;
    const size_t told = r.err.find("cannot write to " + log + " (a full disk, a closed pipe?)");
    EXPECT_NE(told, std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("cannot write to " + log, told + 1), std::string::npos) << "told once: " << r.err;
    EXPECT_GT(r.err.find("could not write every line to " + log), told) << r.err;
    EXPECT_NE(r.out.find("0:20.00"), std::string::npos) << "the match was played to its end: " << r.out;
  }
  std::filesystem::remove_all(dir);
}

TEST(Cli, PlayWithoutASoundCardWarnsOnceAndPlaysSilently) {
  setenv("ALSOFT_DRIVERS", "nosuchdriver", 1);  // no backend: no device can open
  const Outcome r = quantum("play rules/airhockey --seconds 5 --quiet");
  unsetenv("ALSOFT_DRIVERS");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("no sound device"), std::string::npos) << r.err;
}

// tools/play.sh passes its own --seconds; one given after it counts.
TEST(Cli, TheLastOfARepeatedOptionCounts) {
  const Outcome r = quantum("play rules/airhockey --seconds 60 --audio none --seconds 2");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find(", 2 s played"), std::string::npos) << r.out;
}

// Every file a match would write is checked before it plays: a bad path costs a second, not a
// match. The transcript's first line (the sport, its field and seed) is never printed.
TEST(Cli, AnOutputThatCannotBeWrittenStopsPlayBeforeItStarts) {
  const std::string folder = std::filesystem::temp_directory_path();
  const std::pair<std::string, std::string> refused[] = {
      {"--audio wav:/nonexistent/dir/x.wav", "--audio /nonexistent/dir/x.wav: no folder /nonexistent/dir"},
      {"--events /nonexistent/dir/x.jsonl", "--events /nonexistent/dir/x.jsonl: no folder /nonexistent/dir"},
      {"--decisions " + folder, "--decisions " + folder + ": is a folder, not a file"},
      {"--record /dev/null/x", "--record /dev/null/x: cannot make the folder"},
#if QUANTUM_WITH_DESK
      {"--snapshot /nonexistent/dir/x.png", "--snapshot /nonexistent/dir/x.png: no folder /nonexistent/dir"},
      {"--snapshot " + folder + "/quantum_cli.bmpx", "not a picture file OpenCV writes"},
#endif
  };
  for (const auto& [option, said] : refused) {
    const Outcome r = quantum("play rules/airhockey --seconds 600 --quiet " + option);
    EXPECT_EQ(r.status, 1) << option;
    EXPECT_NE(r.err.find(said), std::string::npos) << option << ": " << r.err;
    EXPECT_EQ(r.out, "") << option;
  }
  // A study's results too: nothing is played before its --csv and --plot are known to be writable.
  for (const char* option : {"--csv /nonexistent/dir/x.csv", "--plot /dev/null/x"}) {
    const Outcome r = quantum(std::string("balance rules/airhockey --matches 2 --seconds 5 ") + option);
    EXPECT_EQ(r.status, 1) << option;
    EXPECT_NE(r.err.find(std::string(option).substr(0, 5)), std::string::npos) << option << ": " << r.err;
    EXPECT_EQ(r.out, "") << option;
  }
}

// Past a file size limit (a disk that fills, made here with the shell's ulimit) every file a
// match writes is told once, when its write fails; the match plays to its end, the other files
// are completed, and the exit code says something was lost.
TEST(Cli, EveryFileOnAFullDiskIsToldAtOnceAndTheOthersAreCompleted) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("quantum_cli_full_" + std::to_string(getpid()));
  struct Case {
    std::string option, told;
  };
  const Case cases[] = {
      {"--audio wav:" + (dir / "match.wav").string(), (dir / "match.wav").string()},
      {"--record " + (dir / "recording").string(), (dir / "recording" / "frames.bin").string()},
  };
  for (const Case& c : cases) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    // 24 KiB a file (48 blocks of 512 bytes, as /bin/sh counts them): the sport's copies and the
    // event log fit (about 14 KiB), the sound (3.5 MB) and the frames (about 50 KiB) do not.
    const std::string events = (dir / "events.jsonl").string();
    const Outcome r = quantum("play rules/airhockey --pace fast --seconds 20 --events " + events + " " + c.option,
                              "ulimit -f 48; ");
    EXPECT_EQ(r.status, 1) << c.option << ": " << r.err;
    const size_t told = r.err.find("cannot write to " + c.told + " (a full disk, a closed pipe?)");
    EXPECT_NE(told, std::string::npos) << c.option << ": " << r.err;
    EXPECT_EQ(r.err.find("cannot write to " + c.told, told + 1), std::string::npos) << "told once: " << r.err;
    EXPECT_NE(r.out.find("0:20.00"), std::string::npos) << "the match was played to its end: " << r.out;
    const std::string log = slurp(events);
    EXPECT_NE(log.find("\"type\":\"match_end\""), std::string::npos) << c.option << ": the event log was completed";
  }
  std::filesystem::remove_all(dir);
}

TEST(Cli, PlayRecordsTheMatchToAWav) {
  const std::string stem = std::filesystem::temp_directory_path() / ("quantum_match_" + std::to_string(getpid()));
  const std::string wav = stem + ".wav", events = stem + ".jsonl";
  const Outcome r = quantum("play rules/airhockey --seconds 8 --quiet --audio wav:" + wav + " --events " + events);
  EXPECT_EQ(r.status, 0) << r.err;
  // Nothing on stderr but the two files' confirmations, the log's first.
  EXPECT_EQ(r.err.rfind("quantum: wrote " + events + ": ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("\nquantum: wrote " + wav + ": "), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 2) << r.err;
  // The sound lasts as long as the match and its last phrase, ringing out: when that ends, the
  // events log says (a goal in the last second is called after the whistle).
  double last_phrase = 0;
  std::ifstream log(events);
  for (std::string line; std::getline(log, line);)
    for (const nlohmann::json& p : nlohmann::json::parse(line).value("phrases", nlohmann::json::array()))
      if (p.contains("end")) last_phrase = std::max(last_phrase, p.at("end").get<double>());
  // 44.1 kHz 16-bit stereo: 176,400 bytes a second.
  const double seconds = double(std::filesystem::file_size(wav)) / 176400;
  EXPECT_GT(seconds, 8);
  EXPECT_GE(seconds, last_phrase - 0.05);
  EXPECT_LT(seconds, std::max(8.0, last_phrase) + 1.0) << "the last phrase ends at " << last_phrase << " s";
  std::filesystem::remove(wav), std::filesystem::remove(events);
}

#if QUANTUM_WITH_TRACKING
// `quantum track` on a synthetic recording: one JSON object per depth frame, nobody while the
// background is learnt, both players after it; a corrupt frame is dropped.
TEST(Cli, TrackPrintsOneJsonObjectPerFrame) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("quantum_cli_track_" + std::to_string(getpid()));
  quantum::tools::DepthSceneOptions o;
  o.frames = 20;
  const auto truth = quantum::tools::write_depth_recording(dir.string(), o);
  const Outcome r = quantum("track fakenect:" + dir.string() + " --field-size 0.9,0.45");
  EXPECT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  int n = 0;
  for (std::string line; std::getline(lines, line); ++n) {
    const nlohmann::json j = nlohmann::json::parse(line);
    EXPECT_EQ(j.at("frame").get<int>(), n);
    EXPECT_NEAR(j.at("t").get<double>(), truth[size_t(n)].t, 1e-5);
    const nlohmann::json& players = j.at("players");
    if (n < o.background_frames) {
      EXPECT_TRUE(players.empty()) << line;
      continue;
    }
    for (const nlohmann::json& p : players) {
      for (const char* key : {"id", "team", "x", "y", "vx", "vy"}) EXPECT_TRUE(p.contains(key)) << key << ": " << line;
      EXPECT_TRUE(p.at("team") == "blue" || p.at("team") == "red") << line;
    }
  }
  EXPECT_EQ(n, o.background_frames + o.frames);

  // A corrupt depth frame is data: dropped and told on stderr, and every other frame is out.
  std::ifstream index(dir / "INDEX.txt");
  std::string line, fifth_depth;
  for (int d = 0; std::getline(index, line);)
    if (line[0] == 'd' && ++d == 5) fifth_depth = line;
  std::ofstream(dir / fifth_depth) << "P5 640 480 65535\nshort";
  const Outcome bad = quantum("track fakenect:" + dir.string() + " --field-size 0.9,0.45");
  EXPECT_EQ(bad.status, 0) << bad.err;
  EXPECT_EQ(std::count(bad.out.begin(), bad.out.end(), '\n'), o.background_frames + o.frames - 1);
  EXPECT_NE(bad.err.find("1 tracking value dropped"), std::string::npos) << bad.err;
  std::filesystem::remove_all(dir);
}

// A table mapped to a wrong --field-size sees nobody: one warning says what to check and what
// the pipeline saw, not silence.
TEST(Cli, TrackWarnsOnceWhenItSeesNobody) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("quantum_cli_nobody_" + std::to_string(getpid()));
  quantum::tools::DepthSceneOptions o;
  o.frames = 150;  // five seconds
  quantum::tools::write_depth_recording(dir.string(), o);
  const Outcome right = quantum("track fakenect:" + dir.string() + " --field-size 0.9,0.45");
  EXPECT_EQ(right.status, 0) << right.err;
  EXPECT_EQ(right.err.find("no player seen"), std::string::npos) << right.err;
  const Outcome wrong = quantum("track fakenect:" + dir.string() + " --field-size 2.0,1.0");
  EXPECT_EQ(wrong.status, 0) << wrong.err;
  EXPECT_EQ(wrong.out.find("\"id\""), std::string::npos);  // nobody, as the warning says
  const size_t at = wrong.err.find("no player seen in the first 3 s");
  ASSERT_NE(at, std::string::npos) << wrong.err;
  EXPECT_EQ(wrong.err.find("no player seen", at + 1), std::string::npos) << "once";
  EXPECT_NE(wrong.err.find("2.00 x 1.00 m apart (--field-size"), std::string::npos) << wrong.err;
  // What the pipeline saw: the markers, and arms that all read as hovering on a table taken for
  // one twice its size (every height is scaled with it).
  EXPECT_NE(wrong.err.find("Seen: markers 4 of 4 (field 2.00 x 1.00 m), camera"), std::string::npos) << wrong.err;
  EXPECT_NE(wrong.err.find("reaching in over an end"), std::string::npos) << wrong.err;
  std::filesystem::remove_all(dir);
}

// Without --field-size the Kinect measures the table: one calibration line; a table that is not
// the sport's field is a warning (an error with --strict), and --fit-field stretches the field over
// it, on track and play alike.
TEST(Cli, AKinectMeasuresItsTableAndSaysWhenItIsNotTheSportsField) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("quantum_cli_measure_" + std::to_string(getpid()));
  quantum::tools::DepthSceneOptions o;
  o.frames = 60;
  quantum::tools::write_depth_recording(dir.string(), o);  // 0.9 x 0.45 m; air hockey's field is 2 x 1 m
  const Outcome plain = quantum("track fakenect:" + dir.string());
  EXPECT_EQ(plain.status, 0) << plain.err;
  EXPECT_NE(plain.err.find("quantum: calibration: 4 of 4 markers, camera 1.30 m above the table, tilted"),
            std::string::npos) << plain.err;
  EXPECT_NE(plain.err.find("field 0.90"), std::string::npos) << plain.err;
  EXPECT_NE(plain.err.find("warning: the markers span 0.90 x 0.45 m but the sport's field is 2.00 x 1.00 m"),
            std::string::npos) << plain.err;
  EXPECT_EQ(plain.err.find("no player seen"), std::string::npos) << plain.err;

  const Outcome strict = quantum("track fakenect:" + dir.string() + " --strict");
  EXPECT_EQ(strict.status, 1);
  EXPECT_NE(strict.err.find("the markers span 0.90 x 0.45 m but the sport's field is 2.00 x 1.00 m"), std::string::npos)
      << strict.err;
  EXPECT_NE(strict.err.find("(--strict)"), std::string::npos) << strict.err;

  // --fit-field: the same frames, every position stretched by the field's size over the table's.
  const Outcome fit = quantum("track fakenect:" + dir.string() + " --fit-field");
  EXPECT_EQ(fit.status, 0) << fit.err;
  EXPECT_NE(fit.err.find("--fit-field: the sport's 2.00 x 1.00 m field is stretched over the 0.90 x 0.45 m table"),
            std::string::npos) << fit.err;
  std::istringstream a(plain.out), b(fit.out);
  int compared = 0;
  for (std::string la, lb; std::getline(a, la) && std::getline(b, lb);) {
    const nlohmann::json pa = nlohmann::json::parse(la).at("players"), pb = nlohmann::json::parse(lb).at("players");
    ASSERT_EQ(pa.size(), pb.size());
    for (size_t k = 0; k < pa.size(); ++k, ++compared) {
      EXPECT_NEAR(pb[k].at("x").get<double>(), pa[k].at("x").get<double>() * 2.0 / 0.9, 0.01);
      EXPECT_NEAR(pb[k].at("y").get<double>(), pa[k].at("y").get<double>() * 1.0 / 0.45, 0.01);
    }
  }
  EXPECT_GT(compared, 60);

  const Outcome play = quantum("play " + kTable + " --input fakenect:" + dir.string() + " --audio none --quiet --strict");
  EXPECT_EQ(play.status, 1);
  EXPECT_NE(play.err.find("(--strict)"), std::string::npos) << play.err;
  const Outcome fitted = quantum("play " + kTable + " --input fakenect:" + dir.string() + " --audio none --quiet --fit-field");
  EXPECT_EQ(fitted.status, 0) << fitted.err;
  EXPECT_NE(fitted.err.find("quantum: calibration: 4 of 4 markers"), std::string::npos) << fitted.err;
  EXPECT_NE(fitted.err.find("--fit-field: the sport's 2.00 x 1.00 m field is stretched"), std::string::npos) << fitted.err;
  std::filesystem::remove_all(dir);
}

// A hat camera's markers cannot measure the field: without --field the default's (air hockey's
// 2 m table) is said to be taken, and a field the markers do not fit is a warning (an error with
// --strict): the synthetic hall is 20 x 10 m seen from 13 m up, which a 2 x 1 m field puts 1.3 m
// up, under the hats; a square field is not the markers' shape. The hall's own field is quiet.
TEST(Cli, TrackSaysWhenAHatCamerasFieldIsNotTheHallItSees) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("quantum_cli_hall_" + std::to_string(getpid()));
  quantum::tools::HatSceneOptions o;
  o.seconds = 0.5;
  quantum::tools::write_hat_video(dir.string(), o);
  const std::string source = "track video:" + (dir / "hats.avi").string() + " --frames 3";
  const Outcome table = quantum(source);
  EXPECT_EQ(table.status, 0) << table.err;
  EXPECT_NE(table.err.find("warning: video:" + (dir / "hats.avi").string() + ": no --field: its markers are taken for "
                           "the corners of airhockey's 2.00 x 1.00 m field, the default"), std::string::npos) << table.err;
  EXPECT_NE(table.err.find("the markers, taken for the corners of a 2.00 x 1.00 m field, put the camera 1.30 m above the "
                           "floor, below the hats (1.80 m up): the field they show is larger, at least 4.3 x 2.2 m"),
            std::string::npos) << table.err;
  const Outcome hall = quantum(source + " --field handball");
  EXPECT_EQ(hall.status, 0) << hall.err;
  EXPECT_EQ(hall.err, "");
  const Outcome square = quantum(source + " --field handball --field-size 20,20");
  EXPECT_NE(square.err.find("the markers' rectangle is 2.00 times as long as wide, but the 20.00 x 20.00 m field is 1.00 "
                            "times"), std::string::npos) << square.err;
  const Outcome strict = quantum(source + " --strict");
  EXPECT_EQ(strict.status, 1);
  EXPECT_NE(strict.err.find("below the hats"), std::string::npos) << strict.err;
  EXPECT_NE(strict.err.find("(--strict)"), std::string::npos) << strict.err;
  std::filesystem::remove_all(dir);
}

TEST(Cli, TrackWithoutADeviceSaysSoInOneLine) {
  for (const char* source : {"kinect", "camera:7"}) {
    const Outcome r = quantum(std::string("track ") + source + " --frames 1");
    EXPECT_EQ(r.status, 1) << source;
    EXPECT_EQ(r.out, "") << source;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(std::string("quantum: ") + (source[0] == 'k' ? "kinect: no Kinect found" : "camera:7: cannot open")),
              std::string::npos)
        << r.err;
  }
}

TEST(Cli, TrackRefusesAnUnknownSource) {
  const Outcome r = quantum("track webcam");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("unknown source 'webcam'"), std::string::npos) << r.err;
}
#endif

TEST(Cli, PlayRefusesABadAudioOption) {
  const Outcome r = quantum("play rules/airhockey --seconds 1 --quiet --audio speakers");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--audio speakers"), std::string::npos) << r.err;
}

TEST(Cli, AMistypedCommandOrOptionIsNamedWithTheNearestOne) {
  Outcome r = quantum("paly");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("unknown command 'paly' (did you mean 'play'?"), std::string::npos) << r.err;
  r = quantum("play --sed 3 --audio none");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("unknown option '--sed' (did you mean '--seed'?"), std::string::npos) << r.err;
  r = quantum("balance --matchs=4");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("did you mean '--matches'?"), std::string::npos) << r.err;
  r = quantum("simulate");  // a missing argument is bad input too, with the same code
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("FIELD"), std::string::npos) << r.err;
}

// Whatever is wrong with a command line, the message is the engine's own: it names the command
// and the option, and none of CLI11's wording comes through ("Value 3 not in range 1 to 2",
// "--seconds: 1 required FLOAT missing", "FIELD is required", "Could not convert: ...").
TEST(Cli, EveryBadCommandLineIsToldInTheEnginesWords) {
  struct Bad {
    std::string args, command, option;
  };
  const Bad table[] = {
      {"", "", "command"},
      {"--nope", "", "--nope"},
      {"plya", "", "plya"},
      {"play --threads 3", "play", "--threads"},
      {"play --seconds", "play", "--seconds"},
      {"play --seconds=", "play", "--seconds"},
      {"play --seconds -5", "play", "--seconds"},
      {"play --seed abc", "play", "--seed"},
      {"play --particles 0", "play", "--particles"},
      {"play --field-size", "play", "--field-size"},
      {"play --pace slow", "play", "--pace"},
      {"play --snapshot-at 3", "play", "--snapshot-at"},
      {"play --quiet=abc", "play", "--quiet"},
      {"play --fov", "play", "--fov"},
      {"play --video-fps 0", "play", "--video-fps"},
      {"play --param", "play", "--param"},
      {"play --sed 3", "play", "--sed"},
      {"simulate", "simulate", "FIELD"},
      {"simulate rules/airhockey --backend physx", "simulate", "--backend"},
      {"simulate rules/airhockey --fps abc", "simulate", "--fps"},
      {"simulate rules/airhockey --fps 5", "simulate", "--fps"},
      {"simulate rules/airhockey --purgatory 0", "simulate", "--purgatory"},
      {"simulate rules/airhockey --particles 1.5", "simulate", "--particles"},
      {"replay", "replay", "DIR"},
      {"replay match --until 0", "replay", "--until"},
      {"replay match --pace slow", "replay", "--pace"},
      {"replay match --snapshot-at 2", "replay", "--snapshot-at"},
      {"replay match --view=maybe", "replay", "--view"},
      {"balance --matches abc", "balance", "--matches"},
      {"balance --matches 0", "balance", "--matches"},
      {"balance --factors none", "balance", "--factors"},
      {"balance --sweep-matches 0", "balance", "--sweep-matches"},
      {"balance --csv", "balance", "--csv"},
      {"balance --matchs=4", "balance", "--matchs"},
      {"test --nope", "test", "--nope"},
      {"track", "track", "SOURCE"},
      {"track kinect --frames abc", "track", "--frames"},
      {"track kinect --frames", "track", "--frames"},
      {"track kinect --frames -1", "track", "--frames"},
      {"track kinect --fov 180", "track", "--fov"},
      {"listen", "listen", "MATCH.wav"},
      {"listen match.wav", "listen", "EVENTS.jsonl"},
      {"listen match.wav match.jsonl extra.txt", "listen", "extra.txt"},
      {"audit", "audit", "FILES"},
  };
  const std::string hint = "\n(quantum --help lists the commands, quantum COMMAND --help their options)\n";
  const std::regex clis_words(R"(not in range|required|Could not convert|not in \{|requires|Expected|At least|At Most|)"
                              R"(was not expected|subcommand|true/false|\b(FLOAT|UINT|INT|TEXT)\b)");
  std::set<std::string> commands;
  for (const Bad& bad : table) {
    SCOPED_TRACE(bad.args);
    const Outcome r = quantum(bad.args);
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.out, "");
    ASSERT_GT(r.err.size(), hint.size());
    EXPECT_EQ(r.err.substr(r.err.size() - hint.size()), hint) << r.err;
    const std::string said = r.err.substr(0, r.err.size() - hint.size());
    EXPECT_EQ(said.find('\n'), std::string::npos) << "one line: " << said;
    EXPECT_EQ(said.rfind(bad.command.empty() ? "quantum: " : "quantum " + bad.command + ": ", 0), 0u) << said;
    EXPECT_NE(said.find(bad.option), std::string::npos) << said;
    EXPECT_FALSE(std::regex_search(said, clis_words)) << said;
    commands.insert(bad.command);
  }
  EXPECT_EQ(commands.size(), 9u) << "every command, and none";
}

// --version says which build this is: the project's version, the commit (as recordings and
// decision logs name it) and the build's options.
TEST(Cli, VersionNamesTheProjectVersionTheCommitAndTheBuild) {
  const Outcome r = quantum("--version");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.rfind("quantum " QUANTUM_PROJECT_VERSION " (commit " + std::string(quantum::runtime::engine_version()) +
                            ", " QUANTUM_BUILD_TYPE ", ",
                        0),
            0u)
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(, (gcc|clang) \d+\.\d+[^,]*, sanitizers (on|off)\)\nmodules: )"))) << r.out;
}

// Each command's --help ends with two or three examples, real command lines whose options are
// their command's own; a command's first example is of that command.
// Its second line says which of the optional parts this build has (CMake's QUANTUM_WITH_*).
TEST(Cli, VersionListsTheModulesOfThisBuild) {
  const Outcome r = quantum("--version");
  EXPECT_EQ(r.status, 0) << r.err;
  const auto on = [](bool built) { return built ? " on" : " off"; };
  const std::string modules = std::string("\nmodules: tracking") + on(QUANTUM_WITH_TRACKING) + ", desk" +
                              on(QUANTUM_WITH_DESK) + ", recognizer" + on(QUANTUM_WITH_RECOGNIZER) + ", reference" +
                              on(QUANTUM_WITH_REFERENCE) + "\n";
  EXPECT_TRUE(r.out.ends_with(modules)) << r.out;
}

TEST(Cli, EveryHelpEndsWithExamplesOfRealCommandLines) {
  const std::vector<std::string> commands = {"simulate", "play", "replay", "balance", "test", "track", "listen", "audit"};
  std::map<std::string, std::string> help;
  for (const std::string& command : commands) help[command] = quantum(command + " --help").out;
  help[""] = quantum("--help").out;
  for (const auto& [command, text] : help) {
    SCOPED_TRACE(command);
    const size_t at = text.find("\nExamples:\n");
    ASSERT_NE(at, std::string::npos) << text;
    EXPECT_FALSE(std::regex_search(text.substr(0, at), std::regex(R"(\b(FLOAT|UINT|INT|TEXT)\b)"))) << text;
    std::istringstream lines(text.substr(at + 11));
    int examples = 0;
    for (std::string line; std::getline(lines, line);) {
      if (line.empty() || line.rfind("  # ", 0) == 0) continue;
      ASSERT_EQ(line.rfind("  quantum ", 0), 0u) << line;
      std::istringstream words(line);
      std::string program, sub;
      words >> program >> sub;
      ASSERT_EQ(std::count(commands.begin(), commands.end(), sub), 1) << line;
      if (examples == 0 && !command.empty()) {
        EXPECT_EQ(sub, command) << line;
      }
      const std::string options = help.at(sub).substr(0, help.at(sub).find("\nExamples:\n"));
      for (std::string word; words >> word;) {
        if (word.rfind("--", 0) == 0) {
          EXPECT_NE(options.find(" " + word + " "), std::string::npos) << word << " in " << line;
        }
      }
      ++examples;
    }
    EXPECT_GE(examples, 2);
    EXPECT_LE(examples, 3);
  }
}

TEST(Cli, VersionAndZeroSeconds) {
  Outcome r = quantum("--version");
  EXPECT_EQ(r.status, 0);
  EXPECT_FALSE(r.out.empty());
  // 0 s is refused like any other bad value, not taken as the sport's full time.
  for (const char* command : {"play --audio none", "balance --matches 2", "simulate " QUANTUM_SOURCE_DIR "/rules/airhockey"}) {
    r = quantum(std::string(command) + " --seconds 0");
    EXPECT_EQ(r.status, 1) << command;
    EXPECT_NE(r.err.find("--seconds"), std::string::npos) << command << ": " << r.err;
  }
}

TEST(Cli, TestNamesEachSpecFileAsItRunsAndExitsTwoOnAFailure) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "quantum_cli_specs";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "good_spec.lua") << "describe('good', function() it('holds', function() assert.are.equal(2, 1 + 1) end) end)\n";
  Outcome r = quantum("test " + dir.string());
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("good_spec.lua + ok 1 specs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("every spec passed in"), std::string::npos) << r.out;
  std::ofstream(dir / "bad_spec.lua") << "describe('bad', function() it('fails', function() assert.are.equal(3, 1 + 1) end) end)\n";
  r = quantum("test " + dir.string());
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_NE(r.out.find("bad_spec.lua - FAILED 1 of 1 specs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 failed in"), std::string::npos) << r.out;
  r = quantum("test " + (dir / "nothing_here").string());
  EXPECT_EQ(r.status, 1);
}

}  // namespace

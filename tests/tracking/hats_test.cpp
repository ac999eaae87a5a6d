// Handball hat tracking on synthetic hall videos (tools/synthetic.h): positions, identities
// through crossings, throws from accelerometers, and bad accelerometer input.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <opencv2/videoio.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include "synthetic.h"
#include "tracking/lines.h"
#include "tracking/tracking.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

// A tracker for a synthetic hall, seen as the scene's camera sees it.
tracking::HatTracker tracker_for(const tools::HatSceneOptions& o) {
  tracking::TrackedField field;
  field.length = o.length, field.width = o.width;
  tracking::HatConfig config;
  config.horizontal_fov = o.horizontal_fov;
  return tracking::HatTracker(field, config);
}

// The figures: identity kept through crossings, position error mean <= 5 cm on a 20 m
// hall. Two seeds: two camera poses, each with two same-team crossings. Throws from the
// accelerometers come out once each, by the right player, in the direction they run.
TEST(Hats, PlayersAreFollowedThroughCrossingsAndTheirThrowsFound) {
  for (const uint64_t seed : {1u, 2u}) {
    const fs::path dir = fs::temp_directory_path() / ("quantum_hats_" + std::to_string(seed));
    tools::HatSceneOptions o;
    o.seed = seed;
    const tools::HatTruth truth = tools::write_hat_video(dir.string(), o);
    tracking::HatTracker tracker = tracker_for(o);
    tracking::AccelSource accel((dir / "accel.csv").string());
    tracking::ThrowDetector throws;
    cv::VideoCapture video((dir / "hats.avi").string());
    ASSERT_TRUE(video.isOpened());
    cv::Mat image;
    double sum = 0;
    int n = 0, lost = 0;
    std::vector<tracking::TrackedAction> actions;
    std::vector<double> action_times;
    for (int f = 0; video.read(image); ++f) {
      const double t = f / o.fps;
      tracking::TrackedFrame seen = tracker.feed(image, f, t);
      throws.add(accel.until(t), seen);
      for (const auto& a : seen.actions) actions.push_back(a), action_times.push_back(t);
      const tools::TruthFrame& want = truth.frames.at(size_t(f));
      ASSERT_EQ(seen.players.size(), want.players.size()) << "frame " << f;
      for (const tools::TruthPlayer& p : want.players) {
        const auto it = std::find_if(seen.players.begin(), seen.players.end(),
                                     [&](const tracking::TrackedPlayer& s) { return s.id == p.id; });
        ASSERT_NE(it, seen.players.end()) << p.id;
        const double e = std::hypot(it->x - p.x, it->y - p.y);
        sum += e, ++n;
        lost += e > 1.0;  // a swapped or lost identity is metres off, a crossing's coast decimetres
      }
    }
    fs::remove_all(dir);
    std::cout << "seed " << seed << ": mean error " << 100 * sum / n << " cm over " << n << " positions, " << lost
              << " more than 1 m off\n";
    EXPECT_EQ(n, int(truth.frames.size() * 6));
    EXPECT_LE(sum / n, 0.05);
    EXPECT_EQ(lost, 0);
    ASSERT_EQ(actions.size(), truth.throws.size());
    for (size_t k = 0; k < actions.size(); ++k) {
      EXPECT_EQ(actions[k].type, "throw");
      EXPECT_EQ(actions[k].player, truth.throws[k].player);
      EXPECT_NEAR(action_times[k], truth.throws[k].t, 0.05);
      EXPECT_GT(actions[k].dx * truth.throws[k].dx + actions[k].dy * truth.throws[k].dy, 0.95);
    }
  }
}

// Players who walk in after the first frame get their team's next numbers, in the order they come;
// one who leaves the hall and comes back keeps theirs. Of the six-player hall: Blue's circling
// player walks in at 3 s and one of its crossing pair at 6 s (only one blue hat is there at the
// start); Red's circling player jogs out at 2 s and is back at 6.5 s, out of the picture for
// about three seconds.
TEST(Hats, PlayersWhoWalkInLaterGetTheNextNumbersAndOneWhoComesBackKeepsTheirs) {
  const fs::path dir = fs::temp_directory_path() / "quantum_hats_late";
  tools::HatSceneOptions o;
  o.away = {{2, 0, 3}, {1, 0, 6}, {5, 2, 6.5}};
  const tools::HatTruth truth = tools::write_hat_video(dir.string(), o);
  tracking::HatTracker tracker = tracker_for(o);
  cv::VideoCapture video((dir / "hats.avi").string());
  ASSERT_TRUE(video.isOpened());
  // Per id: when the truth first shows it, when the tracker first reports it, and since when it
  // is in the picture this time.
  std::map<std::string, double> shown, reported, back;
  double sum = 0;
  int n = 0, off = 0;
  cv::Mat image;
  for (int f = 0; video.read(image); ++f) {
    const double t = f / o.fps;
    const tracking::TrackedFrame seen = tracker.feed(image, f, t);
    for (const tracking::TrackedPlayer& p : seen.players) reported.try_emplace(p.id, t);
    const tools::TruthFrame& want = truth.frames.at(size_t(f));
    for (const tools::TruthPlayer& p : want.players) {
      shown.try_emplace(p.id, t);
      const bool before = f > 0 && std::any_of(truth.frames[size_t(f - 1)].players.begin(),
                                               truth.frames[size_t(f - 1)].players.end(),
                                               [&](const tools::TruthPlayer& q) { return q.id == p.id; });
      if (!before) back[p.id] = t;
      if (t - back[p.id] < 0.5) continue;  // coming in: not yet followed, or just found again
      const auto it = std::find_if(seen.players.begin(), seen.players.end(),
                                   [&](const tracking::TrackedPlayer& s) { return s.id == p.id; });
      ASSERT_NE(it, seen.players.end()) << p.id << " at " << t << " s";
      const double e = std::hypot(it->x - p.x, it->y - p.y);
      sum += e, ++n;
      off += e > 1.0;  // another player's hat, or none
    }
  }
  fs::remove_all(dir);
  std::cout << "mean error " << 100 * sum / n << " cm over " << n << " positions, " << off << " more than 1 m off\n";
  for (const auto& [id, t] : shown)
    std::cout << id << ": in the picture at " << t << " s, followed at " << reported[id] << " s\n";
  // Blue's crossing pair starts with the one at the blue end; the two walk-ins follow in turn.
  EXPECT_EQ(shown.size(), 6u);
  EXPECT_EQ(shown["blue 1"], 0.0);
  EXPECT_GT(shown["blue 2"], 1.5);
  EXPECT_GT(shown["blue 3"], shown["blue 2"] + 1.5);
  EXPECT_EQ(reported.size(), shown.size()) << "an id for no one";
  for (const auto& [id, t] : shown) {
    ASSERT_TRUE(reported.count(id)) << id;
    EXPECT_GE(reported[id], t) << id;
    EXPECT_LE(reported[id], t + tracking::HatConfig{}.arrival + 0.2) << id;
  }
  EXPECT_GT(back["red 1"], 4.0) << "red 1 left and came back";
  EXPECT_LE(sum / n, 0.05);
  EXPECT_EQ(off, 0);
}

TEST(Hats, ABadAccelerometerLineIsNamed) {
  const fs::path file = fs::temp_directory_path() / "quantum_accel_bad.csv";
  std::ofstream(file) << "t,player,ax,ay,az\n0.00,blue 1,0,0,9.8\n0.01,blue 1,zero,0,9.8\n";
  try {
    tracking::AccelSource accel(file.string());
    FAIL() << "no error";
  } catch (const tracking::TrackingError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ":3: expected t,player,ax,ay,az"), std::string::npos) << e.what();
  }
  fs::remove(file);
}

// `text` as an accelerometer file (`name` in the temporary folder), read as --accel reads it:
// what it dropped, and the samples of its first second.
struct AccelFile {
  size_t dropped;
  std::vector<tracking::AccelSample> samples;
};
AccelFile read_accel(const std::string& name, const std::string& text) {
  const fs::path file = fs::temp_directory_path() / name;
  std::ofstream(file, std::ios::binary) << text;
  tracking::AccelSource accel(file.string());
  AccelFile read{accel.dropped(), accel.until(1)};
  fs::remove(file);
  return read;
}

// A sensor's glitch is data: a sample whose value is NaN or infinite is dropped and counted, and
// the file's other samples play.
TEST(Hats, AnAccelerometerValueThatIsNotANumberIsDroppedAndCounted) {
  const AccelFile read = read_accel("quantum_accel_nan.csv",
                                    "t,player,ax,ay,az\n0.00,blue 1,0,0,9.8\n0.01,blue 1,nan,0,9.8\n"
                                    "0.02,blue 1,0,inf,9.8\n0.03,blue 1,0,0,9.8\n");
  EXPECT_EQ(read.dropped, 2u);
  ASSERT_EQ(read.samples.size(), 2u);
  EXPECT_DOUBLE_EQ(read.samples[1].t, 0.03);
}

// A line of only spaces or a tab is as blank as an empty one: skipped, not a malformed sample.
TEST(Hats, ABlankAccelerometerLineIsSkipped) {
  const AccelFile read =
      read_accel("quantum_accel_blank.csv", "t,player,ax,ay,az\n0.00,blue 1,0,0,9.8\n   \n\t\n \t \r\n\n0.01,blue 1,0,0,9.8\n");
  EXPECT_EQ(read.dropped, 0u);
  EXPECT_EQ(read.samples.size(), 2u);
}

// A line longer than a sample can be (here 8 MB of NULs, the last line without a newline, and
// one of commas between samples) is dropped and counted, never held whole.
TEST(Hats, AnOverlongAccelerometerLineIsDroppedAndCounted) {
  const AccelFile read = read_accel("quantum_accel_long.csv", "t,player,ax,ay,az\n0.00,blue 1,0,0,9.8\n" +
                                                                  std::string(5000, ',') + "\n0.01,blue 1,0,0,9.8\n" +
                                                                  std::string(8 << 20, '\0'));
  EXPECT_EQ(read.dropped, 2u);
  EXPECT_EQ(read.samples.size(), 2u);
}

// A file is read up to kMostLines lines (lines.h): the rest of a longer one, or of an endless
// pipe, is one drop; a device is no file of samples (/dev/zero would never end).
TEST(Hats, AnAccelerometerFileIsReadUpToItsLimitAndADeviceIsRefused) {
  std::string text = "t,player,ax,ay,az\n";
  for (size_t k = 1; k < tracking::kMostLines; ++k) text += "#\n";
  text += "0.00,blue 1,0,0,9.8\n0.01,blue 1,0,0,9.8\n";  // lines kMostLines + 1 and + 2: never read
  const AccelFile read = read_accel("quantum_accel_many.csv", text);
  EXPECT_EQ(read.dropped, 1u);
  EXPECT_EQ(read.samples.size(), 0u);
  try {
    tracking::AccelSource zero("/dev/zero");
    ADD_FAILURE() << "/dev/zero was taken as a file of samples";
  } catch (const tracking::TrackingError& e) {
    EXPECT_NE(std::string(e.what()).find("--accel /dev/zero: not a file of samples or a pipe"), std::string::npos)
        << e.what();
  }
}

// Live accelerometers: one sample per UDP datagram, stamped when it is read.
TEST(Hats, AccelerometerSamplesArriveOverUdp) {
  const int port = 47000 + int(getpid() % 1000);
  tracking::AccelSource accel("udp:" + std::to_string(port));
  const int out = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(uint16_t(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  for (const char* line : {"0.5,red 2,31.0,2.0,9.8", "not a sample", "0.55,red 2,nan,2.0,9.8", "0.6,red 2,1,2,3"})
    ::sendto(out, line, std::strlen(line), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
  ::close(out);
  std::vector<tracking::AccelSample> got;
  for (int tries = 0; tries < 100 && got.size() < 2; ++tries) {
    const auto more = accel.until(1.25);
    got.insert(got.end(), more.begin(), more.end());
    if (got.size() < 2) usleep(10000);
  }
  ASSERT_EQ(got.size(), 2u);  // the malformed datagram and the one at NaN are dropped, and counted
  EXPECT_EQ(accel.dropped(), 2u);
  EXPECT_EQ(got[0].player, "red 2");
  EXPECT_DOUBLE_EQ(got[0].ax, 31.0);
  EXPECT_DOUBLE_EQ(got[0].t, 1.25);
  EXPECT_DOUBLE_EQ(got[1].az, 3.0);
}

}  // namespace
}  // namespace quantum

// A whip's share along the sensor's z axis lifts the throw (gravity taken off); a level whip is
// a flat throw. Directions stay unit vectors, along the player's run.
TEST(Hats, AnUpwardWhipThrowsUp) {
  quantum::tracking::ThrowDetector detector;
  quantum::tracking::TrackedFrame frame;
  frame.players.push_back({"home 1", "home", 0, 5, 2, 0});  // running along +x
  frame.players.push_back({"home 2", "home", 3, 5, 0, 2});  // running along +y
  const double g = 9.81;
  detector.add({{0.0, "home 1", 20, 0, g + 20}, {0.0, "home 2", 0, 30, g}}, frame);
  ASSERT_EQ(frame.actions.size(), 2u);
  const quantum::tracking::TrackedAction& shot = frame.actions[0];
  const quantum::tracking::TrackedAction& pass = frame.actions[1];
  EXPECT_NEAR(std::atan2(shot.dz, std::hypot(shot.dx, shot.dy)), std::atan2(20.0, 20.0), 1e-9);  // 45 degrees
  EXPECT_NEAR(shot.dx * shot.dx + shot.dy * shot.dy + shot.dz * shot.dz, 1.0, 1e-9);
  EXPECT_GT(shot.dx, 0.7);
  EXPECT_EQ(pass.dz, 0.0);
  EXPECT_NEAR(pass.dy, 1.0, 1e-9);
}

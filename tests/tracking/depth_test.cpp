// The air hockey depth pipeline on synthetic Kinect recordings (tools/synthetic.h) whose truth is
// known: accuracy, hover rejection, the recording format and bad input.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "field_loader.h"
#include "play.h"
#include "synthetic.h"
#include "tracking/tracking.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;
using tracking::DepthTracker;
using tracking::FakenectReader;
using tracking::RecordedFrame;

// A fresh directory for one test's recording, removed afterwards (recordings are large).
struct TempDir {
  explicit TempDir(const std::string& name) : path(fs::temp_directory_path() / ("quantum_tracking_" + name)) {
    fs::remove_all(path);
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path path;
};

tracking::TrackedField table(const tools::DepthSceneOptions& o) {
  return tracking::tracked_field(lua::load_field(QUANTUM_SOURCE_DIR "/rules/airhockey"), Vec2{o.length, o.width});
}

struct Accuracy {
  std::vector<double> errors;  // m, per tracked frame of a hand on the table
  int on_table = 0, missed = 0, hovering = 0, hover_rejected = 0;
};

Accuracy run(const std::string& dir, const std::vector<tools::TruthFrame>& truth, DepthTracker& tracker) {
  FakenectReader reader(dir);
  RecordedFrame frame;
  Accuracy a;
  while (reader.next(frame)) {
    const std::optional<tracking::TrackedFrame> seen = tracker.feed(frame);
    const tools::TruthFrame& t = truth.at(size_t(frame.index));
    if (!seen) {
      EXPECT_TRUE(t.players.empty()) << "frame " << frame.index << ": the players came before the background was learnt";
      continue;
    }
    for (const tools::TruthPlayer& p : t.players) {
      const auto it = std::find_if(seen->players.begin(), seen->players.end(),
                                   [&](const tracking::TrackedPlayer& s) { return s.id == p.id; });
      if (p.hovering) {
        ++a.hovering;
        a.hover_rejected += it == seen->players.end();
      } else {
        ++a.on_table;
        if (it == seen->players.end()) ++a.missed;
        else a.errors.push_back(std::hypot(it->x - p.x, it->y - p.y));
      }
    }
  }
  return a;
}

Accuracy run(const std::string& dir, const std::vector<tools::TruthFrame>& truth, const tools::DepthSceneOptions& o) {
  DepthTracker tracker(table(o));
  return run(dir, truth, tracker);
}

struct Figures {
  double mean = 0, p95 = 0;
};

Figures figures(Accuracy& a) {
  std::sort(a.errors.begin(), a.errors.end());
  Figures f;
  for (double e : a.errors) f.mean += e / double(a.errors.size());
  f.p95 = a.errors.empty() ? 0 : a.errors[a.errors.size() * 95 / 100];
  return f;
}

// What the tracker says when it stops on `rec`: the TrackingError's message ("" when it ran through).
std::string stop_reason(const std::string& rec, DepthTracker& tracker) {
  FakenectReader reader(rec);
  RecordedFrame f;
  try {
    while (reader.next(f)) tracker.feed(f);
  } catch (const tracking::TrackingError& e) {
    return e.what();
  }
  return "";
}

// The figures: mallet error mean <= 1.5 cm and 95th percentile <= 3 cm; hovering hands
// rejected >= 99 % of the time. Two recordings, the camera 1.0 m and 1.5 m above the table.
TEST(Depth, MalletsAreFoundWithinCentimetresAndHoveringHandsAreRejected) {
  for (const float height : {1.0f, 1.5f}) {
    TempDir dir("accuracy");
    tools::DepthSceneOptions o;
    o.height = height;
    o.frames = 240;
    o.seed = uint64_t(height * 10);
    const auto truth = tools::write_depth_recording(dir.path.string(), o);
    Accuracy a = run(dir.path.string(), truth, o);
    ASSERT_GT(a.errors.size(), 300u);
    ASSERT_GT(a.hovering, 80);
    const auto [mean, p95] = figures(a);
    std::cout << "camera at " << height << " m: mean " << mean * 100 << " cm, 95th percentile " << p95 * 100
              << " cm, " << a.missed << " of " << a.on_table << " hands on the table missed, " << a.hover_rejected
              << " of " << a.hovering << " hovering hands rejected\n";
    EXPECT_LE(mean, 0.015);
    EXPECT_LE(p95, 0.03);
    EXPECT_GE(a.hover_rejected, 0.99 * a.hovering);
    EXPECT_LE(a.missed, a.on_table / 100) << "a hand on the table must give input";
  }
}

// Full-size tables (the range): 1.6-2.2 m long, the camera 1.8-2.4 m up and tilted up to
// 3 degrees, 2 raw units of depth noise, 3 % holes, the projector's shadow and edge dropout,
// mallets up to 2 m/s, hands hovering 15-25 cm up. Each corner: the tracker is given only the
// sport's field (2 x 1 m) and measures the table itself. Targets: mean error <= 1.5 cm, 95th
// percentile <= 3 cm, a position in >= 95 % of the frames with a mallet on the table, >= 99 % of
// hovering frames rejected, and the measured field within 1 cm of the truth.
struct Rig {
  const char* name;
  float length, width, height, tilt, tilt_toward, noise, holes;
  uint64_t seed;
};

void PrintTo(const Rig& rig, std::ostream* out) { *out << rig.name; }

class FullSizeTable : public testing::TestWithParam<Rig> {};

TEST_P(FullSizeTable, MalletsAreTrackedAndTheTableIsMeasured) {
  const Rig& s = GetParam();
  TempDir dir(std::string("full_") + s.name);
  tools::DepthSceneOptions o;
  o.length = s.length, o.width = s.width, o.height = s.height, o.tilt = s.tilt, o.tilt_toward = s.tilt_toward;
  o.noise = s.noise, o.holes = s.holes, o.seed = s.seed;
  o.frames = 240;
  const auto truth = tools::write_depth_recording(dir.path.string(), o);
  DepthTracker tracker(tracking::tracked_field(lua::load_field(QUANTUM_SOURCE_DIR "/rules/airhockey")));
  Accuracy a = run(dir.path.string(), truth, tracker);
  const tracking::Calibration& c = tracker.calibration();
  const auto [mean, p95] = figures(a);
  const double reported = double(a.on_table - a.missed) / a.on_table, rejected = double(a.hover_rejected) / a.hovering;
  std::cout << s.name << ": " << s.length << " x " << s.width << " m table, camera " << s.height << " m up, tilt " << s.tilt
            << " deg, noise " << s.noise << ": mean " << mean * 100 << " cm, 95th percentile " << p95 * 100 << " cm, "
            << reported * 100 << " % of " << a.on_table << " on-table frames reported, " << rejected * 100 << " % of "
            << a.hovering << " hovering rejected; measured " << c.length << " x " << c.width << " m, camera " << c.height
            << " m, tilt " << c.tilt << " deg, noise " << c.noise * 100 << " cm\n";
  ASSERT_GT(a.on_table, 250);
  ASSERT_GT(a.hovering, 80);
  EXPECT_LE(mean, 0.015);
  EXPECT_LE(p95, 0.03);
  EXPECT_GE(reported, 0.95);
  EXPECT_GE(rejected, 0.99);
  EXPECT_EQ(c.markers, 4);
  EXPECT_NEAR(c.length, s.length, 0.01);
  EXPECT_NEAR(c.width, s.width, 0.01);
  EXPECT_NEAR(c.height, s.height, 0.02);
  EXPECT_NEAR(c.tilt, s.tilt, 0.3);
}

// Tilt toward 0 is along the table, 90 across: a long table tilted along its length from the
// lowest height that sees it straight on would lose its far markers, as physics says.
INSTANTIATE_TEST_SUITE_P(
    Range, FullSizeTable,
    testing::Values(Rig{"short_low_level", 1.6f, 0.8f, 1.8f, 0, 0, 2, 0.03f, 1},
                    Rig{"short_low_tilted", 1.6f, 0.8f, 1.8f, 3, 90, 2, 0.03f, 2},
                    Rig{"short_high_tilted", 1.6f, 0.8f, 2.4f, 3, 0, 2, 0.03f, 3},
                    Rig{"seven_foot_tilted", 2.0f, 1.0f, 2.2f, 2, 45, 2, 0.03f, 4},
                    Rig{"long_high_level", 2.2f, 1.1f, 2.4f, 0, 0, 2, 0.03f, 5},
                    Rig{"long_high_tilted", 2.2f, 1.1f, 2.4f, 3, 90, 2, 0.03f, 6},
                    Rig{"long_high_noiseless", 2.2f, 1.1f, 2.4f, 0, 0, 0, 0, 7},
                    Rig{"short_low_noiseless", 1.6f, 0.8f, 1.8f, 3, 90, 0, 0, 8}),
    [](const testing::TestParamInfo<Rig>& info) { return std::string(info.param.name); });

// A camera too low for its table cannot see the far markers: the error names them and says how
// high the camera must hang, from the height it measured.
TEST(Depth, ACameraTooLowForItsTableSaysHowHighItMustHang) {
  TempDir dir("too_low");
  tools::DepthSceneOptions o;
  o.length = 2.2f, o.width = 1.1f, o.height = 1.8f, o.frames = 1;
  tools::write_depth_recording(dir.path.string(), o);
  DepthTracker tracker(tracking::tracked_field(lua::load_field(QUANTUM_SOURCE_DIR "/rules/airhockey")));
  const std::string m = stop_reason(dir.path.string(), tracker);
  EXPECT_NE(m.find("markers not found in the colour image: id 0, 1, 2, 3"), std::string::npos) << m;
  EXPECT_NE(m.find("The camera is 1.80 m above the table"), std::string::npos) << m;
  EXPECT_NE(m.find("needs it at least 2.1"), std::string::npos) << m;  // 2.0 x 1.0 m, 10 cm beyond, 1 degree tilt
}

TEST(Depth, KinectDisparityModel) {
  EXPECT_EQ(tracking::raw_to_metres(tracking::kNoDepth), 0.0f);
  EXPECT_EQ(tracking::raw_to_metres(1084), 0.0f);  // near the fit's pole: no depth, not 533 m
  EXPECT_NEAR(tracking::raw_to_metres(0), 0.300, 0.001);
  for (float z : {0.5f, 1.0f, 1.3f, 2.0f, 4.0f}) {
    const uint16_t raw = tracking::metres_to_raw(z);
    // One raw step is about 0.003 z^2 m: quantization grows with distance.
    EXPECT_NEAR(tracking::raw_to_metres(raw), z, 0.0016 * z * z) << z;
  }
  EXPECT_EQ(tracking::metres_to_raw(0.1f), tracking::kNoDepth);
}

// Copies the first `frames` depth frames (and what comes before them) of a recording.
std::string small_recording(const TempDir& dir) {
  tools::DepthSceneOptions o;
  o.frames = 20;
  tools::write_depth_recording(dir.path.string(), o);
  return dir.path.string();
}

std::vector<std::string> index_of(const std::string& dir) {
  std::ifstream in(dir + "/INDEX.txt");
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

void write_index(const std::string& dir, const std::vector<std::string>& lines) {
  std::ofstream out(dir + "/INDEX.txt");
  for (const std::string& l : lines) out << l << '\n';
}

// A frame is data: a truncated one is dropped and counted, named in last_dropped(), and the
// recording plays on past it.
TEST(Depth, ATruncatedFrameIsDroppedAndNamed) {
  TempDir dir("truncated");
  const std::string rec = small_recording(dir);
  std::vector<std::string> depth;
  for (const std::string& l : index_of(rec))
    if (l[0] == 'd') depth.push_back(l);
  fs::resize_file(fs::path(rec) / depth[12], 1000);
  FakenectReader reader(rec);
  RecordedFrame f;
  std::vector<std::string> read;
  while (reader.next(f)) read.push_back(fs::path(f.file).filename().string());
  EXPECT_EQ(reader.dropped(), 1u);
  EXPECT_EQ(read.size(), depth.size() - 1);
  EXPECT_EQ(std::find(read.begin(), read.end(), depth[12]), read.end());
  const std::string m = reader.last_dropped();
  EXPECT_NE(m.find(depth[12]), std::string::npos) << m;
  EXPECT_NE(m.find("truncated, 983 of 614400 bytes"), std::string::npos) << m;
}

// A frame whose name's time is not a number ("nan", "inf") or lies far from the others' cannot be
// placed: it is dropped and counted, and the recording plays on at its own pace (not all at once).
TEST(Depth, FramesWhoseTimeIsNotANumberAreDroppedAndCounted) {
  TempDir dir("nan_times");
  const std::string rec = small_recording(dir);
  std::vector<std::string> lines = index_of(rec), depth;
  for (const std::string& l : lines)
    if (l[0] == 'd') depth.push_back(l);
  auto renamed = [&](const std::string& name, const std::string& time) {
    const std::string to = name.substr(0, 2) + time + name.substr(name.find('-', 2));
    fs::rename(fs::path(rec) / name, fs::path(rec) / to);
    for (std::string& l : lines)
      if (l == name) l = to;
  };
  renamed(depth[3], "nan");
  renamed(depth[5], "inf");
  renamed(depth[7], "1000");  // far past the recording's other frames
  std::ofstream index(fs::path(rec) / "INDEX.txt");
  for (const std::string& l : lines) index << l << "\n";
  index.close();
  FakenectReader reader(rec);
  RecordedFrame f;
  std::vector<double> times;
  while (reader.next(f)) times.push_back(f.t);
  EXPECT_EQ(reader.dropped(), 3u);
  EXPECT_EQ(times.size(), depth.size() - 3);
  for (size_t k = 1; k < times.size(); ++k) EXPECT_GT(times[k], times[k - 1]) << k;
  EXPECT_GT(times.back(), 0.5);  // still the recording's own pace
}

TEST(Depth, ANonRecordingIsNamed) {
  try {
    FakenectReader reader("/nonexistent/recording");
    FAIL() << "no error";
  } catch (const tracking::RecordingError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/recording/INDEX.txt"), std::string::npos) << e.what();
  }
}

// Everything a recording's reader gives: each depth frame's file name, time and whether it came
// with a colour frame.
struct Replayed {
  std::vector<std::string> files;
  std::vector<double> times;
  std::vector<bool> coloured;
  size_t dropped = 0;
};

Replayed replay(const std::string& rec) {
  FakenectReader reader(rec);
  RecordedFrame f;
  Replayed r;
  while (reader.next(f)) {
    r.files.push_back(fs::path(f.file).filename().string());
    r.times.push_back(f.t);
    r.coloured.push_back(!f.rgb.empty());
  }
  r.dropped = reader.dropped();
  return r;
}

// Renames a file of the recording (and its line in INDEX.txt) to carry the time `time`; its new name.
std::string retime(const std::string& rec, const std::string& name, const std::string& time) {
  const std::string to = name.substr(0, 2) + time + name.substr(name.find('-', 2));
  fs::rename(fs::path(rec) / name, fs::path(rec) / to);
  std::vector<std::string> lines = index_of(rec);
  for (std::string& l : lines)
    if (l == name) l = to;
  write_index(rec, lines);
  return to;
}

// One huge but finite time (1000 s, 1e12, 1e308 in a 1 s recording) neither holds the match for
// as long nor makes the frames after it "go back": the frame is dropped and counted, and every
// other frame plays at its own time.
TEST(Fakenect, AFrameFarPastTheOthersIsDroppedAndTheRestPlayAtTheirTimes) {
  TempDir dir("far_frame");
  const std::string rec = small_recording(dir);
  const Replayed clean = replay(rec);
  ASSERT_EQ(clean.dropped, 0u);
  std::string name;
  for (const std::string& l : index_of(rec))
    if (l[0] == 'd' && l.find("-30.pgm") != std::string::npos) name = l;
  ASSERT_FALSE(name.empty());
  const size_t at = size_t(std::find(clean.files.begin(), clean.files.end(), name) - clean.files.begin());
  for (const char* time : {"1000", "1e12", "1e308"}) {
    name = retime(rec, name, time);
    const Replayed r = replay(rec);
    EXPECT_EQ(r.dropped, 1u) << time;
    ASSERT_EQ(r.times.size(), clean.times.size() - 1) << time;
    for (size_t k = 0; k < r.times.size(); ++k) EXPECT_EQ(r.times[k], clean.times[k + (k >= at)]) << time << " " << k;
  }
}

// INDEX.txt's order is not the recording's: frames play in the order of their times, a colour
// frame going with the depth frames at or after its time. A colour frame named 1e12 s, listed
// first, is dropped; the lines after the first in reverse order play as the clean recording.
TEST(Fakenect, FramesPlayInTheOrderOfTheirTimesWhateverTheIndexSays) {
  TempDir dir("shuffled");
  const std::string rec = small_recording(dir);
  const Replayed clean = replay(rec);
  std::vector<std::string> lines = index_of(rec);
  std::reverse(lines.begin() + 1, lines.end());
  write_index(rec, lines);
  const Replayed reversed = replay(rec);
  EXPECT_EQ(reversed.dropped, 0u);
  EXPECT_EQ(reversed.files, clean.files);
  EXPECT_EQ(reversed.times, clean.times);
  EXPECT_EQ(reversed.coloured, clean.coloured);

  std::reverse(lines.begin() + 1, lines.end());
  write_index(rec, lines);
  std::string colour;
  for (const std::string& l : lines)
    if (l[0] == 'r' && colour.empty()) colour = l;
  ASSERT_EQ(lines[0], colour) << "the synthetic recording starts with a colour frame";
  retime(rec, colour, "1e12");
  const Replayed far = replay(rec);
  EXPECT_EQ(far.dropped, 1u);
  EXPECT_EQ(far.files, clean.files);
  EXPECT_EQ(far.times, clean.times);
}

// Files named like frames that are not frames are dropped and counted and the recording plays
// on: none is opened unless it is a regular file (a FIFO nobody writes would block for ever, a
// link to /dev/zero never ends), none is read past the size its header gives (a 1 GB frame of
// NULs costs a header's bytes), and a legal PGM with a comment in its header is read.
TEST(Fakenect, FilesThatAreNotFramesAreDroppedAndCounted) {
  TempDir dir("not_frames");
  const std::string rec = small_recording(dir);
  std::vector<std::string> depth;
  for (const std::string& l : index_of(rec))
    if (l[0] == 'd') depth.push_back(l);
  auto path = [&](size_t k) { return fs::path(rec) / depth.at(k); };
  auto write = [&](size_t k, const std::string& bytes) {
    fs::remove(path(k));
    std::ofstream(path(k), std::ios::binary) << bytes;
  };
  const std::vector<uint16_t> samples(640 * 480, 700);
  const std::string wide(reinterpret_cast<const char*>(samples.data()), samples.size() * 2);
  fs::remove(path(2));                                          // missing
  write(3, "");                                                 // 0 bytes
  write(4, "P2 640 480 65535\n0 0 0\n");                        // a text PGM
  write(5, "P5 640 480 255\n" + std::string(640 * 480, '\1'));  // 8-bit
  write(6, "P5 320 240 65535\n" + wide.substr(0, 320 * 240 * 2));  // another size
  fs::remove(path(7));
  fs::create_directory(path(7));  // a directory
  fs::remove(path(8));
  fs::create_symlink("/dev/zero", path(8));
  fs::remove(path(9));
  ASSERT_EQ(::mkfifo(path(9).c_str(), 0600), 0);
  write(10, "");
  fs::resize_file(path(10), 1ull << 30);  // sparse: 1 GB of NULs, no whitespace
  write(11, "P5\n# written by hand\n640 480\n# 16-bit\n65535\n" + wide);  // legal, with comments
  const Replayed r = replay(rec);
  EXPECT_EQ(r.dropped, 9u);
  EXPECT_EQ(r.files.size(), depth.size() - 9);
  EXPECT_NE(std::find(r.files.begin(), r.files.end(), depth[11]), r.files.end()) << "the PGM with comments was refused";
  FakenectReader reader(rec);
  RecordedFrame f;
  while (reader.next(f) && fs::path(f.file).filename() != depth[11]) {
  }
  ASSERT_EQ(fs::path(f.file).filename(), depth[11]);
  EXPECT_EQ(cv::countNonZero(f.depth != 700), 0);
}

// An INDEX.txt line longer than a name can be (a megabyte of NULs, the last line without its
// newline; 5,000 letters) or that is no frame's name is dropped and counted, never held whole.
TEST(Fakenect, IndexLinesThatAreNotNamesAreDroppedAndCounted) {
  TempDir dir("long_lines");
  const std::string rec = small_recording(dir);
  const Replayed clean = replay(rec);
  std::vector<std::string> lines = index_of(rec);
  lines.insert(lines.begin() + 5, std::string(5000, 'd'));
  lines.insert(lines.begin() + 9, "notes.txt");
  write_index(rec, lines);
  std::ofstream(fs::path(rec) / "INDEX.txt", std::ios::app | std::ios::binary) << std::string(1 << 20, '\0');
  const Replayed r = replay(rec);
  EXPECT_EQ(r.dropped, 3u);
  EXPECT_EQ(r.files, clean.files);
  EXPECT_EQ(r.times, clean.times);
}

// A recording in which no depth frame can be read is refused, saying so.
TEST(Fakenect, ARecordingWithoutAReadableFrameIsRefused) {
  TempDir dir("unreadable");
  const std::string rec = small_recording(dir);
  for (const std::string& l : index_of(rec))
    if (l[0] == 'd') fs::resize_file(fs::path(rec) / l, 100);
  try {
    replay(rec);
    FAIL() << "no error";
  } catch (const tracking::RecordingError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(rec + ": no depth frame could be read"), std::string::npos) << m;
    EXPECT_NE(m.find("truncated"), std::string::npos) << m;
  }
}

// What a match drops is told at the first drop, then at most every 5 s; what was dropped after
// the last of those lines is told at the match's end, in one line. A 1.7 s recording: a frame
// whose time is not a number (told with the first frame), and a truncated frame near the end.
TEST(Fakenect, DropsNotToldYetAreToldAtTheMatchsEnd) {
  TempDir dir("tally");
  const std::string rec = small_recording(dir);
  std::vector<std::string> depth;
  for (const std::string& l : index_of(rec))
    if (l[0] == 'd') depth.push_back(l);
  retime(rec, depth[35], "nan");
  fs::resize_file(fs::path(rec) / depth[45], 1000);
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/airhockey";
  o.input = "fakenect:" + rec;
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  std::ostringstream out, errors;
  tools::play(o, out, errors);
  const std::string e = errors.str();
  const std::string first = "quantum: fakenect:" + rec + ": 1 tracking value dropped (";
  const size_t at = e.find(first);
  ASSERT_NE(at, std::string::npos) << e;
  EXPECT_NE(e.find("; 1 in all), the match goes on\n", at), std::string::npos) << e;
  const size_t last = e.find(first, at + 1);
  ASSERT_NE(last, std::string::npos) << "the last drop was never told: " << e;
  EXPECT_NE(e.find("; 2 in all) by the end of the match\n", last), std::string::npos) << e;
  EXPECT_EQ(e.find(first, last + 1), std::string::npos) << "one line at the end: " << e;
  EXPECT_NE(out.str().find("(the recording is over)"), std::string::npos) << out.str();
}

// Dropped frames (gaps in the index) and frames without a single depth reading go by: the
// tracker reports nobody for the dark frame and picks the hands up again after it.
TEST(Depth, DroppedAndDarkFramesAreTolerated) {
  TempDir dir("dropped");
  tools::DepthSceneOptions o;
  o.frames = 40;
  const auto truth = tools::write_depth_recording(dir.path.string(), o);
  const std::string rec = dir.path.string();
  std::vector<std::string> kept;
  int depth_frames = 0, dark = -1;
  for (const std::string& l : index_of(rec)) {
    if (l[0] != 'd') {
      kept.push_back(l);
      continue;
    }
    ++depth_frames;
    if (depth_frames % 7 == 0) continue;  // dropped
    kept.push_back(l);
    if (depth_frames == 50) {  // a frame with no reading at all
      std::ofstream out(fs::path(rec) / l, std::ios::binary);
      out << "P5 640 480 65535\n";
      const std::vector<uint16_t> none(640 * 480, tracking::kNoDepth);
      out.write(reinterpret_cast<const char*>(none.data()), std::streamsize(none.size() * 2));
      dark = int(kept.size());
    }
  }
  ASSERT_GT(dark, 0);
  write_index(rec, kept);
  DepthTracker tracker(table(o));
  FakenectReader reader(rec);
  RecordedFrame f;
  int tracked_frames = 0, with_both = 0;
  bool dark_seen = false;
  while (reader.next(f)) {
    const auto seen = tracker.feed(f);
    if (!seen) continue;
    ++tracked_frames;
    if (f.file.find(kept[size_t(dark - 1)]) != std::string::npos) {
      dark_seen = true;
      EXPECT_TRUE(seen->players.empty());
    }
    with_both += seen->players.size() == 2;
  }
  EXPECT_TRUE(dark_seen);
  EXPECT_GT(tracked_frames, 25);
  EXPECT_GT(with_both, 10);  // tracking went on around the gaps
}

TEST(Depth, MissingMarkersAreNamed) {
  TempDir dir("markers");
  const std::string rec = small_recording(dir);
  // Paint over the blue end's two markers in every colour frame.
  for (const std::string& l : index_of(rec)) {
    if (l[0] != 'r') continue;
    const fs::path p = fs::path(rec) / l;
    std::ifstream in(p, std::ios::binary);
    std::string header;
    std::getline(in, header);
    std::vector<char> rgb((std::istreambuf_iterator<char>(in)), {});
    for (int v = 0; v < 480; ++v)
      for (int u = 0; u < 200; ++u)
        for (int c = 0; c < 3; ++c) rgb[size_t((v * 640 + u) * 3 + c)] = char(200);
    std::ofstream out(p, std::ios::binary);
    out << header << '\n';
    out.write(rgb.data(), std::streamsize(rgb.size()));
  }
  DepthTracker tracker(table(tools::DepthSceneOptions{}));
  const std::string m = stop_reason(rec, tracker);
  EXPECT_NE(m.find("markers not found in the colour image: id 2, 3"), std::string::npos) << m;
}

// Markers 0 and 1 on each other's corners: the centres cross, and the tracker says so instead of
// measuring a diagonal as the field's length.
TEST(Depth, MarkersOutOfOrderAreNamed) {
  TempDir dir("crossed");
  const std::string rec = small_recording(dir);
  for (const std::string& l : index_of(rec)) {
    if (l[0] != 'r') continue;
    const fs::path p = fs::path(rec) / l;
    cv::Mat rgb = cv::imread(p.string(), cv::IMREAD_COLOR);
    const std::vector<tracking::MarkerImage> found = tracking::find_markers(rgb);
    ASSERT_EQ(found.size(), 4u);
    // Swap the squares around markers 0 and 1, each a little larger than the marker.
    const auto square = [&](const tracking::MarkerImage& m) {
      const float side = float(cv::norm(m.corners[0] - m.corners[2])) * 0.8f;
      return cv::Rect(int(m.centre.x - side), int(m.centre.y - side), int(2 * side), int(2 * side));
    };
    const cv::Rect a = square(found[0]), b(square(found[1]).x, square(found[1]).y, square(found[0]).width,
                                          square(found[0]).height);
    cv::Mat patch = rgb(a).clone();
    rgb(b).copyTo(rgb(a));
    patch.copyTo(rgb(b));
    ASSERT_TRUE(cv::imwrite(p.string(), rgb));  // binary P6, as libfreenect writes it
  }
  DepthTracker tracker(table(tools::DepthSceneOptions{}));
  const std::string m = stop_reason(rec, tracker);
  EXPECT_NE(m.find("markers are not in order round the field"), std::string::npos) << m;
}

// The printable markers: four A4 pages in markers.pdf (one marker each) beside the PNGs; sizes
// that do not fit a page, or are too small to print, are refused.
TEST(Markers, ThePdfHasOneA4PageAMarker) {
  TempDir dir("markers_pdf");
  tools::write_markers(dir.path.string(), 0.12);
  std::ifstream in(dir.path / "markers.pdf", std::ios::binary);
  const std::string pdf((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(pdf.rfind("%PDF-", 0), 0u);
  size_t pages = 0;
  for (size_t at = pdf.find("/MediaBox [ 0 0 595.276 841.89 ]"); at != std::string::npos;
       at = pdf.find("/MediaBox [ 0 0 595.276 841.89 ]", at + 1))
    ++pages;
  EXPECT_EQ(pages, 4u);
  for (int id = 0; id < 4; ++id) EXPECT_TRUE(fs::exists(dir.path / ("marker-" + std::to_string(id) + ".png"))) << id;
  EXPECT_THROW(tools::write_markers(dir.path.string(), 0.25), std::invalid_argument);
  EXPECT_THROW(tools::write_markers(dir.path.string(), 0.01), std::invalid_argument);
}

}  // namespace
}  // namespace quantum

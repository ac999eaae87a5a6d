// Seeking at the desk is exact: a replay sought back and forth to a moment shows the picture, and
// has written the events, of the same replay played straight to it; a live match looked back at
// shows its own past from the recording it keeps, and waits meanwhile.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "desk_support.h"
#include "picture.h"
#include "playback.h"
#include "lua_sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& file) {
  std::ostringstream s;
  s << std::ifstream(file).rdbuf();
  return s.str();
}

cv::Mat picture_of(const game::Match& match) {
  runtime::Picture picture(match.field());
  cv::Mat image;
  picture.draw(match, runtime::Overlay{"", "", "", nullptr, ""}, image);
  return image;
}

bool same(const cv::Mat& a, const cv::Mat& b) { return a.size() == b.size() && cv::norm(a, b, cv::NORM_INF) == 0; }

// A recorded handball match (12 s, seed 3) in `dir`.
void record(const fs::path& dir) {
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/handball";
  o.seconds = 12, o.seed = 3, o.record = dir.string();
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  session.run();
  ASSERT_EQ(errors.str(), "");
}

runtime::SessionOptions replay_of(const fs::path& recording, const fs::path& events) {
  runtime::SessionOptions o;
  o.replay = recording.string();
  o.events = events.string();
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  return o;
}

TEST(Playback, SeekingInAReplayGivesThePictureAndEventsOfPlayingToThatTime) {
  const test::TempFolder f("quantum-seek");
  record(f.path / "match");
  std::ostringstream errors;
  tools::Playback straight(replay_of(f.path / "match", f.path / "straight.jsonl"), nullptr, errors);
  while (straight.shown().match().time() < 7.5 - 1e-9) ASSERT_TRUE(straight.frame());
  const cv::Mat straight_picture = picture_of(straight.shown().match());
  straight.live().finish();

  tools::Playback sought(replay_of(f.path / "match", f.path / "sought.jsonl"), nullptr, errors);
  EXPECT_DOUBLE_EQ(sought.played(), 12) << "a replay may be sought anywhere in its recording";
  sought.seek(10);
  EXPECT_NEAR(sought.shown().match().time(), 10, 1e-6);
  sought.seek(4);  // back: the replay starts again, its event log too
  EXPECT_NEAR(sought.shown().match().time(), 4, 1e-6);
  sought.seek(7.5);
  EXPECT_NEAR(sought.shown().match().time(), 7.5, 1e-6);
  EXPECT_TRUE(same(picture_of(sought.shown().match()), straight_picture));
  sought.live().finish();
  const std::string events = read(f.path / "straight.jsonl");
  EXPECT_GT(std::count(events.begin(), events.end(), '\n'), 5);
  EXPECT_EQ(read(f.path / "sought.jsonl"), events);
  EXPECT_EQ(errors.str(), "");
}

// Looking back in a live match (simulated players) replays the recording the match keeps: what
// is shown at 1.5 s is what a replay of the match shows there, the match waits at 4 s meanwhile,
// and playing on from the look back comes back to the match where it waited.
TEST(Playback, ALiveMatchLookedBackAtShowsItsOwnPastAndWaits) {
  const test::TempFolder f("quantum-look-back");
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/airhockey";
  o.seconds = 30, o.seed = 4, o.record = (f.path / "match").string();
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  std::ostringstream errors;
  tools::Playback live(o, nullptr, errors);
  while (live.live().match().time() < 4 - 1e-9) ASSERT_TRUE(live.frame());
  live.seek(1.5);
  ASSERT_TRUE(live.looking_back());
  EXPECT_NEAR(live.shown().match().time(), 1.5, 1e-6);
  EXPECT_NEAR(live.live().match().time(), 4, 1e-6);
  const cv::Mat past = picture_of(live.shown().match());

  tools::Playback replay(replay_of(f.path / "match", f.path / "events.jsonl"), nullptr, errors);
  replay.seek(1.5);
  EXPECT_TRUE(same(past, picture_of(replay.shown().match())));

  int frames = 0;
  while (live.looking_back() && frames < 1000) live.frame(), ++frames;
  EXPECT_FALSE(live.looking_back());
  EXPECT_NEAR(frames, 2.5 * 60, 2) << "the look back plays up to where the match waits";
  EXPECT_NEAR(live.live().match().time(), 4, 1e-6) << "the match waited";
  live.seek(2);
  EXPECT_TRUE(live.looking_back());
  live.seek(4);  // the match's moment: the look back ends there
  EXPECT_FALSE(live.looking_back());
  EXPECT_TRUE(live.frame());
  EXPECT_NEAR(live.live().match().time(), 4 + 1 / 60.0, 1e-6);
}

// Without a --record, a live match keeps its recording in a folder of its own, gone with it.
TEST(Playback, ALiveMatchKeepsItsOwnRecordingToLookBackAt) {
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/airhockey";
  o.seconds = 30, o.seed = 4;
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  std::ostringstream errors;
  {
    tools::Playback live(o, nullptr, errors);
    while (live.live().match().time() < 2 - 1e-9) ASSERT_TRUE(live.frame());
    live.seek(0.5);
    EXPECT_TRUE(live.looking_back());
    EXPECT_NEAR(live.shown().match().time(), 0.5, 1e-6);
    live.restart();
    EXPECT_FALSE(live.looking_back());
    EXPECT_NEAR(live.live().match().time(), 0, 1e-9);
  }
  EXPECT_EQ(errors.str(), "");
}

}  // namespace
}  // namespace quantum

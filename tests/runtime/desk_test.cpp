// The designer's desk: the live view opens a window that shows the field and the players (on a
// virtual display, photographed); a video has the frames, the length and the sound it should;
// a snapshot is a readable picture; the mouse moves a player. (The decision log is audited in
// decision_log_test.cpp.)
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "count_of.h"
#include "players.h"
#include "desk_support.h"
#include "session.h"
#include "lua_sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

// A new empty folder of this test process's own (CTest runs tests side by side).
fs::path fresh_folder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("quantum_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

using test::count_of;
using test::output_of;
using test::pixels_of;

const cv::Vec3b kWall(230, 230, 230), kBlue(235, 140, 45), kRed(70, 70, 235);

TEST(Desk, TheLiveViewShowsTheFieldAndThePlayers) {
  const fs::path shot = fs::temp_directory_path() / "quantum_view.png";
  fs::remove(shot);
  // A virtual display; the window is photographed from the screen itself, as a person sees it,
  // once anything is drawn on the black screen (a slow build, such as the sanitizers', takes
  // seconds to open it), then a second later.
  const std::string out = output_of(
      "timeout 120 xvfb-run -a -s '-screen 0 1280x1024x24' sh -c '" QUANTUM_BINARY " play " QUANTUM_SOURCE_DIR
      "/rules/airhockey --view --seconds 60 --audio none --quiet & p=$!; "
      "for i in $(seq 100); do sleep 0.5; import -window root " + shot.string() + "; "
      "[ \"$(convert " + shot.string() + " -format \"%[fx:mean>0.01]\" info:)\" = 1 ] && break; done; "
      "sleep 1; import -window root " + shot.string() + "; kill $p'");
  const cv::Mat image = cv::imread(shot.string());
  ASSERT_FALSE(image.empty()) << out;
  EXPECT_GT(pixels_of(image, kWall), 3000) << "the walls";   // 2 m + 1 m of wall, 3 px thick
  EXPECT_GT(pixels_of(image, kBlue), 600) << "Blue's mallet";
  EXPECT_GT(pixels_of(image, kRed), 600) << "Red's mallet";
}

TEST(Desk, TheViewNeedsADisplayAndSaysSo) {
  const std::string out = output_of("env -u DISPLAY " QUANTUM_BINARY " play --view --seconds 1 --audio none");
  EXPECT_NE(out.find("--view needs a display"), std::string::npos) << out;
}

TEST(Desk, AMouseForNoSuchPlayerListsThePlayers) {
  const std::string out = output_of("timeout 60 xvfb-run -a " QUANTUM_BINARY " play handball --view --input mouse:Bob "
                                    "--audio none --quiet 2>&1; echo exit $?");
  EXPECT_NE(out.find("--input mouse:Bob: unknown player 'Bob' (did you mean 'Ben'? known: Anna, Ben, Clara, Hugo, Ida, "
                     "Jonas)"), std::string::npos) << out;
  EXPECT_NE(out.find("exit 1"), std::string::npos) << out;
}

TEST(Desk, AVideoHasItsFramesItsLengthAndItsSound) {
  const fs::path dir = fs::temp_directory_path() / "quantum_video";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string video = (dir / "match.mp4").string();
  const std::string run = output_of(QUANTUM_BINARY " play " QUANTUM_SOURCE_DIR "/rules/airhockey --seconds 4 --quiet "
                                    "--audio wav:" + (dir / "match.wav").string() + " --video " + video);
  const std::string probe = output_of("ffprobe -v error -count_frames -show_entries stream=codec_type,nb_read_frames,duration "
                                      "-of compact " + video);
  EXPECT_NE(probe.find("codec_type=video|duration=4.000000|nb_read_frames=120"), std::string::npos) << probe << run;
  EXPECT_NE(probe.find("codec_type=audio"), std::string::npos) << probe;  // the match's sound, muxed in
}

TEST(Desk, ASnapshotIsAReadablePictureOfThatMoment) {
  const fs::path png = fs::temp_directory_path() / "quantum_snapshot.png";
  fs::remove(png);
  const std::string run = output_of(QUANTUM_BINARY " play " QUANTUM_SOURCE_DIR "/rules/airhockey --seconds 6 --quiet "
                                    "--audio none --snapshot " + png.string() + " --snapshot-at 2.5");
  const cv::Mat image = cv::imread(png.string());
  ASSERT_FALSE(image.empty()) << run;
  EXPECT_GE(image.cols, 1000);
  EXPECT_GT(pixels_of(image, kWall), 3000);
  EXPECT_GT(pixels_of(image, kBlue), 600);
  EXPECT_GT(pixels_of(image, kRed), 600);
}

TEST(Desk, TheHandMovesItsPlayerWithinTheFieldAndItsSpeed) {
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/airhockey";
  o.seconds = 5;
  runtime::Hand hand;
  std::ostringstream errors;
  const Field field = lua::ScriptedRules(o.sport).spec().field;
  runtime::Session session(o, tools::lua_sport, nullptr, errors,
                           std::make_unique<runtime::HandPlayers>(field, std::vector<double>{0.6, 0.6}, 1, 10.0, 0, hand));
  hand.over = true;
  hand.at = {-0.5f, 0.3f};
  for (int frame = 0; frame < 30; ++frame) session.frame();
  const game::Player& blue = session.match().players()[0];
  EXPECT_NEAR(blue.position.x, -0.5, 1e-5);
  EXPECT_NEAR(blue.position.y, 0.3, 1e-5);
  hand.at = {-0.4f, 0.3f};  // 10 cm in one frame: 6 m/s
  session.frame();
  EXPECT_NEAR(session.match().players()[0].velocity.x, 6.0, 0.01);
  hand.at = {-5.0f, 9.0f};  // off the table: the mallet stops at its edge
  for (int frame = 0; frame < 60; ++frame) session.frame();
  EXPECT_NEAR(session.match().players()[0].position.y, field.bounds_max.y - field.bodies[0].radius, 1e-5);
  EXPECT_EQ(errors.str(), "");
}

// Handball at the desk: the hand plays Clara, who holds the ball at the throw-off. Nobody throws
// for her while she holds it; a click throws it the way the hand moves, at the sport's speed.
TEST(Desk, AClickThrowsTheBallTheWayTheHandMoves) {
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/handball";
  o.seconds = 30;
  runtime::Hand hand;
  std::ostringstream errors;
  const lua::ScriptedRules sport(o.sport);
  const Field& field = sport.spec().field;
  int clara = 0;
  while (field.bodies[size_t(clara)].name != "Clara") ++clara;
  runtime::Session session(o, tools::lua_sport, nullptr, errors,
                           std::make_unique<runtime::HandPlayers>(field, std::vector<double>(field.bodies.size(), 0.6), 1,
                                                                  sport.spec().match.throw_speed, clara, hand));
  std::vector<game::GameEvent> throws;
  std::vector<std::string> throwers;
  session.watch([&](const runtime::News& news) {
    for (const game::GameEvent& e : news.events)
      if (e.type == game::EventKind::Throw) throws.push_back(e), throwers.emplace_back(e.actor);
  });
  hand.over = true;
  hand.at = field.bodies[size_t(clara)].start;
  for (int frame = 0; frame < 5 * 60; ++frame) session.frame();  // the throw-off, and 3 s more
  ASSERT_EQ(session.match().holder(), clara);
  EXPECT_TRUE(throws.empty());  // the bots leave her throws to her
  // The hand moves toward the left side line (+y), then clicks.
  for (int frame = 0; frame < 10; ++frame) {
    hand.at.y += 0.05f;  // 3 m/s
    session.frame();
  }
  ++hand.throws;  // the hand has stopped: its motion just before decides
  session.frame();
  ASSERT_EQ(throws.size(), 1u);
  EXPECT_EQ(throwers[0], "Clara");
  EXPECT_NEAR(std::hypot(throws[0].velocity.x, throws[0].velocity.y), sport.spec().match.throw_speed, 1e-3);
  EXPECT_NEAR(throws[0].velocity.x, 0, 1e-3);
  EXPECT_GT(throws[0].velocity.y, 0);
  EXPECT_NE(session.match().holder(), clara);
  // A click when she does not hold the ball throws nothing.
  ++hand.throws;
  session.frame();
  EXPECT_EQ(throws.size(), 1u);
  EXPECT_EQ(errors.str(), "");
}

// The container is the one the file's name ends in, with codecs that make sense in it, the
// sound muxed in too (ffprobe reads what the file is, not what it is called).
TEST(Desk, TheVideosContainerFollowsItsEnding) {
  const fs::path dir = fresh_folder("containers");
  struct Case {
    std::string ending, format, video, audio;
  };
  const Case cases[] = {
      {"mp4", "format_name=mov,mp4,m4a,3gp,3g2,mj2|tag:major_brand=isom", "h264", "aac"},
      {"mov", "format_name=mov,mp4,m4a,3gp,3g2,mj2|tag:major_brand=qt", "h264", "aac"},
      {"mkv", "format_name=matroska,webm", "h264", "aac"},
      {"AVI", "format_name=avi", "mjpeg", "pcm_s16le"},
      {"webm", "format_name=matroska,webm", "vp9", "opus"},
  };
  for (const Case& c : cases) {
    const std::string video = (dir / ("match." + c.ending)).string();
    const std::string run = output_of(QUANTUM_BINARY " play " QUANTUM_SOURCE_DIR "/rules/airhockey --seconds 1 --quiet "
                                      "--audio wav:" + (dir / "match.wav").string() + " --video " + video);
    const std::string probe = output_of("ffprobe -v error -show_entries format=format_name:format_tags=major_brand:"
                                        "stream=codec_name,codec_type -of compact " + video);
    EXPECT_NE(probe.find("format|" + c.format), std::string::npos) << c.ending << ": " << probe << run;
    EXPECT_NE(probe.find("codec_name=" + c.video + "|codec_type=video"), std::string::npos) << c.ending << ": " << probe;
    EXPECT_NE(probe.find("codec_name=" + c.audio + "|codec_type=audio"), std::string::npos) << c.ending << ": " << probe;
    if (c.format.find("matroska") != std::string::npos) {
      // Matroska and WebM share ffprobe's reader: the file's EBML header names which it is.
      std::ifstream in(video, std::ios::binary);
      std::string head(64, '\0');
      in.read(head.data(), std::streamsize(head.size()));
      EXPECT_NE(head.find(c.ending == "webm" ? "webm" : "matroska"), std::string::npos) << c.ending;
    }
  }
  fs::remove_all(dir);
}

// A name whose ending is no container quantum writes is refused before anything plays: no
// transcript, no file.
TEST(Desk, AVideoOfAnotherEndingIsRefusedBeforeTheMatch) {
  const fs::path dir = fresh_folder("ending");
  for (const std::string name : {"match.flv", "match"}) {
    const std::string video = (dir / name).string(), events = (dir / "events.jsonl").string();
    const std::string run = output_of(QUANTUM_BINARY " play " QUANTUM_SOURCE_DIR "/rules/airhockey --seconds 1 --audio none "
                                      "--events " + events + " --video " + video + " 2>&1; echo exit $?");
    EXPECT_NE(run.find("quantum: --video " + video + ": " +
                       (name == "match" ? "no ending names its container" : ".flv names no container quantum writes") +
                       "; name it .mp4, .mov, .mkv, .avi or .webm"),
              std::string::npos) << run;
    EXPECT_NE(run.find("exit 1"), std::string::npos) << run;
    EXPECT_EQ(run.find("Quantum air hockey"), std::string::npos) << "no transcript: " << run;
    EXPECT_TRUE(fs::is_empty(dir)) << run;
  }
  fs::remove_all(dir);
}

// Every file a match writes is confirmed once, when it is whole, with what it holds and its size;
// on stderr, so that --quiet keeps them and stdout keeps the transcript.
TEST(Desk, EveryOutputIsConfirmedOnceItIsWhole) {
  const fs::path dir = fresh_folder("confirmed");
  const std::string wav = (dir / "match.wav").string(), events = (dir / "events.jsonl").string(),
                    decisions = (dir / "decisions.jsonl").string(), record = (dir / "recording").string(),
                    video = (dir / "match.mp4").string(), png = (dir / "moment.png").string();
  const std::string err = (dir / "stderr.txt").string();
  const std::string out = output_of("(" QUANTUM_BINARY " play " QUANTUM_SOURCE_DIR "/rules/airhockey --seconds 2 --quiet "
                                    "--audio wav:" + wav + " --events " + events + " --decisions " + decisions +
                                    " --record " + record + " --video " + video + " --snapshot " + png +
                                    " --snapshot-at 1) 2>" + err + "; true");
  EXPECT_EQ(out, "") << "--quiet: nothing on stdout";
  std::ifstream in(err);
  const std::string said((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto lines_in = [](const std::string& file) {
    std::ifstream f(file);
    int n = 0;
    for (std::string line; std::getline(f, line);) ++n;
    return n;
  };
  const std::pair<std::string, std::string> confirmed[] = {
      {events, std::to_string(lines_in(events)) + " lines, "},
      {decisions, std::to_string(lines_in(decisions)) + " lines, "},
      {wav, " s of sound, "},
      {record, "120 frames (2.0 s), "},
      {video, "2.0 s, 60 frames, 1100x924, H.264 in MP4, with sound, "},
      {png, "1100x924, the match at 1.0 s, "},
  };
  for (const auto& [file, what] : confirmed) {
    EXPECT_EQ(count_of(said, "quantum: wrote " + file + ": "), 1) << file << "\n" << said;
    const size_t at = said.find("quantum: wrote " + file + ": ");
    ASSERT_NE(at, std::string::npos) << said;
    const std::string line = said.substr(at, said.find('\n', at) - at);
    EXPECT_NE(line.find(what), std::string::npos) << line;
    EXPECT_TRUE(line.ends_with(" KB") || line.ends_with(" MB")) << line;
  }
  // A replay's video, at the end of a replay.
  const std::string again = (dir / "again.mkv").string();
  const std::string replayed = output_of(QUANTUM_BINARY " replay " + record + " --quiet --video " + again);
  EXPECT_NE(replayed.find("quantum: wrote " + again + ": 2.0 s, 60 frames, 1100x924, H.264 in Matroska, "),
            std::string::npos) << replayed;
  fs::remove_all(dir);
}

// Long work says how far it is: on a terminal (here a pseudo-terminal, from script(1)) a line
// drawn again in place up to its end, then wiped before the confirmation. Where the transcript
// is on that terminal, its own lines say how far the match is: no line between them.
TEST(Desk, AVideoSaysHowFarItIsOnATerminal) {
  const fs::path dir = fresh_folder("progress");
  const std::string video = (dir / "match.mp4").string(), record = (dir / "recording").string();
  const std::string play = QUANTUM_BINARY " play " QUANTUM_SOURCE_DIR "/rules/airhockey --seconds 1 --audio none --video " +
                           video + " --record " + record;
  const std::string quiet = output_of("script -qec '" + play + " --quiet' /dev/null");
  EXPECT_NE(quiet.find("\rvideo " + video + ": 1.0 of 1.0 s (100 %)"), std::string::npos) << quiet;
  EXPECT_NE(quiet.find("    \rquantum: wrote "), std::string::npos) << "wiped first: " << quiet;
  EXPECT_NE(quiet.find("quantum: wrote " + video + ": 1.0 s, 30 frames"), std::string::npos) << quiet;
  const std::string replay = output_of("script -qec '" QUANTUM_BINARY " replay " + record + " --quiet --video " + video +
                                       "' /dev/null");
  EXPECT_NE(replay.find("\rvideo " + video + ": 1.0 of 1.0 s (100 %)"), std::string::npos) << replay;
  fs::remove_all(record);
  const std::string told = output_of("script -qec '" + play + "' /dev/null");
  EXPECT_NE(told.find("final score"), std::string::npos) << told;
  EXPECT_EQ(told.find(" of 1.0 s ("), std::string::npos) << told;
  EXPECT_NE(told.find("quantum: wrote " + video), std::string::npos) << told;
  fs::remove_all(dir);
}

// A snapshot of a moment the match never reaches is refused before it starts, naming where the
// match ends and why: its time limit, --until, or a replay's recording. Nothing is written.
TEST(Desk, ASnapshotPastTheMatchsEndIsRefusedBeforeItStarts) {
  const fs::path dir = fresh_folder("snapshot_at");
  const std::string png = (dir / "moment.png").string(), events = (dir / "events.jsonl").string(),
                    record = (dir / "recording").string();
  const std::string play = output_of(QUANTUM_BINARY " play " QUANTUM_SOURCE_DIR "/rules/airhockey --seconds 5 --audio none "
                                     "--events " + events + " --snapshot " + png + " --snapshot-at 30 2>&1; echo exit $?");
  EXPECT_NE(play.find("quantum: --snapshot-at 30: the match ends at 5.0 s (--seconds), before that moment"),
            std::string::npos) << play;
  EXPECT_NE(play.find("exit 1"), std::string::npos) << play;
  EXPECT_TRUE(fs::is_empty(dir)) << "nothing written: " << play;
  output_of(QUANTUM_BINARY " play " QUANTUM_SOURCE_DIR "/rules/airhockey --seconds 2 --quiet --audio none --record " + record);
  const std::string until = output_of(QUANTUM_BINARY " replay " + record + " --until 1 --snapshot " + png +
                                      " --snapshot-at 1.5 2>&1; echo exit $?");
  EXPECT_NE(until.find("quantum: --snapshot-at 1.5: the match ends at 1.0 s (--until), before that moment"),
            std::string::npos) << until;
  const std::string past = output_of(QUANTUM_BINARY " replay " + record + " --snapshot " + png + " --snapshot-at 3");
  EXPECT_NE(past.find("quantum: --snapshot-at 3: the match ends at 2.0 s (the recording's time limit)"), std::string::npos)
      << past;
  EXPECT_FALSE(fs::exists(png));
  // Up to the end is a moment of the match.
  const std::string last = output_of(QUANTUM_BINARY " replay " + record + " --quiet --snapshot " + png + " --snapshot-at 2");
  EXPECT_NE(last.find("quantum: wrote " + png + ": 1100x924, the match at 2.0 s"), std::string::npos) << last;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace quantum

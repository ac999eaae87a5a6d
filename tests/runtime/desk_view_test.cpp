// The desk's window as a person meets it, on virtual displays of a laptop's and a desktop's size
// (Xvfb), its keys pressed with xdotool and the screen photographed: it fits the screen, shows
// a reload's error until it is dismissed, keeps the final whistle up until a key, says which
// keys the sport's mouse player has, and a display that cannot be opened is one line. What the
// view shows in words (--view-log) is read beside the pixels.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "desk_support.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;
using test::output_of;
using test::pixels_of;

// The time bar's play head and the error screen's red (desk_screens.cpp).
const cv::Vec3b kHead(40, 215, 255), kError(50, 50, 255);

// Runs `quantum ARGS --view --view-log LOG` on a virtual screen of `screen` ("1280x800"); `then`
// is shell run beside it once its window shows a picture (`shot NAME` photographs the
// screen into the folder, `until_shown TEXT` waits for the view log to say TEXT). Returns what
// the command and the shell printed, and "exit N".
std::string at_desk(const test::TempFolder& f, const std::string& screen, const std::string& args, const std::string& then) {
  std::ofstream(f.path / "desk.sh") << "shot() { import -window root " << f.path.string() << "/$1.png; }\n"
      << QUANTUM_BINARY " " << args << " --view --view-log " << (f.path / "view.jsonl").string() << " &\n"
      << "p=$!\n"
      // `until_shown TEXT`: waits for the view log to have TEXT (a slow build draws late).
      << "until_shown() { for i in $(seq 400); do grep -q \"$1\" " << (f.path / "view.jsonl").string()
      << " && return; sleep 0.3; done; }\n"
      // The window has shown its first picture (a sanitizer build takes seconds to).
      << "until_shown '\"shows\":\"window\"'\n"
      << "sleep 1\n"
      << then << "\n"
      << "wait $p; echo exit $?\n";
  return output_of("timeout 240 xvfb-run -a -s '-screen 0 " + screen + "x24' sh " + (f.path / "desk.sh").string());
}

// Each line of the view log: what it shows, and the text.
std::vector<std::pair<std::string, std::string>> view_log(const test::TempFolder& f) {
  std::vector<std::pair<std::string, std::string>> lines;
  std::ifstream in(f.path / "view.jsonl");
  for (std::string line; std::getline(in, line);) {
    const nlohmann::json j = nlohmann::json::parse(line);
    lines.emplace_back(j.at("shows"), j.at("text"));
  }
  return lines;
}

bool shows(const std::vector<std::pair<std::string, std::string>>& log, const std::string& what, const std::string& part) {
  for (const auto& [w, text] : log)
    if (w == what && text.find(part) != std::string::npos) return true;
  return false;
}

// The window: the rows of the screen that are not the empty (black) desktop.
cv::Rect window_of(const cv::Mat& screen) {
  cv::Mat grey, lit;
  cv::cvtColor(screen, grey, cv::COLOR_BGR2GRAY);
  cv::threshold(grey, lit, 8, 255, cv::THRESH_BINARY);
  return cv::boundingRect(lit);
}

// On a laptop's screen and a desktop's, the tallest picture (basketball, with its side view) and
// a flat one open whole: the time bar under the picture, the last row of the window, is on the
// screen, and the window takes a good part of it.
TEST(DeskView, TheWindowFitsTheScreen) {
  for (const std::string screen : {"1280x800", "1920x1080"})
    for (const std::string sport : {"basketball", "airhockey"}) {
      const test::TempFolder f("quantum-fit");
      const std::string out = at_desk(f, screen, "play " QUANTUM_SOURCE_DIR "/rules/" + sport + " --seconds 60 --audio none --quiet",
                                      "shot screen; kill $p");
      const cv::Mat image = cv::imread((f.path / "screen.png").string());
      ASSERT_FALSE(image.empty()) << out;
      const cv::Rect window = window_of(image);
      EXPECT_GT(pixels_of(image(window), kHead), 20) << sport << " on " << screen << ": the time bar's play head";
      EXPECT_LE(window.br().y, image.rows) << sport << " on " << screen;
      EXPECT_GT(window.height, image.rows / 2) << sport << " on " << screen << ": " << window;
    }
}

// A sport.lua saved with a mistake: the window shows the error (file, line and message) over the
// match until Enter dismisses it; the match goes on under it.
TEST(DeskView, AReloadErrorIsShownInTheWindowUntilDismissed) {
  const test::TempFolder f("quantum-error");
  fs::copy(QUANTUM_SOURCE_DIR "/rules/airhockey", f.path / "sport", fs::copy_options::recursive);
  const std::string sport_lua = (f.path / "sport" / "sport.lua").string();
  const std::string out = at_desk(f, "1280x800", "play " + (f.path / "sport").string() + " --seconds 60 --audio none --quiet",
                                  "shot before; echo 'error(\"oops\")' >> " + sport_lua +
                                      "; until_shown 'reload failed'; sleep 1; shot error; xdotool key Return; sleep 1; "
                                      "shot dismissed; kill $p");
  const cv::Mat before = cv::imread((f.path / "before.png").string()), error = cv::imread((f.path / "error.png").string()),
                dismissed = cv::imread((f.path / "dismissed.png").string());
  ASSERT_FALSE(before.empty() || error.empty() || dismissed.empty()) << out;
  EXPECT_EQ(pixels_of(before, kError), 0);
  EXPECT_GT(pixels_of(error, kError), 100) << "the error screen's red";
  EXPECT_EQ(pixels_of(dismissed, kError), 0);
  const auto log = view_log(f);
  EXPECT_TRUE(shows(log, "problem", "reload failed: " + sport_lua + ":")) << out;
  EXPECT_TRUE(shows(log, "problem", "'<eof>' expected near 'error'")) << out;
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log.back(), std::make_pair(std::string("problem"), std::string(""))) << "dismissed";
}

// At the final whistle the window stays, with the score, until a key; the key ends the command.
TEST(DeskView, TheEndStaysOnScreenUntilAKey) {
  const test::TempFolder f("quantum-end");
  const std::string out = at_desk(f, "1280x800", "play airhockey --seconds 2 --audio none --quiet",
                                  "until_shown 'final whistle'; sleep 3; shot end; kill -0 $p && echo still open; "
                                  "xdotool key space");
  EXPECT_NE(out.find("still open"), std::string::npos) << out;
  EXPECT_NE(out.find("exit 0"), std::string::npos) << out;
  const auto log = view_log(f);
  EXPECT_TRUE(shows(log, "final whistle", "final score: blue ")) << out;
  const cv::Mat end = cv::imread((f.path / "end.png").string());
  ASSERT_FALSE(end.empty()) << out;
  EXPECT_GT(pixels_of(end, kHead), 100) << "'Final whistle' and the play head";
}

// The keys the view lists are the sport's: air hockey's mallet is bounced off, handball's player
// throws.
TEST(DeskView, EachSportsMousePlayerHasItsOwnKeys) {
  for (const auto& [sport, player, says, not_says] :
       std::vector<std::array<std::string, 4>>{{"airhockey", "", "mouse: Blue's mallet (the ball bounces off it)", "throw"},
                                               {"handball", "Clara", "mouse: Clara, click or t: throw", "bounces"}}) {
    const test::TempFolder f("quantum-keys");
    const std::string out = at_desk(f, "1280x800", "play " + sport + " --input mouse" + (player.empty() ? "" : ":" + player) +
                                                       " --seconds 60 --audio none --quiet", "kill $p");
    const auto log = view_log(f);
    ASSERT_FALSE(log.empty()) << out;
    EXPECT_EQ(log[0].first, "keys");
    EXPECT_NE(log[0].second.find(says), std::string::npos) << log[0].second;
    EXPECT_EQ(log[0].second.find(not_says), std::string::npos) << log[0].second;
    EXPECT_NE(log[0].second.find("left/right 5 s"), std::string::npos) << log[0].second;
  }
}

// A DISPLAY with no X server behind it is one line naming it, not highgui's abort.
TEST(DeskView, ADisplayThatCannotBeOpenedIsOneLine) {
  const std::string out = output_of("DISPLAY=:87 " QUANTUM_BINARY " play airhockey --view --seconds 1 --audio none --quiet 2>&1; echo exit $?");
  EXPECT_NE(out.find("--view needs a display, and DISPLAY=:87 cannot be opened"), std::string::npos) << out;
  EXPECT_NE(out.find("exit 1"), std::string::npos) << out;
  EXPECT_EQ(out.find("Qt"), std::string::npos) << out;
}

}  // namespace
}  // namespace quantum

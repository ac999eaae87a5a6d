// Real-time pacing that cannot keep up: a frame made slow on purpose (a watcher or a drawing that
// sleeps, a cloud of many particles) at a speed the clock demands a frame every 0.17 ms, so the
// match is late on any machine; the warning names what took the frames' time.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "count_of.h"
#include "session.h"
#include "lua_sport.h"

namespace quantum {
namespace {

using test::count_of;

// 60 frames, each held 40 ms or more by the watcher (it hears two tells a frame), at a hundred
// times real time: at least 2.4 s of wall clock for 10 ms of due time. With `drawing`, the
// front end's drawing holds each frame instead, 40 ms between frames.
std::string warnings_of_a_slow_match(runtime::SessionOptions::Pacing pacing, bool drawing = false) {
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/airhockey";
  o.particles = 300;
  o.pacing = pacing;
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  session.set_speed(100);
  if (!drawing) session.watch([](const runtime::News&) { std::this_thread::sleep_for(std::chrono::milliseconds(20)); });
  for (int frame = 0; frame < 60; ++frame) {
    session.frame();
    if (drawing) {
      const runtime::Session::Drawing drawn(session);
      std::this_thread::sleep_for(std::chrono::milliseconds(40));
    }
  }
  session.finish();
  return errors.str();
}

// A cloud whose every frame takes milliseconds of the engine, at a hundred times real time: late
// within a few hundred frames, the engine its cost.
std::string warnings_of_a_large_cloud() {
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/airhockey";
  o.particles = 200'000;
  o.pacing = runtime::SessionOptions::Pacing::RealTime;
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  session.set_speed(100);
  // Late, and a second of play at least, whatever the machine: the doc quotes its end line so.
  for (int frame = 0; frame < 3000 && (errors.str().empty() || frame < 60); ++frame) session.frame();
  session.finish();
  return errors.str();
}

TEST(Pacing, AMatchLateOnTheClockSaysSoOnceAndHowSlowItRan) {
  const std::string said = warnings_of_a_slow_match(runtime::SessionOptions::Pacing::RealTime);
  EXPECT_EQ(count_of(said, "quantum: the match runs "), 1) << said;
  EXPECT_EQ(count_of(said, " behind real time after "), 1) << said;
  // The watcher is neither the engine, the drawing nor the sound: no advice it would not take.
  EXPECT_EQ(count_of(said, "longer than the 0.2 ms they may, and the rest of the frame takes most of it: "), 1) << said;
  EXPECT_EQ(count_of(said, " a frame, for the players' input, the logs, watchers and reloads (the engine "), 1) << said;
  EXPECT_EQ(said.find("--particles"), std::string::npos) << said;
  EXPECT_EQ(count_of(said, "quantum: 1.0 s of play took "), 1) << said;
  EXPECT_EQ(count_of(said, " of the clock ("), 1) << said;
  EXPECT_EQ(count_of(said, " times real time)\n"), 1) << said;
  // The frames were held 2.4 s at least, and the ratio is that over the second of play.
  std::smatch took;
  ASSERT_TRUE(std::regex_search(said, took, std::regex(R"(took ([0-9.]+) s of the clock \(([0-9.]+) times)"))) << said;
  EXPECT_GE(std::stod(took[1]), 2.4);
  EXPECT_EQ(took[1], took[2]);
}

// The drawing a front end reports (a view that cannot keep up) is named, and fewer particles are
// not offered as the cure; a cloud too large for the machine names the engine and its size.
TEST(Pacing, ALateMatchNamesWhatTookItsFramesTheirTime) {
  const std::string drawn = warnings_of_a_slow_match(runtime::SessionOptions::Pacing::RealTime, true);
  EXPECT_EQ(count_of(drawn, "and the drawing takes most of it: "), 1) << drawn;
  EXPECT_EQ(count_of(drawn, " a frame (the engine "), 1) << drawn;
  EXPECT_EQ(count_of(drawn, "); a video (--video FILE) is drawn without the clock\n"), 1) << drawn;
  EXPECT_EQ(drawn.find("--particles"), std::string::npos) << drawn;
  const std::string engine = warnings_of_a_large_cloud();
  EXPECT_EQ(count_of(engine, "and the engine takes most of it: "), 1) << engine;
  EXPECT_EQ(count_of(engine, " a frame with a cloud of 200000 particles (the drawing "), 1) << engine;
  EXPECT_EQ(count_of(engine, "; fewer particles (--particles) keep it in time\n"), 1) << engine;
}

// docs/desk.md quotes the two lines a late match prints: they must be what the session says,
// numbers aside, and a duration's unit (how far a cloud's frames run late depends on the machine).
TEST(Pacing, TheDeskDocQuotesWhatALateMatchSays) {
  std::ifstream doc(QUANTUM_SOURCE_DIR "/docs/desk.md");
  std::vector<std::string> quoted;
  bool in_pacing = false, in_block = false;
  for (std::string line; std::getline(doc, line);) {
    if (line.rfind("## ", 0) == 0) in_pacing = line == "## Pacing";
    else if (in_pacing && line.rfind("```", 0) == 0) in_block = !in_block;
    else if (in_block) quoted.push_back(line);
  }
  ASSERT_EQ(quoted.size(), 2u);
  const std::string said = warnings_of_a_large_cloud();
  for (const std::string& line : quoted) {
    // The quoted line as a pattern: its punctuation taken literally, every number any number,
    // a duration in either unit ("350.0 ms", "1.2 s").
    const std::string literal = std::regex_replace(line, std::regex(R"([()|.*+?^$\\[\]{}])"), R"(\$&)");
    const std::regex number(R"([0-9]+(\\\.[0-9]+)?( m?s\b)?)");
    std::string pattern;
    auto from = literal.cbegin();
    for (auto m = std::sregex_iterator(literal.begin(), literal.end(), number); m != std::sregex_iterator(); ++m) {
      pattern.append(from, (*m)[0].first).append((*m)[2].matched ? "[0-9.]+ m?s\\b" : "[0-9.]+");
      from = (*m)[0].second;
    }
    pattern.append(from, literal.cend());
    EXPECT_TRUE(std::regex_search(said, std::regex("(^|\n)" + pattern + "\n"))) << line << "\nnot in\n" << said;
  }
}

// A match played as fast as it goes keeps no time, so it is never late.
TEST(Pacing, AFastMatchIsNeverLate) {
  EXPECT_EQ(warnings_of_a_slow_match(runtime::SessionOptions::Pacing::Fast), "");
}

}  // namespace
}  // namespace quantum

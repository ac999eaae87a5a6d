// Real-time pacing that cannot keep up: a frame made slow on purpose (a watcher that sleeps) at a
// speed the clock demands a frame every 0.17 ms, so the match is late on any machine.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "session.h"

namespace quantum {
namespace {

// How often `what` occurs in `text`.
int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// 60 frames, each held 40 ms or more by the watcher (it hears two tells a frame), at a hundred
// times real time: at least 2.4 s of wall clock for 10 ms of due time.
std::string warnings_of_a_slow_match(runtime::SessionOptions::Pacing pacing) {
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/airhockey";
  o.particles = 300;
  o.pacing = pacing;
  std::ostringstream errors;
  runtime::Session session(o, nullptr, errors);
  session.set_speed(100);
  session.watch([](const runtime::News&) { std::this_thread::sleep_for(std::chrono::milliseconds(20)); });
  for (int frame = 0; frame < 60; ++frame) session.frame();
  session.finish();
  return errors.str();
}

TEST(Pacing, AMatchLateOnTheClockSaysSoOnceAndHowSlowItRan) {
  const std::string said = warnings_of_a_slow_match(runtime::SessionOptions::Pacing::RealTime);
  EXPECT_EQ(count_of(said, "quantum: the match runs "), 1) << said;
  EXPECT_EQ(count_of(said, " behind real time after "), 1) << said;
  EXPECT_EQ(count_of(said, "longer than the 0.2 ms they may, with a cloud of 300 particles; fewer (--particles)"), 1) << said;
  EXPECT_EQ(count_of(said, "quantum: 1.0 s of play took "), 1) << said;
  EXPECT_EQ(count_of(said, " of the clock ("), 1) << said;
  EXPECT_EQ(count_of(said, " times real time)\n"), 1) << said;
  // The frames were held 2.4 s at least, and the ratio is that over the second of play.
  std::smatch took;
  ASSERT_TRUE(std::regex_search(said, took, std::regex(R"(took ([0-9.]+) s of the clock \(([0-9.]+) times)"))) << said;
  EXPECT_GE(std::stod(took[1]), 2.4);
  EXPECT_EQ(took[1], took[2]);
}

// docs/desk.md quotes the two lines a late match prints: they must be what the session says,
// numbers aside.
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
  const std::string said = warnings_of_a_slow_match(runtime::SessionOptions::Pacing::RealTime);
  for (const std::string& line : quoted) {
    // The quoted line as a pattern: its punctuation taken literally, every number any number.
    const std::string literal = std::regex_replace(line, std::regex(R"([()|.*+?^$\\[\]{}])"), R"(\$&)");
    const std::string pattern = std::regex_replace(literal, std::regex(R"([0-9]+(\\\.[0-9]+)?)"), "[0-9.]+");
    EXPECT_TRUE(std::regex_search(said, std::regex("(^|\n)" + pattern + "\n"))) << line << "\nnot in\n" << said;
  }
}

// A match played as fast as it goes keeps no time, so it is never late.
TEST(Pacing, AFastMatchIsNeverLate) {
  EXPECT_EQ(warnings_of_a_slow_match(runtime::SessionOptions::Pacing::Fast), "");
}

}  // namespace
}  // namespace quantum

// Every shipped sport's seeded event and decision logs, byte for byte against the ones kept in
// tests/golden/ (but for the build the decision log's header names): a change meant to move no
// ball (a refactoring of the physics, of the rules' plumbing, of the logs' writers) proves it
// here, line by line. A change that does move balls regenerates them, and the diff of the golden
// files is then part of its review:
//
//   QUANTUM_UPDATE_GOLDEN=1 build/tests/quantum_tests --gtest_filter='GoldenLogs/*'
//
// The logs are what this build's floating point makes of the match: GCC at -O3 -march=native
// contracts a * b + c into one fused multiply-add wherever it can (gnu++20), clang at -O1 (the
// sanitizer build) only within one expression, and the last bits that differ send a particle to
// another wall a few frames later. So the test runs in the optimized build only (its CTest label
// `golden`, tools/test.sh), and the files are that build's on the CPU that wrote them: another
// compiler, another -march, or a CPU without FMA writes other logs, and regenerating them there
// (the command above, before the change) gives the comparison its ground.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>

#include <unistd.h>

#include "../shipped_sports.h"
#include "output_files.h"
#include "lua_sport.h"
#include "session.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

constexpr const char* kRegenerate = "QUANTUM_UPDATE_GOLDEN=1 build/tests/quantum_tests --gtest_filter='GoldenLogs/*'";

const fs::path kGolden = fs::path(QUANTUM_SOURCE_DIR) / "tests/golden";

// A seeded 25 s match of `sport` between simulated players with the sport's own particles,
// writing both logs to `events` and `decisions` (gzip-compressed where the name ends in .gz).
void play(const std::string& sport, const fs::path& events, const fs::path& decisions) {
  runtime::SessionOptions o;
  o.sport = std::string(QUANTUM_SOURCE_DIR "/rules/") + sport;
  o.seconds = 25;
  o.seed = 45;
  o.events = events.string();
  o.decisions = decisions.string();
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  session.run();
}

// A log's line as the comparison sees it: the decision log's header names the build that wrote
// it (its "engine", docs/decisions.md), which every commit changes; everything else counts.
std::string compared(std::string line) {
  static const std::regex engine(R"("engine":"[^"]*")");
  return std::regex_replace(line, engine, R"("engine":"")", std::regex_constants::format_first_only);
}

// "" when the two files hold the same lines, else where and how they first differ.
std::string first_difference(const fs::path& kept, const fs::path& written) {
  runtime::LineReader a(kept.string()), b(written.string());
  std::string x, y;
  for (size_t line = 1;; ++line) {
    const bool more_a = a.next(x), more_b = b.next(y);
    if (!more_a && !more_b) break;
    if (more_a && more_b && (x == y || (line == 1 && compared(x) == compared(y)))) continue;
    std::ostringstream said;
    said << written.filename().string() << " line " << line << " differs from " << kept.string() << "\n  kept:    "
         << (more_a ? x : "(the end)") << "\n  written: " << (more_b ? y : "(the end)");
    return said.str();
  }
  return a.torn() + b.torn();
}

class GoldenLogs : public testing::TestWithParam<const char*> {};

TEST_P(GoldenLogs, AreByteIdenticalToTheKeptOnes) {
  const std::string sport = GetParam();
  const fs::path events = kGolden / (sport + ".events.jsonl.gz"), decisions = kGolden / (sport + ".decisions.jsonl.gz");
  if (std::getenv("QUANTUM_UPDATE_GOLDEN")) {
    play(sport, events, decisions);
    GTEST_SKIP() << "wrote " << events << " and " << decisions;
  }
  const fs::path dir = fs::temp_directory_path() / ("quantum_golden_" + sport + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  play(sport, dir / "events.jsonl", dir / "decisions.jsonl");
  for (const auto& [kept, written] : {std::pair{events, dir / "events.jsonl"}, std::pair{decisions, dir / "decisions.jsonl"}}) {
    ASSERT_TRUE(fs::exists(kept)) << kept << " is missing; write it with\n  " << kRegenerate;
    const std::string difference = first_difference(kept, written);
    EXPECT_TRUE(difference.empty()) << difference
        << "\nIf the change is meant to move the balls, write the files again and review their diff:\n  " << kRegenerate;
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(GoldenLogs, GoldenLogs, testing::ValuesIn(test::kShippedSports),
                         [](const testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

}  // namespace
}  // namespace quantum

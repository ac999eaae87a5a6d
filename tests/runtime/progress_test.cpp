// Long work says how far it is (runtime/progress.h): on a terminal one line drawn again in place,
// with the time left; in a log a few plain lines, none for work of a few seconds. The clock is
// the test's own, so that no figure depends on the machine.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "count_of.h"
#include "output_files.h"
#include "progress.h"

namespace quantum {
namespace {

using test::count_of;

TEST(Progress, OnATerminalTheLineIsDrawnAgainInPlaceWithTheTimeLeft) {
  double now = 100;
  std::ostringstream out;
  {
    runtime::ProgressLine line(out, true, "video match.mp4", 6, "s", 1, [&] { return now; });
    now = 100.5, line(0.5);   // no pace to go by yet: no time left
    now = 100.6, line(0.6);   // a tenth of a second later: not drawn again
    now = 102, line(2);       // 2 s of video in 2 s: 4 s left
    now = 106, line(6);
    line.clear();
    line(6);                  // drawn again after a clear, at once
  }
  const std::string said = out.str();
  EXPECT_EQ(said.find('\n'), std::string::npos) << said;
  EXPECT_NE(said.find("\rvideo match.mp4: 0.5 of 6.0 s (8 %)\r"), std::string::npos) << said;
  EXPECT_EQ(said.find("0.6 of"), std::string::npos) << said;
  EXPECT_NE(said.find("\rvideo match.mp4: 2.0 of 6.0 s (33 %), 0:04 left\r"), std::string::npos) << said;
  // The shorter line covers the longer one's end; a clear wipes the line, and the end does too.
  EXPECT_NE(said.find("\rvideo match.mp4: 6.0 of 6.0 s (100 %)          \r"), std::string::npos) << said;
  EXPECT_EQ(count_of(said, "6.0 of 6.0 s"), 2) << said;
  const std::string last = "video match.mp4: 6.0 of 6.0 s (100 %)";
  EXPECT_EQ(said.substr(said.size() - last.size() - 2), "\r" + std::string(last.size(), ' ') + "\r") << said;
}

TEST(Progress, InALogPlainLinesComeEveryTenthAndNotOftenerThanEveryFiveSeconds) {
  double now = 0;
  std::ostringstream out;
  {
    // 100 matches, one every quarter of a second: 25 s.
    runtime::ProgressLine line(out, false, "balance", 100, "matches", 0, [&] { return now; });
    for (int done = 1; done <= 100; ++done) now = 0.25 * done, line(done);
  }
  EXPECT_EQ(out.str(),
            "quantum: balance: 20 of 100 matches (20 %), 0:20 left\n"
            "quantum: balance: 40 of 100 matches (40 %), 0:15 left\n"
            "quantum: balance: 60 of 100 matches (60 %), 0:10 left\n"
            "quantum: balance: 80 of 100 matches (80 %), 0:05 left\n"
            "quantum: balance: 100 of 100 matches (100 %)\n");
  // Work of four seconds: nothing at all.
  std::ostringstream short_work;
  {
    runtime::ProgressLine line(short_work, false, "balance", 100, "matches", 0, [&] { return now; });
    for (int done = 1; done <= 100; ++done) now = 0.04 * done, line(done);
  }
  EXPECT_EQ(short_work.str(), "");
}

TEST(Progress, AWrittenFileIsConfirmedWithWhatItHoldsAndItsSize) {
  const std::string file = testing::TempDir() + "progress_written_" + std::to_string(getpid()) + ".txt";
  {
    std::ofstream(file) << std::string(1500, 'x');
  }
  std::ostringstream out;
  runtime::say_written(out, {file, "3 lines"});
  runtime::say_written(out, {"-", "standard output"});  // not a file: nothing
  EXPECT_EQ(out.str(), "quantum: wrote " + file + ": 3 lines, 2 KB\n");
  std::remove(file.c_str());
  EXPECT_EQ(runtime::bytes(312), "312 bytes");
  EXPECT_EQ(runtime::bytes(1'234'567), "1.2 MB");
}

}  // namespace
}  // namespace quantum

// Values from the network (docs/reliability.md, "Faults"), built with tracking: tracking values
// that are not numbers or out of range are dropped and counted, by `quantum track` as by `play`;
// what a source keeps per player name or cursor id is bounded, the oldest dropped and counted.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <lo/lo.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <thread>

#include "track.h"
#include "tracking/input.h"
#include "tracking/tracking.h"

namespace quantum {
namespace {

// Ports of this test process's own (Tuio.* take 43000 and up): five each.
int port(int k) { return 45000 + int(getpid() % 400) * 5 + k; }

// The air hockey table, as tracking sees it: 2 x 1 m, Blue's mallet then Red's.
tracking::TrackedField table() {
  tracking::TrackedField f;
  f.length = 2, f.width = 1;
  f.players = {{"Blue's mallet", "blue", -1}, {"Red's mallet", "red", 1}};
  return f;
}

// TUIO 1.1 sent with liblo: objects (class = player) and cursors, each bundle one frame.
struct Tuio {
  lo_address to;
  int frame = 0;
  explicit Tuio(int port) : to(lo_address_new("127.0.0.1", std::to_string(port).c_str())) {}
  ~Tuio() { lo_address_free(to); }
  // Objects {session (and class), x, y, X, Y}, then the frame's end.
  void objects(const std::vector<std::array<float, 5>>& objects) {
    lo_bundle b = lo_bundle_new(LO_TT_IMMEDIATE);
    for (const auto& o : objects) {
      lo_message set = lo_message_new();
      lo_message_add_string(set, "set");
      lo_message_add_int32(set, int(o[0]));
      lo_message_add_int32(set, int(o[0]));
      for (float v : {o[1], o[2], 0.0f, o[3], o[4], 0.0f, 0.0f, 0.0f}) lo_message_add_float(set, v);
      lo_bundle_add_message(b, "/tuio/2Dobj", set);
    }
    end(b, "/tuio/2Dobj");
  }
  // Cursors of sessions first..first + n - 1, never said to be gone (no alive message).
  void new_cursors(int first, int n) {
    lo_bundle b = lo_bundle_new(LO_TT_IMMEDIATE);
    for (int id = first; id < first + n; ++id) {
      lo_message set = lo_message_new();
      lo_message_add_string(set, "set");
      lo_message_add_int32(set, id);
      for (float v : {0.5f, 0.5f, 0.0f, 0.0f, 0.0f}) lo_message_add_float(set, v);
      lo_bundle_add_message(b, "/tuio/2Dcur", set);
    }
    end(b, "/tuio/2Dcur");
  }
  void end(lo_bundle b, const char* path) {
    lo_message fseq = lo_message_new();
    lo_message_add_string(fseq, "fseq");
    lo_message_add_int32(fseq, ++frame);
    lo_bundle_add_message(b, path, fseq);
    EXPECT_GT(lo_send_bundle(to, b), 0);
    lo_bundle_free_recursive(b);
  }
};

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN(), kInf = std::numeric_limits<float>::infinity();

// `quantum track tuio:PORT` printed "x":null for NaN and infinity and 6.8e+39 for 3.4e38, and told
// of no drop: now those players are left out of their frames, and the drops told.
TEST(FaultValues, TrackDropsTuioObjectsThatAreNotNumbersOrOutOfRangeAndCountsThem) {
  tools::TrackOptions o;
  o.source = "tuio:" + std::to_string(port(0));
  o.frames = 40;
  std::ostringstream out, told;
  std::streambuf* cerr = std::cerr.rdbuf(told.rdbuf());  // where track tells its drops
  std::atomic<bool> done{false};
  std::thread track([&] {
    tools::track(o, out);
    done = true;
  });
  Tuio send(port(0));
  const float bad[][4] = {{kNaN, 0.5f, 0, 0}, {kInf, 0.5f, 0, 0}, {3.4e38f, 0.5f, 0, 0}, {0.75f, 0.5f, 1e30f, 0}};
  for (int k = 0; !done && k < 2000; ++k) {
    const float* red = bad[k % 4];
    send.objects({{0, 0.25f, 0.5f, 0, 0}, {1, red[0], red[1], red[2], red[3]}});
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  track.join();
  std::cerr.rdbuf(cerr);
  ASSERT_TRUE(done);
  EXPECT_EQ(out.str().find("null"), std::string::npos) << out.str();
  std::istringstream lines(out.str());
  int frames = 0;
  for (std::string line; std::getline(lines, line); ++frames) {
    const nlohmann::json frame = nlohmann::json::parse(line);
    ASSERT_EQ(frame["players"].size(), 1u) << line;
    EXPECT_EQ(frame["players"][0]["id"], "Blue's mallet");
    EXPECT_DOUBLE_EQ(frame["players"][0]["x"].get<double>(), -0.5);
  }
  EXPECT_EQ(frames, 40);
  EXPECT_NE(told.str().find("tracking values dropped (not a number or out of range"), std::string::npos) << told.str();
  EXPECT_NE(told.str().find("40 in all"), std::string::npos) << told.str();
}

// What `play` and `track` both read: each bad value is one drop, counted, the player left out of
// that frame; in range, the same object is back.
TEST(FaultValues, EachTrackedValueOutOfRangeIsOneDrop) {
  tracking::TrackingInput input("tuio:" + std::to_string(port(1)), table(), {});
  Tuio send(port(1));
  const auto next = [&] {
    tracking::TrackedFrame f;
    for (int tries = 0; tries < 20; ++tries)
      if (input.next(f, 0.1) == tracking::TrackingInput::Status::Frame) return f;
    ADD_FAILURE() << "no frame";
    return f;
  };
  size_t dropped = 0;
  // NaN; at 3 m beyond the table's far end (TUIO's 3 is 5 m from its centre); 600 m/s across it.
  for (const std::array<float, 5> red : {std::array<float, 5>{1, kNaN, 0.5f, 0, 0}, {1, 3, 0.5f, 0, 0}, {1, 0.5f, 0.5f, 0, 600}}) {
    send.objects({{0, 0.25f, 0.5f, 0, 0}, red});
    const tracking::TrackedFrame f = next();
    ASSERT_EQ(f.players.size(), 1u);
    EXPECT_EQ(f.players[0].id, "Blue's mallet");
    EXPECT_EQ(input.dropped(), ++dropped);
  }
  send.objects({{0, 0.25f, 0.5f, 0, 0}, {1, 1.2f, 0.5f, 0, 0}});  // just past the table's end: a player
  EXPECT_EQ(next().players.size(), 2u);
  EXPECT_EQ(input.dropped(), dropped);
}

// A sender of ever new cursor ids, never saying one is gone: 100,000 of them leave the source
// holding the newest kMostTracked, each older one dropped and counted, and its frames still whole.
TEST(FaultValues, AFloodOfCursorIdsKeepsTheNewestAndCountsTheRest) {
  tracking::TuioSource source(port(2), table());
  Tuio send(port(2));
  constexpr int kIds = 100'000, kPerBundle = 500;
  for (int first = 0; first < kIds; first += kPerBundle) {
    send.new_cursors(first, kPerBundle);
    const std::optional<tracking::TrackedFrame> f = source.next(2.0);
    ASSERT_TRUE(f) << "bundle " << first / kPerBundle;
    ASSERT_EQ(f->players.size(), 2u);
  }
  EXPECT_EQ(source.dropped(), size_t(kIds) - tracking::kMostTracked);
}

// --- Accelerometers.

// A whip of `name` at `t`: well past the detector's 25 m/s^2.
tracking::AccelSample whip(const std::string& name, double t) { return {t, name, 40, 0, 0}; }

// 100,000 players' names, each whipping once: the detector remembers the last kMostTracked, and
// counts the others it forgot (they grew 14 MB and slowed every frame).
TEST(FaultValues, AFloodOfAccelerometerNamesIsRememberedUpToItsBound) {
  tracking::ThrowDetector detector;
  std::vector<tracking::AccelSample> flood;
  for (int k = 0; k < 100'000; ++k) flood.push_back(whip("player " + std::to_string(k), k * 1e-4));
  tracking::TrackedFrame frame;
  detector.add(flood, frame);
  EXPECT_EQ(frame.actions.size(), flood.size());  // each a throw, once
  EXPECT_EQ(detector.players(), tracking::kMostTracked);
  EXPECT_EQ(detector.dropped(), flood.size() - tracking::kMostTracked);
}

// The oldest go first: the newest name is still within its half second between throws, the
// first one, forgotten, throws again.
TEST(FaultValues, TheOldestAccelerometerNamesAreForgottenFirst) {
  tracking::ThrowDetector detector;
  tracking::TrackedFrame frame;
  for (int k = 0; k < 1000; ++k) detector.add({whip("player " + std::to_string(k), k * 1e-4)}, frame);
  frame.actions.clear();
  detector.add({whip("player 999", 0.11), whip("player 0", 0.11)}, frame);
  ASSERT_EQ(frame.actions.size(), 1u);
  EXPECT_EQ(frame.actions[0].player, "player 0");
}

// Over UDP beside a TUIO tracker, as `play --accel udp:PORT` reads them: a flood of new names is
// counted with the source's drops (what the detector forgot), and the frames go on.
TEST(FaultValues, AFloodOfAccelerometerPacketsIsCountedWithTheSourcesDrops) {
  tracking::SourceOptions options;
  options.accel = "udp:" + std::to_string(port(4));
  tracking::TrackingInput input("tuio:" + std::to_string(port(3)), table(), options);
  Tuio send(port(3));
  const int out = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(out, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(uint16_t(port(4)));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  size_t throws = 0;
  for (int name = 0; name < 20'000;) {
    for (int k = 0; k < 50; ++k, ++name) {
      const std::string sample = "0,player " + std::to_string(name) + ",40,0,0";
      sendto(out, sample.data(), sample.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
    }
    send.objects({{0, 0.25f, 0.5f, 0, 0}});
    tracking::TrackedFrame f;
    auto status = tracking::TrackingInput::Status::Waiting;
    for (int tries = 0; tries < 20 && status != tracking::TrackingInput::Status::Frame; ++tries) status = input.next(f, 0.1);
    ASSERT_EQ(status, tracking::TrackingInput::Status::Frame);
    throws += f.actions.size();
  }
  close(out);
  ASSERT_GT(throws, 2 * tracking::kMostTracked);  // the kernel may drop a few datagrams of its own
  EXPECT_EQ(input.dropped(), throws - tracking::kMostTracked);
}

}  // namespace
}  // namespace quantum

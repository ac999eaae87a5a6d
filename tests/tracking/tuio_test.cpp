// TUIO 1.1 over OSC/UDP, sent with liblo as a tracker would send it.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <lo/lo.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <thread>

#include "play.h"
#include "tracking/input.h"
#include "tracking/tracking.h"

namespace quantum {
namespace {

tracking::TrackedField table() {
  tracking::TrackedField f;
  f.length = 2, f.width = 1;
  f.players = {{"Blue's mallet", "blue", -1}, {"Red's mallet", "red", 1}};
  return f;
}

int test_port() { return 43000 + int(getpid() % 2000); }

// One TUIO frame as a bundle: alive, set for each, fseq.
struct Sender {
  lo_address to = lo_address_new("127.0.0.1", std::to_string(test_port()).c_str());
  int frame = 0;
  ~Sender() { lo_address_free(to); }

  void cursors(const std::vector<std::array<float, 3>>& touches) {  // session, x, y
    lo_bundle b = lo_bundle_new(LO_TT_IMMEDIATE);
    lo_message alive = lo_message_new();
    lo_message_add_string(alive, "alive");
    for (const auto& t : touches) lo_message_add_int32(alive, int(t[0]));
    lo_bundle_add_message(b, "/tuio/2Dcur", alive);
    for (const auto& t : touches) {
      lo_message set = lo_message_new();
      lo_message_add_string(set, "set");
      lo_message_add_int32(set, int(t[0]));
      for (float v : {t[1], t[2], 0.1f, 0.0f, 0.0f}) lo_message_add_float(set, v);
      lo_bundle_add_message(b, "/tuio/2Dcur", set);
    }
    lo_message fseq = lo_message_new();
    lo_message_add_string(fseq, "fseq");
    lo_message_add_int32(fseq, ++frame);
    lo_bundle_add_message(b, "/tuio/2Dcur", fseq);
    lo_send_bundle(to, b);
    lo_bundle_free_recursive(b);
  }

  void object(int session, int cls, float x, float y) {
    lo_bundle b = lo_bundle_new(LO_TT_IMMEDIATE);
    lo_message alive = lo_message_new();
    lo_message_add_string(alive, "alive");
    lo_message_add_int32(alive, session);
    lo_bundle_add_message(b, "/tuio/2Dobj", alive);
    lo_message set = lo_message_new();
    lo_message_add_string(set, "set");
    lo_message_add_int32(set, session);
    lo_message_add_int32(set, cls);
    for (float v : {x, y, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f}) lo_message_add_float(set, v);
    lo_bundle_add_message(b, "/tuio/2Dobj", set);
    lo_message fseq = lo_message_new();
    lo_message_add_string(fseq, "fseq");
    lo_message_add_int32(fseq, ++frame);
    lo_bundle_add_message(b, "/tuio/2Dobj", fseq);
    lo_send_bundle(to, b);
    lo_bundle_free_recursive(b);
  }
};

const tracking::TrackedPlayer* find(const tracking::TrackedFrame& f, const std::string& id) {
  for (const auto& p : f.players)
    if (p.id == id) return &p;
  return nullptr;
}

TEST(Tuio, CursorsAndObjectsBecomePlayersInFieldMetres) {
  tracking::TuioSource source(test_port(), table());
  Sender send;
  EXPECT_FALSE(source.next(0.05));  // nothing sent yet

  // One cursor: the first free player, Blue; TUIO's (0.25, 0.25) is x = -0.5, y = +0.25.
  send.cursors({{{7, 0.25f, 0.25f}}});
  std::optional<tracking::TrackedFrame> f = source.next(1.0);
  ASSERT_TRUE(f);
  ASSERT_EQ(f->players.size(), 1u);
  EXPECT_EQ(f->players[0].id, "Blue's mallet");
  EXPECT_NEAR(f->players[0].x, -0.5, 1e-6);
  EXPECT_NEAR(f->players[0].y, 0.25, 1e-6);
  EXPECT_NEAR(f->players[0].vx, 0.2, 1e-6);  // 0.1 of the length per second

  // A second cursor takes Red; the first keeps Blue.
  send.cursors({{{7, 0.3f, 0.5f}}, {{9, 0.9f, 0.5f}}});
  f = source.next(1.0);
  ASSERT_TRUE(f);
  ASSERT_EQ(f->players.size(), 2u);
  ASSERT_TRUE(find(*f, "Red's mallet"));
  EXPECT_NEAR(find(*f, "Red's mallet")->x, 0.8, 1e-6);
  EXPECT_NEAR(find(*f, "Blue's mallet")->x, -0.4, 1e-6);

  // The first cursor leaves: Blue has no input.
  send.cursors({{{9, 0.8f, 0.5f}}});
  f = source.next(1.0);
  ASSERT_TRUE(f);
  ASSERT_EQ(f->players.size(), 1u);
  EXPECT_EQ(f->players[0].id, "Red's mallet");
}

TEST(Tuio, AnObjectIsThePlayerOfItsClass) {
  tracking::TuioSource source(test_port() + 1, table());
  Sender send;
  lo_address_free(send.to);
  send.to = lo_address_new("127.0.0.1", std::to_string(test_port() + 1).c_str());
  send.object(3, 1, 0.75f, 0.1f);  // class 1: Red
  const std::optional<tracking::TrackedFrame> f = source.next(1.0);
  ASSERT_TRUE(f);
  ASSERT_EQ(f->players.size(), 1u);
  EXPECT_EQ(f->players[0].id, "Red's mallet");
  EXPECT_NEAR(f->players[0].x, 0.5, 1e-6);
  EXPECT_NEAR(f->players[0].y, 0.4, 1e-6);
}

// One datagram, byte for byte, to a TUIO port: packets liblo's own senders never make.
void send_raw(int port, const std::string& bytes) {
  const int out = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(out, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(uint16_t(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(sendto(out, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to),
            ssize_t(bytes.size()));
  close(out);
}

// An OSC bundle to be played at once, holding `element`.
std::string bundle_of(const std::string& element) {
  const uint32_t size = htonl(uint32_t(element.size()));
  return std::string("#bundle\0\0\0\0\0\0\0\0\1", 16) + std::string(reinterpret_cast<const char*>(&size), 4) + element;
}

// Packets liblo 0.31 would read past their end are dropped, counted, and the frame after them
// still plays. The first is what the TUIO fuzzer found: a bundle ending in an empty element.
TEST(Tuio, PacketsLibloWouldReadPastAreDroppedAndCounted) {
  const int port = test_port() + 6;
  tracking::TuioSource source(port, table());
  const std::string empty_message("/x\0\0,\0\0\0", 8);
  std::ifstream found(QUANTUM_SOURCE_DIR "/tests/fuzz/corpus/tuio/bundle_ending_in_an_empty_element.osc", std::ios::binary);
  const std::string fuzzed((std::istreambuf_iterator<char>(found)), std::istreambuf_iterator<char>());
  ASSERT_EQ(fuzzed.size(), 96u);
  std::string too_deep = empty_message;
  for (int level = 0; level < 9; ++level) too_deep = bundle_of(too_deep);
  std::string claims_more = bundle_of(empty_message);
  claims_more[19] = 64;  // its element's size: 64 bytes, of the 8 there are
  for (const std::string& p : {fuzzed, claims_more, std::string("/tuio/"), too_deep}) send_raw(port, p);
  Sender send;
  lo_address_free(send.to);
  send.to = lo_address_new("127.0.0.1", std::to_string(port).c_str());
  send.cursors({{{7, 0.25f, 0.25f}}});
  const std::optional<tracking::TrackedFrame> f = source.next(1.0);
  ASSERT_TRUE(f);
  ASSERT_EQ(f->players.size(), 1u);
  EXPECT_NEAR(f->players[0].x, -0.5, 1e-6);
  EXPECT_EQ(source.dropped(), 4u);

  // Eight bundles deep, the same message is whole: read, and not counted.
  std::string nested = empty_message;
  for (int level = 0; level < 8; ++level) nested = bundle_of(nested);
  send_raw(port, nested);
  send.cursors({{{7, 0.5f, 0.5f}}});
  ASSERT_TRUE(source.next(1.0));
  EXPECT_EQ(source.dropped(), 4u);
}

// A TUIO tracker and a player's accelerometer together: the whip is a throw by that player, in
// the frame that reaches its time.
TEST(Tuio, AccelerometersThrowForTuioPlayers) {
  const int port = test_port() + 4;
  const std::string csv =
      (std::filesystem::temp_directory_path() / ("quantum_tuio_accel_" + std::to_string(port) + ".csv")).string();
  std::ofstream(csv) << "t,player,ax,ay,az\n0.0,Red's mallet,40,0,0\n";
  tracking::SourceOptions options;
  options.accel = csv;
  tracking::TrackingInput input("tuio:" + std::to_string(port), table(), options);
  Sender send;
  lo_address_free(send.to);
  send.to = lo_address_new("127.0.0.1", std::to_string(port).c_str());
  send.cursors({{{1, 0.2f, 0.5f}}, {{2, 0.8f, 0.5f}}});
  tracking::TrackedFrame frame;
  auto status = tracking::TrackingInput::Status::Waiting;
  for (int tries = 0; tries < 20 && status != tracking::TrackingInput::Status::Frame; ++tries) status = input.next(frame, 0.1);
  ASSERT_EQ(status, tracking::TrackingInput::Status::Frame);
  ASSERT_EQ(frame.actions.size(), 1u);
  EXPECT_EQ(frame.actions[0].type, "throw");
  EXPECT_EQ(frame.actions[0].player, "Red's mallet");
  EXPECT_EQ(frame.actions[0].dx, -1);  // standing still: toward the other end
}

TEST(Tuio, APortInUseIsNamed) {
  tracking::TuioSource first(test_port() + 2, table());
  try {
    tracking::TuioSource second(test_port() + 2, table());
    FAIL() << "no error";
  } catch (const tracking::TrackingError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot listen on UDP port " + std::to_string(test_port() + 2)),
              std::string::npos)
        << e.what();
  }
}

// `quantum play --input tuio:PORT`: the match waits for the tracker, plays while its frames come,
// pauses with an announcement when it falls silent for a second, and resumes when it is back.
TEST(Tuio, AMatchPausesWhileItsTrackerIsSilent) {
  const int port = test_port() + 3;
  const std::string events = (std::filesystem::temp_directory_path() / ("quantum_tuio_play_" + std::to_string(port))).string();
  runtime::SessionOptions o;
  o.input = "tuio:" + std::to_string(port);
  o.seconds = 3;  // 1 s of frames, up to 1 s more before the silence counts, then the rest
  o.events = events;
  std::ostringstream out, errors;
  std::atomic<bool> done{false};
  tools::PlayResult result;
  std::thread match([&] {
    result = tools::play(o, out, errors);
    done = true;
  });
  Sender send;
  lo_address_free(send.to);
  send.to = lo_address_new("127.0.0.1", std::to_string(port).c_str());
  // The two mallets as cursors, 60 frames a second: 1 s, then 2 s of silence, then on until the end.
  auto play_for = [&](double seconds) {
    for (int k = 0; k < int(seconds * 60) && !done; ++k) {
      send.cursors({{{1, 0.1f, 0.5f}}, {{2, 0.9f, 0.5f}}});
      std::this_thread::sleep_for(std::chrono::microseconds(16667));
    }
  };
  play_for(1.0);
  std::this_thread::sleep_for(std::chrono::seconds(2));
  play_for(10.0);
  match.join();
  ASSERT_TRUE(done);
  const std::string transcript = out.str();
  EXPECT_NE(transcript.find("The players cannot be seen. The match is paused"), std::string::npos) << transcript;
  EXPECT_NE(transcript.find("Play on"), std::string::npos) << transcript;
  EXPECT_NEAR(result.stats.seconds, 3, 0.02);  // match time: the pause is not played
  std::ifstream log(events);
  int paused = 0, resumed = 0;
  for (std::string line; std::getline(log, line);) {
    if (line.find("\"type\":\"paused\"") != std::string::npos) {
      ++paused;
      // Before the first frame, or once the tracker has been silent for a second after 1 s of
      // frames: never while frames come.
      const double t = std::stod(line.substr(line.find("\"t\":") + 4));
      EXPECT_TRUE(t < 0.05 || t > 1.5) << line;
    }
    resumed += line.find("\"type\":\"resumed\"") != std::string::npos;
  }
  // Once before the first frame (the match waits for its players), once for the silence (more if
  // this machine stalled the sender for a second), and every pause ends.
  EXPECT_GE(paused, 2);
  EXPECT_EQ(resumed, paused);
  std::filesystem::remove(events);
}

// A tracker that sends only what is dropped: the match waits for a frame it can play, and says
// meanwhile what it drops, not only once a good frame comes.
TEST(Tuio, DropsAreToldWhileTheMatchWaitsForItsFirstFrame) {
  const int port = test_port() + 6;
  const std::string warnings = (std::filesystem::temp_directory_path() / ("quantum_tuio_waits_" + std::to_string(port))).string();
  runtime::SessionOptions o;
  o.input = "tuio:" + std::to_string(port);
  o.seconds = 1;
  std::ostringstream out;
  std::ofstream errors(warnings);
  errors << std::unitbuf;  // read by this thread while the match writes it
  std::atomic<bool> done{false};
  std::thread match([&] {
    tools::play(o, out, errors);
    done = true;
  });
  // 6 bytes, not a whole OSC packet, every 50 ms: the first ones may come before the match listens.
  std::string said;
  for (int wait = 0; wait < 100 && said.find(" dropped (not a number") == std::string::npos; ++wait) {
    send_raw(port, "/tuio/");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::ifstream in(warnings);
    said.assign(std::istreambuf_iterator<char>(in), {});
  }
  EXPECT_FALSE(done) << "the match waits for a frame";
  EXPECT_NE(said.find("tracking value"), std::string::npos) << said;
  EXPECT_NE(said.find(" dropped (not a number"), std::string::npos) << said;
  Sender send;
  lo_address_free(send.to);
  send.to = lo_address_new("127.0.0.1", std::to_string(port).c_str());
  for (int k = 0; k < 60 * 5 && !done; ++k) {
    send.cursors({{{1, 0.1f, 0.5f}}, {{2, 0.9f, 0.5f}}});
    std::this_thread::sleep_for(std::chrono::microseconds(16667));
  }
  match.join();
  EXPECT_TRUE(done);
  std::filesystem::remove(warnings);
}

// Input from the network is data, never a reason to stop: cursors at NaN, infinity or 1e38 are
// dropped, counted and told (at most every 5 s), and the match plays to its end.
TEST(Tuio, ValuesThatAreNotNumbersAreDroppedAndTheMatchGoesOn) {
  const int port = test_port() + 5;
  runtime::SessionOptions o;
  o.input = "tuio:" + std::to_string(port);
  o.seconds = 2;
  std::ostringstream out, errors;
  std::atomic<bool> done{false};
  tools::PlayResult result;
  std::thread match([&] {
    try {
      result = tools::play(o, out, errors);
    } catch (const std::exception& e) {
      errors << "stopped: " << e.what();
    }
    done = true;
  });
  Sender send;
  lo_address_free(send.to);
  send.to = lo_address_new("127.0.0.1", std::to_string(port).c_str());
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (int k = 0; k < 60 * 6 && !done; ++k) {
    // The second player starts far outside the field (1e38), then comes and goes between it and
    // the field every other frame.
    const float bad = k % 3 == 0 ? 1e38f : k % 3 == 1 ? nan : inf;
    send.cursors({{{1, 0.1f, 0.5f}}, {{2, k % 2 ? 0.9f : bad, 0.5f}}});
    std::this_thread::sleep_for(std::chrono::microseconds(16667));
  }
  match.join();
  ASSERT_TRUE(done);
  EXPECT_EQ(errors.str().find("stopped"), std::string::npos) << errors.str();
  EXPECT_NEAR(result.stats.seconds, 2, 0.02);
  EXPECT_NE(errors.str().find("tracking value dropped (not a number"), std::string::npos) << errors.str();
}

}  // namespace
}  // namespace quantum

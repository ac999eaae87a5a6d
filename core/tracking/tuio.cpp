#include <arpa/inet.h>
#include <lo/lo.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <map>

#include "tracking/tracking.h"

namespace quantum::tracking {

using Clock = std::chrono::steady_clock;

namespace {

// liblo's arguments point into the packet at 4-byte boundaries, while its lo_arg union asks for 8
// (it holds doubles): read them as bytes, not through a misaligned union.
int32_t int_arg(const lo_arg* a) {
  int32_t v;
  std::memcpy(&v, a, sizeof v);
  return v;
}
float float_arg(const lo_arg* a) {
  float v;
  std::memcpy(&v, a, sizeof v);
  return v;
}
const char* string_arg(const lo_arg* a) { return reinterpret_cast<const char*>(a); }

// Bundles inside bundles deeper than this are not a tracker's: refused before liblo recurses.
constexpr int kDeepestBundle = 8;

// Whether liblo can take this packet apart without reading past its end. liblo 0.31 walks a
// bundle's elements without checking their sizes against what is left, and compares 8 bytes of
// each with "#bundle" before it looks at its size: a bundle ending in an element of 0 to 7 bytes,
// or one claiming more than is left, is read past the packet (the TUIO fuzzer's crash). A message
// (an OSC address, then its types and arguments) liblo checks itself.
bool whole_packet(const uint8_t* p, size_t n, int depth = 0) {
  if (n < 8 || n % 4 != 0) return false;  // the shortest message, "/\0\0\0,\0\0\0", is 8 bytes
  if (std::memcmp(p, "#bundle", 8) != 0) return p[0] == '/';
  if (n < 16 || depth >= kDeepestBundle) return false;  // "#bundle", then its 8-byte time tag
  for (size_t at = 16; at < n;) {
    if (n - at < 4) return false;
    uint32_t size;
    std::memcpy(&size, p + at, sizeof size);
    size = ntohl(size);
    at += 4;
    if (size > n - at || !whole_packet(p + at, size, depth + 1)) return false;
    at += size;
  }
  return true;
}

}  // namespace

struct TuioSource::State {
  TrackedField field;
  lo_server server = nullptr;
  Clock::time_point opened = Clock::now(), last = opened;
  std::optional<Clock::time_point> first;
  struct Touch {
    int player = -1;
    bool placed = false;  // a set message has given its position
    double x = 0, y = 0, vx = 0, vy = 0;
    uint64_t heard = 0;   // when a message last named it (heard_ counts them): the least is the oldest
  };
  std::map<int32_t, Touch> objects, cursors;  // by session id, most_tracked(field's players) of each
  uint64_t heard = 0;
  int frames = 0;
  bool complete = false;  // an fseq closed a frame since the last next()
  size_t dropped = 0;     // packets that were not OSC or that liblo refused, and touches forgotten
  std::array<uint8_t, 65536> packet{};  // one UDP datagram at most

  // Reads one datagram, waiting up to `timeout_ms`, and hands it to liblo if it is whole. False
  // when none came.
  bool receive(int timeout_ms) {
    pollfd ready{lo_server_get_socket_fd(server), POLLIN, 0};
    if (poll(&ready, 1, timeout_ms) <= 0) return false;
    const ssize_t n = recv(ready.fd, packet.data(), packet.size(), MSG_DONTWAIT);
    if (n < 0) return false;
    if (!whole_packet(packet.data(), size_t(n)) || lo_server_dispatch_data(server, packet.data(), size_t(n)) < 0)
      ++dropped;
    return true;
  }

  double seconds(Clock::time_point t) const { return std::chrono::duration<double>(t - *first).count(); }

  // Field metres from TUIO's unit square.
  void place(Touch& t, float x, float y, float vx, float vy) const {
    t.x = (x - 0.5) * field.length, t.y = (0.5 - y) * field.width;
    t.vx = vx * field.length, t.vy = -vy * field.width;
    t.placed = true;
  }

  // Players held by objects, then free ones for cursors in the order they came.
  void assign_cursors() {
    std::vector<bool> held(field.players.size(), false);
    for (const auto& [id, o] : objects)
      if (o.player >= 0) held[size_t(o.player)] = true;
    for (auto& [id, c] : cursors) {
      if (c.player >= 0 && !held[size_t(c.player)]) {
        held[size_t(c.player)] = true;
        continue;
      }
      c.player = -1;
      for (size_t k = 0; k < held.size() && c.player < 0; ++k)
        if (!held[k]) c.player = int(k), held[k] = true;
    }
  }

  // The touch of session `id`, made as `was` when new; when that would take `touches` past its
  // most, the one heard of longest ago is forgotten first, and counted.
  Touch& touch(std::map<int32_t, Touch>& touches, int32_t id, const Touch& was) {
    const auto [it, made] = touches.try_emplace(id, was);
    it->second.heard = ++heard;
    if (made) forget_oldest(touches);
    return it->second;
  }
  void forget_oldest(std::map<int32_t, Touch>& touches) {
    for (const size_t most = most_tracked(field.players.size()); touches.size() > most; ++dropped)
      touches.erase(std::min_element(touches.begin(), touches.end(),
                                     [](const auto& a, const auto& b) { return a.second.heard < b.second.heard; }));
  }

  void message(bool object, const char* types, lo_arg** argv, int argc) {
    last = Clock::now();
    if (!first) first = last;
    if (argc < 1 || types[0] != 's') return;
    const std::string command = string_arg(argv[0]);
    std::map<int32_t, Touch>& touches = object ? objects : cursors;
    if (command == "alive") {
      std::map<int32_t, Touch> alive;
      for (int k = 1; k < argc; ++k)
        if (types[k] == 'i') {
          const int32_t id = int_arg(argv[k]);
          const auto known = touches.find(id);
          touch(alive, id, known != touches.end() ? known->second : Touch{});
        }
      touches = std::move(alive);
    } else if (command == "set") {
      // 2Dcur: s x y X Y m; 2Dobj: s i x y a X Y A m r.
      const std::string want = object ? "siiffffffff" : "sifffff";
      if (argc < int(want.size()) || std::string(types).compare(0, want.size(), want) != 0)
        return;  // not TUIO 1.1's shape: ignored, like any other unknown message
      Touch& t = touch(touches, int_arg(argv[1]), Touch{});
      if (object) {
        const int32_t cls = int_arg(argv[2]);
        t.player = cls >= 0 && size_t(cls) < field.players.size() ? cls : -1;
        place(t, float_arg(argv[3]), float_arg(argv[4]), float_arg(argv[6]), float_arg(argv[7]));
      } else {
        place(t, float_arg(argv[2]), float_arg(argv[3]), float_arg(argv[4]), float_arg(argv[5]));
      }
    } else if (command == "fseq") {
      complete = true;
    }
  }
};

namespace {

int on_message(const char* path, const char* types, lo_arg** argv, int argc, lo_message, void* user) {
  static_cast<TuioSource::State*>(user)->message(std::string(path) == "/tuio/2Dobj", types, argv, argc);
  return 0;
}

void on_error(int number, const char* message, const char* where) {
  // Reported by the constructor's check; a bad packet later is dropped.
  (void)number, (void)message, (void)where;
}

}  // namespace

TuioSource::TuioSource(int port, TrackedField field) : state_(std::make_unique<State>()) {
  state_->field = std::move(field);
  if (port <= 0 || port > 65535) throw TrackingError("tuio: port " + std::to_string(port) + " is not a UDP port");
  state_->server = lo_server_new(std::to_string(port).c_str(), on_error);
  if (!state_->server) throw TrackingError("tuio: cannot listen on UDP port " + std::to_string(port));
  // A bundle is played when it comes, whatever its time tag says: a far future one would
  // otherwise wait in liblo's queue, and a sender could fill it.
  lo_server_enable_queue(state_->server, 0, 1);
  lo_server_add_method(state_->server, "/tuio/2Dcur", nullptr, on_message, state_.get());
  lo_server_add_method(state_->server, "/tuio/2Dobj", nullptr, on_message, state_.get());
}

TuioSource::~TuioSource() {
  if (state_->server) lo_server_free(state_->server);
}

size_t TuioSource::dropped() const { return state_->dropped; }

double TuioSource::silent() const { return std::chrono::duration<double>(Clock::now() - state_->last).count(); }

std::optional<TrackedFrame> TuioSource::next(double timeout) {
  State& s = *state_;
  const auto until = Clock::now() + std::chrono::duration<double>(timeout);
  // Whatever is waiting is read even with no time to wait; then up to the timeout for more.
  while (!s.complete) {
    const int left = std::max(0, int(std::chrono::duration<double, std::milli>(until - Clock::now()).count()));
    if (!s.receive(left) && left == 0) return std::nullopt;
  }
  s.complete = false;
  s.assign_cursors();
  TrackedFrame f;
  f.frame = s.frames++;
  f.t = s.seconds(s.last);
  std::vector<bool> listed(s.field.players.size(), false);
  for (const auto* touches : {&s.objects, &s.cursors})
    for (const auto& [id, t] : *touches) {
      if (t.player < 0 || !t.placed || listed[size_t(t.player)]) continue;
      listed[size_t(t.player)] = true;
      const TrackedField::Player& p = s.field.players[size_t(t.player)];
      f.players.push_back({p.id, p.team, t.x, t.y, t.vx, t.vy});
    }
  return f;
}

}  // namespace quantum::tracking

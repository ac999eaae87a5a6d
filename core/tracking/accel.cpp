#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "tracking/lines.h"
#include "tracking/tracking.h"

namespace quantum::tracking {
namespace {

constexpr double kSteepest = 1.3;  // rad, 75 degrees: a throw straighter up is the sensor's noise
constexpr double kGravity = 9.81;

enum class Parsed { Sample, Malformed, NotFinite };

// "t,player,ax,ay,az". A line of that shape with a number that is NaN or infinite is a sensor's
// glitch (dropped and counted), not a malformed file.
Parsed parse_sample(const std::string& line, AccelSample& s) {
  std::stringstream in(line);
  std::string field[5];
  for (int k = 0; k < 5; ++k)
    if (!std::getline(in, field[k], ',')) return Parsed::Malformed;
  bool finite = true;
  double* numbers[] = {&s.t, &s.ax, &s.ay, &s.az};
  const int columns[] = {0, 2, 3, 4};
  for (int k = 0; k < 4; ++k) {
    const std::string& text = field[columns[k]];
    char* end = nullptr;
    *numbers[k] = std::strtod(text.c_str(), &end);
    while (end && (*end == ' ' || *end == '\r' || *end == '\n')) ++end;
    if (end == text.c_str() || !end || *end != 0) return Parsed::Malformed;
    finite = finite && std::isfinite(*numbers[k]);
  }
  s.player = field[1];
  if (s.player.empty()) return Parsed::Malformed;
  return finite ? Parsed::Sample : Parsed::NotFinite;
}

}  // namespace

AccelSource::AccelSource(const std::string& spec) {
  if (spec.rfind("udp:", 0) == 0) {
    const int port = std::atoi(spec.c_str() + 4);
    if (port <= 0 || port > 65535) throw TrackingError("--accel " + spec + ": expected udp:PORT");
    socket_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(uint16_t(port));
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    if (socket_ < 0 || ::bind(socket_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      if (socket_ >= 0) ::close(socket_);
      throw TrackingError("--accel " + spec + ": cannot listen on UDP port " + std::to_string(port));
    }
    return;
  }
  // Opened as it is (a pipe from another program is fine: the file is read whole before the
  // match, up to kMostLines or kMostBytes); a line longer than kLongestLine is dropped and
  // counted, never held. A device is no file of samples (/dev/zero would be read forever).
  const int fd = ::open(spec.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw TrackingError(spec + ": cannot open the accelerometer file");
  BoundedLines lines(fd);
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !(S_ISREG(st.st_mode) || S_ISFIFO(st.st_mode)))
    throw TrackingError("--accel " + spec + ": not a file of samples or a pipe");
  int n = 0;
  for (std::string line;;) {
    const BoundedLines::Line got = lines.next(line);
    if (got == BoundedLines::Line::End) break;
    ++n;
    if (got == BoundedLines::Line::TooLong) {
      ++dropped_;
      continue;
    }
    const bool blank = line.find_first_not_of(" \t\r\v\f") == std::string::npos;
    if (blank || line[0] == '#' || (n == 1 && line.rfind("t,", 0) == 0)) continue;  // header, comments
    AccelSample s;
    const Parsed parsed = parse_sample(line, s);
    if (parsed == Parsed::Malformed) throw TrackingError(spec + ":" + std::to_string(n) + ": expected t,player,ax,ay,az");
    if (parsed == Parsed::NotFinite) ++dropped_;
    else samples_.push_back(s);
  }
  dropped_ += lines.cut();  // the rest of a file past what is read: one drop, told with the others
  std::stable_sort(samples_.begin(), samples_.end(), [](const AccelSample& a, const AccelSample& b) { return a.t < b.t; });
}

AccelSource::~AccelSource() {
  if (socket_ >= 0) ::close(socket_);
}

std::vector<AccelSample> AccelSource::until(double t) {
  std::vector<AccelSample> out;
  if (socket_ >= 0) {
    char buf[512];
    // An empty datagram reads as 0 bytes: a datagram all the same, dropped, and more may follow.
    for (ssize_t n; (n = ::recv(socket_, buf, sizeof buf - 1, 0)) >= 0;) {
      AccelSample s;
      if (parse_sample(std::string(buf, size_t(n)), s) == Parsed::Sample) s.t = t, out.push_back(s);
      else ++dropped_;
    }
    return out;
  }
  while (cursor_ < samples_.size() && samples_[cursor_].t <= t) out.push_back(samples_[cursor_++]);
  return out;
}

void ThrowDetector::add(const std::vector<AccelSample>& samples, TrackedFrame& frame) {
  for (const AccelSample& s : samples) {
    if (std::sqrt(s.ax * s.ax + s.ay * s.ay + s.az * s.az) < threshold_) continue;
    auto last = std::find_if(last_.begin(), last_.end(), [&](const auto& l) { return l.first == s.player; });
    if (last != last_.end() && s.t - last->second < refractory_) continue;
    if (last == last_.end() && last_.size() == most_) {  // room made: the one who threw longest ago is forgotten
      last = std::min_element(last_.begin(), last_.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
      last->first = s.player;
      ++dropped_;
    }
    if (last == last_.end()) last_.push_back({s.player, s.t});
    else last->second = s.t;
    const auto p = std::find_if(frame.players.begin(), frame.players.end(),
                                [&](const TrackedPlayer& q) { return q.id == s.player; });
    double dx = 0, dy = 0;
    if (p != frame.players.end()) {
      const double speed = std::hypot(p->vx, p->vy);
      if (speed > 0.3) dx = p->vx / speed, dy = p->vy / speed;
      else dx = p->team == "blue" ? 1 : -1;  // standing: toward the other end (blue attacks +x)
    }
    // The whip's share along the sensor's z axis (worn z up; gravity, which the sensor feels at
    // rest, taken off) lifts the throw: a shot goes up, a chest pass flat. Never steeper than
    // kSteepest, never down.
    const double up = std::clamp(std::atan2(s.az - kGravity, std::hypot(s.ax, s.ay)), 0.0, kSteepest);
    frame.actions.push_back({"throw", s.player, dx * std::cos(up), dy * std::cos(up), std::sin(up)});
  }
}

}  // namespace quantum::tracking

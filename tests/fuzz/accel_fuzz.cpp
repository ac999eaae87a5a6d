// Accelerometer input, from a file and over UDP: a file's samples load or the file is refused
// with a TrackingError naming its line; a datagram is a sample or dropped and counted. Every
// sample that comes out is finite, and the throws found in them have finite directions.
#include <cmath>

#include "fuzz_support.h"
#include "tracking/tracking.h"

namespace tracking = quantum::tracking;

namespace {

void check(const std::vector<tracking::AccelSample>& samples) {
  tracking::TrackedFrame frame;
  frame.players.push_back({"blue 1", "blue", 0, 0, 1, 0});
  tracking::ThrowDetector throws;
  throws.add(samples, frame);
  for (const tracking::AccelSample& s : samples)
    if (!std::isfinite(s.t) || !std::isfinite(s.ax) || !std::isfinite(s.ay) || !std::isfinite(s.az)) __builtin_trap();
  for (const tracking::TrackedAction& a : frame.actions)
    if (!std::isfinite(a.dx) || !std::isfinite(a.dy) || !std::isfinite(a.dz)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto file = quantum::fuzz::scratch() / "accel.csv";
  quantum::fuzz::write_file(file, data, size);
  try {
    tracking::AccelSource source(file.string());
    check(source.until(INFINITY));
  } catch (const tracking::TrackingError&) {
  }

  static const int port = quantum::fuzz::free_port();
  static tracking::AccelSource live("udp:" + std::to_string(port));
  const size_t before = live.dropped();
  quantum::fuzz::send_datagram(port, data, size);
  const auto samples = live.until(1);
  check(samples);
  if (samples.size() + live.dropped() - before != 1) __builtin_trap();  // one datagram: a sample, or counted
  return 0;
}

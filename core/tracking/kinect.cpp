#include "tracking/kinect.h"

#include <cmath>

namespace quantum::tracking {

constexpr double kA = -0.0030711016, kB = 3.3309495161;

float raw_to_metres(uint16_t raw) {
  const double d = raw * kA + kB;
  return raw < kNoDepth && d > 0.1 ? float(1 / d) : 0.0f;  // beyond 10 m the fit runs off to infinity
}

uint16_t metres_to_raw(float z) {
  if (!(z >= 0.4f && z <= 8.0f)) return kNoDepth;
  return uint16_t(std::lround((1 / double(z) - kB) / kA));
}

float depth_step(float z) { return float(-kA) * z * z; }

}  // namespace quantum::tracking

// The Kinect v1 depth camera as the tracking pipelines see it: a pinhole, and the relation of its
// raw 11-bit disparity to depth. Colour and depth are taken as registered (one pinhole).
#pragma once

#include <cstdint>

namespace quantum::tracking {

constexpr uint16_t kNoDepth = 2047;  // the Kinect's "no reading"

struct DepthCamera {
  int width = 640, height = 480;
  float fx = 589.4f, fy = 589.4f;  // 57 degrees across 640 pixels (and 44 across 480)
  float cx = 319.5f, cy = 239.5f;
};

// Depth in metres along the optical axis, z = 1 / (raw * -0.0030711016 + 3.3309495161), a
// common fit for the Kinect v1. 0 for kNoDepth and beyond 10 m (raw >= 1052), where the fit
// heads for its pole at raw 1084.6.
float raw_to_metres(uint16_t raw);

// The raw value the Kinect reports for depth z (the nearest one): what synthetic recordings
// quantize to. kNoDepth outside 0.4-8 m.
uint16_t metres_to_raw(float z);

// The depth one raw unit spans at depth z: 0.0030711 z^2 m (5 mm at 1.3 m, 18 mm at 2.4 m).
float depth_step(float z);

}  // namespace quantum::tracking

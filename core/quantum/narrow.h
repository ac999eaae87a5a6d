// Numbers from scripts, files and the network arrive as doubles and the core keeps floats. C++
// leaves converting a finite double beyond float's range undefined (a script's 1e300 is one), so
// every such value narrows here, and the callers refuse the infinity as any non-finite value.
#pragma once

#include <limits>

namespace quantum {

// The nearest float; beyond float's range, the infinity of that sign; NaN stays NaN.
inline float to_float(double v) {
  constexpr double kMost = std::numeric_limits<float>::max();
  if (v > kMost) return std::numeric_limits<float>::infinity();
  if (v < -kMost) return -std::numeric_limits<float>::infinity();
  return float(v);
}

}  // namespace quantum

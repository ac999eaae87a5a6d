// World's private working state that needs the internal contact types.
#pragma once

#include <vector>

#include "quantum/contact.h"
#include "step_tracer.h"

namespace quantum {

struct Tally {
  double tweaked = 0, newtonian = 0, cx = 0, cy = 0;
  uint32_t count = 0;
};

struct WorldInternals {
  explicit WorldInternals(const Field& field) : geometry(field), tracer(geometry) {}
  detail::Geometry geometry;
  detail::StepTracer tracer;              // carries purgatory particles forward at a realized hit
  std::vector<detail::BodyPath> resting;  // bodies held at their current positions
  std::vector<Tally> tally;               // per decision target, reused every step
};

}  // namespace quantum

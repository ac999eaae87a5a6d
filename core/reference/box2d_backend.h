// The reference backend: the same scene with one Box2D 2.4 body per particle, for the
// differential test and as the benchmark baseline. Keep it at or below ~10k particles: Box2D's
// broadphase finds every particle-particle pair before the filter drops it.
#pragma once

#include <memory>

#include "quantum/backend.h"

namespace quantum {

std::unique_ptr<Backend> make_box2d_backend(const Field& field);

}  // namespace quantum

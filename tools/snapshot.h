// The debug view of the paper's Figure 2: field, particles and their predicted trajectories
// coloured by fate. Players never see this; developers and designers do.
#pragma once

#include <string>

#include "quantum/world.h"

namespace quantum::tools {

// Predicts the current cloud and writes the picture to `png`. Throws std::runtime_error when
// the file cannot be written.
void write_snapshot(const World& world, const std::string& png, float horizon = 3.0f);

}  // namespace quantum::tools

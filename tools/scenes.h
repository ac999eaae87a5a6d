// Scenes shared by `quantum simulate`, the benchmarks and the tests: scripted mallets, blind to
// the ball, and a cloud spread over the whole field.
#pragma once

#include <vector>

#include "quantum/field.h"
#include "quantum/world.h"

namespace quantum::tools {

// Each body sweeps across in front of its home (its start position) and now and then lunges
// toward the middle of the field, like a defending player who strikes at a guess (a player who
// catches: to the middle, where balls drop). Positions and velocities are exact derivatives of
// one smooth curve per body. Every body stays within the field's bounds and under half its
// max_body_speed, on any field (a mallet on a table, a player in a hall).
std::vector<BodyInput> scripted_mallets(const Field& field, double t);

// n particles of equal weight, uniform over the field's safe interior, moving in random
// directions at 0.5 to 3 m/s: a ball nobody has heard of for a while.
Cloud spread_cloud(const Field& field, uint32_t n, uint64_t seed);

}  // namespace quantum::tools

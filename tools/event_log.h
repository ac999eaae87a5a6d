// Events as the outside world sees them: JSON lines for tools, one sentence for people.
#pragma once

#include <string>

#include "quantum/field.h"
#include "quantum/world.h"

namespace quantum::tools {

// One JSON object, no newline: {"t", "type", "actor", "team", "p", "p_newtonian", "particles", "x", "y"},
// plus "vx", "vy" (the shot's mean velocity) for a hit.
// actor and team name the spot (drop), the body (hit) or the goal (goal, own_goal: the team
// defending it); out has actor "out" and no team.
std::string event_json(const Event& e, const Field& field);

// "  3.417  hit    Red's mallet (p = 0.231)"
std::string event_line(const Event& e, const Field& field);

}  // namespace quantum::tools

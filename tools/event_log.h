// Events as the outside world sees them: JSON lines for tools, one sentence for people.
#pragma once

#include <fstream>
#include <ostream>
#include <string>

#include "quantum/field.h"
#include "quantum/world.h"

namespace quantum::tools {

// One JSON object, no newline: {"t", "type", "actor", "team", "p", "p_newtonian", "particles", "x", "y"},
// plus "vx", "vy" (the shot's mean velocity) for a hit.
// actor and team name the spot (drop), the body (hit) or the goal (goal, own_goal: the team
// defending it); out has actor "out" and no team.
std::string event_json(const Event& e, const Field& field);

// Micrometres and microseconds: plenty for the field, and logs stay diff-able.
double rounded(double v);

// Where JSON lines go for an --events option: nowhere (""), stdout ("-"), or `path` opened
// into `file`. Throws naming the path when it cannot be written.
std::ostream* open_event_log(const std::string& path, std::ofstream& file);

// "  3.417  hit    Red's mallet (p = 0.231)"
std::string event_line(const Event& e, const Field& field);

}  // namespace quantum::tools

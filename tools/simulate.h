// `quantum simulate`: a field, a cloud and scripted bodies (tools/scenes.h), with decisions,
// fate factors and respawns, written out as JSON-lines events and a short summary. Players who
// catch hold the ball a moment and throw it on; on a field with a hoop, a shooting practice
// instead: one player shoots at it again and again.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "quantum/fate.h"
#include "quantum/world.h"

namespace quantum::tools {

struct SimulateOptions {
  std::string field;           // field file or sport folder
  double seconds = 20;
  uint32_t particles = 1000;
  uint64_t seed = 1;
  std::string backend = "fast";  // fast | box2d
  std::string events;          // JSON-lines file, "-" for stdout, empty for none
  std::string snapshot;        // PNG, empty for none
  std::string decisions;       // every draw as a JSON line (docs/decisions.md), "-" for stdout, empty for none
  double fps = 60;
  uint32_t purgatory = 3;
  KindFactors factors;
  std::string shooter;         // fields with a hoop: who shoots ("" for the first player who catches)
  std::vector<std::string> params;  // NAME=VALUE for the field file (param(NAME, default))
};

// Runs the simulation; the summary goes to `summary`. Throws on bad options or a bad field.
void simulate(const SimulateOptions& options, std::ostream& summary);

// One core event as a JSON line: {"t", "type", "actor", "team", "p", "p_newtonian", "particles",
// "x", "y"}, plus "vx", "vy" (the ball's mean velocity after it) for a hit or a bounce. actor
// and team name the spot (drop), the body (hit), the wall (bounce) or the goal (goal, own_goal:
// the team defending it); out has actor "out" and no team.
void write_event(std::ostream& out, const Event& e, const Field& field);

}  // namespace quantum::tools

#include "event_log.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>

namespace quantum::tools {
namespace {

struct Actor {
  std::string name, team;
};

Actor actor_of(const Event& e, const Field& f) {
  switch (e.type) {
    case EventType::Drop: return {f.spots[e.actor].name, f.spots[e.actor].team};
    case EventType::Hit: return {f.bodies[e.actor].name, f.bodies[e.actor].team};
    case EventType::Bounce: return {f.wall_names[e.actor], ""};
    case EventType::Goal:
    case EventType::OwnGoal: return {f.goals[e.actor].name, f.goals[e.actor].team};
    case EventType::Out: return {"out", ""};
  }
  return {};
}

}  // namespace

double rounded(double v) { return std::round(v * 1e6) / 1e6; }

std::ostream* open_event_log(const std::string& path, std::ofstream& file) {
  if (path.empty()) return nullptr;
  if (path == "-") return &std::cout;
  file.open(path);
  if (!file) throw std::runtime_error("cannot write events to " + path);
  return &file;
}

std::string event_json(const Event& e, const Field& f) {
  const Actor a = actor_of(e, f);
  nlohmann::ordered_json j;
  j["t"] = rounded(e.t);
  j["type"] = to_string(e.type);
  j["actor"] = a.name;
  if (!a.team.empty()) j["team"] = a.team;
  j["p"] = rounded(e.p);
  j["p_newtonian"] = rounded(e.p_newtonian);
  j["particles"] = e.particles;
  j["x"] = rounded(e.at.x);
  j["y"] = rounded(e.at.y);
  if (e.type == EventType::Hit || e.type == EventType::Bounce) j["vx"] = rounded(e.velocity.x), j["vy"] = rounded(e.velocity.y);
  return j.dump();
}

std::string event_line(const Event& e, const Field& f) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%8.3f  %-8s %s (p = %.3f)", e.t, to_string(e.type), actor_of(e, f).name.c_str(), e.p);
  return buf;
}

}  // namespace quantum::tools

#include "track.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <iostream>
#include <thread>

#include "event_log.h"
#include "field_loader.h"
#include "play.h"
#include "tracked_input.h"

namespace quantum::tools {
namespace {

std::string frame_json(const tracking::TrackedFrame& f) {
  nlohmann::ordered_json j;
  j["frame"] = f.frame;
  j["t"] = rounded(f.t);
  j["players"] = nlohmann::json::array();
  for (const tracking::TrackedPlayer& p : f.players)
    j["players"].push_back({{"id", p.id}, {"team", p.team}, {"x", rounded(p.x)}, {"y", rounded(p.y)},
                            {"vx", rounded(p.vx)}, {"vy", rounded(p.vy)}});
  for (const tracking::TrackedAction& a : f.actions)
    j["actions"].push_back({{"type", a.type}, {"player", a.player}, {"dx", rounded(a.dx)}, {"dy", rounded(a.dy)}});
  return j.dump();
}

}  // namespace

void track(const TrackOptions& o, std::ostream& out) {
  const Field field = lua::load_field(o.field);
  std::optional<Vec2> size;
  if (!o.field_size.empty()) {
    const std::vector<double> lw = parse_list(o.field_size, "--field-size");
    if (lw.size() != 2 || !(lw[0] > 0 && lw[1] > 0)) throw std::invalid_argument("--field-size needs L,W in metres, both > 0");
    size = Vec2{float(lw[0]), float(lw[1])};
  }
  const tracking::TrackedField tracked = tracking::tracked_field(field, size);
  TrackingInput input(o.source, tracked, {o.accel, o.fov});
  bool lost = false;
  tracking::TrackedFrame frame;
  for (int n = 0; o.frames == 0 || n < o.frames;) {
    const TrackingInput::Status status = input.next(frame, 0.1);
    if (status == TrackingInput::Status::Ended) break;
    if (status == TrackingInput::Status::Lost) {
      if (!lost) std::cerr << "quantum: " << o.source << " is gone; waiting for it to come back\n";
      lost = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      continue;
    }
    if (status == TrackingInput::Status::Waiting) continue;
    lost = false;
    out << frame_json(frame) << '\n' << std::flush;  // other tools read it as it comes
    ++n;
  }
}

}  // namespace quantum::tools

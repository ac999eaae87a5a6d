#include "track.h"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <thread>

#include "json_lines.h"
#include "field_loader.h"
#include "params.h"
#include "players.h"
#include "play.h"
#include "tracking/input.h"

namespace quantum::tools {
namespace {

void write_frame(std::ostream& out, const tracking::TrackedFrame& f) {
  runtime::JsonLine line(out);
  line.field("frame", uint64_t(f.frame)).field("t", f.t).array("players");
  for (const tracking::TrackedPlayer& p : f.players)
    line.object().field("id", p.id).field("team", p.team).field("x", p.x).field("y", p.y).field("vx", p.vx)
        .field("vy", p.vy).close();
  line.close();
  if (!f.actions.empty()) {
    line.array("actions");
    for (const tracking::TrackedAction& a : f.actions)
      line.object().field("type", a.type).field("player", a.player).field("dx", a.dx).field("dy", a.dy).close();
    line.close();
  }
  line.end();
}

}  // namespace

void track(const TrackOptions& o, std::ostream& out) {
  lua::Params params(o.params);
  const Field field = lua::load_field(o.field, &params);
  params.check_read(o.field);
  const tracking::TrackedField tracked = tracking::tracked_field(field, parse_field_size(o.field_size));
  tracking::TrackingInput input(o.source, tracked, {o.accel, o.fov});
  // A hat camera's markers cannot measure the field (a Kinect's can): the size is the field's,
  // and the default's is a table's, never a hall's.
  const bool hats = o.source.rfind("video:", 0) == 0 || o.source.rfind("camera:", 0) == 0;
  if (hats && !o.field_given && o.field_size.empty()) {
    char size[64];
    std::snprintf(size, sizeof size, "%.2f x %.2f m", tracked.length, tracked.width);
    std::cerr << "quantum: warning: " << o.source << ": no --field: its markers are taken for the corners of " << o.field
              << "'s " << size << " field, the default; give the field the camera sees (--field SPORT or FILE, or "
              << "--field-size L,W)\n";
  }
  bool lost = false;
  tracking::SetupCheck setup(o.source, tracking::tracked_field(field), o.setup);
  tracking::TrackedFrame frame;
  // Told on stderr as a match tells them: stdout is the frames' JSON.
  runtime::DroppedValues dropped(o.source, "tracking value", runtime::DroppedValues::kTrackingWhy, &std::cerr);
  for (int n = 0; o.frames == 0 || n < o.frames;) {
    const tracking::TrackingInput::Status status = input.next(frame, 0.1);
    if (status == tracking::TrackingInput::Status::Ended) break;
    if (status == tracking::TrackingInput::Status::Lost) {
      if (!lost) std::cerr << "quantum: " << o.source << " is gone; waiting for it to come back\n";
      lost = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      continue;
    }
    if (status == tracking::TrackingInput::Status::Waiting) continue;
    lost = false;
    for (const std::string& line : setup.check(frame, input, tracked)) std::cerr << "quantum: " << line << '\n';
    write_frame(out, frame);
    out << std::flush;  // other tools read it as it comes
    dropped.tell(frame.t, input.dropped());
    ++n;
  }
  dropped.tell(frame.t, input.dropped(), true);
}

}  // namespace quantum::tools

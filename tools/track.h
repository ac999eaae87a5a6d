// `quantum track SOURCE`: the players a tracking source sees, one JSON object per frame.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "tracking/options.h"

namespace quantum::tools {

struct TrackOptions {
  std::string source;                    // fakenect:DIR, kinect, video:FILE, camera:N or tuio:PORT
  std::string accel;                     // with video, camera or tuio: accelerometers, FILE (CSV) or udp:PORT
  float fov = 82;                        // with video or camera: its horizontal field of view, degrees
  std::string field = "airhockey";       // a field file or a sport (folder or name): who plays from which end
  bool field_given = false;              // `field` was chosen (--field), not the default
  std::string field_size;                // "L,W": the field between the markers, instead of what a Kinect measures
  tracking::SetupOptions setup;          // a table that is not the sport's field: an error (strict) or fitted
  int frames = 0;                        // stop after this many frames (0: at the end of the source)
  std::vector<std::string> params;       // NAME=VALUE for the field's script (--param length=40)
};

// Writes {"frame": n, "t": s, "players": [{"id", "team", "x", "y", "vx", "vy"}]} per frame to
// `out`, with "actions": [{"type": "throw", "player", "dx", "dy"}] when something was thrown.
// Warnings go to stderr: a hat camera without a field chosen, and a field its markers do not fit
// (tracking::hat_view_mismatch). Throws for bad input (the message names the file and frame);
// frames before it are out.
void track(const TrackOptions& options, std::ostream& out);

}  // namespace quantum::tools

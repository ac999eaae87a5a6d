// What a tracking source is opened with (input.h), in a header of plain values: the session's
// and the front ends' options name it in a quantum built without tracking too.
#pragma once

#include <string>

namespace quantum::tracking {

struct SourceOptions {
  std::string accel;  // with video, camera or tuio: FILE (CSV) or udp:PORT
  float fov = 82;     // with video or camera: horizontal field of view, degrees
};

// How a table that is not the sport's field is taken (SetupCheck, input.h): with `strict` it stops
// the source; with `fit` its metres are stretched over the sport's field.
struct SetupOptions {
  bool strict = false, fit = false;
};

}  // namespace quantum::tracking

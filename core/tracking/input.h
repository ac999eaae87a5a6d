// Every tracking source behind one interface, for `quantum track` and `quantum play --input`:
// fakenect:DIR and video:FILE are recordings, kinect, camera:N and tuio:PORT are live.
#pragma once

#include <memory>
#include <string>

#include "tracking/tracking.h"

namespace quantum::tracking {

struct SourceOptions {
  std::string accel;  // with video, camera or tuio: FILE (CSV) or udp:PORT
  float fov = 82;     // with video or camera: horizontal field of view, degrees
};

class TrackingInput {
 public:
  enum class Status {
    Frame,        // `frame` holds the next scene
    Calibrating,  // a frame went into calibration (the depth background): no scene yet
    Waiting,      // a live source has nothing new yet
    Lost,         // a live source stopped delivering (unplugged, silent for a second): try again later
    Ended,        // a recording is over
  };

  // Throws std::invalid_argument for an unknown source, TrackingError when it cannot be opened.
  TrackingInput(const std::string& spec, const TrackedField& field, const SourceOptions& options);
  ~TrackingInput();

  // The next frame. Recordings return every frame in order; live sources wait up to `timeout`
  // seconds. Throws RecordingError or TrackingError for bad input.
  Status next(TrackedFrame& frame, double timeout);

  bool live() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace quantum::tracking

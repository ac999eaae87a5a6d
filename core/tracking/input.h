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

// No silent nothing: a source that has seen no player for its first seconds of frames says so
// once, with what to check (a wrong --field-size maps every player off the field).
class NobodySeen {
 public:
  explicit NobodySeen(double after = 3) : after_(after) {}
  // The warning, once: at the first frame `after` seconds past the first one while no frame has
  // had a player; "" otherwise.
  std::string check(const TrackedFrame& frame, const std::string& source, const TrackedField& field);

 private:
  double after_;
  double first_ = -1;
  bool seen_ = false, told_ = false;
};

}  // namespace quantum::tracking

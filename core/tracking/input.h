// Every tracking source behind one interface, for `quantum track` and `quantum play --input`:
// fakenect:DIR and video:FILE are recordings, kinect, camera:N and tuio:PORT are live.
#pragma once

#include <memory>
#include <string>

#include "tracking/options.h"
#include "tracking/tracking.h"

namespace quantum::tracking {

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

  // A Kinect's self-calibration, once its background is learnt; null before and for other sources.
  const Calibration* calibration() const;
  // What a hat camera's markers said of the field, after its first frame; null before and for
  // other sources.
  const HatView* hat_view() const;
  // What the source has seen since the last call (for a Kinect: markers, background, blobs and
  // arms), to tell an operator whose players are not found; "" when it has nothing to add.
  std::string sightings();
  // Frames of a recording dropped so far because they could not be placed in time (fakenect.h),
  // accelerometer samples that were not numbers or not samples, and TUIO packets that were not
  // whole OSC packets.
  size_t dropped() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The calibration line: "calibration: 4 of 4 markers, camera 2.21 m above the table, tilted 2.0
// degrees, field 2.00 x 1.00 m measured, depth noise 0.4 cm, 3 % of the table without a reading".
std::string describe(const Calibration& c);

// "" when the field the markers are mapped to (measured, or --field-size) is the sport's `field`
// within 3 cm each way; else what differs and what to do about it.
std::string size_mismatch(const Calibration& c, const TrackedField& field);

// No silent nothing: a source that has seen no player for its first seconds of frames says so
// once, with what to check (a wrong --field-size maps every player off the field) and what the
// pipeline sees (`sightings`).
class NobodySeen {
 public:
  explicit NobodySeen(double after = 3) : after_(after) {}
  // The warning, once: at the first frame `after` seconds past the first one while no frame has
  // had a player; "" otherwise. `input` says what it saw meanwhile.
  std::string check(const TrackedFrame& frame, const std::string& source, const TrackedField& field,
                    TrackingInput& input);

 private:
  double after_;
  double first_ = -1;
  bool seen_ = false, told_ = false;
};

// What `quantum track` and `play --input` do with a source's frames before using them: tell its
// calibration once, and when the table is not the sport's field warn (or with `strict` stop); with
// `fit`, stretch the table's metres over the sport's field; warn (or stop) once when a hat
// camera's markers do not fit the field (hat_view_mismatch); warn once when nobody is seen
// (SetupOptions: options.h).
class SetupCheck {
 public:
  // `sport`: the sport's own field (tracked_field without --field-size).
  SetupCheck(std::string source, TrackedField sport, SetupOptions options)
      : source_(std::move(source)), sport_(std::move(sport)), options_(options) {}
  // Lines to tell the operator, each once; `frame` fitted to the sport's field with `fit`. Throws
  // TrackingError for a table of another size with `strict`.
  std::vector<std::string> check(TrackedFrame& frame, TrackingInput& input, const TrackedField& tracked);

 private:
  std::string source_;
  TrackedField sport_;
  SetupOptions options_;
  bool calibrated_ = false, viewed_ = false;
  float sx_ = 1, sy_ = 1;  // --fit-field's stretch
  NobodySeen nobody_;
};

}  // namespace quantum::tracking

// Tracking: players on the field, from a camera or a recording, as one per-frame scene in field
// metres. Field coordinates: origin at the field's centre, x from the blue end (x = -L/2) to the
// red end (x = +L/2), y to the blue player's left, z up toward the camera.
//
// The air hockey pipeline (the paper's section 8.1): four ArUco markers on the field's corners
// calibrate the camera; a depth background is learnt from the first frames of an empty table;
// each frame, the arms reaching in over the short ends are cut out of it, and each arm's mallet
// is found, rejected while its hand hovers, and smoothed by a Kalman filter. docs/tracking.md.
#pragma once

#include <opencv2/core.hpp>

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "quantum/field.h"
#include "tracking/fakenect.h"
#include "tracking/kalman.h"
#include "tracking/kinect.h"

namespace quantum::tracking {

struct TrackedPlayer {
  std::string id, team;
  double x = 0, y = 0, vx = 0, vy = 0;  // field metres and m/s
};

struct TrackedFrame {
  int frame = 0;
  double t = 0;  // seconds since the source's first frame
  std::vector<TrackedPlayer> players;  // those with input this frame (a hovering hand has none)
};

// Bad tracking input (markers not found, no camera, ...): the message says what and where.
struct TrackingError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What the trackers need of a field: its size for the marker mapping, and who plays from which
// end (air hockey: the body that starts in that half).
struct TrackedField {
  float length = 0, width = 0;
  struct Player {
    std::string id, team;
    int end = 0;  // -1: reaches in over the blue end (x = -L/2), +1: over the red end
  };
  std::vector<Player> players;
};

// Size from the field's walls (or `size` when given: L, W), players from its bodies.
TrackedField tracked_field(const Field& field, std::optional<Vec2> size = std::nullopt);

// The playfield markers: ArUco DICT_4X4_50, ids 0-3, lying flat with their centres on the
// corners: 0 at (+L/2, +W/2), 1 at (+L/2, -W/2), 2 at (-L/2, -W/2), 3 at (-L/2, +W/2).
constexpr int kMarkerDictionary = 0;  // cv::aruco::DICT_4X4_50
Vec2 marker_position(int id, float length, float width);

// Where the camera is: field-to-camera rotation and translation (cv::solvePnP convention).
struct CameraPose {
  cv::Matx33d r;
  cv::Vec3d t;
};

// Finds the four markers in a colour image and the camera's pose from their centres. Throws
// TrackingError naming the markers it did not see.
CameraPose locate_camera(const cv::Mat& bgr, const TrackedField& field, const DepthCamera& camera);

struct DepthConfig {
  int background_frames = 30;    // depth frames of the empty table averaged into the background
  float foreground = 0.02f;      // m: nearer than the background by this much is an arm
  int min_area = 300;            // px: smaller blobs are noise
  float mallet_offset = 0.04f;   // m: from the arm's farthest point back to the mallet's centre
  int hand_window = 20;          // px: around the mallet's centre, whose median height is the hand's
  float hover_height = 0.13f;    // m: a hand higher than this above the table is hovering
  float arm_reach = 0.25f;       // m: the arm's direction is taken from this much of it behind the tip
  double filter_acceleration = 60;    // Kalman: m/s^2 of hand acceleration allowed
  double filter_measurement = 0.003;  // Kalman: m of measurement noise
};

// One arm as measured in one frame, before filtering.
struct ArmMeasurement {
  int player = -1;       // index into TrackedField::players
  double x = 0, y = 0;   // the mallet's centre on the table
  double hand_height = 0;
  bool hovering = false;
};

class DepthTracker {
 public:
  explicit DepthTracker(TrackedField field, DepthConfig config = {}, DepthCamera camera = {});

  // One recorded frame. Until the markers are found and the background is learnt it returns
  // nothing; after that every frame gives a TrackedFrame. Throws TrackingError when no colour
  // frame of the background phase showed all four markers.
  std::optional<TrackedFrame> feed(const RecordedFrame& frame);

  // This frame's arms (after feed()); hovering ones included.
  const std::vector<ArmMeasurement>& arms() const { return arms_; }
  bool ready() const { return learnt_ >= config_.background_frames && pose_.has_value(); }

 private:
  void learn(const cv::Mat& raw);
  void finish_background();
  void measure(const cv::Mat& raw);
  void measure_arm(int label, const cv::Rect& box);

  TrackedField field_;
  DepthConfig config_;
  DepthCamera camera_;
  std::optional<CameraPose> pose_;
  std::string marker_problem_;
  float to_metres_[2048];
  cv::Mat sum_, count_, background_;  // CV_32F metres, CV_32S, CV_32F
  int learnt_ = 0;
  cv::Mat z_, mask_, labels_, stats_, centroids_;
  std::vector<float> ray_x_, ray_y_;  // per column and row: (u - cx) / fx, (v - cy) / fy
  struct Point {
    float x, y, h;  // field metres
    int u, v;
  };
  std::vector<Point> points_;
  std::vector<ArmMeasurement> arms_;
  std::vector<PointFilter> filters_;
  double last_t_ = 0;
};

}  // namespace quantum::tracking

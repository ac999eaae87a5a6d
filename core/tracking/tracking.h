// Tracking: players on the field, from a camera or a recording, as one per-frame scene in field
// metres. Field coordinates: origin at the field's centre, x from the blue end (x = -L/2) to the
// red end (x = +L/2), y to the blue player's left, z up toward the camera.
//
// The air hockey pipeline (the paper's section 8.1): a depth background is learnt from the first
// frames of an empty table; with the four ArUco markers on the field's corners it calibrates the
// camera (its height, tilt and pose, and the field's size); each frame, the arms reaching in over
// the short ends are cut out of it, and each arm's mallet is found, rejected while its hand
// hovers, and smoothed by a Kalman filter. docs/tracking.md.
#pragma once

#include <opencv2/core.hpp>

#include <algorithm>
#include <array>
#include <memory>
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

// Something a player did: a throw, with its direction (a unit vector): along the field (dx, dy)
// and upward (dz, from the accelerometer's vertical axis; a flat field ignores it).
struct TrackedAction {
  std::string type, player;
  double dx = 0, dy = 0, dz = 0;
};

struct TrackedFrame {
  int frame = 0;
  double t = 0;  // seconds since the source's first frame
  std::vector<TrackedPlayer> players;  // those with input this frame (a hovering hand has none)
  std::vector<TrackedAction> actions;  // what they did since the last frame
};

// Bad tracking input (markers not found, no camera, ...): the message says what and where.
struct TrackingError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What the trackers need of a field: its size for the marker mapping, and who plays from which
// end (air hockey: the body that starts in that half).
struct TrackedField {
  float length = 0, width = 0;
  bool size_given = false;  // the operator's (--field-size): the depth pipeline maps to it, not to what it measures
  struct Player {
    std::string id, team;
    int end = 0;  // -1: reaches in over the blue end (x = -L/2), +1: over the red end
  };
  std::vector<Player> players;
};

// Size from the field's walls (or `size` when given: L, W, and then size_given), players from its
// bodies.
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

// One playfield marker as a colour image shows it: its id (0-3), its centre (where its diagonals
// cross: exact under perspective) and its corners in ArUco's order, sub-pixel.
struct MarkerImage {
  int id = 0;
  cv::Point2f centre;
  std::array<cv::Point2f, 4> corners;
};
std::vector<MarkerImage> find_markers(const cv::Mat& bgr);   // those of ids 0-3 it shows, in id order
std::string missing_markers(const std::vector<MarkerImage>& found);  // "2, 3"; "" when all four are there
// "playfield markers not found in the colour image: id 2, 3 (...)." for the missing ones.
std::string markers_not_found(const std::vector<MarkerImage>& found);

// The camera's pose from the four markers' centres and corners, given the field's size. Throws
// TrackingError naming the markers it did not see.
CameraPose locate_camera(const std::vector<MarkerImage>& found, const TrackedField& field, const DepthCamera& camera);
CameraPose locate_camera(const cv::Mat& bgr, const TrackedField& field, const DepthCamera& camera);

// What the markers and the empty table's depth say about a Kinect's set-up (the depth pipeline's
// self-calibration): the table's plane fitted to the background's depth inside the markers,
// each marker's centre where its pixel's ray meets that plane.
struct Calibration {
  int markers = 0;               // found in the colour image, of 4
  double height = 0;             // m: the camera above the table's plane
  double tilt = 0;               // degrees the camera looks off straight down
  double length = 0, width = 0;  // m: the field between the markers' centres, measured (each the mean of two sides)
  double noise = 0;              // m: depth noise on the empty table, after the 5x5 median (per pixel, frame to frame)
  double holes = 0;              // share of the table's pixels without a reading in any background frame
  double depth_step = 0;         // m: one raw disparity unit at the table's distance
  double pixel = 0;              // m: one pixel's footprint on the table
  float used_length = 0, used_width = 0;  // what the markers are mapped to: measured, or --field-size
  bool size_given = false;
};

// The table's plane in camera coordinates (n . X = d, n toward the camera's side, |n| = 1) from
// depth pixels (CV_32F metres, 0 = none) inside `region` (CV_8U, nonzero), robustly: a least-squares
// fit, then again without the points more than 3 sigma off it (an arm, a cup). Throws TrackingError
// with too few readings.
struct Plane {
  cv::Vec3d n;
  double d = 0;
};
Plane fit_table(const cv::Mat& depth, const cv::Mat& region, const DepthCamera& camera);

// Every threshold is physical (metres on and above the table); DepthTracker turns them into
// pixels and depth steps at the camera's measured height (Calibration), so one set of numbers
// holds from a camera 1 m over a small table to 2.4 m over a full-size one. docs/tracking.md.
struct DepthConfig {
  int background_frames = 30;    // depth frames of the empty table averaged into the background
  float foreground = 0.02f;      // m: nearer than the background by at least this much is an arm ...
  float foreground_noise = 3.5f; // ... and by this many times the depth noise measured on the empty table
  float min_area = 0.0015f;      // m^2 on the table (300 px at 1.3 m): smaller blobs are noise
  float mallet_offset = 0.04f;   // m: from the mallet's far rim back to its centre (its radius)
  float hand_window = 0.044f;    // m: around the mallet's centre, whose median height is the hand's (20 px at 1.3 m)
  float hand_on_table = 0.075f;  // m: a hand gripping a mallet on the table, its centre's height
  float hover_margin = 0.035f;   // m: a hand this much higher is hovering, or two depth steps when more, ...
  float hover_noise = 1.5f;      // ... plus this many times the depth noise measured on the empty table
  float arm_reach = 0.25f;       // m: the arm's direction is taken from this much of it behind the tip
  int blind_columns = 8;         // the Kinect's left columns without depth: an arm reaching in there leaves the image
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
  // nothing; after that every frame gives a TrackedFrame, in metres of the measured table (or of
  // --field-size). Throws TrackingError when no colour frame of the background phase showed all
  // four markers, saying what the camera sees of the table.
  std::optional<TrackedFrame> feed(const RecordedFrame& frame);

  // This frame's arms (after feed()); hovering ones included.
  const std::vector<ArmMeasurement>& arms() const { return arms_; }
  bool ready() const { return learnt_ >= config_.background_frames && pose_.has_value(); }
  const Calibration& calibration() const { return calibration_; }  // once ready()
  // What the pipeline has seen since the last call, for an operator whose players are not found:
  // "markers 4 of 4, ...; in 90 frames: 0 blobs, 0 arms reaching in over an end, 0 hovering".
  std::string sightings();

 private:
  void learn(const cv::Mat& raw);
  void finish_background();
  void scale();
  void measure(const cv::Mat& raw);
  void measure_arm(int label, const cv::Rect& box);

  TrackedField field_;
  DepthConfig config_;
  DepthCamera camera_;
  std::optional<CameraPose> pose_;
  std::vector<MarkerImage> markers_;  // the most found in one colour frame so far
  bool colour_seen_ = false;
  std::string failed_;  // why calibration failed: every later frame says it again
  Calibration calibration_;
  float to_metres_[2048];
  cv::Mat filtered_;                        // CV_16U: the raw frame through a 5x5 median
  cv::Mat sum_, sum2_, count_, background_;  // CV_64F metres, CV_64F, CV_32S, CV_32F metres
  int learnt_ = 0;
  // The thresholds at the measured height (scale()).
  float foreground_ = 0, hover_height_ = 0, offset_ = 0;
  int min_area_ = 0;
  cv::Mat z_, mask_, labels_, stats_, centroids_;
  std::vector<float> ray_x_, ray_y_;  // per column and row: (u - cx) / fx, (v - cy) / fy
  struct Point {
    float x, y, h;  // field metres
    int u, v;
  };
  std::vector<Point> points_;
  std::vector<float> heights_;
  std::vector<uint8_t> seen_players_;  // per player: input this frame
  cv::Mat opening_;                    // the 3x3 kernel that clears single-pixel noise
  std::vector<ArmMeasurement> arms_;
  std::vector<PointFilter> filters_;
  double last_t_ = 0;
  struct Seen {
    int frames = 0, blobs = 0, arms = 0, hovering = 0, strays = 0;  // strays: arm-sized blobs not over an end
  } seen_;
};

// --- Handball: coloured hats seen from above, and accelerometers for throws.

// A team's hat colour: OpenCV hue (0-180, wrapping), how far from it a pixel may be, and the
// least saturation and value that count as coloured at all.
struct HatColour {
  std::string team;
  int hue = 0, tolerance = 12, saturation = 110, value = 70;
};

struct HatConfig {
  std::vector<HatColour> colours = {{"blue", 110}, {"red", 0}};
  float hat_height = 1.8f;            // m above the floor: where the hats are, for the parallax
  float horizontal_fov = 82;          // degrees: the camera's field of view across the image
  int min_area = 25;                  // px: smaller coloured blobs are not hats
  float merged = 0.5f;                // m: hats of one team nearer than this are crossing: both coast
  float max_speed = 8;                // m/s: how far a lost hat may have run when it is found again
  double arrival = 0.3;               // s: a hat that comes later is followed once no other has held it this long
  double filter_acceleration = 30;    // Kalman: m/s^2 a player may accelerate
  double filter_measurement = 0.03;   // Kalman: m of measurement noise
};

// What a hat camera's markers say of the field they are taken to be the corners of. They fix the
// field's shape and the camera's pose, but not their scale: a field taken ten times too small
// puts the camera ten times too low. The hats give the scale away: they are hat_height up, and a
// camera that sees a game from above is well above them.
struct HatView {
  double camera_height = 0;  // m above the floor, at the field's size
  double hat_height = 0;     // m: HatConfig::hat_height
  double shape = 0;          // the markers' rectangle, length over width, as the picture shows it
};

// "" when `view` fits `field`: the camera at least kAboveHats over the hats, and the markers'
// rectangle the field's shape within kShapeTolerance; else what differs and what to do.
inline constexpr double kAboveHats = 1.0, kShapeTolerance = 0.15;
std::string hat_view_mismatch(const HatView& view, const TrackedField& field);

// One CamShift tracker per hat. The first frame calibrates the camera from the playfield
// markers and starts a tracker for every hat it shows; ids are the team and a number in order
// along x ("blue 1", "blue 2", ...). A hat that comes later (a player walking in) gets the next
// number of its team once it has been seen for `arrival` seconds, unless a lost hat of its team
// could have got there: then it is that player, back. When two hats of one team meet, their
// trackers coast on their Kalman filters until the hats part again, so identities survive
// crossings.
class HatTracker {
 public:
  explicit HatTracker(TrackedField field, HatConfig config = {});

  // One colour frame (BGR). Throws TrackingError when the first frame lacks a marker.
  TrackedFrame feed(const cv::Mat& bgr, int index, double t);

  // Where a pixel at the hats' height is on the field (after the first frame).
  Vec2 to_field(cv::Point2f pixel) const;
  // What the first frame's markers said of the field (none before it).
  const std::optional<HatView>& view() const { return view_; }

 private:
  struct Hat {
    std::string id, team;
    int colour;       // index into config_.colours
    PointFilter filter;
    int side;             // px: the CamShift window's side
    double coasting = 0;  // s since it was last seen
    double lost = 0;      // of which not crossing another hat
  };
  struct Blob {
    Vec2 at;
    int area;
  };
  // A blob no hat holds, not yet seen long enough to be a hat of its own.
  struct Newcomer {
    size_t colour;
    Blob blob;         // where it is now, and the largest it has been (a hat walks in over the picture's edge)
    double seen = 0;   // s
  };
  void calibrate(const cv::Mat& bgr);
  std::vector<Blob> blobs(size_t colour);
  // Moves the hats on; returns, per colour, the blobs none of them holds.
  std::vector<std::vector<Blob>> follow(cv::Size image, double dt);
  void arrive(const std::vector<std::vector<Blob>>& free, double dt);
  void start(std::vector<Newcomer> hats);
  void masks(const cv::Mat& bgr);
  cv::Point2f to_image(double x, double y) const;

  TrackedField field_;
  HatConfig config_;
  DepthCamera camera_;  // the colour camera's pinhole, from its size and field of view
  std::optional<CameraPose> pose_;
  std::optional<HatView> view_;
  std::vector<Hat> hats_;
  std::vector<Newcomer> newcomers_;
  std::vector<cv::Mat> masks_;  // per team colour: 255 where a pixel has it
  cv::Mat hsv_;
  cv::Mat labels_, stats_, centroids_;  // blobs' scratch: a frame's labels are a megabyte, kept
  double last_t_ = 0;
};

// Accelerometer samples (m/s^2) per player, from a CSV file (t,player,ax,ay,az, t in seconds
// from the video's first frame) or live over UDP (the same fields, one sample per datagram).
struct AccelSample {
  double t = 0;
  std::string player;
  double ax = 0, ay = 0, az = 0;
};

class AccelSource {
 public:
  // "FILE" (CSV) or "udp:PORT". Throws TrackingError naming the file and line of bad input; blank
  // lines (spaces and tabs at most) are skipped, a line longer than kLongestLine (lines.h) is
  // dropped and counted.
  explicit AccelSource(const std::string& spec);
  ~AccelSource();
  // Samples up to time t (for UDP: everything received so far, stamped t).
  std::vector<AccelSample> until(double t);
  // Samples dropped so far: a value NaN or infinite, a line too long, or a datagram that is not a
  // sample.
  size_t dropped() const { return dropped_; }

 private:
  std::vector<AccelSample> samples_;
  size_t cursor_ = 0, dropped_ = 0;
  int socket_ = -1;
};

// The most ids (TUIO objects, TUIO cursors) and names (accelerometers) one source keeps state for,
// for a field of `players`: 64, six times the most players a shipped sport has (soccer's ten) and
// room for a side of 22 with as many stray touches, or twice the field's players when it has
// more. A sender of ever new ones (a flood: 100,000 names grew 14 MB and slowed every frame)
// holds no more; the oldest is forgotten first, and counted as a dropped value.
inline constexpr size_t kMostTracked = 64;
inline size_t most_tracked(size_t players) { return std::max(kMostTracked, 2 * players); }

// Turns accelerometer peaks into throws: a player's acceleration magnitude crossing `threshold`
// (default 25 m/s^2, about 2.5 g: an arm's whip, well above running's 1-1.5 g) is a throw, in
// the direction the player is moving (toward the other end when standing still). One throw per
// player per `refractory` seconds, remembered for `most` players (most_tracked).
class ThrowDetector {
 public:
  explicit ThrowDetector(size_t most = kMostTracked, double threshold = 25, double refractory = 0.5)
      : most_(most), threshold_(threshold), refractory_(refractory) {}
  // Adds the throws among `samples` to `frame`, whose players give the directions.
  void add(const std::vector<AccelSample>& samples, TrackedFrame& frame);
  size_t players() const { return last_.size(); }  // remembered now, at most `most`
  size_t dropped() const { return dropped_; }      // the oldest forgotten to make room

 private:
  size_t most_;
  double threshold_, refractory_;
  std::vector<std::pair<std::string, double>> last_;  // player, time of their last throw
  size_t dropped_ = 0;
};

// --- TUIO 1.1 over OSC/UDP (liblo), so existing trackers can feed the engine.
//
// /tuio/2Dobj objects are players by class id: class i is the field's player i (its bodies'
// order). /tuio/2Dcur cursors take the players no object holds, in the order they appear, and
// free them when they leave. TUIO's normalized coordinates span the field: x from 0 at the blue
// end to 1 at the red end, y from 0 at the blue player's left (TUIO's top) to 1 at the right.
class TuioSource {
 public:
  // Listens on `port` (UDP). Throws TrackingError when it cannot.
  TuioSource(int port, TrackedField field);
  ~TuioSource();
  TuioSource(const TuioSource&) = delete;
  TuioSource& operator=(const TuioSource&) = delete;

  // The next complete TUIO frame (closed by its fseq message), waiting up to `timeout` seconds;
  // nothing when none came.
  std::optional<TrackedFrame> next(double timeout);
  double silent() const;  // seconds since the last message (since opening, before the first)
  // Packets dropped so far (not OSC, cut short, or refused by liblo), and objects and cursors
  // forgotten beyond most_tracked(field's players), the oldest first. The match goes on.
  size_t dropped() const;

  struct State;

 private:
  std::unique_ptr<State> state_;
};

}  // namespace quantum::tracking

#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "tracking/tracking.h"

namespace quantum::tracking {

DepthTracker::DepthTracker(TrackedField field, DepthConfig config, DepthCamera camera)
    : field_(std::move(field)), config_(config), camera_(camera) {
  if (config_.background_frames < 1) throw std::invalid_argument("the background needs at least one frame");
  for (int raw = 0; raw < 2048; ++raw) to_metres_[raw] = raw_to_metres(uint16_t(raw));
  for (int u = 0; u < camera_.width; ++u) ray_x_.push_back((float(u) - camera_.cx) / camera_.fx);
  for (int v = 0; v < camera_.height; ++v) ray_y_.push_back((float(v) - camera_.cy) / camera_.fy);
  for (size_t k = 0; k < field_.players.size(); ++k) filters_.emplace_back(config_.filter_acceleration, config_.filter_measurement);
  // Doubles: the variance is a difference of two sums of squares of depths near 2.4 m, which
  // floats round by as much as a quiet pixel's variance.
  sum_ = cv::Mat::zeros(camera_.height, camera_.width, CV_64F);
  sum2_ = cv::Mat::zeros(camera_.height, camera_.width, CV_64F);
  seen_players_.assign(field_.players.size(), 0);
  opening_ = cv::getStructuringElement(cv::MORPH_RECT, {3, 3});
  count_ = cv::Mat::zeros(camera_.height, camera_.width, CV_32S);
}

std::optional<TrackedFrame> DepthTracker::feed(const RecordedFrame& frame) {
  if (!failed_.empty()) throw TrackingError(failed_);  // a calibration that failed does not come back
  if (frame.depth.rows != camera_.height || frame.depth.cols != camera_.width || frame.depth.type() != CV_16UC1)
    throw TrackingError(frame.file + ": expected " + std::to_string(camera_.width) + "x" +
                        std::to_string(camera_.height) + " 16-bit depth");
  // Per-pixel speckle noise is what a Kinect far from its table mostly has (2 raw units are 3.5 cm
  // at 2.4 m); a 5x5 median takes most of it and keeps the edges the mallet is found by.
  cv::medianBlur(frame.depth, filtered_, 5);
  if (learnt_ < config_.background_frames) {
    if (!frame.rgb.empty() && markers_.size() < 4) {
      std::vector<MarkerImage> found = find_markers(frame.rgb);
      if (found.size() > markers_.size()) markers_ = std::move(found);
      colour_seen_ = true;
    }
    learn(filtered_);
    if (learnt_ == config_.background_frames) {
      try {
        finish_background();
      } catch (const TrackingError& e) {
        failed_ = e.what();
        throw;
      }
    }
    last_t_ = frame.t;
    return std::nullopt;
  }
  measure(filtered_);
  const double dt = std::max(0.0, frame.t - last_t_);
  last_t_ = frame.t;
  TrackedFrame out;
  out.frame = frame.index;
  out.t = frame.t;
  std::vector<uint8_t>& seen = seen_players_;
  std::fill(seen.begin(), seen.end(), 0);
  for (const ArmMeasurement& a : arms_) {
    if (a.player < 0 || a.hovering || seen[size_t(a.player)]) continue;
    seen[size_t(a.player)] = 1;
    PointFilter& f = filters_[size_t(a.player)];
    f.predict(dt);
    f.correct(a.x, a.y);
    const TrackedField::Player& p = field_.players[size_t(a.player)];
    out.players.push_back({p.id, p.team, f.x(), f.y(), f.vx(), f.vy()});
  }
  // A hand not seen (hovering, or out of view) starts afresh when it comes back: after a lift
  // its velocity says nothing about where it lands.
  for (size_t k = 0; k < filters_.size(); ++k)
    if (!seen[k]) filters_[k].reset();
  return out;
}

void DepthTracker::learn(const cv::Mat& raw) {
  for (int v = 0; v < raw.rows; ++v) {
    const uint16_t* r = raw.ptr<uint16_t>(v);
    double* s = sum_.ptr<double>(v);
    double* s2 = sum2_.ptr<double>(v);
    int* c = count_.ptr<int>(v);
    for (int u = 0; u < raw.cols; ++u) {
      const float z = to_metres_[r[u] & 2047];
      if (z > 0) s[u] += z, s2[u] += z * z, ++c[u];
    }
  }
  ++learnt_;
}

namespace {

// How high a camera must hang to see a field of length x width metres and its markers (each
// `margin` beyond the corner), looking straight down or tilted by `tilt` degrees.
double mounting_height(double length, double width, double margin, double tilt, const DepthCamera& c) {
  const double t = std::tan(std::min(tilt, 15.0) * M_PI / 180);  // a camera tilted further is set up anew anyway
  const double across = (c.width / 2.0) / c.fx, down = (c.height / 2.0) / c.fy;  // tangents of the half angles
  return std::max((length / 2 + margin) / ((across - t) / (1 + across * t)), (width / 2 + margin) / ((down - t) / (1 + down * t)));
}

}  // namespace

void DepthTracker::finish_background() {
  background_ = cv::Mat(sum_.size(), CV_32F);
  cv::Mat holes = cv::Mat::zeros(sum_.size(), CV_8U), noise(sum_.size(), CV_32F);
  for (int v = 0; v < sum_.rows; ++v)
    for (int u = 0; u < sum_.cols; ++u) {
      const int c = count_.at<int>(v, u);
      const double mean = c > 0 ? sum_.at<double>(v, u) / c : 0.0;
      background_.at<float>(v, u) = float(mean);
      noise.at<float>(v, u) = c > 1 ? float(std::sqrt(std::max(0.0, sum2_.at<double>(v, u) / c - mean * mean))) : -1.0f;
      holes.at<uint8_t>(v, u) = c == 0;
    }
  // The table: inside the markers' centres when all four were seen, else the picture's middle.
  cv::Mat table = cv::Mat::zeros(sum_.size(), CV_8U);
  const bool all = markers_.size() == 4;
  if (all) {
    std::vector<cv::Point> corners;
    for (const MarkerImage& m : markers_) corners.emplace_back(int(std::lround(m.centre.x)), int(std::lround(m.centre.y)));
    cv::fillConvexPoly(table, corners, cv::Scalar(255));
  } else {
    table(cv::Rect(sum_.cols / 4, sum_.rows / 4, sum_.cols / 2, sum_.rows / 2)).setTo(255);
  }
  Calibration& c = calibration_;
  c.markers = int(markers_.size());
  std::vector<float> spread;
  int pixels = 0, none = 0;
  for (int v = 0; v < sum_.rows; ++v)
    for (int u = 0; u < sum_.cols; ++u)
      if (table.at<uint8_t>(v, u)) {
        ++pixels;
        none += holes.at<uint8_t>(v, u);
        if (noise.at<float>(v, u) >= 0) spread.push_back(noise.at<float>(v, u));
      }
  c.holes = pixels ? double(none) / pixels : 1.0;
  if (!spread.empty()) {
    std::nth_element(spread.begin(), spread.begin() + long(spread.size() / 2), spread.end());
    c.noise = spread[spread.size() / 2];
  }
  if (!colour_seen_)
    throw TrackingError("no colour frame among the first " + std::to_string(config_.background_frames) +
                        " depth frames: the markers cannot be found");
  if (all) {
    // The centres go round the field in id order (docs/tracking.md); two markers on each other's
    // corners make a crossed quadrilateral, and the "length" would be a diagonal.
    int turns = 0;
    for (size_t k = 0; k < 4; ++k) {
      const cv::Point2f a = markers_[k].centre, b = markers_[(k + 1) % 4].centre, d = markers_[(k + 2) % 4].centre;
      turns += (b - a).cross(d - b) > 0 ? 1 : -1;
    }
    if (std::abs(turns) != 4)
      throw TrackingError("the playfield markers are not in order round the field: 0 and 1 go on the red end, 2 and 3 "
                          "on the blue end, 0 and 3 on Blue's left (docs/tracking.md, Playfield markers)");
  }
  const Plane plane = fit_table(background_, table, camera_);
  c.height = -plane.d;
  c.tilt = std::acos(std::min(1.0, -plane.n[2])) * 180 / M_PI;
  c.depth_step = depth_step(float(c.height));
  c.pixel = c.height / camera_.fx;
  sum_.release();
  sum2_.release();
  count_.release();
  if (!all) {
    char sees[400];
    std::snprintf(sees, sizeof sees,
                  " The camera is %.2f m above the table and sees %.2f x %.2f m of it around its centre; a %.2f x %.2f m "
                  "field (%s) with its markers needs it at least %.2f m up (docs/tracking.md, Setting up a full-size "
                  "table)",
                  c.height, 2 * c.height * (camera_.width / 2.0) / camera_.fx,
                  2 * c.height * (camera_.height / 2.0) / camera_.fy, field_.length, field_.width,
                  field_.size_given ? "--field-size" : "the sport's",
                  mounting_height(field_.length, field_.width, 0.1, c.tilt, camera_));
    throw TrackingError(markers_not_found(markers_) + sees);
  }
  // Each marker's centre where its pixel's ray meets the table.
  std::array<cv::Vec3d, 4> at;
  for (const MarkerImage& m : markers_) {
    const cv::Vec3d ray((m.centre.x - camera_.cx) / camera_.fx, (m.centre.y - camera_.cy) / camera_.fy, 1);
    at[size_t(m.id)] = ray * (plane.d / plane.n.dot(ray));
  }
  c.length = (cv::norm(at[0] - at[3]) + cv::norm(at[1] - at[2])) / 2;
  c.width = (cv::norm(at[0] - at[1]) + cv::norm(at[3] - at[2])) / 2;
  c.size_given = field_.size_given;
  if (!field_.size_given) field_.length = float(c.length), field_.width = float(c.width);
  c.used_length = field_.length, c.used_width = field_.width;
  pose_ = locate_camera(markers_, field_, camera_);
  scale();
  // Pixels that never gave a reading (shadows, the Kinect's blind edges) take their neighbours'
  // background, so an arm over them still stands out.
  if (cv::countNonZero(holes) > 0) cv::inpaint(background_, holes, background_, 5, cv::INPAINT_TELEA);
}

void DepthTracker::scale() {
  const Calibration& c = calibration_;
  // A false arm needs a blob of pixels nearer than the background by several times the noise;
  // the mallet (5 cm tall) stays above this up to about 2 raw units of noise at 2.4 m.
  foreground_ = std::max(config_.foreground, config_.foreground_noise * float(c.noise));
  // A hovering hand reads higher than a resting one by its lift: the margin covers the depth's
  // quantization there (two steps) and its noise (a resting hand 2.4 m below read up to 11.3 cm
  // with 1 cm of noise, the lowest hovering one 14.4 cm).
  hover_height_ = config_.hand_on_table + std::max(config_.hover_margin, 2 * float(c.depth_step)) +
                  config_.hover_noise * float(c.noise);
  // The farthest pixel's centre lies half a pixel inside the mallet's rim, on average.
  offset_ = config_.mallet_offset - 0.5f * float(c.pixel);
  min_area_ = int(config_.min_area / (c.pixel * c.pixel));
}

std::string DepthTracker::sightings() {
  char line[400];
  if (!ready()) {
    std::snprintf(line, sizeof line, "still calibrating: %d of %d background frames", learnt_, config_.background_frames);
    return line;
  }
  const Calibration& c = calibration_;
  std::snprintf(line, sizeof line,
                "markers %d of 4 (field %.2f x %.2f m), camera %.2f m up, background from %d frames (%.0f %% of the table "
                "without a reading); in the last %d frames: %d blobs of an arm's size, %d reaching in over an end "
                "(%d of them hovering: hand above %.0f cm), %d not over an end",
                c.markers, c.used_length, c.used_width, c.height, config_.background_frames, c.holes * 100, seen_.frames,
                seen_.blobs, seen_.arms, seen_.hovering, hover_height_ * 100, seen_.strays);
  seen_ = {};
  return line;
}

void DepthTracker::measure(const cv::Mat& raw) {
  // Hand-written: the one pass over all 307,200 pixels each frame. Depth through a table and the
  // foreground test in the same loop, so each pixel is read once.
  z_.create(raw.size(), CV_32F);
  mask_.create(raw.size(), CV_8U);
  const float near = foreground_;
  for (int v = 0; v < raw.rows; ++v) {
    const uint16_t* r = raw.ptr<uint16_t>(v);
    const float* b = background_.ptr<float>(v);
    float* z = z_.ptr<float>(v);
    uint8_t* m = mask_.ptr<uint8_t>(v);
    for (int u = 0; u < raw.cols; ++u) {
      const float d = to_metres_[r[u] & 2047];
      z[u] = d;
      m[u] = uint8_t(d > 0 && b[u] - d > near ? 255 : 0);
    }
  }
  // Isolated pixels are depth noise, not arms.
  cv::morphologyEx(mask_, mask_, cv::MORPH_OPEN, opening_);
  const int n = cv::connectedComponentsWithStats(mask_, labels_, stats_, centroids_, 8, CV_32S);
  arms_.clear();
  ++seen_.frames;
  for (int label = 1; label < n; ++label) {
    if (stats_.at<int>(label, cv::CC_STAT_AREA) < min_area_) continue;
    ++seen_.blobs;
    measure_arm(label, cv::Rect(stats_.at<int>(label, cv::CC_STAT_LEFT), stats_.at<int>(label, cv::CC_STAT_TOP),
                                stats_.at<int>(label, cv::CC_STAT_WIDTH), stats_.at<int>(label, cv::CC_STAT_HEIGHT)));
  }
}

void DepthTracker::measure_arm(int label, const cv::Rect& box) {
  const cv::Matx33d rt = pose_->r.t();
  const cv::Vec3d t = pose_->t;
  points_.clear();
  // Every pixel of the arm in field coordinates: its depth along its ray, then camera to field.
  for (int v = box.y; v < box.y + box.height; ++v) {
    const int* l = labels_.ptr<int>(v);
    const float* z = z_.ptr<float>(v);
    for (int u = box.x; u < box.x + box.width; ++u) {
      if (l[u] != label) continue;
      const cv::Vec3d c(ray_x_[size_t(u)] * z[u], ray_y_[size_t(v)] * z[u], z[u]);
      const cv::Vec3d f = rt * (c - t);
      points_.push_back({float(f[0]), float(f[1]), float(f[2]), u, v});
    }
  }
  if (points_.empty()) return;
  // The arm reaches in over the end its outermost point is beyond.
  const Point& root = *std::max_element(points_.begin(), points_.end(),
                                         [](const Point& a, const Point& b) { return std::fabs(a.x) < std::fabs(b.x); });
  const int end = root.x < 0 ? -1 : 1;
  int player = -1;
  for (size_t k = 0; k < field_.players.size() && player < 0; ++k)
    if (field_.players[k].end == end) player = int(k);
  // An arm reaches in over the end: it crosses the end line, or leaves the image (a camera that
  // sees little beyond the table loses the arm before the line, at the arm's height).
  const bool leaves_image = box.x <= config_.blind_columns || box.y == 0 || box.x + box.width == camera_.width ||
                            box.y + box.height == camera_.height;
  if (player < 0 || !(std::fabs(root.x) >= field_.length / 2 || leaves_image)) {
    ++seen_.strays;
    return;
  }

  // The arm's direction: principal axis of its points, first of all of them, then of the last
  // arm_reach behind the tip (a bent arm points where its forearm does). The farthest point
  // along it is the mallet's far rim; the centre lies the offset behind.
  double ax = -end, ay = 0, tip_x = 0, tip_y = 0;
  const Point* tip = nullptr;
  for (int pass = 0; pass < 2; ++pass) {
    double n = 0, mx = 0, my = 0;
    for (const Point& p : points_) {
      if (pass == 1 && (p.x - tip_x) * ax + (p.y - tip_y) * ay < -config_.arm_reach) continue;
      n += 1, mx += p.x, my += p.y;
    }
    if (n < 3) break;
    mx /= n, my /= n;
    double sxx = 0, sxy = 0, syy = 0;
    for (const Point& p : points_) {
      if (pass == 1 && (p.x - tip_x) * ax + (p.y - tip_y) * ay < -config_.arm_reach) continue;
      sxx += (p.x - mx) * (p.x - mx), sxy += (p.x - mx) * (p.y - my), syy += (p.y - my) * (p.y - my);
    }
    // Largest eigenvector of [[sxx sxy] [sxy syy]].
    const double theta = 0.5 * std::atan2(2 * sxy, sxx - syy);
    double ex = std::cos(theta), ey = std::sin(theta);
    if (ex * -end < 0) ex = -ex, ey = -ey;  // pointing into the field, away from the player's end
    ax = ex, ay = ey;
    double best = -1e9;
    for (const Point& p : points_) {
      const double along = p.x * ax + p.y * ay;
      if (along > best) best = along, tip = &p;
    }
    tip_x = tip->x, tip_y = tip->y;
  }
  if (!tip) return;
  ArmMeasurement a;
  a.player = player;
  a.x = tip_x - offset_ * ax;
  a.y = tip_y - offset_ * ay;
  // The hand's height: the median over a disc of the mallet's size around its centre, in metres
  // (a window of fixed pixels grows with the camera's height and takes in the forearm rising
  // behind the hand). The centre's pixel is the tip's moved back by the offset seen at the tip's
  // depth.
  const double metres_per_px = double(z_.at<float>(tip->v, tip->u)) / camera_.fx;
  const cv::Vec3d back = pose_->r * cv::Vec3d(ax, ay, 0);  // the arm's direction in the camera frame
  const double bu = tip->u - offset_ * back[0] / metres_per_px;
  const double bv = tip->v - offset_ * back[1] / metres_per_px;
  std::vector<float>& heights = heights_;
  heights.clear();
  const double window = config_.hand_window / metres_per_px, w2 = window * window;
  for (const Point& p : points_)
    if ((p.u - bu) * (p.u - bu) + (p.v - bv) * (p.v - bv) <= w2) heights.push_back(p.h);
  if (heights.empty()) heights.push_back(tip->h);
  std::nth_element(heights.begin(), heights.begin() + long(heights.size() / 2), heights.end());
  a.hand_height = heights[heights.size() / 2];
  a.hovering = a.hand_height > hover_height_;
  ++seen_.arms;
  seen_.hovering += a.hovering;
  arms_.push_back(a);
}

}  // namespace quantum::tracking

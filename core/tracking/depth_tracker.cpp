#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include <algorithm>
#include <cmath>

#include "tracking/tracking.h"

namespace quantum::tracking {

DepthTracker::DepthTracker(TrackedField field, DepthConfig config, DepthCamera camera)
    : field_(std::move(field)), config_(config), camera_(camera) {
  if (config_.background_frames < 1) throw std::invalid_argument("the background needs at least one frame");
  for (int raw = 0; raw < 2048; ++raw) to_metres_[raw] = raw_to_metres(uint16_t(raw));
  for (int u = 0; u < camera_.width; ++u) ray_x_.push_back((float(u) - camera_.cx) / camera_.fx);
  for (int v = 0; v < camera_.height; ++v) ray_y_.push_back((float(v) - camera_.cy) / camera_.fy);
  for (size_t k = 0; k < field_.players.size(); ++k) filters_.emplace_back(config_.filter_acceleration, config_.filter_measurement);
  sum_ = cv::Mat::zeros(camera_.height, camera_.width, CV_32F);
  count_ = cv::Mat::zeros(camera_.height, camera_.width, CV_32S);
}

std::optional<TrackedFrame> DepthTracker::feed(const RecordedFrame& frame) {
  if (frame.depth.rows != camera_.height || frame.depth.cols != camera_.width || frame.depth.type() != CV_16UC1)
    throw TrackingError(frame.file + ": expected " + std::to_string(camera_.width) + "x" +
                        std::to_string(camera_.height) + " 16-bit depth");
  if (!pose_ && !frame.rgb.empty()) {
    try {
      pose_ = locate_camera(frame.rgb, field_, camera_);
    } catch (const TrackingError& e) {
      marker_problem_ = e.what();
    }
  }
  if (learnt_ < config_.background_frames) {
    learn(frame.depth);
    if (learnt_ == config_.background_frames) {
      if (!pose_)
        throw TrackingError(marker_problem_.empty() ? "no colour frame among the first " +
                                                          std::to_string(config_.background_frames) +
                                                          " depth frames: the markers cannot be found"
                                                    : marker_problem_);
      finish_background();
    }
    last_t_ = frame.t;
    return std::nullopt;
  }
  measure(frame.depth);
  const double dt = std::max(0.0, frame.t - last_t_);
  last_t_ = frame.t;
  TrackedFrame out;
  out.frame = frame.index;
  out.t = frame.t;
  std::vector<bool> seen(field_.players.size(), false);
  for (const ArmMeasurement& a : arms_) {
    if (a.player < 0 || a.hovering || seen[size_t(a.player)]) continue;
    seen[size_t(a.player)] = true;
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
    float* s = sum_.ptr<float>(v);
    int* c = count_.ptr<int>(v);
    for (int u = 0; u < raw.cols; ++u) {
      const float z = to_metres_[r[u] & 2047];
      if (z > 0) s[u] += z, ++c[u];
    }
  }
  ++learnt_;
}

void DepthTracker::finish_background() {
  background_ = cv::Mat(sum_.size(), CV_32F);
  cv::Mat holes = cv::Mat::zeros(sum_.size(), CV_8U);
  for (int v = 0; v < sum_.rows; ++v)
    for (int u = 0; u < sum_.cols; ++u) {
      const int c = count_.at<int>(v, u);
      background_.at<float>(v, u) = c > 0 ? sum_.at<float>(v, u) / float(c) : 0.0f;
      holes.at<uint8_t>(v, u) = c == 0;
    }
  // Pixels that never gave a reading (shadows, the Kinect's blind edges) take their neighbours'
  // background, so an arm over them still stands out.
  if (cv::countNonZero(holes) > 0) cv::inpaint(background_, holes, background_, 5, cv::INPAINT_TELEA);
  sum_.release();
  count_.release();
}

void DepthTracker::measure(const cv::Mat& raw) {
  // Hand-written: the one pass over all 307,200 pixels each frame. Depth through a table and the
  // foreground test in the same loop, so each pixel is read once.
  z_.create(raw.size(), CV_32F);
  mask_.create(raw.size(), CV_8U);
  const float near = config_.foreground;
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
  cv::morphologyEx(mask_, mask_, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
  const int n = cv::connectedComponentsWithStats(mask_, labels_, stats_, centroids_, 8, CV_32S);
  arms_.clear();
  for (int label = 1; label < n; ++label) {
    if (stats_.at<int>(label, cv::CC_STAT_AREA) < config_.min_area) continue;
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
  const bool leaves_image = box.x == 0 || box.y == 0 || box.x + box.width == camera_.width ||
                            box.y + box.height == camera_.height;
  if (player < 0 || !(std::fabs(root.x) >= field_.length / 2 || leaves_image)) return;

  // The arm's direction: principal axis of its points, first of all of them, then of the last
  // arm_reach behind the tip (a bent arm points where its forearm does). The farthest point
  // along it is the mallet's far rim; the centre lies mallet_offset behind.
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
  a.x = tip_x - config_.mallet_offset * ax;
  a.y = tip_y - config_.mallet_offset * ay;
  // The hand's height: the median over the mallet centre's pixel neighbourhood. The centre's pixel
  // is the tip's moved back by the offset seen at the tip's depth.
  const double metres_per_px = double(z_.at<float>(tip->v, tip->u)) / camera_.fx;
  const cv::Vec3d back = pose_->r * cv::Vec3d(ax, ay, 0);  // the arm's direction in the camera frame
  const double bu = tip->u - config_.mallet_offset * back[0] / metres_per_px;
  const double bv = tip->v - config_.mallet_offset * back[1] / metres_per_px;
  std::vector<float> heights;
  const double w2 = double(config_.hand_window) * config_.hand_window;
  for (const Point& p : points_)
    if ((p.u - bu) * (p.u - bu) + (p.v - bv) * (p.v - bv) <= w2) heights.push_back(p.h);
  if (heights.empty()) heights.push_back(tip->h);
  std::nth_element(heights.begin(), heights.begin() + long(heights.size() / 2), heights.end());
  a.hand_height = heights[heights.size() / 2];
  a.hovering = a.hand_height > config_.hover_height;
  arms_.push_back(a);
}

}  // namespace quantum::tracking

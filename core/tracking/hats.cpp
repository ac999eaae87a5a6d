#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "quantum/limits.h"
#include "tracking/tracking.h"

namespace quantum::tracking {

HatTracker::HatTracker(TrackedField field, HatConfig config) : field_(std::move(field)), config_(std::move(config)) {
  if (config_.colours.empty()) throw std::invalid_argument("hat tracking needs at least one team colour");
  limits::check(limits::kFieldOfView, config_.horizontal_fov, "the camera's field of view");
}

cv::Point2f HatTracker::to_image(double x, double y) const {
  const cv::Vec3d c = pose_->r * cv::Vec3d(x, y, config_.hat_height) + pose_->t;
  if (!(c[2] > 0)) return {NAN, NAN};  // behind the camera
  return {float(camera_.fx * c[0] / c[2] + camera_.cx), float(camera_.fy * c[1] / c[2] + camera_.cy)};
}

Vec2 HatTracker::to_field(cv::Point2f p) const {
  // The pixel's ray, from the camera's centre, meets the plane of the hats.
  const cv::Matx33d rt = pose_->r.t();
  const cv::Vec3d centre = -(rt * pose_->t);
  const cv::Vec3d d = rt * cv::Vec3d((p.x - camera_.cx) / camera_.fx, (p.y - camera_.cy) / camera_.fy, 1);
  const double s = (config_.hat_height - centre[2]) / d[2];
  return {float(centre[0] + s * d[0]), float(centre[1] + s * d[1])};
}

void HatTracker::calibrate(const cv::Mat& bgr) {
  camera_.width = bgr.cols, camera_.height = bgr.rows;
  camera_.fx = camera_.fy = float((bgr.cols / 2.0) / std::tan(config_.horizontal_fov * M_PI / 360));
  camera_.cx = (bgr.cols - 1) / 2.0f, camera_.cy = (bgr.rows - 1) / 2.0f;
  const std::vector<MarkerImage> found = find_markers(bgr);
  pose_ = locate_camera(found, field_, camera_);
  // The field's shape, free of its assumed size: the markers' centres as the picture of a unit
  // square, taken back through the pinhole, have the field's length and width as the lengths of
  // its first two columns (the rotation's columns, scaled).
  std::vector<cv::Point2f> square, image;
  for (const MarkerImage& m : found) {
    const Vec2 p = marker_position(m.id, 1, 1);
    square.emplace_back(p.x, p.y);
    image.push_back(m.centre);
  }
  const cv::Matx33d k(camera_.fx, 0, camera_.cx, 0, camera_.fy, camera_.cy, 0, 0, 1);
  const cv::Matx33d h = k.inv() * cv::Matx33d(cv::findHomography(square, image));
  const double length = std::hypot(h(0, 0), h(1, 0), h(2, 0)), width = std::hypot(h(0, 1), h(1, 1), h(2, 1));
  view_ = HatView{(-(pose_->r.t() * pose_->t))[2], config_.hat_height, length / width};
}

std::string hat_view_mismatch(const HatView& view, const TrackedField& field) {
  char line[600];
  const double above = view.camera_height - view.hat_height;
  if (above < kAboveHats) {
    // The field that would put the camera kAboveHats over the hats: the size scales the height.
    const double scale = (view.hat_height + kAboveHats) / view.camera_height;
    std::snprintf(line, sizeof line,
                  "the markers, taken for the corners of a %.2f x %.2f m field, put the camera %.2f m above the floor, "
                  "%s the hats (%.2f m up): the field they show is larger, at least %.1f x %.1f m for a camera %.0f m "
                  "over the hats. Give the field the camera sees (--field on track, the sport on play) or "
                  "--field-size L,W",
                  field.length, field.width, view.camera_height, above < 0 ? "below" : "barely above", view.hat_height,
                  scale * field.length, scale * field.width, kAboveHats);
    return line;
  }
  const double shape = field.length / field.width;
  if (std::fabs(view.shape / shape - 1) <= kShapeTolerance) return "";
  std::snprintf(line, sizeof line,
                "the markers' rectangle is %.2f times as long as wide, but the %.2f x %.2f m field is %.2f times: a "
                "field of another shape (--field, --field-size L,W), or markers not on its corners (ids 0-3 as in "
                "docs/tracking.md)",
                view.shape, field.length, field.width, shape);
  return line;
}

void HatTracker::masks(const cv::Mat& bgr) {
  cv::cvtColor(bgr, hsv_, cv::COLOR_BGR2HSV);
  masks_.resize(config_.colours.size());
  for (size_t k = 0; k < config_.colours.size(); ++k) {
    const HatColour& c = config_.colours[k];
    cv::Mat& m = masks_[k];
    m.create(hsv_.size(), CV_8U);
    for (int v = 0; v < hsv_.rows; ++v) {
      const cv::Vec3b* p = hsv_.ptr<cv::Vec3b>(v);
      uint8_t* out = m.ptr<uint8_t>(v);
      for (int u = 0; u < hsv_.cols; ++u) {
        const int d = std::abs(int(p[u][0]) - c.hue), hue = std::min(d, 180 - d);  // hue wraps at 180
        out[u] = uint8_t(hue <= c.tolerance && p[u][1] >= c.saturation && p[u][2] >= c.value ? 255 : 0);
      }
    }
    cv::morphologyEx(m, m, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, {3, 3}));
  }
}

std::vector<HatTracker::Blob> HatTracker::blobs(size_t colour) {
  const int n = cv::connectedComponentsWithStats(masks_[colour], labels_, stats_, centroids_);
  std::vector<Blob> out;
  for (int l = 1; l < n; ++l) {
    const int area = stats_.at<int>(l, cv::CC_STAT_AREA);
    if (area < config_.min_area) continue;
    out.push_back({to_field({float(centroids_.at<double>(l, 0)), float(centroids_.at<double>(l, 1))}), area});
  }
  return out;
}

std::vector<std::vector<HatTracker::Blob>> HatTracker::follow(cv::Size image, double dt) {
  // A hat lost (not crossing) for more than half a second stays where it was last thought to
  // be: its old velocity would carry it off the field.
  for (Hat& h : hats_) {
    if (h.lost < 0.5) h.filter.predict(dt);
    h.coasting += dt;
  }
  // Two hats of one team about to meet, by their filters: their blobs are about to become one.
  // Both coast on the velocities they had while apart, which carry them past each other, so
  // each comes out of the crossing on its own side.
  std::vector<bool> crossing(hats_.size(), false);
  for (size_t i = 0; i < hats_.size(); ++i)
    for (size_t j = i + 1; j < hats_.size(); ++j)
      if (hats_[i].colour == hats_[j].colour &&
          std::hypot(hats_[i].filter.x() - hats_[j].filter.x(), hats_[i].filter.y() - hats_[j].filter.y()) <
              config_.merged)
        crossing[i] = crossing[j] = true;
  // The others: CamShift on their team's colour, from where their filter expects them.
  std::vector<std::optional<Vec2>> seen(hats_.size());
  for (size_t i = 0; i < hats_.size(); ++i) {
    Hat& h = hats_[i];
    if (crossing[i]) continue;
    const cv::Point2f p = to_image(h.filter.x(), h.filter.y());
    if (!(p.x > -h.side && p.y > -h.side && p.x < image.width + h.side && p.y < image.height + h.side))
      continue;  // out of the picture (or behind the camera: NaN)
    cv::Rect window(int(p.x) - h.side / 2, int(p.y) - h.side / 2, h.side, h.side);
    window &= cv::Rect(0, 0, image.width, image.height);
    if (window.area() == 0) continue;
    const cv::RotatedRect found =
        cv::CamShift(masks_[size_t(h.colour)], window, {cv::TermCriteria::EPS | cv::TermCriteria::COUNT, 10, 0.5});
    if (found.size.area() < config_.min_area) continue;
    const Vec2 m = to_field(found.center);
    if (std::hypot(m.x - h.filter.x(), m.y - h.filter.y()) < config_.merged) seen[i] = m;
  }
  // A hat lost for a while (its CamShift found nothing near where it should be) takes the nearest
  // blob of its colour that no other hat holds, within what it can have walked meanwhile.
  std::vector<std::vector<Blob>> unheld(masks_.size());
  for (size_t colour = 0; colour < masks_.size(); ++colour) {
    std::vector<Blob>& free = unheld[colour];
    free = blobs(colour);
    for (size_t i = 0; i < hats_.size(); ++i) {
      if (hats_[i].colour != int(colour)) continue;
      const Vec2 at = seen[i] ? *seen[i] : Vec2{float(hats_[i].filter.x()), float(hats_[i].filter.y())};
      if (seen[i] || crossing[i])
        std::erase_if(free, [&](const Blob& b) { return std::hypot(b.at.x - at.x, b.at.y - at.y) < config_.merged; });
    }
    for (size_t i = 0; i < hats_.size(); ++i) {
      Hat& h = hats_[i];
      if (h.colour != int(colour) || seen[i] || crossing[i] || free.empty()) continue;
      const double reach = config_.merged + config_.max_speed * h.coasting;
      auto nearest = std::min_element(free.begin(), free.end(), [&](const Blob& a, const Blob& b) {
        return std::hypot(a.at.x - h.filter.x(), a.at.y - h.filter.y()) < std::hypot(b.at.x - h.filter.x(), b.at.y - h.filter.y());
      });
      if (std::hypot(nearest->at.x - h.filter.x(), nearest->at.y - h.filter.y()) > reach) continue;
      // Where it was is all it knows: it starts afresh there.
      h.filter.reset();
      seen[i] = nearest->at;
      free.erase(nearest);
    }
  }
  for (size_t i = 0; i < hats_.size(); ++i) {
    Hat& h = hats_[i];
    if (seen[i]) h.filter.correct(seen[i]->x, seen[i]->y), h.coasting = h.lost = 0;
    else if (!crossing[i]) h.lost += dt;
  }
  return unheld;
}

// A blob no hat holds is someone new only once it has stayed free for a while: a speck of colour
// (a shirt, a reflection) comes and goes within a few frames, and a hat coming out of a crossing
// is taken back by its tracker within a frame or two.
void HatTracker::arrive(const std::vector<std::vector<Blob>>& free, double dt) {
  std::vector<Newcomer> still, ready;
  for (size_t colour = 0; colour < free.size(); ++colour)
    for (const Blob& b : free[colour]) {
      // The same newcomer as last frame: the nearest of its colour within a step of it.
      auto same = newcomers_.end();
      double best = config_.merged + config_.max_speed * dt;
      for (auto it = newcomers_.begin(); it != newcomers_.end(); ++it) {
        const double d = std::hypot(it->blob.at.x - b.at.x, it->blob.at.y - b.at.y);
        if (it->colour == colour && d < best) best = d, same = it;
      }
      Newcomer n{colour, b};
      if (same != newcomers_.end()) {
        n.blob.area = std::max(b.area, same->blob.area);
        n.seen = same->seen + dt;
        newcomers_.erase(same);
      }
      (n.seen >= config_.arrival ? ready : still).push_back(n);
    }
  newcomers_ = std::move(still);  // one not seen this frame is forgotten
  start(std::move(ready));
}

// A tracker per new hat, numbered within its team after the hats it already has, in order along
// x (then y) among those starting together.
void HatTracker::start(std::vector<Newcomer> hats) {
  std::sort(hats.begin(), hats.end(), [](const Newcomer& a, const Newcomer& b) {
    return a.blob.at.x != b.blob.at.x ? a.blob.at.x < b.blob.at.x : a.blob.at.y < b.blob.at.y;
  });
  for (const Newcomer& n : hats) {
    const std::string& team = config_.colours[n.colour].team;
    const long number = 1 + std::count_if(hats_.begin(), hats_.end(), [&](const Hat& h) { return h.team == team; });
    // The CamShift window: twice the hat's diameter, room for a step between frames.
    const int side = int(std::ceil(4 * std::sqrt(n.blob.area / M_PI)));
    Hat h{team + " " + std::to_string(number), team, int(n.colour),
          PointFilter(config_.filter_acceleration, config_.filter_measurement), side};
    h.filter.correct(n.blob.at.x, n.blob.at.y);
    hats_.push_back(std::move(h));
  }
}

TrackedFrame HatTracker::feed(const cv::Mat& bgr, int index, double t) {
  if (bgr.empty() || bgr.type() != CV_8UC3) throw TrackingError("frame " + std::to_string(index) + ": not a colour image");
  const bool first = !pose_;
  if (first) calibrate(bgr);
  masks(bgr);
  const double dt = first ? 0 : std::max(0.0, t - last_t_);
  last_t_ = t;
  if (first) {
    // The players in their places: a tracker per hat at once.
    std::vector<Newcomer> all;
    for (size_t k = 0; k < masks_.size(); ++k)
      for (const Blob& b : blobs(k)) all.push_back({k, b});
    start(std::move(all));
  } else {
    arrive(follow(bgr.size(), dt), dt);
  }
  TrackedFrame out;
  out.frame = index;
  out.t = t;
  for (const Hat& h : hats_) out.players.push_back({h.id, h.team, h.filter.x(), h.filter.y(), h.filter.vx(), h.filter.vy()});
  return out;
}

}  // namespace quantum::tracking

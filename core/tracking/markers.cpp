#include <opencv2/aruco.hpp>
#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>

#include "tracking/tracking.h"

namespace quantum::tracking {

TrackedField tracked_field(const Field& field, std::optional<Vec2> size) {
  TrackedField t;
  if (size) {
    t.length = size->x, t.width = size->y;
  } else {
    float x0 = 1e9f, x1 = -1e9f, y0 = 1e9f, y1 = -1e9f;
    for (const Segment& s : field.segments)
      for (Vec2 p : {s.a, s.b}) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    if (x1 <= x0 || y1 <= y0) throw TrackingError("the field has no walls to take its size from; give --field-size L,W");
    t.length = x1 - x0, t.width = y1 - y0;
  }
  if (!(t.length > 0 && t.width > 0)) throw TrackingError("the field's length and width must be > 0");
  for (const BodySpec& b : field.bodies) t.players.push_back({b.name, b.team, b.start.x < 0 ? -1 : 1});
  return t;
}

Vec2 marker_position(int id, float length, float width) {
  const float x = length / 2, y = width / 2;
  switch (id) {
    case 0: return {x, y};
    case 1: return {x, -y};
    case 2: return {-x, -y};
    case 3: return {-x, y};
  }
  throw std::invalid_argument("no playfield marker " + std::to_string(id));
}

CameraPose locate_camera(const cv::Mat& bgr, const TrackedField& field, const DepthCamera& camera) {
  std::vector<std::vector<cv::Point2f>> corners;
  std::vector<int> ids;
  const cv::Ptr<cv::aruco::Dictionary> dictionary = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50);
  cv::aruco::detectMarkers(bgr, dictionary, corners, ids, cv::aruco::DetectorParameters::create());
  std::vector<cv::Point3f> world;
  std::vector<cv::Point2f> image;
  std::string missing;
  for (int id = 0; id < 4; ++id) {
    const auto it = std::find(ids.begin(), ids.end(), id);
    if (it == ids.end()) {
      missing += (missing.empty() ? "" : ", ") + std::to_string(id);
      continue;
    }
    // The centre is where the diagonals cross: exact under perspective, unlike the corners' mean.
    const std::vector<cv::Point2f>& c = corners[size_t(it - ids.begin())];
    const cv::Point2f d1 = c[2] - c[0], d2 = c[3] - c[1], o = c[1] - c[0];
    const float den = d1.x * d2.y - d1.y * d2.x;
    const float s = std::fabs(den) > 1e-6f ? (o.x * d2.y - o.y * d2.x) / den : 0.5f;
    image.push_back(c[0] + s * d1);
    const Vec2 p = marker_position(id, field.length, field.width);
    world.emplace_back(p.x, p.y, 0.0f);
  }
  if (!missing.empty())
    throw TrackingError("playfield markers not found in the colour image: id " + missing +
                        " (ArUco DICT_4X4_50, ids 0-3 on the field's corners; see docs/tracking.md)");
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::Vec3d rvec, tvec;
  if (!cv::solvePnP(world, image, k, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE))
    throw TrackingError("the playfield markers give no camera pose (are they on the field's corners?)");
  CameraPose pose;
  cv::Rodrigues(rvec, pose.r);
  pose.t = tvec;
  // The camera must look down at the field from above (z up toward it).
  const cv::Vec3d centre = -(pose.r.t() * pose.t);
  if (centre[2] <= 0) throw TrackingError("the playfield markers put the camera below the field: check their ids");
  return pose;
}

}  // namespace quantum::tracking

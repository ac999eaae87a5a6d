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
    t.size_given = true;
  } else if (field.has_bounds) {  // a hall's court: its lines are the bounds, and its walls only posts
    t.length = field.bounds_max.x - field.bounds_min.x, t.width = field.bounds_max.y - field.bounds_min.y;
  } else {
    float x0 = 1e9f, x1 = -1e9f, y0 = 1e9f, y1 = -1e9f;
    for (const Segment& s : field.segments)
      for (Vec2 p : {s.a, s.b}) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    if (x1 <= x0 || y1 <= y0) throw TrackingError("the field has no walls to take its size from; give --field-size L,W");
    t.length = x1 - x0, t.width = y1 - y0;
  }
  if (!(t.length > 0 && t.width > 0)) throw TrackingError("the field's length and width must be > 0");
  for (const BodySpec& b : field.bodies) t.players.push_back({b.tracked_as(), b.team, b.start.x < 0 ? -1 : 1});
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

std::vector<MarkerImage> find_markers(const cv::Mat& bgr) {
  std::vector<std::vector<cv::Point2f>> corners;
  std::vector<int> ids;
  const cv::Ptr<cv::aruco::Dictionary> dictionary = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50);
  // Sub-pixel corners: the markers are the whole calibration, and a pixel's error at a corner
  // tilts the pose enough to move a hat 1.8 m up by decimetres.
  const cv::Ptr<cv::aruco::DetectorParameters> params = cv::aruco::DetectorParameters::create();
  params->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
  // A small window: the default (5 px) reaches past a marker's border when it is only a few
  // pixels a cell (2.4 m up), and the table's edge beside it pulled the corners outward by 1.6 px.
  params->cornerRefinementWinSize = 3;
  cv::aruco::detectMarkers(bgr, dictionary, corners, ids, params);
  std::vector<MarkerImage> found;
  for (int id = 0; id < 4; ++id) {
    const auto it = std::find(ids.begin(), ids.end(), id);
    if (it == ids.end()) continue;
    // The centre is where the diagonals cross: exact under perspective, unlike the corners' mean.
    const std::vector<cv::Point2f>& c = corners[size_t(it - ids.begin())];
    const cv::Point2f d1 = c[2] - c[0], d2 = c[3] - c[1], o = c[1] - c[0];
    const float den = d1.x * d2.y - d1.y * d2.x;
    const float s = std::fabs(den) > 1e-6f ? (o.x * d2.y - o.y * d2.x) / den : 0.5f;
    found.push_back({id, c[0] + s * d1, {c[0], c[1], c[2], c[3]}});
  }
  return found;
}

std::string missing_markers(const std::vector<MarkerImage>& found) {
  std::string missing;
  for (int id = 0; id < 4; ++id)
    if (std::none_of(found.begin(), found.end(), [&](const MarkerImage& m) { return m.id == id; }))
      missing += (missing.empty() ? "" : ", ") + std::to_string(id);
  return missing;
}

std::string markers_not_found(const std::vector<MarkerImage>& found) {
  return "playfield markers not found in the colour image: id " + missing_markers(found) +
         " (ArUco DICT_4X4_50, ids 0-3 on the field's corners; see docs/tracking.md).";
}

CameraPose locate_camera(const cv::Mat& bgr, const TrackedField& field, const DepthCamera& camera) {
  return locate_camera(find_markers(bgr), field, camera);
}

CameraPose locate_camera(const std::vector<MarkerImage>& found, const TrackedField& field, const DepthCamera& camera) {
  if (found.size() < 4) throw TrackingError(markers_not_found(found));
  std::vector<cv::Point3f> world;
  std::vector<cv::Point2f> image;
  for (const MarkerImage& m : found) {
    image.push_back(m.centre);
    const Vec2 p = marker_position(m.id, field.length, field.width);
    world.emplace_back(p.x, p.y, 0.0f);
  }
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::Vec3d rvec, tvec;
  if (!cv::solvePnP(world, image, k, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE))
    throw TrackingError("the playfield markers give no camera pose (are they on the field's corners?)");
  // Four points leave a camera looking straight down free to trade a shift for a tilt: invisible
  // on the floor, but a hat 1.8 m up moves with the shift (by 7 cm in the synthetic hall). The
  // markers' corners pin it down. Their size and turn are not part of the convention, so they
  // are read off the floor: every marker is the same square, of the mean side, turned as it lies.
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  const cv::Matx33d floor_to_image =
      k * cv::Matx33d(r(0, 0), r(0, 1), tvec[0], r(1, 0), r(1, 1), tvec[1], r(2, 0), r(2, 1), tvec[2]);
  const cv::Matx33d image_to_floor = floor_to_image.inv();
  auto on_floor = [&](cv::Point2f p) {
    const cv::Vec3d q = image_to_floor * cv::Vec3d(p.x, p.y, 1);
    return cv::Point2d(q[0] / q[2], q[1] / q[2]);
  };
  double side = 0;
  std::vector<double> turn;
  for (const MarkerImage& m : found) {
    const auto& c = m.corners;
    const cv::Point2d a = on_floor(c[0]), b = on_floor(c[1]), d = on_floor(c[3]);
    side += (std::hypot(b.x - a.x, b.y - a.y) + std::hypot(d.x - a.x, d.y - a.y)) / (2.0 * double(found.size()));
    turn.push_back(std::atan2(b.y - a.y, b.x - a.x));
  }
  std::vector<cv::Point3f> corner_world = world;
  std::vector<cv::Point2f> corner_image = image;
  for (size_t m = 0; m < found.size(); ++m) {
    // ArUco's corners go round the marker: top-left, top-right, bottom-right, bottom-left as
    // printed; a->b is the top edge. On the floor (y up) the next corner is a quarter turn clockwise.
    const double ux = std::cos(turn[m]) * side, uy = std::sin(turn[m]) * side;  // along the top edge
    const double vx = uy, vy = -ux;                                              // down the marker
    const double cx = world[m].x - (ux + vx) / 2, cy = world[m].y - (uy + vy) / 2;  // top-left corner
    const double offsets[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int j = 0; j < 4; ++j) {
      corner_world.emplace_back(float(cx + offsets[j][0] * ux + offsets[j][1] * vx),
                                float(cy + offsets[j][0] * uy + offsets[j][1] * vy), 0.0f);
      corner_image.push_back(found[m].corners[size_t(j)]);
    }
  }
  cv::solvePnP(corner_world, corner_image, k, cv::noArray(), rvec, tvec, true, cv::SOLVEPNP_ITERATIVE);
  CameraPose pose;
  cv::Rodrigues(rvec, pose.r);
  pose.t = tvec;
  // The camera must look down at the field from above (z up toward it).
  const cv::Vec3d centre = -(pose.r.t() * pose.t);
  if (centre[2] <= 0) throw TrackingError("the playfield markers put the camera below the field: check their ids");
  return pose;
}

}  // namespace quantum::tracking

// The depth pipeline's self-calibration: the table's plane from the empty table's depth, and the
// markers' centres on it.
#include <opencv2/core.hpp>

#include <cmath>

#include "tracking/tracking.h"

namespace quantum::tracking {

Plane fit_table(const cv::Mat& depth, const cv::Mat& region, const DepthCamera& camera) {
  std::vector<cv::Vec3d> points;
  // Every second pixel each way: tens of thousands of readings, plenty for three unknowns.
  for (int v = 0; v < depth.rows; v += 2) {
    const float* z = depth.ptr<float>(v);
    const uint8_t* in = region.ptr<uint8_t>(v);
    for (int u = 0; u < depth.cols; u += 2)
      if (in[u] && z[u] > 0)
        points.emplace_back((u - camera.cx) / camera.fx * z[u], (v - camera.cy) / camera.fy * z[u], z[u]);
  }
  Plane plane;
  double limit = INFINITY;
  for (int pass = 0; pass < 2; ++pass) {
    cv::Vec3d mean(0, 0, 0);
    size_t n = 0;
    for (const cv::Vec3d& p : points)
      if (std::fabs(plane.n.dot(p) - plane.d) <= limit) mean += p, ++n;
    if (n < 100) throw TrackingError("the empty table gave too few depth readings to find its plane (" +
                                     std::to_string(n) + "): is the Kinect 0.5-8 m above it?");
    mean /= double(n);
    cv::Matx33d scatter = cv::Matx33d::zeros();
    for (const cv::Vec3d& p : points)
      if (std::fabs(plane.n.dot(p) - plane.d) <= limit) scatter += (p - mean) * (p - mean).t();
    // The plane's normal is the direction the points spread least along.
    cv::Matx31d values;
    cv::Matx33d vectors;
    cv::eigen(scatter, values, vectors);
    cv::Vec3d normal(vectors(2, 0), vectors(2, 1), vectors(2, 2));
    if (normal[2] > 0) normal = -normal;  // toward the camera, which looks down along +z
    plane.n = normal;
    plane.d = normal.dot(mean);
    // At least 5 mm: a noiseless, level table would otherwise leave no point within the limit.
    limit = std::max(0.005, 3 * std::sqrt(std::max(values(2), 0.0) / double(n)));
  }
  return plane;
}

}  // namespace quantum::tracking

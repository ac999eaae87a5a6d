#include "snapshot.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>

namespace quantum::tools {
namespace {

constexpr int kPixelsPerMetre = 450;
constexpr int kMargin = 30;
constexpr int kLineHeight = 20;
constexpr size_t kDrawnPaths = 250;  // enough lines to see the fan, few enough to see each one
constexpr size_t kLegendGroups = 12;

cv::Scalar team_colour(const std::string& team) {
  if (team == "blue") return {230, 120, 40};
  if (team == "red") return {50, 50, 220};
  return {200, 200, 200};
}

cv::Scalar fate_colour(const FateGroup& g, const Field& f, size_t index) {
  // Groups of one kind differ in brightness so "via left wall" and "direct" stay apart.
  const double shade = 1.0 - 0.18 * double(index % 4);
  cv::Scalar c;
  switch (g.fate.kind) {
    case FateKind::Goal: c = {60, 210, 60}; break;
    case FateKind::OwnGoal: c = {0, 140, 255}; break;
    case FateKind::Body: c = team_colour(f.bodies[g.fate.target].team); break;
    case FateKind::Out: c = {200, 60, 200}; break;
    case FateKind::Field: c = {150, 150, 150}; break;
  }
  return c * shade;
}

}  // namespace

void write_snapshot(const World& world, const std::string& png, float horizon) {
  const Field& f = world.field();
  const FateReport report = world.predict(horizon);
  const float w = f.bounds_max.x - f.bounds_min.x, h = f.bounds_max.y - f.bounds_min.y;
  const int width = int(w * kPixelsPerMetre) + 2 * kMargin;
  const int field_height = int(h * kPixelsPerMetre) + 2 * kMargin;
  const int legend = int(std::min(report.groups.size(), kLegendGroups) + 3) * kLineHeight;
  cv::Mat img(field_height + legend, width, CV_8UC3, cv::Scalar(25, 25, 25));
  // Field y points up (to Blue's left), image rows point down.
  auto px = [&](Vec2 p) {
    return cv::Point(kMargin + int((p.x - f.bounds_min.x) * kPixelsPerMetre),
                     kMargin + int((f.bounds_max.y - p.y) * kPixelsPerMetre));
  };

  const Cloud& c = world.cloud();
  std::vector<size_t> sorted(report.groups.size());
  for (size_t g = 0; g < sorted.size(); ++g) sorted[g] = g;
  std::sort(sorted.begin(), sorted.end(),
            [&](size_t a, size_t b) { return report.groups[a].tweaked_mass > report.groups[b].tweaked_mass; });
  std::vector<size_t> rank(sorted.size());
  for (size_t k = 0; k < sorted.size(); ++k) rank[sorted[k]] = k;

  const size_t stride = std::max<size_t>(1, c.size() / kDrawnPaths);
  for (size_t i = 0; i < c.size(); i += stride) {
    const std::vector<Vec2> path = world.predict_path(i, horizon);
    const size_t g = report.group_of[i];
    for (size_t k = 1; k < path.size(); ++k)
      cv::line(img, px(path[k - 1]), px(path[k]), fate_colour(report.groups[g], f, rank[g]) * 0.55, 1, cv::LINE_AA);
  }
  for (const Segment& s : f.segments) cv::line(img, px(s.a), px(s.b), {235, 235, 235}, 3, cv::LINE_AA);
  for (const Goal& g : f.goals) cv::line(img, px(g.a), px(g.b), team_colour(g.team), 3, cv::LINE_AA);
  for (const Spot& s : f.spots) cv::drawMarker(img, px(s.at), {120, 120, 120}, cv::MARKER_CROSS, 10, 1);
  for (size_t k = 0; k < f.bodies.size(); ++k)
    cv::circle(img, px(world.body_positions()[k]), int(f.bodies[k].radius * kPixelsPerMetre),
               team_colour(f.bodies[k].team), 2, cv::LINE_AA);
  for (size_t i = 0; i < c.size(); ++i)
    cv::circle(img, px({c.x[i], c.y[i]}), 1, fate_colour(report.groups[report.group_of[i]], f, rank[report.group_of[i]]),
               cv::FILLED);

  int y = field_height + kLineHeight / 2;
  char line[256];
  std::snprintf(line, sizeof line, "t = %.2f s   %zu particles   horizon %.1f s   (Newtonian / tweaked)", world.time(),
                c.size(), horizon);
  cv::putText(img, line, {kMargin, y}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {220, 220, 220}, 1, cv::LINE_AA);
  for (size_t k : sorted) {
    if (rank[k] == kLegendGroups) {
      y += kLineHeight;
      std::snprintf(line, sizeof line, "... and %zu rarer fates", sorted.size() - kLegendGroups);
      cv::putText(img, line, {kMargin, y}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {160, 160, 160}, 1, cv::LINE_AA);
      break;
    }
    const FateGroup& g = report.groups[k];
    y += kLineHeight;
    std::snprintf(line, sizeof line, "%5.1f%% / %5.1f%%  %6u  %s", 100 * g.mass, 100 * g.tweaked_mass, g.count,
                  describe(g.fate, f).c_str());
    cv::putText(img, line, {kMargin, y}, cv::FONT_HERSHEY_SIMPLEX, 0.45, fate_colour(g, f, rank[k]), 1, cv::LINE_AA);
  }
  if (!cv::imwrite(png, img)) throw std::runtime_error("cannot write snapshot " + png);
}

}  // namespace quantum::tools

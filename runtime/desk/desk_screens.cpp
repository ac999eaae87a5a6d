#include "desk_screens.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace quantum::runtime {
namespace {

const cv::Scalar kBar(60, 60, 60), kPlayed(120, 120, 120), kHead(40, 215, 255), kText(235, 235, 235),
    kDim(160, 160, 160), kError(50, 50, 255);  // brighter than the red team's
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

void text(cv::Mat& img, const std::string& s, cv::Point at, const cv::Scalar& colour, double size = 0.5) {
  cv::putText(img, s, at, kFont, size, colour, 1, cv::LINE_AA);
}

int text_width(const std::string& s, double size) {
  int baseline = 0;
  return cv::getTextSize(s, kFont, size, 1, &baseline).width;
}

// `s` broken at spaces (or anywhere, in a word wider than a line) into lines of at most
// `width` pixels.
std::vector<std::string> wrapped(const std::string& s, int width, double size) {
  std::vector<std::string> lines;
  std::string line;
  size_t k = 0;
  while (k < s.size()) {
    const size_t end = std::min(s.find(' ', k + 1), s.size());
    const std::string word = s.substr(k, end - k);
    if (!line.empty() && text_width(line + word, size) > width) {
      lines.push_back(line);
      line = word.substr(word.front() == ' ' ? 1 : 0);
    } else {
      line += word;
    }
    while (text_width(line, size) > width && line.size() > 1) {
      size_t fits = line.size() - 1;
      while (fits > 1 && text_width(line.substr(0, fits), size) > width) --fits;
      lines.push_back(line.substr(0, fits));
      line = line.substr(fits);
    }
    k = end;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

// A dark panel over `area` of `image`, the picture still faintly seen through it.
void panel(cv::Mat& image, cv::Rect area) {
  area &= cv::Rect(0, 0, image.cols, image.rows);
  cv::Mat roi = image(area);
  roi.convertTo(roi, -1, 0.25, 8);
}

}  // namespace

std::string clock_text(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%d:%05.2f", int(t / 60), std::fmod(std::max(0.0, t), 60.0));
  return buf;
}

double TimeBar::time_at(int x, int width) const {
  const int left = 10, right = width - 10;
  const double t = length * double(x - left) / std::max(1, right - left);
  return std::clamp(t, 0.0, played);
}

void draw_time_bar(const TimeBar& bar, cv::Mat& strip) {
  strip.setTo(cv::Scalar(28, 28, 28));
  const int left = 10, right = strip.cols - 10, y = 8, h = 8;
  auto column = [&](double t) { return left + int((right - left) * std::clamp(t / std::max(bar.length, 1e-9), 0.0, 1.0)); };
  cv::rectangle(strip, cv::Rect(left, y, right - left, h), kBar, cv::FILLED);
  cv::rectangle(strip, cv::Rect(left, y, column(bar.played) - left, h), kPlayed, cv::FILLED);
  cv::rectangle(strip, cv::Rect(column(bar.now) - 2, y - 4, 5, h + 8), kHead, cv::FILLED);
  if (bar.pointed >= 0) {
    const int x = column(bar.pointed);
    cv::line(strip, {x, y - 3}, {x, y + h + 2}, kText, 1);
  }
  char speed[32];
  std::snprintf(speed, sizeof speed, "speed %gx", bar.speed);
  std::string line = clock_text(bar.now) + " / " + clock_text(bar.length) + "   " + speed;
  if (!bar.note.empty()) line += "   " + bar.note;
  if (bar.pointed >= 0) line += "   (click: go to " + clock_text(bar.pointed) + ")";
  text(strip, line, {left, y + h + 18}, kText, 0.45);
  // The keys in one line: smaller in a narrow window rather than cut off.
  const double keys_size = std::clamp(0.4 * (right - left) / std::max(1, text_width(bar.keys, 0.4)), 0.3, 0.4);
  text(strip, bar.keys, {left, y + h + 38}, kDim, keys_size);
}

void draw_problems(std::span<const Session::Problem> problems, cv::Mat& image) {
  if (problems.empty()) return;
  const double size = 0.5;
  const int line_height = 20, width = image.cols - 60;
  std::vector<std::pair<std::string, cv::Scalar>> lines;
  for (const Session::Problem& p : problems) {
    lines.push_back({p.kind, kError});
    for (const std::string& l : wrapped(p.text, width, size)) lines.push_back({l, kText});
    lines.push_back({"", kText});
  }
  lines.push_back({"Fix the script and save it: it reloads.  Enter: dismiss   q: quit", kDim});
  const int height = std::min(image.rows, int(lines.size()) * line_height + 50);
  panel(image, cv::Rect(0, 0, image.cols, height));
  // A red rule under the panel: seen at a glance, and at any scale of the window.
  cv::rectangle(image, cv::Rect(0, height - 4, image.cols, 4), kError, cv::FILLED);
  text(image, "Error", {30, 30}, kError, 0.7);
  int y = 30 + line_height + 6;
  for (const auto& [l, colour] : lines) {
    if (y > height - 6) break;
    text(image, l, {30, y}, colour, size);
    y += line_height;
  }
}

void draw_final_whistle(const std::string& score, cv::Mat& image) {
  const int h = 90, top = std::max(0, (image.rows - h) / 2);
  panel(image, cv::Rect(0, top, image.cols, h));
  text(image, "Final whistle", {30, top + 30}, kHead, 0.7);
  text(image, score, {30, top + 56}, kText, 0.6);
  text(image, "any key or closing the window ends; arrows and the time bar look back", {30, top + 78}, kDim, 0.45);
}

}  // namespace quantum::runtime

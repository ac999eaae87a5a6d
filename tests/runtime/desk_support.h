// What the desk's tests share: a shell command's output, a picture's pixels of one colour, and a
// folder of the test process's own (CTest runs tests side by side).
#pragma once

#include <opencv2/core.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

namespace quantum::test {

// What a shell command prints, stdout and stderr alike.
inline std::string output_of(const std::string& command) {
  std::string out;
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) return out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
  pclose(p);
  return out;
}

// Pixels of `image` within 12 of colour (B, G, R) on every channel.
inline int pixels_of(const cv::Mat& image, cv::Vec3b colour) {
  int n = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      n += std::abs(p[0] - colour[0]) < 12 && std::abs(p[1] - colour[1]) < 12 && std::abs(p[2] - colour[2]) < 12;
    }
  return n;
}

// A new empty folder of this test process's own, removed with it.
struct TempFolder {
  std::filesystem::path path;
  explicit TempFolder(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("quantum_" + name + "_" + std::to_string(getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempFolder() { std::filesystem::remove_all(path); }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
};

}  // namespace quantum::test

// Kinect recordings in libfreenect's own record format ("fakenect"), read and written directly,
// no device or libfreenect needed. A recording is a directory: INDEX.txt lists the files in
// playback order, named `%c-%f-%u.%s` (type, wall-clock seconds, device timestamp, extension):
// d-*.pgm raw 11-bit depth (P5 640 480 65535, host byte order), r-*.ppm RGB (P6 640 480 255),
// a-*.dump the accelerometer and tilt state.
#pragma once

#include <opencv2/core.hpp>

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace quantum::tracking {

// A recording that cannot be read: the message names the file and, for a frame, its number.
struct RecordingError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct RecordedFrame {
  int index = 0;      // depth frames counted from 0
  double t = 0;       // seconds since the recording's first file
  cv::Mat depth;      // CV_16UC1 raw disparity
  cv::Mat rgb;        // CV_8UC3 in BGR order: the latest colour frame at or before this depth frame (may be empty)
  std::string file;   // the depth file
};

class FakenectReader {
 public:
  // Throws RecordingError when the directory has no readable INDEX.txt.
  explicit FakenectReader(std::string dir);

  // The next depth frame; false after the last. Throws RecordingError for a file that is
  // missing, truncated or not what its name says.
  bool next(RecordedFrame& out);

  const std::string& dir() const { return dir_; }
  // Frames skipped so far because their name's time was not a number or went back.
  size_t dropped() const { return dropped_; }

 private:
  std::string dir_;
  std::vector<std::string> files_;
  size_t cursor_ = 0;
  int frames_ = 0;
  double t0_ = -1, last_t_ = 0;
  size_t dropped_ = 0;
  cv::Mat rgb_;
};

class FakenectWriter {
 public:
  // Creates the directory; throws RecordingError when it cannot.
  explicit FakenectWriter(std::string dir);
  ~FakenectWriter();

  void depth(double t, const cv::Mat& raw);  // CV_16UC1
  void rgb(double t, const cv::Mat& bgr);    // CV_8UC3, BGR order (written as RGB)
  void accel(double t);                      // a level, still Kinect

 private:
  std::string name(char type, double t, const char* extension);
  std::string dir_;
  std::ofstream index_;
  uint32_t timestamp_ = 0;
};

}  // namespace quantum::tracking

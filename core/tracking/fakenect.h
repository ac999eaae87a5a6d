// Kinect recordings in libfreenect's own record format ("fakenect"), read and written directly,
// no device or libfreenect needed. A recording is a directory: INDEX.txt lists the files,
// named `%c-%f-%u.%s` (type, wall-clock seconds, device timestamp, extension):
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

// Reading a recording is reading data others wrote: a file that cannot be a frame is dropped and
// counted, never a reason to stop (docs/tracking.md, "Bad input"). Frames play in the order of
// their names' times, whatever INDEX.txt's order; a frame whose time lies more than kGap past the
// others (or before them) is dropped. Nothing but a regular file is opened, and no more is read
// than a frame's header says it holds.
class FakenectReader {
 public:
  // Seconds between two files' times beyond which they are not one recording: the files on the
  // side with fewer depth frames are dropped.
  static constexpr double kGap = 5;

  // Throws RecordingError when the directory has no readable INDEX.txt.
  explicit FakenectReader(std::string dir);

  // The next depth frame; false after the last. A file that is missing, not a regular file,
  // truncated or not what its name says is dropped and counted. Throws RecordingError when the
  // recording is over without a single depth frame read.
  bool next(RecordedFrame& out);

  const std::string& dir() const { return dir_; }
  // Files dropped so far: an INDEX.txt line too long or not a name `%c-%f-%u.%s`, a time that is
  // not a number or lies apart from the recording's, and frames that could not be read.
  size_t dropped() const { return dropped_; }
  // The file last dropped for what it holds and why ("" when none was): "DIR/d-...pgm: truncated,
  // 1000 of 614400 bytes of samples".
  const std::string& last_dropped() const { return last_dropped_; }

 private:
  struct File {
    char type;
    double time;  // the name's seconds
    std::string name;
  };
  std::string dir_;
  std::vector<File> files_;
  size_t cursor_ = 0;
  int frames_ = 0;
  double t0_ = 0;
  size_t dropped_ = 0;
  std::string last_dropped_;
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

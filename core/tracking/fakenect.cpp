#include "tracking/fakenect.h"

#include <libfreenect.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace quantum::tracking {
namespace fs = std::filesystem;

namespace {

// Wall-clock seconds from a name `%c-%f-%u.%s`; -1 when it does not parse, NaN when the time is
// not a finite number ("nan", "inf").
double time_of(const std::string& name) {
  if (name.size() < 4 || name[1] != '-') return -1;
  char* end = nullptr;
  const double t = std::strtod(name.c_str() + 2, &end);
  if (!end || *end != '-') return -1;
  return std::isfinite(t) && t >= 0 ? t : std::nan("");
}

// A binary PNM (P5 or P6) as libfreenect writes it. `what` names the file and frame in errors.
cv::Mat read_pnm(const fs::path& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RecordingError(what + ": cannot open");
  std::string magic;
  long width = 0, height = 0, maxval = 0;
  in >> magic >> width >> height >> maxval;
  if (!in || (magic != "P5" && magic != "P6") || width <= 0 || height <= 0 || width > 8192 || height > 8192 ||
      maxval <= 0 || maxval > 65535)
    throw RecordingError(what + ": not a binary PGM/PPM file");
  in.get();  // the single whitespace before the samples
  const bool colour = magic == "P6", wide = maxval > 255;
  if (colour == wide) throw RecordingError(what + ": expected 16-bit depth (P5) or 8-bit colour (P6)");
  cv::Mat m(int(height), int(width), colour ? CV_8UC3 : CV_16UC1);
  const size_t bytes = m.total() * m.elemSize();
  in.read(reinterpret_cast<char*>(m.data), std::streamsize(bytes));
  if (size_t(in.gcount()) != bytes)
    throw RecordingError(what + ": truncated, " + std::to_string(in.gcount()) + " of " + std::to_string(bytes) +
                         " bytes of samples");
  // Depth is in host byte order (not PGM's big-endian), colour in RGB order.
  if (colour) cv::cvtColor(m, m, cv::COLOR_RGB2BGR);
  return m;
}

}  // namespace

FakenectReader::FakenectReader(std::string dir) : dir_(std::move(dir)) {
  const fs::path index = fs::path(dir_) / "INDEX.txt";
  std::ifstream in(index);
  if (!in) throw RecordingError(index.string() + ": no such file (not a fakenect recording?)");
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) files_.push_back(line);
  }
}

bool FakenectReader::next(RecordedFrame& out) {
  while (cursor_ < files_.size()) {
    const std::string& name = files_[cursor_++];
    const double wall = time_of(name);
    const fs::path path = fs::path(dir_) / name;
    const std::string what = path.string() + " (depth frame " + std::to_string(frames_) + ")";
    if (wall < 0) throw RecordingError(what + ": the name is not type-seconds-timestamp.ext");
    // A frame whose time is not a number, or goes back, cannot be placed: dropped and counted.
    if (std::isnan(wall) || (name[0] == 'd' && t0_ >= 0 && wall - t0_ < last_t_)) {
      ++dropped_;
      continue;
    }
    if (t0_ < 0) t0_ = wall;
    if (name[0] == 'r') {
      rgb_ = read_pnm(path, path.string());
      if (rgb_.type() != CV_8UC3) throw RecordingError(path.string() + ": a colour frame must be a PPM");
    } else if (name[0] == 'd') {
      out.depth = read_pnm(path, what);
      if (out.depth.type() != CV_16UC1) throw RecordingError(what + ": a depth frame must be a 16-bit PGM");
      out.rgb = rgb_;
      out.index = frames_++;
      out.t = last_t_ = wall - t0_;
      out.file = path.string();
      return true;
    }
    // 'a': the tilt state, which the pipelines do not use.
  }
  return false;
}

FakenectWriter::FakenectWriter(std::string dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  index_.open(fs::path(dir_) / "INDEX.txt");
  if (ec || !index_) throw RecordingError(dir_ + ": cannot create the recording");
}

FakenectWriter::~FakenectWriter() = default;

std::string FakenectWriter::name(char type, double t, const char* extension) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%c-%f-%u.%s", type, t, timestamp_, extension);
  index_ << buf << '\n';
  return (fs::path(dir_) / buf).string();
}

void FakenectWriter::depth(double t, const cv::Mat& raw) {
  CV_Assert(raw.type() == CV_16UC1 && raw.isContinuous());
  ++timestamp_;  // the device's own frame clock; the pipelines go by the wall-clock seconds
  std::ofstream out(name('d', t, "pgm"), std::ios::binary);
  out << "P5 " << raw.cols << ' ' << raw.rows << " 65535\n";
  out.write(reinterpret_cast<const char*>(raw.data), std::streamsize(raw.total() * raw.elemSize()));
}

void FakenectWriter::rgb(double t, const cv::Mat& bgr) {
  CV_Assert(bgr.type() == CV_8UC3);
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  std::ofstream out(name('r', t, "ppm"), std::ios::binary);
  out << "P6 " << rgb.cols << ' ' << rgb.rows << " 255\n";
  out.write(reinterpret_cast<const char*>(rgb.data), std::streamsize(rgb.total() * rgb.elemSize()));
}

void FakenectWriter::accel(double t) {
  freenect_raw_tilt_state state{};
  state.accelerometer_z = 819;  // 1 g along the camera's axis: looking straight down
  std::ofstream out(name('a', t, "dump"), std::ios::binary);
  out.write(reinterpret_cast<const char*>(&state), sizeof state);
}

}  // namespace quantum::tracking

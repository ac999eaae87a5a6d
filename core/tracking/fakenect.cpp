#include "tracking/fakenect.h"

#include <libfreenect.h>
#include <unistd.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "system/regular_file.h"
#include "tracking/kinect.h"
#include "tracking/lines.h"

namespace quantum::tracking {
namespace fs = std::filesystem;

namespace {

// A PGM/PPM header is a few dozen bytes; comments may make it longer, never this long.
constexpr size_t kLongestHeader = 1024;

// Wall-clock seconds from a name `%c-%f-%u.%s`; -1 when it does not parse, NaN when the time is
// not a finite number ("nan", "inf") or is negative.
double time_of(const std::string& name) {
  if (name.size() < 4 || name[1] != '-') return -1;
  char* end = nullptr;
  const double t = std::strtod(name.c_str() + 2, &end);
  if (!end || *end != '-') return -1;
  return std::isfinite(t) && t >= 0 ? t : std::nan("");
}

// Up to `n` bytes at `offset`; how many were read.
size_t read_at(int fd, char* to, size_t n, off_t offset) {
  size_t got = 0;
  while (got < n) {
    const ssize_t k = ::pread(fd, to + got, n - got, offset + off_t(got));
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) break;
    got += size_t(k);
  }
  return got;
}

// A binary PNM as libfreenect writes it: 16-bit depth (P5) or 8-bit colour (P6), the Kinect's
// 640 x 480. Empty, with `why`, for anything else. Comments ('#' to the end of the line) may come
// between the header's fields; no more than the header and the samples it announces is read.
cv::Mat read_pnm(const fs::path& path, bool depth, std::string& why) {
  off_t size = 0;
  const int fd = system::open_regular(path, why, &size);
  if (fd < 0) return {};
  const system::FileDescriptor closer(fd);
  char head[kLongestHeader];
  const size_t n = read_at(fd, head, sizeof head, 0);
  size_t at = 2;
  // The next field, after whitespace and comments; false when the header has no such number.
  auto number = [&](long& v) {
    for (;;) {
      while (at < n && std::isspace(static_cast<unsigned char>(head[at]))) ++at;
      if (at >= n || head[at] != '#') break;
      while (at < n && head[at] != '\n') ++at;
    }
    if (at >= n || !std::isdigit(static_cast<unsigned char>(head[at]))) return false;
    for (v = 0; at < n && std::isdigit(static_cast<unsigned char>(head[at])) && v < 1000000; ++at)
      v = 10 * v + (head[at] - '0');
    return at < n && std::isspace(static_cast<unsigned char>(head[at]));
  };
  long width = 0, height = 0, maxval = 0;
  if (n < 2 || head[0] != 'P' || (head[1] != '5' && head[1] != '6') || !number(width) || !number(height) ||
      !number(maxval) || maxval <= 0 || maxval > 65535) {
    why = "not a binary PGM/PPM file";
    return {};
  }
  ++at;  // the single whitespace before the samples
  const DepthCamera kinect;
  const bool colour = head[1] == '6', wide = maxval > 255;
  if (width != kinect.width || height != kinect.height || colour == depth || colour == wide) {
    why = std::string("expected ") + std::to_string(kinect.width) + "x" + std::to_string(kinect.height) +
          (depth ? " 16-bit depth (P5)" : " 8-bit colour (P6)") + ", not " + std::to_string(width) + "x" +
          std::to_string(height) + (colour ? " P6" : " P5") + " with maxval " + std::to_string(maxval);
    return {};
  }
  cv::Mat m(int(height), int(width), colour ? CV_8UC3 : CV_16UC1);
  const size_t bytes = m.total() * m.elemSize();
  const size_t got = size_t(size) > at ? read_at(fd, reinterpret_cast<char*>(m.data), bytes, off_t(at)) : 0;
  if (got != bytes) {
    why = "truncated, " + std::to_string(got) + " of " + std::to_string(bytes) + " bytes of samples";
    return {};
  }
  // Depth is in host byte order (not PGM's big-endian), colour in RGB order.
  if (colour) cv::cvtColor(m, m, cv::COLOR_RGB2BGR);
  return m;
}

}  // namespace

FakenectReader::FakenectReader(std::string dir) : dir_(std::move(dir)) {
  const fs::path index = fs::path(dir_) / "INDEX.txt";
  std::string why;
  const int fd = system::open_regular(index, why);
  if (fd < 0) throw RecordingError(index.string() + " " + why + " (not a fakenect recording?)");
  BoundedLines lines(fd);
  for (std::string line;;) {
    const BoundedLines::Line got = lines.next(line);
    if (got == BoundedLines::Line::End) break;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (got == BoundedLines::Line::Read && line.empty()) continue;
    // A line too long, a name that is not `%c-%f-%u.%s` of a file in the folder, or a time that
    // is not a number cannot be placed: dropped and counted.
    const double t = got == BoundedLines::Line::Read ? time_of(line) : -1;
    const bool named = line[0] == 'd' || line[0] == 'r' || line[0] == 'a';
    if (!(t >= 0) || !named || line.find_first_of(std::string("/\0", 2)) != std::string::npos) {
      ++dropped_;
      continue;
    }
    files_.push_back({line[0], t, line});
  }
  dropped_ += lines.cut();  // an INDEX.txt past what is read: one drop, told with the others
  // Played in the order of their times (INDEX.txt's order may be shuffled); at equal times the
  // colour frame first, as libfreenect writes them, so that it goes with the depth frame. A
  // recording is one run of files no more than kGap apart: the run with the most depth frames
  // plays, the others (a time far past the rest, or far before) are dropped.
  auto rank = [](char type) { return type == 'r' ? 0 : type == 'd' ? 1 : 2; };
  std::stable_sort(files_.begin(), files_.end(), [&](const File& a, const File& b) {
    return a.time < b.time || (a.time == b.time && rank(a.type) < rank(b.type));
  });
  size_t first = 0, last = 0, most = 0;
  for (size_t begin = 0, end = 0; begin < files_.size(); begin = end) {
    size_t depth = 0;
    for (end = begin; end < files_.size() && (end == begin || files_[end].time - files_[end - 1].time <= kGap); ++end)
      depth += files_[end].type == 'd';
    if (depth > most) first = begin, last = end, most = depth;
  }
  dropped_ += files_.size() - (last - first);
  files_.erase(files_.begin() + long(last), files_.end());
  files_.erase(files_.begin(), files_.begin() + long(first));
  if (!files_.empty()) t0_ = files_.front().time;
}

bool FakenectReader::next(RecordedFrame& out) {
  while (cursor_ < files_.size()) {
    const File& file = files_[cursor_++];
    if (file.type == 'a') continue;  // the tilt state, which the pipelines do not use
    const fs::path path = fs::path(dir_) / file.name;
    std::string why;
    cv::Mat m = read_pnm(path, file.type == 'd', why);
    if (m.empty()) {
      ++dropped_;
      last_dropped_ = path.string() + ": " + why;
      continue;
    }
    if (file.type == 'r') {
      rgb_ = std::move(m);
      continue;
    }
    out.depth = std::move(m);
    out.rgb = rgb_;
    out.index = frames_++;
    out.t = file.time - t0_;
    out.file = path.string();
    return true;
  }
  if (frames_ == 0)
    throw RecordingError(dir_ + ": no depth frame could be read, " + std::to_string(dropped_) + " file" +
                         (dropped_ == 1 ? "" : "s") + " dropped" +
                         (last_dropped_.empty() ? "" : " (the last: " + last_dropped_ + ")"));
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

#include "video.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "output_files.h"
#include "quantum/limits.h"

namespace quantum::runtime {
namespace {

// A container ffmpeg writes, by the name's ending, with the codecs the players of that kind of
// file expect: H.264 for the ones every player plays; Motion JPEG in AVI, which editors and old
// players take where they balk at H.264 in it; VP9 and Opus, the codecs WebM allows (Debian's
// ffmpeg has libvpx and libopus).
struct Container {
  const char* ending;
  const char* format;  // ffmpeg's -f
  const char* video;   // the video's codec and settings
  const char* audio;   // the sound's
  const char* name;    // for the confirmation line
};

constexpr const char* kH264 = "-c:v libx264 -preset veryfast -crf 20 -pix_fmt yuv420p";
constexpr Container kContainers[] = {
    {".mp4", "mp4", kH264, "-c:a aac -b:a 160k", "H.264 in MP4"},
    {".mov", "mov", kH264, "-c:a aac -b:a 160k", "H.264 in QuickTime"},
    {".mkv", "matroska", kH264, "-c:a aac -b:a 160k", "H.264 in Matroska"},
    {".avi", "avi", "-c:v mjpeg -q:v 3 -pix_fmt yuvj420p", "-c:a pcm_s16le", "Motion JPEG in AVI"},
    // libvpx's fastest settings: its defaults took minutes for a minute of match.
    {".webm", "webm", "-c:v libvpx-vp9 -deadline realtime -cpu-used 8 -row-mt 1 -crf 32 -b:v 0 -pix_fmt yuv420p",
     "-c:a libopus -b:a 128k", "VP9 in WebM"},
};

std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool have_ffmpeg() { return std::system("command -v ffmpeg > /dev/null 2>&1") == 0; }

// The container `path`'s ending names (in any case: MATCH.MP4), or nothing.
const Container* container_of(const std::string& path) {
  std::string ending = std::filesystem::path(path).extension().string();
  std::transform(ending.begin(), ending.end(), ending.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const Container& c : kContainers)
    if (ending == c.ending) return &c;
  return nullptr;
}

}  // namespace

std::string video_endings() {
  std::string listed;
  const size_t n = std::size(kContainers);
  for (size_t k = 0; k < n; ++k) listed += (k == 0 ? "" : k + 1 == n ? " or " : ", ") + std::string(kContainers[k].ending);
  return listed;
}

void check_video_file(const std::string& path) {
  if (!container_of(path)) {
    const std::string ending = std::filesystem::path(path).extension().string();
    throw std::runtime_error("--video " + path + ": " +
                             (ending.empty() ? "no ending names its container" : ending + " names no container quantum writes") +
                             "; name it " + video_endings() + " (the container follows the ending)");
  }
  if (!have_ffmpeg()) throw std::runtime_error("--video needs ffmpeg (Debian's package ffmpeg; tools/setup.sh installs it)");
  check_output_file("--video", path);
}

VideoFile::VideoFile(const std::string& path, int width, int height, double fps)
    : path_(path), width_(width + width % 2), height_(height + height % 2), fps_(fps) {
  if (!limits::kVideoFps.contains(fps)) throw std::runtime_error("--video: the frame rate " + limits::must_be_in(limits::kVideoFps, fps));
  check_video_file(path);
  const Container& c = *container_of(path);
  silent_ = path + ".video" + c.ending;
  // A player that is gone must not kill the match with SIGPIPE: the write fails and says so.
  std::signal(SIGPIPE, SIG_IGN);
  char size[32];
  std::snprintf(size, sizeof size, "%dx%d", width_, height_);
  const std::string command = "ffmpeg -y -loglevel error -f rawvideo -pix_fmt bgr24 -s " + std::string(size) + " -r " +
                              std::to_string(fps) + " -i - " + c.video + " -f " + c.format + " " + shell_quoted(silent_);
  ffmpeg_ = popen(command.c_str(), "w");
  if (!ffmpeg_) throw std::runtime_error("--video: cannot start ffmpeg");
}

VideoFile::~VideoFile() {
  // Closed before finish (the match failed): the half-made video goes.
  if (ffmpeg_) pclose(ffmpeg_);
  std::error_code ignored;
  std::filesystem::remove(silent_, ignored);
}

void VideoFile::add(const cv::Mat& frame) {
  if (!ffmpeg_) return;
  cv::copyMakeBorder(frame, padded_, 0, height_ - frame.rows, 0, width_ - frame.cols, cv::BORDER_REPLICATE);
  if (padded_.rows != height_ || padded_.cols != width_) throw std::runtime_error("--video: the picture changed its size");
  if (std::fwrite(padded_.data, 1, padded_.total() * padded_.elemSize(), ffmpeg_) != padded_.total() * padded_.elemSize())
    throw std::runtime_error("--video " + path_ + ": ffmpeg stopped taking frames");
  ++frames_;
}

void VideoFile::finish(const std::string& wav) {
  if (!ffmpeg_) return;
  const int status = pclose(ffmpeg_);
  ffmpeg_ = nullptr;
  if (status != 0) {
    std::filesystem::remove(silent_);
    throw std::runtime_error("--video " + path_ + ": ffmpeg failed to encode the video");
  }
  if (wav.empty()) {
    std::filesystem::rename(silent_, path_);
    return;
  }
  const Container& c = *container_of(path_);
  const std::string mux = "ffmpeg -y -loglevel error -i " + shell_quoted(silent_) + " -i " + shell_quoted(wav) +
                          " -c:v copy " + c.audio + " -shortest -f " + c.format + " " + shell_quoted(path_);
  const int muxed = std::system(mux.c_str());
  std::filesystem::remove(silent_);
  if (muxed != 0) throw std::runtime_error("--video " + path_ + ": ffmpeg could not add the sound of " + wav);
  sound_ = true;
}

std::string VideoFile::describe() const {
  char text[160];
  std::snprintf(text, sizeof text, "%.1f s, %d frames, %dx%d, %s%s", frames_ / fps_, frames_, width_, height_,
                container_of(path_)->name, sound_ ? ", with sound" : "");
  return text;
}

}  // namespace quantum::runtime

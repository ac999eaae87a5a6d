#include "video.h"

#include <opencv2/imgproc.hpp>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "output_files.h"

namespace quantum::runtime {
namespace {

std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool have_ffmpeg() { return std::system("command -v ffmpeg > /dev/null 2>&1") == 0; }

}  // namespace

VideoFile::VideoFile(const std::string& path, int width, int height, double fps)
    : path_(path), silent_(path + ".video.mp4"), width_(width + width % 2), height_(height + height % 2), fps_(fps) {
  if (!(fps >= 1 && fps <= 240)) throw std::runtime_error("--video: the frame rate must be in [1, 240]");
  if (!have_ffmpeg()) throw std::runtime_error("--video needs ffmpeg (Debian's package ffmpeg; tools/setup.sh installs it)");
  check_output_file("--video", path);
  // A player that is gone must not kill the match with SIGPIPE: the write fails and says so.
  std::signal(SIGPIPE, SIG_IGN);
  char size[32];
  std::snprintf(size, sizeof size, "%dx%d", width_, height_);
  const std::string command = "ffmpeg -y -loglevel error -f rawvideo -pix_fmt bgr24 -s " + std::string(size) + " -r " +
                              std::to_string(fps) + " -i - -c:v libx264 -preset veryfast -crf 20 -pix_fmt yuv420p " +
                              shell_quoted(silent_);
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
  const std::string mux = "ffmpeg -y -loglevel error -i " + shell_quoted(silent_) + " -i " + shell_quoted(wav) +
                          " -c:v copy -c:a aac -b:a 160k -shortest " + shell_quoted(path_);
  const int muxed = std::system(mux.c_str());
  std::filesystem::remove(silent_);
  if (muxed != 0) throw std::runtime_error("--video " + path_ + ": ffmpeg could not add the sound of " + wav);
}

}  // namespace quantum::runtime

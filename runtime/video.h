// A match rendered to a video file a normal player plays: frames piped to Debian's ffmpeg
// (H.264 in MP4), the match's sound muxed in when it was rendered to a WAV file.
#pragma once

#include <opencv2/core.hpp>

#include <cstdio>
#include <string>

namespace quantum::runtime {

class VideoFile {
 public:
  // Starts ffmpeg writing `path` at `fps` frames a second, frames of width x height (made even).
  // Throws std::runtime_error when ffmpeg is missing or the file cannot be written.
  VideoFile(const std::string& path, int width, int height, double fps);
  ~VideoFile();
  VideoFile(const VideoFile&) = delete;
  VideoFile& operator=(const VideoFile&) = delete;

  // Appends one frame (the picture of the match at the video's next frame time).
  void add(const cv::Mat& frame);
  // Closes the video; with `wav`, its sound is muxed in (AAC). Throws when ffmpeg failed.
  void finish(const std::string& wav = "");
  double fps() const { return fps_; }
  int frames() const { return frames_; }

 private:
  std::string path_, silent_;  // the file, and the video without sound while it is written
  int width_, height_;
  double fps_;
  int frames_ = 0;
  FILE* ffmpeg_ = nullptr;
  cv::Mat padded_;
};

}  // namespace quantum::runtime

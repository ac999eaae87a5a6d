// A match rendered to a video file a normal player plays: frames piped to Debian's ffmpeg, the
// match's sound muxed in when it was rendered to a WAV file. The container follows the file's
// name: .mp4, .mov and .mkv hold H.264 (the sound AAC), .avi Motion JPEG (PCM), .webm VP9 (Opus);
// any other name is refused before the match starts.
#pragma once

#include <opencv2/core.hpp>

#include <cstdio>
#include <string>

namespace quantum::runtime {

// The endings a video's name may have, for messages: ".mp4, .mov, .mkv, .avi or .webm".
std::string video_endings();

// Throws std::runtime_error naming --video when no video can be written at `path`: its ending is
// none of video_endings(), ffmpeg is missing, or check_output_file refuses it. Creates nothing.
void check_video_file(const std::string& path);

class VideoFile {
 public:
  // Starts ffmpeg writing `path` at `fps` frames a second, frames of width x height (made even).
  // Throws std::runtime_error as check_video_file does, or when ffmpeg cannot be started.
  VideoFile(const std::string& path, int width, int height, double fps);
  ~VideoFile();
  VideoFile(const VideoFile&) = delete;
  VideoFile& operator=(const VideoFile&) = delete;

  // Appends one frame (the picture of the match at the video's next frame time).
  void add(const cv::Mat& frame);
  // Closes the video; with `wav`, its sound is muxed in. Throws when ffmpeg failed.
  void finish(const std::string& wav = "");
  double fps() const { return fps_; }
  int frames() const { return frames_; }
  // What was written, for its confirmation line: "6.0 s, 180 frames, 1100x880, H.264 in MP4, with
  // sound".
  std::string describe() const;

 private:
  std::string path_, silent_;  // the file, and the video without sound while it is written
  int width_, height_;
  double fps_;
  int frames_ = 0;
  bool sound_ = false;
  FILE* ffmpeg_ = nullptr;
  cv::Mat padded_;
};

}  // namespace quantum::runtime

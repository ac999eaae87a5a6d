#include "track.h"

#include <libfreenect_sync.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <chrono>
#include <ostream>

#include "event_log.h"
#include "field_loader.h"
#include "play.h"
#include "tracking/tracking.h"

namespace quantum::tools {
namespace {

std::string frame_json(const tracking::TrackedFrame& f) {
  nlohmann::ordered_json j;
  j["frame"] = f.frame;
  j["t"] = rounded(f.t);
  j["players"] = nlohmann::json::array();
  for (const tracking::TrackedPlayer& p : f.players)
    j["players"].push_back({{"id", p.id}, {"team", p.team}, {"x", rounded(p.x)}, {"y", rounded(p.y)},
                            {"vx", rounded(p.vx)}, {"vy", rounded(p.vy)}});
  for (const tracking::TrackedAction& a : f.actions)
    j["actions"].push_back({{"type", a.type}, {"player", a.player}, {"dx", rounded(a.dx)}, {"dy", rounded(a.dy)}});
  return j.dump();
}

// A live Kinect through libfreenect's synchronous wrapper: depth (11-bit) and colour, taken as
// registered.
class LiveKinect {
 public:
  bool next(tracking::RecordedFrame& f) {
    void *depth = nullptr, *video = nullptr;
    uint32_t depth_ts = 0, video_ts = 0;
    if (freenect_sync_get_depth(&depth, &depth_ts, 0, FREENECT_DEPTH_11BIT) != 0 ||
        freenect_sync_get_video(&video, &video_ts, 0, FREENECT_VIDEO_RGB) != 0) {
      if (frames_ == 0) throw tracking::TrackingError("kinect: no Kinect found (is it plugged in, and may this user use it?)");
      throw tracking::TrackingError("kinect: the Kinect stopped sending frames after frame " + std::to_string(frames_));
    }
    const auto now = std::chrono::steady_clock::now();
    if (frames_ == 0) start_ = now;
    f.index = frames_++;
    f.t = std::chrono::duration<double>(now - start_).count();
    f.depth = cv::Mat(480, 640, CV_16UC1, depth).clone();
    cv::Mat rgb(480, 640, CV_8UC3, video);
    cv::cvtColor(rgb, f.rgb, cv::COLOR_RGB2BGR);
    f.file = "kinect";
    return true;
  }
  ~LiveKinect() {
    if (frames_ > 0) freenect_sync_stop();
  }

 private:
  int frames_ = 0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

namespace {

// Hats in colour video (a file, or a camera read live), with throws from accelerometers.
void track_hats(const TrackOptions& o, const tracking::TrackedField& field, std::ostream& out) {
  cv::VideoCapture video;
  const bool live = o.source.rfind("camera:", 0) == 0;
  const std::string name = o.source.substr(live ? 7 : 6);
  if (live) video.open(std::atoi(name.c_str()));
  else video.open(name);
  if (!video.isOpened())
    throw tracking::TrackingError(live ? "camera " + name + ": cannot open it" : name + ": cannot open the video");
  tracking::HatConfig config;
  config.horizontal_fov = o.fov;
  tracking::HatTracker tracker(field, config);
  std::optional<tracking::AccelSource> accel;
  if (!o.accel.empty()) accel.emplace(o.accel);
  tracking::ThrowDetector throws;
  const double fps = video.get(cv::CAP_PROP_FPS) > 0 ? video.get(cv::CAP_PROP_FPS) : 30;
  const auto start = std::chrono::steady_clock::now();
  cv::Mat image;
  for (int n = 0; (o.frames == 0 || n < o.frames) && video.read(image); ++n) {
    const double t = live ? std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() : n / fps;
    tracking::TrackedFrame f = tracker.feed(image, n, t);
    if (accel) throws.add(accel->until(t), f);
    out << frame_json(f) << '\n';
  }
}

}  // namespace

void track(const TrackOptions& o, std::ostream& out) {
  const Field field = lua::load_field(o.field);
  std::optional<Vec2> size;
  if (!o.field_size.empty()) {
    const std::vector<double> lw = parse_list(o.field_size, "--field-size");
    if (lw.size() != 2 || !(lw[0] > 0 && lw[1] > 0)) throw std::invalid_argument("--field-size needs L,W in metres, both > 0");
    size = Vec2{float(lw[0]), float(lw[1])};
  }
  const tracking::TrackedField tracked = tracking::tracked_field(field, size);
  if (o.source.rfind("video:", 0) == 0 || o.source.rfind("camera:", 0) == 0) {
    track_hats(o, tracked, out);
    out.flush();
    return;
  }
  if (!o.accel.empty()) throw std::invalid_argument("--accel goes with video:FILE or camera:N");
  tracking::DepthTracker tracker(tracked);
  std::optional<tracking::FakenectReader> recording;
  std::optional<LiveKinect> kinect;
  if (o.source.rfind("fakenect:", 0) == 0) recording.emplace(o.source.substr(9));
  else if (o.source == "kinect") kinect.emplace();
  else
    throw std::invalid_argument("unknown source '" + o.source + "': expected fakenect:DIR, kinect, video:FILE or camera:N");
  tracking::RecordedFrame frame;
  for (int n = 0; o.frames == 0 || n < o.frames; ++n) {
    if (recording ? !recording->next(frame) : !kinect->next(frame)) break;
    std::optional<tracking::TrackedFrame> seen = tracker.feed(frame);
    if (!seen) seen = tracking::TrackedFrame{frame.index, frame.t, {}, {}};  // still learning the background
    out << frame_json(*seen) << '\n';
  }
  out.flush();
}

}  // namespace quantum::tools

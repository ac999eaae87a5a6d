#include "tracking/input.h"

#include <libfreenect_sync.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <opencv2/core/utils/logger.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "system/quiet.h"

namespace quantum::tracking {

// camera:N is a video device (a webcam, a capture card). Left to choose, OpenCV also asks
// gphoto2 to look for still cameras on USB, a few thousand enumerations that leak each time.
constexpr int kCameraApi = cv::CAP_V4L2;

using Clock = std::chrono::steady_clock;
using Status = TrackingInput::Status;

namespace {

constexpr double kSilence = 1.0;  // s without a TUIO message: the tracker is gone

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Beyond these a tracked value is a source's glitch, not a player (a TUIO sender's NaN, infinity
// or 1e38): a field's own length (width) past its edge, farther than `play` keeps a body
// (players.cpp clamps at half that), and 100 m/s, ten times a sprinter and four times the
// fastest mallet.
constexpr double kFarthestOff = 1;   // field sizes beyond the edge
constexpr double kFastest = 100;     // m/s

// Drops from `f` the players whose values are not numbers or out of range; how many.
size_t drop_bad_values(TrackedFrame& f, const TrackedField& field) {
  const double most_x = (0.5 + kFarthestOff) * field.length, most_y = (0.5 + kFarthestOff) * field.width;
  return std::erase_if(f.players, [&](const TrackedPlayer& p) {
    return !(std::fabs(p.x) <= most_x && std::fabs(p.y) <= most_y && std::hypot(p.vx, p.vy) <= kFastest);
  });
}

// A live Kinect through libfreenect's synchronous wrapper: depth (11-bit) and colour, taken as
// registered.
class LiveKinect {
 public:
  ~LiveKinect() {
    if (asked_) freenect_sync_stop();  // its thread may have started even if a grab failed
  }
  // False when no frame came (after the first one: the Kinect went away; it is asked again on the
  // next call). Throws when there was never a Kinect.
  bool next(RecordedFrame& f) {
    void *depth = nullptr, *video = nullptr;
    uint32_t depth_ts = 0, video_ts = 0;
    bool got = false;
    asked_ = true;
    {
      // libfreenect prints its troubles to stdout, where the JSON lines go.
      const system::Quiet quiet({1, 2});
      got = freenect_sync_get_depth(&depth, &depth_ts, 0, FREENECT_DEPTH_11BIT) == 0 &&
            freenect_sync_get_video(&video, &video_ts, 0, FREENECT_VIDEO_RGB) == 0;
    }
    if (!got) {
      if (frames_ == 0) throw TrackingError("kinect: no Kinect found (is it plugged in, and may this user use it?)");
      return false;
    }
    if (frames_ == 0) start_ = Clock::now();
    f.index = frames_++;
    f.t = since(start_);
    f.depth = cv::Mat(480, 640, CV_16UC1, depth).clone();
    cv::cvtColor(cv::Mat(480, 640, CV_8UC3, video), f.rgb, cv::COLOR_RGB2BGR);
    f.file = "kinect";
    return true;
  }

 private:
  int frames_ = 0;
  bool asked_ = false;
  Clock::time_point start_;
};

}  // namespace

struct TrackingInput::Impl {
  TrackedField field;
  // Kinect depth (a recording or live).
  std::optional<FakenectReader> recording;
  std::optional<LiveKinect> kinect;
  std::optional<DepthTracker> depth;
  // Hats in colour video (a file or a camera).
  std::optional<cv::VideoCapture> video;
  int camera = -1;  // the camera's index when live
  std::optional<HatTracker> hats;
  double fps = 30;
  int frames = 0;
  Clock::time_point start = Clock::now(), retried = start;
  // TUIO.
  std::optional<TuioSource> tuio;
  bool heard = false;
  // Throws from accelerometers, for the players of either hats or TUIO.
  std::optional<AccelSource> accel;
  ThrowDetector throws;
  size_t dropped = 0;  // players of frames whose values were not numbers or out of range

  Status next_depth(TrackedFrame& out) {
    RecordedFrame f;
    if (recording ? !recording->next(f) : !kinect->next(f)) return recording ? Status::Ended : Status::Lost;
    std::optional<TrackedFrame> seen = depth->feed(f);
    if (!seen) {
      out = {f.index, f.t, {}, {}};
      return Status::Calibrating;
    }
    out = std::move(*seen);
    return Status::Frame;
  }

  Status next_hats(TrackedFrame& out) {
    cv::Mat image;
    if (!video->read(image)) {
      if (camera < 0) return Status::Ended;
      // A camera that went away: ask for it again twice a second.
      if (since(retried) > 0.5) retried = Clock::now(), video->open(camera, kCameraApi);
      return Status::Lost;
    }
    const double t = camera >= 0 ? since(start) : frames / fps;
    out = hats->feed(image, frames++, t);
    return Status::Frame;
  }

  Status next_tuio(TrackedFrame& out, double timeout) {
    if (std::optional<TrackedFrame> f = tuio->next(timeout)) {
      heard = true;
      out = std::move(*f);
      return Status::Frame;
    }
    return heard && tuio->silent() > kSilence ? Status::Lost : Status::Waiting;
  }
};

TrackingInput::TrackingInput(const std::string& spec, const TrackedField& field, const SourceOptions& o)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.field = field;
  auto after = [&](const char* prefix) { return spec.substr(std::string(prefix).size()); };
  const bool hats = spec.rfind("video:", 0) == 0 || spec.rfind("camera:", 0) == 0;
  if (!o.accel.empty() && !hats && spec.rfind("tuio:", 0) != 0)
    throw std::invalid_argument("--accel goes with video:FILE, camera:N or tuio:PORT");
  if (spec.rfind("fakenect:", 0) == 0 || spec == "kinect") {
    if (spec == "kinect") m.kinect.emplace();
    else m.recording.emplace(after("fakenect:"));
    m.depth.emplace(field);
  } else if (hats) {
    // OpenCV's capture backends warn about every one they try; the one line below says it.
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
    m.video.emplace();
    if (spec.rfind("camera:", 0) == 0) {
      m.camera = std::atoi(after("camera:").c_str());
      if (!m.video->open(m.camera, kCameraApi)) throw TrackingError(spec + ": cannot open the camera");
    } else if (!m.video->open(after("video:"))) {
      throw TrackingError(after("video:") + ": cannot open the video");
    }
    if (m.camera < 0 && m.video->get(cv::CAP_PROP_FPS) > 0) m.fps = m.video->get(cv::CAP_PROP_FPS);
    HatConfig config;
    config.horizontal_fov = o.fov;
    m.hats.emplace(field, config);
  } else if (spec.rfind("tuio:", 0) == 0) {
    m.tuio.emplace(std::atoi(after("tuio:").c_str()), field);
  } else {
    throw std::invalid_argument("unknown source '" + spec +
                                "': expected fakenect:DIR, kinect, video:FILE, camera:N or tuio:PORT");
  }
  if (!o.accel.empty()) m.accel.emplace(o.accel);
  m.throws = ThrowDetector(most_tracked(field.players.size()));
}

TrackingInput::~TrackingInput() = default;

bool TrackingInput::live() const { return impl_->kinect || impl_->camera >= 0 || impl_->tuio; }

const Calibration* TrackingInput::calibration() const {
  return impl_->depth && impl_->depth->ready() ? &impl_->depth->calibration() : nullptr;
}

const HatView* TrackingInput::hat_view() const {
  return impl_->hats && impl_->hats->view() ? &*impl_->hats->view() : nullptr;
}

size_t TrackingInput::dropped() const {
  return impl_->dropped + impl_->throws.dropped() + (impl_->recording ? impl_->recording->dropped() : 0) +
         (impl_->accel ? impl_->accel->dropped() : 0) + (impl_->tuio ? impl_->tuio->dropped() : 0);
}

std::string TrackingInput::sightings() { return impl_->depth ? impl_->depth->sightings() : ""; }

std::string describe(const Calibration& c) {
  char line[300];
  std::snprintf(line, sizeof line,
                "calibration: %d of 4 markers, camera %.2f m above the table, tilted %.1f degrees, field %.3f x %.3f m "
                "measured%s, depth noise %.1f cm, %.0f %% of the table without a reading",
                c.markers, c.height, c.tilt, c.length, c.width, c.size_given ? " (--field-size given: used instead)" : "",
                c.noise * 100, c.holes * 100);
  return line;
}

std::string size_mismatch(const Calibration& c, const TrackedField& field) {
  constexpr double kTolerance = 0.03;  // m: three times the calibration's own error
  if (std::fabs(c.used_length - field.length) <= kTolerance && std::fabs(c.used_width - field.width) <= kTolerance) return "";
  char line[400];
  std::snprintf(line, sizeof line,
                "the markers span %.2f x %.2f m but the sport's field is %.2f x %.2f m: players are tracked on the table "
                "as it is, so part of the field cannot be reached (or the players reach past it). Use --fit-field to "
                "stretch the sport's field over the table, --field-size L,W if the markers are not on the field's "
                "corners, or a sport whose field is the table's",
                c.used_length, c.used_width, field.length, field.width);
  return line;
}

std::vector<std::string> SetupCheck::check(TrackedFrame& frame, TrackingInput& input, const TrackedField& tracked) {
  std::vector<std::string> lines;
  const Calibration* c = input.calibration();
  if (c && !calibrated_) {
    calibrated_ = true;
    lines.push_back(describe(*c));
    if (const std::string mismatch = size_mismatch(*c, sport_); !mismatch.empty()) {
      if (options_.strict) throw TrackingError(source_ + ": " + mismatch + " (--strict)");
      if (options_.fit) {
        sx_ = sport_.length / c->used_length, sy_ = sport_.width / c->used_width;
        char fitted[200];
        std::snprintf(fitted, sizeof fitted, "--fit-field: the sport's %.2f x %.2f m field is stretched over the "
                      "%.2f x %.2f m table (x %.3f along, x %.3f across)", sport_.length, sport_.width, c->used_length,
                      c->used_width, sx_, sy_);
        lines.push_back(fitted);
      } else {
        lines.push_back("warning: " + mismatch);
      }
    }
  }
  if (const HatView* view = input.hat_view(); view && !viewed_) {
    viewed_ = true;
    if (const std::string mismatch = hat_view_mismatch(*view, tracked); !mismatch.empty()) {
      if (options_.strict) throw TrackingError(source_ + ": " + mismatch + " (--strict)");
      lines.push_back("warning: " + source_ + ": " + mismatch);
    }
  }
  for (TrackedPlayer& p : frame.players) p.x *= sx_, p.y *= sy_, p.vx *= sx_, p.vy *= sy_;
  if (const std::string warning = nobody_.check(frame, source_, tracked, input); !warning.empty())
    lines.push_back("warning: " + warning);
  return lines;
}

Status TrackingInput::next(TrackedFrame& frame, double timeout) {
  Impl& m = *impl_;
  const Status status = m.depth ? m.next_depth(frame) : m.hats ? m.next_hats(frame) : m.next_tuio(frame, timeout);
  if (status != Status::Frame) return status;
  m.dropped += drop_bad_values(frame, m.field);
  if (m.accel) m.throws.add(m.accel->until(frame.t), frame);  // its directions from the players kept
  return status;
}

std::string NobodySeen::check(const TrackedFrame& frame, const std::string& source, const TrackedField& field,
                              TrackingInput& input) {
  if (first_ < 0) first_ = frame.t;
  seen_ = seen_ || !frame.players.empty();
  if (seen_ || told_ || frame.t - first_ < after_) return "";
  told_ = true;
  char size[64];
  std::snprintf(size, sizeof size, "%.2f x %.2f m", field.length, field.width);
  const Calibration* c = input.calibration();
  if (c) std::snprintf(size, sizeof size, "%.2f x %.2f m", c->used_length, c->used_width);
  const std::string sees = input.sightings();
  return source + ": no player seen in the first " + std::to_string(int(after_)) + " s of frames. Check that the " +
         "markers are at the field's corners " + size + " apart" +
         (c && !c->size_given ? " (as measured)" : " (--field-size L,W when the table is another size)") +
         ", that the camera sees the whole field, and that the players are in view (docs/tracking.md)" +
         (sees.empty() ? "" : ". Seen: " + sees);
}

}  // namespace quantum::tracking

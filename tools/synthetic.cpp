#include "synthetic.h"

#include <cairo-pdf.h>
#include <nlohmann/json.hpp>
#include <opencv2/aruco.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <fstream>
#include <map>
#include <random>

#include "tracking/tracking.h"

namespace quantum::tools {
namespace {

using V3 = cv::Vec3d;
constexpr double kMiss = 1e30;

// Uniform and normal draws exactly as libstdc++ makes them from a std::mt19937_64 (its
// generate_canonical, and the polar method of its normal_distribution), written out. Clang does
// not fold the two long double logarithms generate_canonical takes on every draw: they were
// half of a recording's time in the sanitizer build. The same draws, so every recording, and the
// figures in docs/tracking.md, stay the seed's, now whatever the standard library.
double canonical(std::mt19937_64& engine) {
  const double u = double(engine() - std::mt19937_64::min()) / 0x1p64;
  return u < 1 ? u : std::nextafter(1.0, 0.0);
}

// Draws come in pairs; the second is kept for the next call.
class StandardNormal {
 public:
  double operator()(std::mt19937_64& engine) {
    if (has_saved_) {
      has_saved_ = false;
      return saved_;
    }
    double x, y, r2;
    do {
      x = 2.0 * canonical(engine) - 1.0;
      y = 2.0 * canonical(engine) - 1.0;
      r2 = x * x + y * y;
    } while (r2 > 1.0 || r2 == 0.0);
    const double mult = std::sqrt(-2 * std::log(r2) / r2);
    saved_ = x * mult, has_saved_ = true;
    return y * mult;
  }

 private:
  double saved_ = 0;
  bool has_saved_ = false;
};

// Field to camera for a camera looking straight down, image right toward the red end (+x),
// tilted by ta about its x axis and tb about its y axis.
cv::Matx33d looking_down(double ta, double tb) {
  const cv::Matx33d down(1, 0, 0, 0, -1, 0, 0, 0, -1);
  const cv::Matx33d rx(1, 0, 0, 0, std::cos(ta), -std::sin(ta), 0, std::sin(ta), std::cos(ta));
  const cv::Matx33d ry(std::cos(tb), 0, std::sin(tb), 0, 1, 0, -std::sin(tb), 0, std::cos(tb));
  return down * rx * ry;
}

// Smallest t > 0 with o + t d on the sphere (c, r), or kMiss.
double hit_sphere(const V3& o, const V3& d, const V3& c, double r) {
  const V3 q = o - c;
  const double a = d.dot(d), b = q.dot(d), k = q.dot(q) - r * r, disc = b * b - a * k;
  if (disc < 0) return kMiss;
  const double t = (-b - std::sqrt(disc)) / a;
  return t > 0 ? t : kMiss;
}

// A capsule from p to s of radius r: the cylinder between them and the two end spheres.
double hit_capsule(const V3& o, const V3& d, const V3& p, const V3& s, double r) {
  double best = std::min(hit_sphere(o, d, p, r), hit_sphere(o, d, s, r));
  const V3 axis = s - p;
  const double len = std::sqrt(axis.dot(axis));
  const V3 e = axis / len, q = o - p;
  const V3 dp = d - d.dot(e) * e, qp = q - q.dot(e) * e;
  const double a = dp.dot(dp), b = qp.dot(dp), k = qp.dot(qp) - r * r, disc = b * b - a * k;
  if (a > 0 && disc >= 0) {
    const double t = (-b - std::sqrt(disc)) / a;
    const double along = (q + t * d).dot(e);
    if (t > 0 && along >= 0 && along <= len) best = std::min(best, t);
  }
  return best;
}

// A vertical cylinder (a mallet) standing at (x, y) from z0 to z1.
double hit_mallet(const V3& o, const V3& d, double x, double y, double r, double z0, double z1) {
  double best = kMiss;
  if (d[2] < 0) {  // its top, seen from above
    const double t = (z1 - o[2]) / d[2];
    const double px = o[0] + t * d[0] - x, py = o[1] + t * d[1] - y;
    if (t > 0 && px * px + py * py <= r * r) best = t;
  }
  const double qx = o[0] - x, qy = o[1] - y;
  const double a = d[0] * d[0] + d[1] * d[1], b = qx * d[0] + qy * d[1], k = qx * qx + qy * qy - r * r;
  const double disc = b * b - a * k;
  if (a > 0 && disc >= 0) {
    const double t = (-b - std::sqrt(disc)) / a, z = o[2] + t * d[2];
    if (t > 0 && z >= z0 && z <= z1) best = std::min(best, t);
  }
  return best;
}

struct Player {
  int end;  // -1 blue, +1 red
  std::string id;
  double phase[4], rate[4];
  double pace = 1;  // the motion's time scale: its fastest moment is DepthSceneOptions::speed
  std::vector<std::pair<double, double>> lifts;  // [start, end) of each hover, seconds of play
  std::vector<double> lift_height;               // the hand's height while it hovers
};

constexpr double kHandOnTable = 0.075;  // m: the hand's centre while it grips a mallet on the table

struct Pose {
  double x, y, hand;  // the mallet's centre, the hand's height
};

Pose pose_of(const Player& p, double t, float length, float width) {
  const double s = p.pace * t;
  Pose q;
  q.x = p.end * (0.5 * length / 2 + 0.28 * length / 2 * std::sin(p.rate[0] * s + p.phase[0]) +
                 0.08 * length / 2 * std::sin(p.rate[1] * s + p.phase[1]));
  q.y = width / 2 * (0.55 * std::sin(p.rate[2] * s + p.phase[2]) + 0.15 * std::sin(p.rate[3] * s + p.phase[3]));
  q.hand = kHandOnTable;
  for (size_t k = 0; k < p.lifts.size(); ++k)
    if (t >= p.lifts[k].first && t < p.lifts[k].second) q.hand = p.lift_height[k];
  return q;
}

// The fastest the mallet moves over `seconds` of play, sampled every millisecond.
double top_speed(const Player& p, double seconds, float length, float width) {
  double top = 0;
  Pose last = pose_of(p, 0, length, width);
  for (double t = 0.001; t < seconds; t += 0.001) {
    const Pose q = pose_of(p, t, length, width);
    top = std::max(top, std::hypot(q.x - last.x, q.y - last.y) / 0.001);
    last = q;
  }
  return top;
}

// One arm reaching in: the mallet (4 cm in radius, 5 cm tall) lifted by `lift`, the hand gripping
// it from behind and above (so the mallet's far rim is the arm's farthest point and its centre
// lies 4 cm behind it), the forearm from the wrist to the shoulder; and a sphere around it all.
struct Arm {
  V3 wrist, shoulder, hand;
  double x, y, lift;
  V3 around;
  double reach;
};

// The nearest arm surface along o + t d with 0 < t < limit; limit when none.
double hit_arms(const std::vector<Arm>& arms, const V3& o, const V3& d, double limit) {
  double best = limit;
  for (const Arm& a : arms) {
    const V3 q = a.around - o;
    const double along = q.dot(d);
    if (q.dot(q) - along * along / d.dot(d) > a.reach * a.reach) continue;  // the ray passes it by
    best = std::min({best, hit_mallet(o, d, a.x, a.y, 0.04, a.lift, a.lift + 0.05), hit_sphere(o, d, a.hand, 0.035),
                     hit_capsule(o, d, a.wrist, a.shoulder, 0.04)});
  }
  return best;
}

// A generator for one row of one frame: rows render in parallel and the recording is the same
// whatever the number of threads.
std::mt19937_64 row_rng(uint64_t seed, int frame, int row, int pass) {
  std::seed_seq s{uint32_t(seed), uint32_t(seed >> 32), uint32_t(frame), uint32_t(row), uint32_t(pass)};
  return std::mt19937_64(s);
}

}  // namespace

void write_markers(const std::string& dir, double side) {
  constexpr double kPoint = 0.0254 / 72;                     // m
  constexpr double kPageWidth = 595.276, kPageHeight = 841.89;  // A4, points
  if (!(side >= 0.02 && side <= 0.18))
    throw std::invalid_argument("--marker-size must be from 0.02 to 0.18 m (one marker to an A4 page)");
  std::filesystem::create_directories(dir);
  const cv::Ptr<cv::aruco::Dictionary> dict = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50);
  const char* corner[] = {"(+L/2, +W/2): Red's end, Blue's left", "(+L/2, -W/2): Red's end, Blue's right",
                          "(-L/2, -W/2): Blue's end, Blue's right", "(-L/2, +W/2): Blue's end, Blue's left"};
  const std::string pdf = dir + "/markers.pdf";
  cairo_surface_t* surface = cairo_pdf_surface_create(pdf.c_str(), kPageWidth, kPageHeight);
  cairo_t* cr = cairo_create(surface);
  // No creation date: the same markers give the same file.
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATE_DATE, "");
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  for (int id = 0; id < 4; ++id) {
    cv::Mat marker, page(760, 700, CV_8UC1, cv::Scalar(255));
    dict->drawMarker(id, 600, marker);
    marker.copyTo(page(cv::Rect(50, 50, 600, 600)));
    cv::putText(page, "ArUco 4x4_50 id " + std::to_string(id) + ", centre on corner", {50, 700},
                cv::FONT_HERSHEY_SIMPLEX, 0.8, cv::Scalar(0), 2);
    cv::putText(page, corner[id], {50, 740}, cv::FONT_HERSHEY_SIMPLEX, 0.8, cv::Scalar(0), 2);
    const std::string file = dir + "/marker-" + std::to_string(id) + ".png";
    if (!cv::imwrite(file, page)) throw std::runtime_error("cannot write " + file);

    // The PDF page: the marker's 6 x 6 cells (its black border included) as one filled path.
    cv::Mat cells;
    dict->drawMarker(id, 6, cells);
    const double s = side / kPoint, cell = s / 6, x0 = (kPageWidth - s) / 2, y0 = 150;
    for (int v = 0; v < 6; ++v)
      for (int u = 0; u < 6; ++u)
        if (cells.at<uint8_t>(v, u) < 128) cairo_rectangle(cr, x0 + u * cell, y0 + v * cell, cell, cell);
    cairo_fill(cr);
    // Ticks on the marker's middle lines, outside its white margin: where the corner goes.
    cairo_set_line_width(cr, 0.75);
    const double mx = x0 + s / 2, my = y0 + s / 2, gap = 8, tick = 18;
    for (auto [x, y, dx, dy] : {std::tuple{mx, y0 - gap, 0.0, -tick}, {mx, y0 + s + gap, 0.0, tick},
                                {x0 - gap, my, -tick, 0.0}, {x0 + s + gap, my, tick, 0.0}}) {
      cairo_move_to(cr, x, y);
      cairo_rel_line_to(cr, dx, dy);
    }
    cairo_stroke(cr);
    cairo_set_font_size(cr, 16);
    cairo_move_to(cr, 56, 60);
    cairo_show_text(cr, ("ArUco DICT_4X4_50 id " + std::to_string(id) + ": its centre on the field's corner").c_str());
    cairo_move_to(cr, 56, 82);
    cairo_show_text(cr, corner[id]);
    // The check bar: 10 cm when printed at 100 % ("actual size", no "fit to page").
    const double bar = 0.10 / kPoint, by = y0 + s + 70;
    cairo_rectangle(cr, 56, by, bar, 6);
    cairo_fill(cr);
    cairo_set_font_size(cr, 11);
    char caption[160];
    std::snprintf(caption, sizeof caption,
                  "This bar is 10 cm and the marker %.1f cm (black border included) when printed at 100 %%.", side * 100);
    cairo_move_to(cr, 56, by + 24);
    cairo_show_text(cr, caption);
    cairo_show_page(cr);
  }
  cairo_destroy(cr);
  cairo_surface_finish(surface);
  const cairo_status_t status = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) throw std::runtime_error("cannot write " + pdf + ": " + cairo_status_to_string(status));
}

float DepthSceneOptions::printed_marker_size() const {
  return marker_size > 0 ? marker_size : std::max(0.08f, 0.065f * height);
}

std::vector<TruthFrame> write_depth_recording(const std::string& dir, const DepthSceneOptions& o) {
  if (!(o.length > 0 && o.width > 0 && o.height > 0.5f && o.tilt >= 0 && o.tilt < 30 && o.noise >= 0 && o.holes >= 0 &&
        o.holes < 1 && o.speed > 0 && o.hover_low > kHandOnTable + 0.02 && o.hover_high >= o.hover_low && o.fps > 0))
    throw std::invalid_argument("depth scene: sizes, height (> 0.5 m), speed and fps must be positive, tilt under 30 "
                                "degrees, holes a share under 1, hovering hands above the table's 9.5 cm");
  std::mt19937_64 rng(o.seed);
  const tracking::DepthCamera cam;

  // The camera: above the table's centre give or take a few centimetres, looking down, image
  // right toward the red end, tilted by `tilt` degrees in a direction drawn at random.
  // One draw a statement: a function's arguments are evaluated in an order each compiler picks,
  // and the recording must be the seed's on any of them (this is the order GCC took: the
  // recordings, and the figures in docs/tracking.md, stay what they were).
  const double off_y = o.offset * (2 * canonical(rng) - 1);
  const double off_x = o.offset * (2 * canonical(rng) - 1);
  const V3 centre(off_x, off_y, o.height);
  const double drawn = 2 * M_PI * canonical(rng), tilt = o.tilt * M_PI / 180;
  const double way = o.tilt_toward >= 0 ? o.tilt_toward * M_PI / 180 : drawn;
  const cv::Matx33d to_field = looking_down(tilt * std::sin(way), tilt * std::cos(way)).t();  // camera to field directions
  // The Kinect's infrared projector sits 7.5 cm beside its camera: what the camera sees of the
  // table behind an arm, the projector does not light (the projector's shadow).
  const V3 projector = centre + to_field * V3(0.075, 0, 0);

  std::vector<Player> players;
  const double play = o.frames / o.fps;
  for (int end : {-1, 1}) {
    Player p;
    p.end = end;
    p.id = end < 0 ? o.blue : o.red;
    for (int k = 0; k < 4; ++k) p.phase[k] = 6.2832 * canonical(rng), p.rate[k] = 1.0 + 2.5 * canonical(rng);
    for (double t = 0.5 + 2 * canonical(rng); t < play;) {
      const double on = 0.3 + 0.8 * canonical(rng);
      p.lifts.push_back({t, t + on});
      p.lift_height.push_back(o.hover_low + (o.hover_high - o.hover_low) * canonical(rng));
      t += on + on * (1 - o.hover_share) / o.hover_share * (0.5 + canonical(rng));
    }
    p.pace = o.speed / top_speed(p, std::max(play, 10.0), o.length, o.width);
    players.push_back(std::move(p));
  }

  // Marker bitmaps, 6 cells a side (4 data bits and the black border), 10 px a cell.
  const cv::Ptr<cv::aruco::Dictionary> dict = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50);
  std::vector<cv::Mat> bitmaps(4);
  for (int id = 0; id < 4; ++id) dict->drawMarker(id, 60, bitmaps[size_t(id)]);
  const double marker = o.printed_marker_size();
  const double rim = marker / 2 + 0.02;  // the table reaches past the field's corners

  tracking::FakenectWriter writer(dir);
  std::ofstream truth_file(dir + "/truth.jsonl");
  std::vector<TruthFrame> truth;
  cv::Mat depth(cam.height, cam.width, CV_64F), raw(cam.height, cam.width, CV_16UC1), bgr(cam.height, cam.width, CV_8UC3);
  std::vector<V3> rays(size_t(cam.width * cam.height));
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u)
      rays[size_t(v * cam.width + u)] = to_field * V3((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1);

  const int total = o.background_frames + o.frames;
  for (int f = 0; f < total; ++f) {
    const double t = f / o.fps, play_t = (f - o.background_frames) / o.fps;
    const bool colour = f % o.colour_every == 0;
    TruthFrame tf{f, t, {}};
    std::vector<Arm> arms;
    if (f >= o.background_frames) {
      for (const Player& p : players) {
        const Pose q = pose_of(p, play_t, o.length, o.width);
        const double lift = q.hand - kHandOnTable;
        const V3 shoulder(p.end * (o.length / 2 + 0.35), 0.5 * q.y, 0.4);
        V3 dir(q.x - shoulder[0], q.y - shoulder[1], 0);
        dir /= std::sqrt(dir.dot(dir));
        const V3 wrist = V3(q.x, q.y, lift + 0.08) - 0.05 * dir, mallet(q.x, q.y, lift);
        const V3 around = (mallet + shoulder) / 2, half = shoulder - around;
        arms.push_back({wrist, shoulder, V3(q.x, q.y, q.hand) - 0.01 * dir, q.x, q.y, lift, around,
                        std::sqrt(half.dot(half)) + 0.1});
        tf.players.push_back({p.id, q.x, q.y, lift > 0, q.hand});
      }
    }
    // Ray casting, a row at a time in parallel: depth along the optical axis (the ray's
    // parameter: its camera-frame direction has z = 1), 0 where the projector is hidden.
    cv::parallel_for_(cv::Range(0, cam.height), [&](const cv::Range& rows) {
      for (int v = rows.start; v < rows.end; ++v) {
        double* z = depth.ptr<double>(v);
        cv::Vec3b* c = bgr.ptr<cv::Vec3b>(v);
        for (int u = 0; u < cam.width; ++u) {
          const V3& d = rays[size_t(v * cam.width + u)];
          const double tt = -centre[2] / d[2];
          const double px = centre[0] + tt * d[0], py = centre[1] + tt * d[1];
          const bool table = std::fabs(px) <= o.length / 2 + rim && std::fabs(py) <= o.width / 2 + rim;
          const double surface = table ? tt : (-0.75 - centre[2]) / d[2];  // the table, or the floor below
          const double best = hit_arms(arms, centre, d, surface);
          z[u] = best;
          if (o.shadow && !arms.empty()) {
            const V3 s = centre + best * d, to = projector - s;
            const double len = std::sqrt(to.dot(to));
            if (hit_arms(arms, s + 1e-4 * to / len, to / len, len) < len) z[u] = 0;
          }
          if (!colour) continue;
          cv::Vec3b paint(60, 60, 60);
          if (best < surface) paint = cv::Vec3b(140, 170, 215);
          else if (table) {
            paint = cv::Vec3b(215, 215, 215);
            for (int id = 0; id < 4; ++id) {
              const Vec2 m = tracking::marker_position(id, o.length, o.width);
              const double mx = (px - m.x) / marker + 0.5, my = 0.5 - (py - m.y) / marker;
              if (mx >= 0 && mx < 1 && my >= 0 && my < 1) {
                const uint8_t g = bitmaps[size_t(id)].at<uint8_t>(int(my * 60), int(mx * 60));
                paint = cv::Vec3b(g, g, g);
              }
            }
          }
          c[u] = paint;
        }
      }
    });
    // The sensor: raw disparity with noise, random holes, readings lost at depth edges (the
    // speckle pattern breaks up there) and in the blind columns on the left.
    cv::parallel_for_(cv::Range(0, cam.height), [&](const cv::Range& rows) {
      for (int v = rows.start; v < rows.end; ++v) {
        // The row's own normal draws: they keep a spare draw, which would carry into the next row
        // of whatever chunk of rows this thread was given.
        std::mt19937_64 r = row_rng(o.seed, f, v, 1);
        StandardNormal noise;
        const double* z = depth.ptr<double>(v);
        uint16_t* out = raw.ptr<uint16_t>(v);
        for (int u = 0; u < cam.width; ++u) {
          const uint16_t q = z[u] > 0 ? tracking::metres_to_raw(float(z[u])) : tracking::kNoDepth;
          const int noisy = q == tracking::kNoDepth ? q : int(std::lround(q + o.noise * noise(r)));
          bool lost = u < o.blind_columns || canonical(r) < o.holes;
          if (!lost && o.edge_dropout > 0) {
            double step = 0;
            for (auto [du, dv] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
              const int nu = u + du, nv = v + dv;
              if (nu >= 0 && nv >= 0 && nu < cam.width && nv < cam.height)
                step = std::max(step, std::fabs(depth.at<double>(nv, nu) - z[u]));
            }
            lost = step > 0.03 && canonical(r) < o.edge_dropout;
          }
          out[u] = lost ? tracking::kNoDepth : uint16_t(std::clamp(noisy, 0, 2047));
        }
      }
    });
    // The Kinect also loses whole patches (shiny spots).
    for (int k = 0; k < 4; ++k) {
      const int radius = 2 + int(5 * canonical(rng));
      const cv::Point at{int(canonical(rng) * cam.width), int(canonical(rng) * cam.height)};  // braces: in order
      cv::circle(raw, at, radius, cv::Scalar(tracking::kNoDepth), cv::FILLED);
    }
    if (colour) writer.rgb(t, bgr);
    writer.depth(t, raw);
    writer.accel(t);
    nlohmann::ordered_json j;
    j["frame"] = f;
    j["t"] = t;
    j["players"] = nlohmann::json::array();
    for (const TruthPlayer& p : tf.players)
      j["players"].push_back({{"id", p.id}, {"x", p.x}, {"y", p.y}, {"hovering", p.hovering}, {"hand", p.hand}});
    truth_file << j.dump() << '\n';
    truth.push_back(std::move(tf));
  }
  return truth;
}

namespace {

// One hatted player: where they walk at each moment of the clip while on the hall, and when they
// are off it (HatSceneOptions::Away).
struct Walker {
  std::string team, name;  // name: the field's, in a rally
  std::function<Vec2(double)> way;
  double away_from = 0, away_to = 0;
  std::string id = "";  // as the tracker numbers them
};

// Where a walker is at time t: on its way, or off to the side of the hall while away, jogging
// out over the nearer side line (as far again as the hall is wide) and back.
Vec2 place(const Walker& w, double t, double width) {
  Vec2 p = w.way(t);
  if (t < w.away_to && (w.away_from <= 0 || t > w.away_from)) {
    const double jog = 3, side = w.way(w.away_from > 0 ? w.away_from : w.away_to).y < 0 ? -1 : 1;
    double off = jog * (w.away_to - t);
    if (w.away_from > 0) off = std::min(off, jog * (t - w.away_from));
    p.y += float(side * std::min(off, width));
  }
  return p;
}

// Straight from one key (time, place) to the next; standing still before the first and after
// the last.
struct Key {
  double t;
  Vec2 at;
};
std::function<Vec2(double)> through(std::vector<Key> keys) {
  return [keys = std::move(keys)](double t) {
    auto next = std::find_if(keys.begin(), keys.end(), [&](const Key& k) { return k.t > t; });
    if (next == keys.begin()) return keys.front().at;
    if (next == keys.end()) return keys.back().at;
    const Key& a = *(next - 1);
    const double s = (t - a.t) / (next->t - a.t);
    return Vec2{float(a.at.x + (next->at.x - a.at.x) * s), float(a.at.y + (next->at.y - a.at.y) * s)};
  };
}

// A throw in the making: who (index into the walkers), when, and at whom (a walker, or -1 for
// the goal).
struct Throw {
  double t;
  size_t player;
  int to = -1;
};

struct Scene {
  std::vector<Walker> walkers;
  std::vector<Throw> throws;
};

// Films `scene` into dir: hats.avi, truth.jsonl and accel.csv. Numbers the walkers as the tracker
// does: by x (then y) within their team at the first frame, later arrivals in the order they come
// into the picture; one who leaves and comes back keeps their number.
HatTruth film(const std::string& dir, const HatSceneOptions& o, Scene& scene) {
  std::filesystem::create_directories(dir);
  std::mt19937_64 rng(o.seed);
  StandardNormal gauss;
  const double L = o.length, W = o.width, T = o.seconds;
  std::vector<Walker>& walkers = scene.walkers;
  for (const HatSceneOptions::Away& a : o.away) {
    if (a.player < 0 || size_t(a.player) >= walkers.size() || !(a.to > a.from))
      throw std::invalid_argument("away: no player " + std::to_string(a.player) + ", or not from before to");
    walkers[size_t(a.player)].away_from = a.from, walkers[size_t(a.player)].away_to = a.to;
  }

  // The camera, looking down from above the hall's centre, a little off and tilted.
  const double fx = (o.image_width / 2.0) / std::tan(o.horizontal_fov * M_PI / 360);
  const double cx = (o.image_width - 1) / 2.0, cy = (o.image_height - 1) / 2.0;
  const double ta = 0.02 * (2 * canonical(rng) - 1), tb = 0.02 * (2 * canonical(rng) - 1);
  const cv::Matx33d r = looking_down(ta, tb);  // field to camera
  const double off_y = 0.2 * (2 * canonical(rng) - 1);  // one draw a statement, as above
  const double off_x = 0.2 * (2 * canonical(rng) - 1);
  const cv::Vec3d centre(off_x, off_y, o.height);
  const cv::Vec3d t = -(r * centre);
  auto project = [&](double x, double y, double z) {
    const cv::Vec3d c = r * cv::Vec3d(x, y, z) + t;
    return cv::Point2d(fx * c[0] / c[2] + cx, fx * c[1] / c[2] + cy);
  };
  const double scale = fx / (o.height - o.hat_height);  // px a metre at the hats' height
  const double hat_px = o.hat_radius * scale;
  auto in_picture = [&](cv::Point2d c) {
    return c.x >= hat_px && c.y >= hat_px && c.x <= o.image_width - 1 - hat_px && c.y <= o.image_height - 1 - hat_px;
  };

  // Ids: the players in the first frame, then the others as they come.
  const int frames = int(std::lround(T * o.fps));
  for (int f = 0; f < frames; ++f) {
    std::vector<Walker*> coming;
    for (Walker& w : walkers) {
      const Vec2 p = place(w, f / o.fps, W);
      if (w.id.empty() && in_picture(project(p.x, p.y, o.hat_height))) coming.push_back(&w);
    }
    std::sort(coming.begin(), coming.end(), [&](const Walker* a, const Walker* b) {
      const Vec2 p = place(*a, f / o.fps, W), q = place(*b, f / o.fps, W);
      return p.x != q.x ? p.x < q.x : p.y < q.y;
    });
    for (Walker* w : coming) {
      const long n = std::count_if(walkers.begin(), walkers.end(), [&](const Walker& v) {
        return v.team == w->team && !v.id.empty();
      });
      w->id = w->team + " " + std::to_string(n + 1);
    }
  }

  // The floor as a texture, 50 px a metre: wooden boards, the court's lines, the markers.
  const double ppm = 50, margin = 2;
  cv::Mat floor(int((W + 2 * margin) * ppm), int((L + 2 * margin) * ppm), CV_8UC3, cv::Scalar(150, 170, 185));
  auto tex = [&](double x, double y) { return cv::Point2d((x + L / 2 + margin) * ppm, (W / 2 + margin - y) * ppm); };
  for (double x = -L / 2 - margin; x < L / 2 + margin; x += 0.15)
    cv::line(floor, tex(x, -W / 2 - margin), tex(x, W / 2 + margin), cv::Scalar(140, 160, 176), 1);
  cv::rectangle(floor, tex(-L / 2, W / 2), tex(L / 2, -W / 2), cv::Scalar(235, 235, 235), 3);
  cv::line(floor, tex(0, W / 2), tex(0, -W / 2), cv::Scalar(235, 235, 235), 3);
  const cv::Ptr<cv::aruco::Dictionary> dict = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50);
  for (int id = 0; id < 4; ++id) {
    const Vec2 m = tracking::marker_position(id, float(L), float(W));
    const int side = int(o.marker_size * ppm);
    cv::Mat bitmap, colour;
    dict->drawMarker(id, side, bitmap);
    cv::cvtColor(bitmap, colour, cv::COLOR_GRAY2BGR);
    const cv::Point2d c = tex(m.x, m.y);
    colour.copyTo(floor(cv::Rect(int(c.x) - side / 2, int(c.y) - side / 2, side, side)));
  }
  // Texture pixels to image pixels: the floor plane's homography.
  std::vector<cv::Point2f> from, to;
  for (auto [x, y] : {std::pair{-L / 2, -W / 2}, {L / 2, -W / 2}, {L / 2, W / 2}, {-L / 2, W / 2}}) {
    from.push_back(tex(x, y));
    to.push_back(project(x, y, 0));
  }
  const cv::Mat h = cv::getPerspectiveTransform(from, to);

  cv::VideoWriter video(dir + "/hats.avi", cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), o.fps,
                        {o.image_width, o.image_height});
  if (!video.isOpened()) throw std::runtime_error(dir + "/hats.avi: cannot write the video");
  video.set(cv::VIDEOWRITER_PROP_QUALITY, 95);
  HatTruth truth;
  std::ofstream truth_file(dir + "/truth.jsonl");
  cv::Mat image;
  for (int f = 0; f < frames; ++f) {
    const double time = f / o.fps;
    cv::warpPerspective(floor, image, h, {o.image_width, o.image_height}, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                        cv::Scalar(90, 90, 90));
    TruthFrame tf{f, time, {}};
    std::vector<cv::Point2d> pixels;  // where each hat in the picture has its centre
    for (const Walker& w : walkers) {
      const Vec2 p = place(w, time, W);
      // Shoulders (dark shirts) under the hat; then the hat, seen from above.
      const cv::Point2d s = project(p.x, p.y, o.hat_height - 0.3), c = project(p.x, p.y, o.hat_height);
      // Drawn with 4 fractional bits: whole-pixel centres would move a hat by up to 0.8 cm.
      auto fixed = [](cv::Point2d p) { return cv::Point(int(std::lround(p.x * 16)), int(std::lround(p.y * 16))); };
      cv::ellipse(image, fixed(s), cv::Size(int(0.25 * scale * 16), int(0.13 * scale * 16)), 0, 0, 360,
                  cv::Scalar(55, 55, 55), cv::FILLED, cv::LINE_AA, 4);
      const cv::Scalar hat = w.team == "blue" ? cv::Scalar(220, 80, 20) : cv::Scalar(30, 30, 220);
      cv::circle(image, fixed(c), int(std::lround(hat_px * 16)), hat, cv::FILLED, cv::LINE_AA, 4);
      if (!in_picture(c)) continue;
      tf.players.push_back({w.id, p.x, p.y, false});
      pixels.push_back(c);
    }
    video.write(image);
    nlohmann::ordered_json j;
    j["frame"] = f;
    j["t"] = time;
    j["players"] = nlohmann::json::array();
    for (size_t k = 0; k < tf.players.size(); ++k)
      j["players"].push_back({{"id", tf.players[k].id}, {"x", tf.players[k].x}, {"y", tf.players[k].y},
                              {"u", pixels[k].x}, {"v", pixels[k].y}});
    truth_file << j.dump() << '\n';
    truth.frames.push_back(std::move(tf));
  }

  // Accelerometers at 100 Hz: gravity, running's jolts, and a throw's whip (40 m/s^2 for 60 ms).
  for (const Throw& th : scene.throws) {
    const Walker& w = walkers[th.player];
    const Vec2 a = place(w, th.t - 0.01, W), b = place(w, th.t + 0.01, W);
    const double dx = b.x - a.x, dy = b.y - a.y, n = std::hypot(dx, dy);
    truth.throws.push_back({th.t, w.id, dx / n, dy / n, th.to < 0 ? "" : walkers[size_t(th.to)].id});
  }
  std::ofstream accel(dir + "/accel.csv");
  accel << "t,player,ax,ay,az\n";
  for (int k = 0; k < int(T * 100); ++k) {
    const double time = k / 100.0;
    for (const Walker& w : walkers) {
      double whip = 0;
      for (const TruthThrow& th : truth.throws)
        if (th.player == w.id && time >= th.t && time < th.t + 0.06) whip = 40;
      accel << time << ',' << w.id << ',' << 3 * gauss(rng) + whip << ',' << 3 * gauss(rng) << ','
            << 9.81 + 3 * gauss(rng) << '\n';
    }
  }
  return truth;
}

}  // namespace

HatTruth write_hat_video(const std::string& dir, const HatSceneOptions& o) {
  const double L = o.length, W = o.width, T = o.seconds;
  // Two of each team cross at the clip's middle (at x = -L/5 and +L/5); the third circles.
  auto line = [&](const char* team, Vec2 a, Vec2 b) {
    return Walker{team, "", through({{0, a}, {T, b}})};
  };
  auto circle = [](const char* team, Vec2 c, double r, double period) {
    return Walker{team, "", [=](double t) {
                    const double w = 2 * M_PI * t / period;
                    return Vec2{float(c.x + r * std::cos(w)), float(c.y + r * std::sin(w))};
                  }};
  };
  Scene scene;
  scene.walkers = {
      line("blue", {float(-0.45 * L), float(-0.3 * W)}, {float(0.05 * L), float(0.3 * W)}),
      line("blue", {float(-0.425 * L), float(0.3 * W)}, {float(0.025 * L), float(-0.3 * W)}),
      circle("blue", {float(0.15 * L), float(-0.25 * W)}, 0.075 * L, 6),
      line("red", {float(0.45 * L), float(-0.3 * W)}, {float(-0.05 * L), float(0.3 * W)}),
      line("red", {float(0.425 * L), float(0.3 * W)}, {float(-0.025 * L), float(-0.3 * W)}),
      circle("red", {float(-0.15 * L), float(0.25 * W)}, 0.075 * L, 7),
  };
  for (const auto& [who, when] : {std::pair{1, 2.0}, {3, 4.2}, {5, 6.5}, {2, 8.0}})
    scene.throws.push_back({when, size_t(who)});
  return film(dir, o, scene);
}

HatTruth write_rally_video(const std::string& dir, const HatSceneOptions& o, const Field& hall) {
  // The choreography is drawn for the default hall: its places, its goal areas (6 m) and its
  // goals (3 m wide) at x = +-10.
  const Goal* goal = nullptr;
  for (const Goal& g : hall.goals)
    if (g.team == "red") goal = &g;
  // Each team's goalkeeper and field players, by index into the bodies.
  std::map<std::string, std::vector<size_t>> keeper, field;
  for (size_t k = 0; k < hall.bodies.size(); ++k)
    (hall.bodies[k].role == "goalkeeper" ? keeper : field)[hall.bodies[k].team].push_back(k);
  if (std::abs(o.length - 20) > 1e-3 || std::abs(o.width - 10) > 1e-3 || hall.bounds_max.x != 10 ||
      hall.bounds_max.y != 5 || !goal || goal->a.x != 10 || hall.bodies.size() != 6 || keeper["blue"].size() != 1 ||
      keeper["red"].size() != 1 || field["blue"].size() != 2 || field["red"].size() != 2)
    throw std::invalid_argument("the rally is drawn for the default handball hall: 20 m x 10 m, three a side with "
                                "goalkeepers, Red's goal at x = +10");
  // Blue's field player nearest the centre holds the ball as the match starts (match.start =
  // "blue"); the other is the one passed to.
  const auto from_centre = [&](size_t k) { return std::hypot(hall.bodies[k].start.x, hall.bodies[k].start.y); };
  std::vector<size_t>& blue = field["blue"];
  if (from_centre(blue[1]) < from_centre(blue[0])) std::swap(blue[0], blue[1]);
  const size_t holder = blue[0], mate = blue[1], red_keeper = keeper["red"][0];

  std::vector<std::vector<Key>> keys;
  for (const BodySpec& b : hall.bodies) keys.push_back({{0, b.start}});
  auto to = [&](size_t k, double t, Vec2 at) { keys[k].push_back({t, at}); };  // there by t
  auto wait = [&](size_t k, double t) { to(k, t, keys[k].back().at); };      // stays put until t
  // A throw: the thrower stands until `run` s before it, runs straight at the target at 3.5 m/s
  // and throws on the run (the tracker takes a throw's direction from its thrower's motion); then
  // slows to a stop.
  std::vector<Throw> throws;
  auto throw_at = [&](size_t k, double t, Vec2 target, int catcher) {
    const double run = 0.8, speed = 3.5;
    const Vec2 s = keys[k].back().at;
    const double n = std::hypot(target.x - s.x, target.y - s.y);
    const Vec2 u{float((target.x - s.x) / n), float((target.y - s.y) / n)};
    wait(k, t - run);
    const auto ahead = [&](double d) { return Vec2{float(s.x + u.x * d), float(s.y + u.y * d)}; };
    to(k, t, ahead(run * speed));
    to(k, t + 0.3, ahead(run * speed + 0.3 * speed / 2));
    throws.push_back({t, k, catcher});
  };

  // Red's field players fall back to the corners of their goal area's line, out of the passing
  // lanes: Blue's passes go to unmarked players.
  for (size_t k : field["red"]) {
    wait(k, 0.5);
    to(k, 2.0, {4.0f, hall.bodies[k].start.y < 0 ? -4.4f : 4.4f});
  }
  // Pass 1: the teammate runs up the left wing; the holder passes to him there.
  const Vec2 wing{1.5f, 3.0f}, cut{2.0f, -2.8f}, back{0.6f, -2.4f}, goal_centre{10.0f, 0.0f};
  wait(mate, 0.3);
  to(mate, 1.6, wing);
  throw_at(holder, 2.0, wing, int(mate));
  // Pass 2: the holder cuts in on the right; the teammate passes back to her there.
  to(holder, 3.4, cut);
  throw_at(mate, 3.6, cut, int(holder));
  // The shot: she steps back and runs at Red's goal, throwing from well outside its goal area,
  // while Red's goalkeeper has come out to her side.
  wait(holder, 3.9);
  to(holder, 4.4, back);
  wait(red_keeper, 4.4);
  to(red_keeper, 5.0, {8.5f, -2.5f});
  throw_at(holder, 5.2, goal_centre, -1);

  Scene scene;
  for (size_t k = 0; k < hall.bodies.size(); ++k)
    scene.walkers.push_back({hall.bodies[k].team, hall.bodies[k].name, through(keys[k])});
  scene.throws = std::move(throws);
  HatTruth truth = film(dir, o, scene);

  // The tracker's numbers must be the hall's, or the video's players would play as others (a
  // latecomer who is not the last of their team's missing players).
  for (size_t k = 0; k < hall.bodies.size(); ++k)
    if (scene.walkers[k].id != hall.bodies[k].tracked_as())
      throw std::invalid_argument(hall.bodies[k].name + " is tracked as '" + hall.bodies[k].tracked_as() +
                                  "' but the tracker would number their hat '" + scene.walkers[k].id + "'");
  nlohmann::ordered_json j;
  const auto name = [&](const std::string& id) {
    for (const Walker& w : scene.walkers)
      if (w.id == id) return w.name;
    return std::string();
  };
  j["throws"] = nlohmann::json::array();
  for (const TruthThrow& th : truth.throws) {
    nlohmann::ordered_json t{{"t", th.t}, {"player", th.player}, {"name", name(th.player)}};
    if (th.to.empty()) t["at"] = goal->name;
    else t["to"] = th.to, t["to_name"] = name(th.to);
    j["throws"].push_back(t);
  }
  const std::string& scorer = truth.throws.back().player;
  j["goal"] = {{"player", scorer}, {"name", name(scorer)}, {"goal", goal->name}};
  std::ofstream(dir + "/truth.json") << j.dump(2) << '\n';
  return truth;
}

}  // namespace quantum::tools

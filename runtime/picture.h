// The desk's picture of a match: the field, the players (named), the particle cloud coloured by
// fate, the predicted paths of the likeliest fates, a legend of their Newtonian and tweaked
// probabilities, the score, the time, the power-ups and a ticker of the last announcements.
// One drawing serves the live view, the video and the snapshot (docs/desk.md). It only reads:
// the match never depends on it.
#pragma once

#include <opencv2/core.hpp>

#include <deque>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "audio/audio.h"
#include "game/game.h"

namespace quantum::runtime {

struct News;

// The last announcements, each marked with what became of it: said (no sound), spoken, cut off
// by a more urgent one, or dropped stale.
class Ticker {
 public:
  struct Line {
    double t;
    std::string text;
    enum class Fate { Said, Cut, Dropped } fate = Fate::Said;
    uint64_t id = 0;  // the phrase's, as in News::first_phrase
  };
  explicit Ticker(size_t lines = 6) : lines_(lines) {}
  void hear(const News& news);
  // What the announcer did with phrases during the last frame (Session::fates).
  void mark(std::span<const audio::PhraseFate> fates);
  const std::deque<Line>& lines() const { return shown_; }

 private:
  size_t lines_;
  std::deque<Line> shown_;
};

// What the desk adds on top of the match: its state, and what a person is told about it.
struct Overlay {
  std::string title;              // the sport's name
  std::string status;             // "paused", "slow motion (1/4)", ... ("" when playing)
  std::string help;               // the keys, for the live view ("" elsewhere)
  const Ticker* ticker = nullptr;
  std::string last_draw;          // the last draw that realized something, and its alternatives (describe_draw)
};

// "0:12.30  Red's mallet 41% (realized), Blue's mallet 3%, nothing 56%": a draw's alternatives
// with their tweaked chances, for a person asking why.
std::string describe_draw(const Decision& d, const Field& field);

// Fields with height: a report's outcomes as a person reads a shot, Newtonian -> tweaked:
// "basket 8.5% -> 21.8% | rebound Pia 46.0% -> 39.3% | blocked by Quinn ... | out ... | in play ...".
// A catch after the ball touched a wall, the rim, a board or the floor is a rebound; an
// opponent's catch before that a block.
std::string outcome_summary(const FateReport& report, const Field& field);

struct PictureOptions {
  int width = 1100;    // pixels across the image
  int top_fates = 6;   // the likeliest fates drawn and listed first
  bool paths = true;   // draw the predicted paths
};

class Picture {
 public:
  explicit Picture(const Field& field, PictureOptions options = {});
  const PictureOptions& options() const { return options_; }
  void set_paths(bool on) { options_.paths = on; }

  // Draws the match as it is now into `image` (made the right size). Its fates are the match's
  // own prediction of this frame.
  void draw(const game::Match& match, const Overlay& overlay, cv::Mat& image);
  // The same for the quantum core alone (`quantum simulate`): its cloud and `report`, a fresh
  // prediction of it.
  void draw(const World& world, const FateReport& report, const Overlay& overlay, cv::Mat& image);

  // Where a pixel of the field area is on the field, in metres (the desk's mouse), and how tall
  // that area is (the legend is below it).
  Vec2 to_field(int x, int y) const;
  int field_height() const { return field_height_; }

 private:
  struct Row {
    std::string text;
    cv::Scalar colour;
  };
  void draw_field(const World& world, const FateReport& report, cv::Mat& field_area);
  cv::Point px(Vec2 p) const;
  cv::Point px_side(Vec3 p) const;  // the side view's pixel of a point at height p.z
  void draw_side(const World& world, const FateReport& report, bool fated, const std::vector<size_t>& shade,
                 cv::Mat& field_area);
  void header(cv::Mat& image, const std::string& s, const cv::Scalar& colour);  // the next piece of the header line
  cv::Scalar fate_colour(const Fate& fate, size_t rank) const;
  cv::Scalar team_colour(const std::string& team) const;

  Field field_;
  PictureOptions options_;
  double scale_ = 1;  // pixels per metre
  int margin_ = 30, field_height_ = 0, header_x_ = 0;
  int top_height_ = 0;  // rows of the view from above
  int side_axis_ = -1, floor_row_ = 0;  // fields with height: the side view's axis (0 x, 1 y) and its floor's row
  std::map<std::string, cv::Scalar> team_colours_;
  std::vector<size_t> ranked_;  // group indices, likeliest (tweaked) first
  cv::Mat density_, tint_;      // the cloud's weight and colour per pixel
};

// --snapshot FILE: checked before the match plays (its folder, and an image type OpenCV writes,
// told by the name's ending: .png, .jpg, ...); written once the moment comes. Both throw
// std::runtime_error naming the option and the file.
void check_snapshot_file(const std::string& path);
void write_snapshot(const std::string& path, const cv::Mat& image);

}  // namespace quantum::runtime

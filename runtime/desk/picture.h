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
  int hand = -1;                  // the body a person drives with the mouse, marked "you" (-1: none)
};

// "0:12.30  Red's mallet 41% (realized), Blue's mallet 3%, nothing 56%": a draw's alternatives
// with their tweaked chances, for a person asking why.
std::string describe_draw(const Decision& d, const Field& field);

// One outcome of the ball's flight, whichever way it gets there: a goal, an own goal, a body (its
// catch, hit, ...), a landing in an area or outside every area, out, or staying in play. Its
// probabilities are those of every fate group of a report that ends so, added up.
struct OutcomeTotal {
  Fate fate;         // the outcome: a fate without its way (no walls in its path)
  std::string name;  // describe(fate): "goal (Red's goal)", "pass to Anna", "out", "lands in Blue court"
  double mass = 0, tweaked_mass = 0;  // Newtonian and tweaked probability
};
// The legend's totals: every outcome of `report` with its probabilities, likeliest (tweaked)
// first. Every group is in one of them, so they add up to the report's 100 %.
std::vector<OutcomeTotal> outcome_totals(const FateReport& report, const Field& field);

struct PictureOptions {
  int width = 1100;    // pixels across the image
  // Pixels down: the whole image (the field, the legend) fits width x height, the field as large
  // as it goes with its aspect kept. 0: as tall as the field at `width` needs.
  int height = 0;
  int top_fates = 6;   // the likeliest fates whose paths are drawn and listed
  bool paths = true;   // draw the predicted paths
};

// A text the picture wrote on the field: a player's name, a path's probability. Placed where it
// covers no other label, disc or edge it can avoid.
struct FieldLabel {
  std::string text;
  cv::Rect box;  // in the image's pixels
};

class Picture {
 public:
  // Lays the picture out for the options' size and draws what never changes (the field's lines,
  // the legend's titles): under a millisecond for full HD (BM_DeskResize), so a window makes a new
  // one when it is resized (keeping options().paths).
  explicit Picture(const Field& field, PictureOptions options = {});
  const PictureOptions& options() const { return options_; }
  void set_paths(bool on) { options_.paths = on; }

  // Draws the match as it is now into `image` (made the right size). Its fates are the match's
  // own prediction of this frame.
  void draw(const game::Match& match, const Overlay& overlay, cv::Mat& image);
  // The same for the quantum core alone (`quantum simulate`): its cloud and `report`, a fresh
  // prediction of it.
  void draw(const World& world, const FateReport& report, const Overlay& overlay, cv::Mat& image);

  // Where a pixel of the view from above is on the field, in metres (the desk's mouse), and the
  // reverse; whether a pixel is in that view (its margins included); how many rows the field's
  // views take (the legend is under them, or when the box is wide, beside them in a column).
  Vec2 to_field(int x, int y) const;
  cv::Point to_pixel(Vec2 p) const;
  bool over_field(int x, int y) const { return top_.contains({x, y}); }
  int field_height() const { return field_height_; }
  // The names and probabilities the last draw wrote on the field, and where.
  const std::vector<FieldLabel>& labels() const { return labels_; }

 private:
  // Where the legend's parts go: the header line's, the titles' and the other lines' baselines.
  struct Legend {
    cv::Point header, outcomes, paths, announcer, key, last_draw, help;
    int outcome_columns = 1, outcome_rows = 1;
    int room = 0;        // how wide a line may be
    int paths_room = 0;  // how wide a path's line may be (the announcer may be beside it)
    int header_lines = 1, last_draw_lines = 1, help_lines = 1;
    cv::Size size;  // empty: no legend fits
  };
  Legend legend_under(int width, int outcomes) const;
  Legend legend_beside(int width, int height, int outcomes) const;
  void lay_out();
  void draw_layer();
  int key(cv::Mat* layer, int room) const;
  void draw_frame(const World& world, const FateReport& report, const Overlay& overlay, cv::Mat& image);
  void draw_areas(cv::Mat& img) const;
  void draw_cloud(const World& world, const FateReport& report, cv::Mat& image);
  void draw_side(const World& world, const FateReport& report, cv::Mat& image);
  void draw_paths(const World& world, const FateReport& report, cv::Mat& image);
  void draw_bodies(const World& world, int hand, cv::Mat& image);
  void draw_legend(const World& world, const FateReport& report, const Overlay& overlay, cv::Mat& image);
  void place_label(const std::string& text, cv::Point at, int clearance, const cv::Scalar& colour, cv::Mat& image);
  cv::Point px_side(Vec3 p) const;  // the side view's pixel of a point at height p.z
  void header(cv::Mat& image, const std::string& s, const cv::Scalar& colour);
  void text(cv::Mat& image, const std::string& s, cv::Point at, const cv::Scalar& colour, double size = 1) const;
  int text_width(const std::string& s, double size = 1) const;
  std::string fit(const std::string& s, int room) const;  // cut to `room` pixels, marked "..."
  void write(cv::Mat& image, const std::string& s, cv::Point at, int room, int lines, const cv::Scalar& colour) const;
  cv::Size swatch() const { return {line_ * 2 / 3, line_ * 3 / 5}; }  // a colour's square in the legend
  cv::Scalar fate_colour(const Fate& fate, size_t rank) const;
  cv::Scalar team_colour(const std::string& team) const;

  Field field_;
  PictureOptions options_;
  // The layout, fixed by the options: the image's size, the field's scale, the text's.
  cv::Size size_;
  double scale_ = 1;   // pixels per metre
  double font_ = 0.45;  // the text's size (OpenCV's Hershey scale)
  int line_ = 20;       // pixels between text lines
  int margin_ = 30, field_height_ = 0;
  cv::Point header_;  // where the header line goes on
  cv::Rect top_;   // the view from above, its margins included
  cv::Rect side_;  // fields with height: the view from the side, under or beside the top view
  int side_axis_ = -1, floor_row_ = 0;  // fields with height: the side view's axis (0 x, 1 y) and its floor's row
  int outcome_width_ = 0;  // a cell of the legend's outcomes
  Legend legend_;
  std::map<std::string, cv::Scalar> team_colours_;
  cv::Mat layer_;  // what every frame starts from: the background, the field's lines, the legend's titles
  // This frame's fates: group indices likeliest (tweaked) first, each group's colour.
  std::vector<size_t> ranked_;
  std::vector<cv::Vec3b> group_colour_;
  // The cloud gathered per pixel of the view from above, touching only the pixels it covers and
  // those around them: each one's cell (-1: none).
  struct Cell {
    float weight = 0, b = 0, g = 0, r = 0;  // the particles in the pixel, their colours weighed
    float spread = 0;                        // the weight of the heaviest pixel around
    int32_t heaviest = -1;                   // and its cell
    int32_t pixel = 0;
  };
  std::vector<int32_t> cell_of_pixel_;
  std::vector<Cell> cells_;
  struct PathEnd {
    cv::Point at;
    std::string probability;
    cv::Scalar colour;
  };
  std::vector<PathEnd> path_ends_;
  std::vector<FieldLabel> labels_;
  std::vector<cv::Rect> obstacles_;  // the discs labels keep off
};

// --snapshot FILE: checked before the match plays (its folder, and an image type OpenCV writes,
// told by the name's ending: .png, .jpg, ...); written once the moment comes. Both throw
// std::runtime_error naming the option and the file.
void check_snapshot_file(const std::string& path);
void write_snapshot(const std::string& path, const cv::Mat& image);

}  // namespace quantum::runtime

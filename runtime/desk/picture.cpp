#include "picture.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "output_files.h"
#include "session.h"

namespace quantum::runtime {
namespace {

const cv::Scalar kBackground(28, 28, 28), kText(235, 235, 235), kDim(150, 150, 150), kWall(230, 230, 230);
const cv::Scalar kGoal(40, 215, 255), kOwnGoal(0, 140, 255), kOut(210, 90, 210), kStays(165, 165, 165);
const cv::Scalar kWarning(60, 170, 255);  // the desk's status; cut or dropped phrases
// Teams in the order the field names them: blue and red first, as the shipped sports use them.
const cv::Scalar kTeams[] = {{235, 140, 45}, {70, 70, 235}, {90, 200, 90}, {50, 200, 230}, {200, 110, 200}};

// The text's size (OpenCV's Hershey scale) in a picture of the desk's 1100 x 880 pixels, and the
// sizes it keeps to in larger and smaller ones: smaller, names blur into the field; larger, the
// legend takes the field's room.
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kFontAtDesk = 0.45, kSmallestFont = 0.45, kLargestFont = 0.6;
constexpr double kDeskPixels = 1100.0 * 880;
// Rows of outcomes in the legend: at most two under the field, at least three beside it; the
// rarest outcomes of many share the last cell.
constexpr int kOutcomeRowsUnder = 2, kOutcomeRowsBeside = 3;
constexpr int kTickerRows = 6;   // the announcer's lines the legend has room for
constexpr size_t kLongestOutcomeName = 24;  // characters a cell of the outcomes' grid makes room for

std::string clock(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%d:%05.2f", int(t / 60), std::fmod(t, 60.0));
  return buf;
}

std::string percent(double p) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.1f%%", 100 * p);
  return buf;
}

// "12.3% -> 45.6%": Newtonian, then tweaked.
std::string newtonian_to_tweaked(double mass, double tweaked) { return percent(mass) + " -> " + percent(tweaked); }

// A colour as a pixel holds it.
cv::Vec3b pixel(const cv::Scalar& c) {
  return {cv::saturate_cast<uint8_t>(c[0]), cv::saturate_cast<uint8_t>(c[1]), cv::saturate_cast<uint8_t>(c[2])};
}

// A fate without its way: the outcome it is part of.
Fate outcome_of(const Fate& f) {
  Fate o;
  o.kind = f.kind, o.target = f.target;
  return o;
}

// Pixels a rectangle has outside `bounds`, and in common with `other`.
int outside(const cv::Rect& r, const cv::Rect& bounds) { return r.area() - (r & bounds).area(); }
int overlap(const cv::Rect& a, const cv::Rect& b) { return (a & b).area(); }

}  // namespace

std::string describe_draw(const Decision& d, const Field& f) {
  std::string s = clock(d.t) + "  last draw:";
  double rest = 1;
  for (size_t k = 0; k < d.options.size(); ++k) {
    const std::string_view name = target_name(d.options[k].target, f);
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s %.*s %.1f%%%s", k == 0 ? "" : ",", int(name.size()), name.data(), 100 * d.options[k].chance,
                  int(k) == d.realized ? " (realized)" : "");
    s += buf;
    rest -= d.options[k].chance;
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, ", nothing %.1f%%%s", 100 * std::max(0.0, rest), d.realized < 0 ? " (realized)" : "");
  return s + buf;
}

void Ticker::hear(const News& news) {
  for (size_t i = 0; i < news.said.size(); ++i) {
    shown_.push_back({news.said[i].t, news.said[i].text, Line::Fate::Said, news.first_phrase + i});
    if (shown_.size() > lines_) shown_.pop_front();
  }
}

void Ticker::mark(std::span<const audio::PhraseFate> fates) {
  for (const audio::PhraseFate& f : fates) {
    if (f.kind != audio::PhraseFate::Kind::Cut && f.kind != audio::PhraseFate::Kind::Dropped) continue;
    for (Line& line : shown_)
      if (line.id == f.id) line.fate = f.kind == audio::PhraseFate::Kind::Cut ? Line::Fate::Cut : Line::Fate::Dropped;
  }
}

std::vector<OutcomeTotal> outcome_totals(const FateReport& report, const Field& field) {
  std::vector<OutcomeTotal> totals;
  for (const FateGroup& g : report.groups) {
    const Fate o = outcome_of(g.fate);
    auto it = std::find_if(totals.begin(), totals.end(), [&](const OutcomeTotal& t) { return t.fate.key() == o.key(); });
    if (it == totals.end()) it = totals.insert(totals.end(), {o, describe(o, field)});
    it->mass += g.mass, it->tweaked_mass += g.tweaked_mass;
  }
  std::stable_sort(totals.begin(), totals.end(),
                   [](const OutcomeTotal& a, const OutcomeTotal& b) { return a.tweaked_mass > b.tweaked_mass; });
  return totals;
}

Picture::Picture(const Field& field, PictureOptions options) : field_(field), options_(options) {
  size_t k = 0;
  for (const std::string& team : field_.teams()) team_colours_[team] = kTeams[k++ % std::size(kTeams)];
  lay_out();
  draw_layer();
}

// The legend under the field, `width` wide: the header line (sport, time, score, power-ups,
// status), the outcomes in a grid of at most two rows, the likeliest paths beside the announcer,
// the colours' key, the last draw and the keys, a line each.
Picture::Legend Picture::legend_under(int width, int outcomes) const {
  Legend l;
  l.room = width - 2 * margin_;
  l.outcome_columns = std::max(1, l.room / outcome_width_);
  l.outcome_rows = std::clamp((outcomes + l.outcome_columns - 1) / l.outcome_columns, 1, kOutcomeRowsUnder);
  l.header = {margin_, line_};
  l.outcomes = {margin_, l.header.y + line_ * 4 / 3};
  l.paths = {margin_, l.outcomes.y + (l.outcome_rows + 1) * line_ + line_ / 3};
  l.paths_room = width / 2 - margin_;
  l.announcer = {width / 2 + line_, l.paths.y};
  l.key = {margin_, l.paths.y + (std::max(options_.top_fates, kTickerRows) + 1) * line_ + line_ / 3};
  l.last_draw = {margin_, l.key.y + (key(nullptr, l.room) - 1) * line_ + line_ * 4 / 3};
  l.help = {margin_, l.last_draw.y + line_};
  l.size = {width, l.help.y + line_ / 2};
  return l;
}

// The legend in a column beside the field, `width` wide: the same parts one under the other, the
// last draw and the keys on two lines each, and as many rows of outcomes as `height` leaves room
// for, up to every outcome the field can have. Empty when fewer than three fit.
Picture::Legend Picture::legend_beside(int width, int height, int outcomes) const {
  Legend l;
  l.room = width - margin_;
  l.paths_room = l.room;
  l.outcome_columns = std::max(1, l.room / outcome_width_);
  l.header_lines = l.last_draw_lines = l.help_lines = 2;
  const int rest = line_ + line_ * 8 / 3 + line_ + line_ / 3 + (options_.top_fates + 1) * line_ + line_ / 3 +
                   (kTickerRows + 1) * line_ + line_ / 3 + key(nullptr, l.room) * line_ + line_ / 3 + 4 * line_ + line_ / 2;
  const int needed = (outcomes + l.outcome_columns - 1) / l.outcome_columns;
  l.outcome_rows = std::min((height - rest) / line_, needed);
  if (l.outcome_rows < std::min(needed, kOutcomeRowsBeside)) return {};
  l.header = {0, line_};
  l.outcomes = {0, l.header.y + line_ * 8 / 3};
  l.paths = {0, l.outcomes.y + (l.outcome_rows + 1) * line_ + line_ / 3};
  l.announcer = {0, l.paths.y + (options_.top_fates + 1) * line_ + line_ / 3};
  l.key = {0, l.announcer.y + (kTickerRows + 1) * line_ + line_ / 3};
  l.last_draw = {0, l.key.y + (key(nullptr, l.room) - 1) * line_ + line_ * 4 / 3};
  l.help = {0, l.last_draw.y + 2 * line_};
  l.size = {width, height};
  return l;
}

// The legend under the field or beside it, and the field's views (from above, and for fields
// with height from the side, under or beside that), whichever way the field is largest; the views
// centred in the field's part of the image.
void Picture::lay_out() {
  const int width = std::max(options_.width, 1), height = options_.height;
  const double box = height > 0 ? std::sqrt(double(width) * height / kDeskPixels) : width * 880 / kDeskPixels;
  font_ = std::clamp(kFontAtDesk * box, kSmallestFont, kLargestFont);
  line_ = int(std::lround(font_ * 44));
  margin_ = line_ * 3 / 2;

  // The outcomes a report of this field can have, and the widest cell one needs.
  const int outcomes = int(2 * field_.goals.size() + field_.bodies.size()) + 2 + (field_.landings ? int(field_.areas.size()) + 1 : 0);
  int name_width = 0;
  auto measure = [&](const Fate& f) { name_width = std::max(name_width, text_width(describe(f, field_).substr(0, kLongestOutcomeName))); };
  for (int g = 0; g < int(field_.goals.size()); ++g) measure({FateKind::OwnGoal, g});
  for (int b = 0; b < int(field_.bodies.size()); ++b)
    measure({field_.bodies[size_t(b)].catches ? FateKind::Intercept : field_.bodies[size_t(b)].hits ? FateKind::Hit : FateKind::Body, b});
  for (int a = 0; a < int(field_.areas.size()) && field_.landings; ++a) measure({FateKind::Landing, a});
  measure({FateKind::Field, -1});
  outcome_width_ = line_ + text_width(newtonian_to_tweaked(1, 1)) + line_ / 2 + name_width + line_;

  const float w = field_.bounds_max.x - field_.bounds_min.x, h = field_.bounds_max.y - field_.bounds_min.y;
  float along = 0, up = 0;  // fields with height: the side view's length and height, in metres
  if (field_.has_height()) {
    // The side view looks across the axis on which the hoops sit nearest an end (a basket by its
    // baseline), else across the longer one; it is as high as the tallest thing on the field.
    side_axis_ = w >= h ? 0 : 1;
    for (const Goal& g : field_.goals) {
      if (!g.hoop()) continue;
      const float ex = std::min(g.a.x - field_.bounds_min.x, field_.bounds_max.x - g.a.x) / w;
      const float ey = std::min(g.a.y - field_.bounds_min.y, field_.bounds_max.y - g.a.y) / h;
      side_axis_ = ex < ey ? 0 : 1;
    }
    up = 4;
    for (const Goal& g : field_.goals) up = std::max(up, g.rim_height + 1);
    for (const Board& b : field_.boards) up = std::max(up, b.top + 0.5f);
    for (size_t k = 0; k < field_.bodies.size(); ++k) up = std::max(up, field_.reach_of(int(k)) + 1);
    if (field_.ceiling > 0) up = field_.ceiling;
    along = side_axis_ == 0 ? w : h;
  }
  // Pixels per metre for the views in `room` (no limit down when its height is 0): the side view
  // under the top view, or beside it.
  auto fit = [&](cv::Size room, bool side_beside) {
    const float across = side_axis_ < 0 ? w : side_beside ? w + along : std::max(w, along);
    const float down = side_axis_ < 0 ? h : side_beside ? std::max(h, up) : h + up;
    const int gaps_across = side_beside ? 4 : 2, gaps_down = side_axis_ < 0 || side_beside ? 2 : 4;
    const double s = (room.width - gaps_across * margin_) / double(across);
    return room.height > 0 ? std::min(s, (room.height - gaps_down * margin_) / double(down)) : s;
  };
  // A box with no room left for the field still gets one: the image is then taller than the box.
  const int least = 4 * margin_ + 4;
  const Legend under = legend_under(width, outcomes);
  cv::Size room(width, height > 0 ? std::max(height - under.size.height, least) : 0);
  legend_ = under;
  bool side_beside = false;
  scale_ = fit(room, false);
  // Another layout when it makes the field larger; the legend leaves its usual place under the
  // field only when that makes the field much larger.
  bool in_column = false;
  auto consider = [&](const Legend& legend, cv::Size r, bool beside, bool column) {
    constexpr double kMuchLarger = 1.1;
    if (const double s = fit(r, beside); s > scale_ * (column && !in_column ? kMuchLarger : 1))
      scale_ = s, room = r, legend_ = legend, side_beside = beside, in_column = column;
  };
  if (height > 0 && side_axis_ >= 0) consider(under, room, true, false);
  // Beside the field the legend's column takes a third of the width, more for a legend of many outcomes.
  const int column = std::clamp(width / 3, outcome_width_ + margin_, width / 2);
  if (const Legend beside = height > 0 ? legend_beside(column, height, outcomes) : Legend{}; beside.size.width > 0) {
    consider(beside, {width - column, height}, false, true);
    if (side_axis_ >= 0) consider(beside, {width - column, height}, true, true);
  }
  scale_ = std::max(scale_, 1e-3);
  top_ = {0, 0, int(w * scale_) + 2 * margin_, int(h * scale_) + 2 * margin_};
  if (side_axis_ >= 0) side_ = {0, 0, int(along * scale_) + 2 * margin_, int(up * scale_) + 2 * margin_};
  const cv::Size views = side_.empty() ? top_.size()
                         : side_beside ? cv::Size(top_.width + side_.width, std::max(top_.height, side_.height))
                                       : cv::Size(std::max(top_.width, side_.width), top_.height + side_.height);
  field_height_ = std::max(views.height, room.height);
  const cv::Point at((room.width - views.width) / 2, (field_height_ - views.height) / 2);
  top_ += at;
  // Beside, the side view stands on the top view's bottom line; under it, at its left.
  if (side_beside) side_ += cv::Point(top_.br().x, top_.br().y - side_.height);
  else if (!side_.empty()) side_ += cv::Point(at.x, top_.br().y);
  floor_row_ = side_.y + margin_ + int(up * scale_);
  // The legend's place: under the field's rows, or in the column right of them.
  const cv::Point legend_at = in_column ? cv::Point(room.width, 0) : cv::Point(0, field_height_);
  for (cv::Point* p : {&legend_.header, &legend_.outcomes, &legend_.paths, &legend_.announcer, &legend_.key, &legend_.last_draw,
                       &legend_.help})
    *p += legend_at;
  size_ = {width, std::max(height, legend_at.y + legend_.size.height)};
  cell_of_pixel_.assign(size_t(top_.area()), -1);
}

cv::Point Picture::to_pixel(Vec2 p) const {
  // Field y points to the left of a player facing +x; image rows go down.
  return {top_.x + margin_ + int((p.x - field_.bounds_min.x) * scale_), top_.y + margin_ + int((field_.bounds_max.y - p.y) * scale_)};
}

cv::Point Picture::px_side(Vec3 p) const {
  const float u = side_axis_ == 0 ? p.x : p.y, u0 = side_axis_ == 0 ? field_.bounds_min.x : field_.bounds_min.y;
  return {side_.x + margin_ + int((u - u0) * scale_), floor_row_ - int(p.z * scale_)};
}

Vec2 Picture::to_field(int x, int y) const {
  return {float(field_.bounds_min.x + (x - top_.x - margin_) / scale_), float(field_.bounds_max.y - (y - top_.y - margin_) / scale_)};
}

void Picture::text(cv::Mat& img, const std::string& s, cv::Point at, const cv::Scalar& colour, double size) const {
  cv::putText(img, s, at, kFont, font_ * size, colour, 1, cv::LINE_AA);
}

int Picture::text_width(const std::string& s, double size) const {
  int baseline = 0;
  return cv::getTextSize(s, kFont, font_ * size, 1, &baseline).width;
}

cv::Scalar Picture::team_colour(const std::string& team) const {
  const auto it = team_colours_.find(team);
  return it == team_colours_.end() ? kStays : it->second;
}

// A fate's colour: its kind's (a body's is its team's); the likelier of two fates of one kind
// is the brighter, so "via the left wall" and "direct" stay apart.
cv::Scalar Picture::fate_colour(const Fate& f, size_t rank) const {
  cv::Scalar c;
  switch (f.kind) {
    case FateKind::Goal: c = kGoal; break;
    case FateKind::OwnGoal: c = kOwnGoal; break;
    case FateKind::Body:
    case FateKind::Catch:
    case FateKind::Pass:
    case FateKind::Intercept:
    case FateKind::Pickup:
    case FateKind::Tackle:
    case FateKind::Hit: c = team_colour(field_.bodies[f.target].team); break;
    case FateKind::Out: c = kOut; break;
    case FateKind::Field: c = kStays; break;
    case FateKind::Landing: c = f.target >= 0 ? team_colour(field_.areas[f.target].team) : kOut; break;
  }
  return c * (1.0 - 0.12 * double(std::min<size_t>(rank, 4)));
}

// A field's areas (goal areas, a three-point line) outlined in their team's colour, as far as they
// lie on the field: a goal area's arc beyond the goal line is not drawn.
void Picture::draw_areas(cv::Mat& layer) const {
  // Drawn into the field's part of the layer, which OpenCV's drawing does not leave.
  const cv::Rect field = cv::Rect(to_pixel({field_.bounds_min.x, field_.bounds_max.y}),
                                  to_pixel({field_.bounds_max.x, field_.bounds_min.y}) + cv::Point(1, 1)) &
                         cv::Rect({}, layer.size());
  cv::Mat img = layer(field);
  auto px = [&](Vec2 p) { return to_pixel(p) - field.tl(); };
  for (const Area& a : field_.areas) {
    if (a.box) {
      cv::rectangle(img, px(a.a), px(a.b), team_colour(a.team) * 0.6, 1, cv::LINE_AA);
      continue;
    }
    std::vector<cv::Point> outline;
    const float heading = std::atan2(a.b.y - a.a.y, a.b.x - a.a.x);
    for (int end = 0; end < 2; ++end)
      for (int k = 0; k <= 32; ++k) {
        const float angle = heading + float(std::numbers::pi) * (0.5f + float(end) + float(k) / 32);
        const Vec2 c = end == 0 ? a.a : a.b;
        outline.push_back(px({c.x + a.radius * std::cos(angle), c.y + a.radius * std::sin(angle)}));
      }
    cv::polylines(img, outline, true, team_colour(a.team) * 0.6, 1, cv::LINE_AA);
  }
}

// What every frame draws alike, drawn once: the field's lines, the side view's floor, boards and
// rings, the legend's titles and the key of its colours.
void Picture::draw_layer() {
  layer_.create(size_, CV_8UC3);
  layer_.setTo(kBackground);
  draw_areas(layer_);
  cv::Mat top = layer_(top_);
  const cv::Point origin = -top_.tl();
  auto px = [&](Vec2 p) { return to_pixel(p) + origin; };
  if (field_.has_bounds) cv::rectangle(top, px(field_.bounds_min), px(field_.bounds_max), kDim, 1, cv::LINE_AA);
  for (const Segment& s : field_.segments) cv::line(top, px(s.a), px(s.b), kWall, 3, cv::LINE_AA);
  for (const Goal& g : field_.goals) {
    if (g.hoop()) cv::circle(top, px(g.a), std::max(3, int(g.rim_radius * scale_)), kGoal, 2, cv::LINE_AA);
    else cv::line(top, px(g.a), px(g.b), team_colour(g.team), 5, cv::LINE_AA);
  }
  for (const Board& b : field_.boards) cv::line(top, px(b.a), px(b.b), kWall, 3, cv::LINE_AA);
  for (const Spot& s : field_.spots) cv::drawMarker(top, px(s.at), kDim, cv::MARKER_CROSS, 12, 1);
  if (side_axis_ >= 0) {
    const Vec2 lo = field_.bounds_min, hi = field_.bounds_max;
    cv::line(layer_, px_side({lo.x, lo.y, 0}), px_side({hi.x, hi.y, 0}), kDim, 2, cv::LINE_AA);
    text(layer_, side_axis_ == 0 ? "from the side (across x)" : "from the side (across y)",
         side_.tl() + cv::Point(margin_, line_), kDim);
    if (field_.ceiling > 0)
      cv::line(layer_, px_side({lo.x, lo.y, field_.ceiling}), px_side({hi.x, hi.y, field_.ceiling}), kDim, 1, cv::LINE_AA);
    for (const Board& b : field_.boards)
      cv::rectangle(layer_, px_side({std::min(b.a.x, b.b.x), std::min(b.a.y, b.b.y), b.bottom}),
                    px_side({std::max(b.a.x, b.b.x), std::max(b.a.y, b.b.y), b.top}), kWall, 2, cv::LINE_AA);
    for (const Goal& g : field_.goals)
      if (g.hoop())
        cv::line(layer_, px_side({g.a.x - g.rim_radius, g.a.y - g.rim_radius, g.rim_height}),
                 px_side({g.a.x + g.rim_radius, g.a.y + g.rim_radius, g.rim_height}), kGoal, 3, cv::LINE_AA);
  }
  // The legend's titles and key (the announcer's comes with its lines: `quantum simulate` has none).
  text(layer_, fit("outcomes, Newtonian -> tweaked (together 100%)", legend_.room), legend_.outcomes, kDim);
  text(layer_, fit("likeliest paths, Newtonian -> tweaked", legend_.paths_room), legend_.paths, kDim);
  key(&layer_, legend_.room);
}

// Every colour the picture uses, the rarer fates' included, on as many lines as `room` makes
// them; draws them into `layer` at the legend's key when there is one. Returns the lines.
int Picture::key(cv::Mat* layer, int room) const {
  std::vector<std::pair<std::string, cv::Scalar>> keys;
  for (const auto& [team, colour] : team_colours_) keys.emplace_back(team + " player", colour);
  if (!field_.goals.empty()) keys.emplace_back("goal", kGoal), keys.emplace_back("own goal", kOwnGoal);
  keys.emplace_back(field_.landings ? "out, lands outside" : "out", kOut);
  keys.emplace_back("stays in field", kStays);
  int x = 0, lines = 1;
  for (const auto& [name, colour] : keys) {
    const int w = line_ + text_width(name);
    if (x > 0 && x + w > room) x = 0, ++lines;
    const cv::Point at = legend_.key + cv::Point(x, (lines - 1) * line_);
    if (layer) {
      cv::rectangle(*layer, cv::Rect(at + cv::Point(0, -line_ / 2), swatch()), colour, cv::FILLED);
      text(*layer, name, at + cv::Point(line_, 0), kDim);
    }
    x += w + line_;
  }
  return lines;
}

// The cloud from above: every particle's weight and fate colour gathered per pixel, so a million
// particles cost one pass, and drawn with an alpha that grows with the weight there. A lone
// particle still shows, as a dot of three pixels: each pixel takes the colour and the weight of
// the heaviest pixel around it. Only the pixels the cloud covers are touched (a frame costs its
// particles, not the picture's size), and the field's lines stay on top.
void Picture::draw_cloud(const World& world, const FateReport& report, cv::Mat& image) {
  const Cloud& cloud = world.cloud();
  const bool fated = !ranked_.empty();
  const int cols = top_.width, rows = top_.height;
  const cv::Vec3b stays = pixel(kStays);
  auto cell_at = [&](int32_t at) {
    int32_t& k = cell_of_pixel_[size_t(at)];
    if (k < 0) k = int32_t(cells_.size()), cells_.push_back({}), cells_.back().pixel = at;
    return size_t(k);
  };
  cells_.clear();
  float most = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const cv::Point p = to_pixel({cloud.x[i], cloud.y[i]}) - top_.tl();
    if (p.x < 0 || p.y < 0 || p.x >= cols || p.y >= rows) continue;
    Cell& cell = cells_[cell_at(p.y * cols + p.x)];
    const float w = float(cloud.weight(i));
    const cv::Vec3b& c = fated ? group_colour_[report.group_of[i]] : stays;
    cell.weight += w, cell.b += c[0] * w, cell.g += c[1] * w, cell.r += c[2] * w;
    most = std::max(most, cell.weight);
  }
  const size_t covered = cells_.size();
  cells_.reserve(9 * covered);
  for (size_t k = 0; k < covered; ++k) {
    const int x = cells_[k].pixel % cols, y = cells_[k].pixel / cols;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (x + dx < 0 || y + dy < 0 || x + dx >= cols || y + dy >= rows) continue;
        Cell& around = cells_[cell_at(cells_[k].pixel + dy * cols + dx)];
        if (cells_[k].weight > around.spread) around.spread = cells_[k].weight, around.heaviest = int32_t(k);
      }
  }
  const cv::Vec3b background = pixel(kBackground);
  for (const Cell& cell : cells_) {
    cell_of_pixel_[size_t(cell.pixel)] = -1;
    const cv::Point p(cell.pixel % cols + top_.x, cell.pixel / cols + top_.y);
    if (layer_.at<cv::Vec3b>(p) != background) continue;  // a line of the field
    const Cell& from = cells_[size_t(cell.heaviest)];
    const float alpha = 0.35f + 0.65f * std::sqrt(std::min(1.0f, cell.spread / most)), keep = 1 - alpha;
    const float to_colour = alpha / from.weight;
    cv::Vec3b& out = image.at<cv::Vec3b>(p);
    out = {cv::saturate_cast<uint8_t>(out[0] * keep + from.b * to_colour), cv::saturate_cast<uint8_t>(out[1] * keep + from.g * to_colour),
           cv::saturate_cast<uint8_t>(out[2] * keep + from.r * to_colour)};
  }
}

// Fields with height: the view from the side. The players as high as they reach, every particle
// at its height in its fate's colour (the floor, the boards and the rings are in the layer; the
// predicted paths are drawn with the top view's).
void Picture::draw_side(const World& world, const FateReport& report, cv::Mat& image) {
  for (size_t k = 0; k < field_.bodies.size(); ++k) {
    const Vec2 p = world.body_positions()[k];
    const float r = field_.bodies[k].radius;
    cv::rectangle(image, px_side({p.x - r, p.y - r, 0}), px_side({p.x + r, p.y + r, world.reach(int(k))}),
                  team_colour(field_.bodies[k].team) * 0.7, 1, cv::LINE_AA);
  }
  const Cloud& cloud = world.cloud();
  const bool fated = !ranked_.empty();
  const cv::Vec3b stays = pixel(kStays);
  const cv::Vec3b background = pixel(kBackground);
  for (size_t i = 0; i < cloud.size() && cloud.tall(); ++i) {
    const cv::Point p = px_side({cloud.x[i], cloud.y[i], cloud.z[i]});
    if (!side_.contains(p) || layer_.at<cv::Vec3b>(p) != background) continue;
    image.at<cv::Vec3b>(p) = fated ? group_colour_[report.group_of[i]] : stays;
  }
  if (world.holder() >= 0) {
    const Vec2 p = world.body_positions()[size_t(world.holder())];
    cv::circle(image, px_side({p.x, p.y, world.reach(world.holder())}), std::max(4, int(field_.ball_radius * scale_)), kText,
               cv::FILLED, cv::LINE_AA);
  }
}

// The likeliest fates' ways: each one's heaviest particle's path, the likeliest three bold.
// Staying in the field is drawn faint: it is where the ball goes when nothing happens. Where each
// ends is kept for its tweaked probability, written there once the players' names are placed.
void Picture::draw_paths(const World& world, const FateReport& report, cv::Mat& image) {
  cv::Mat top = image(top_), side = side_.empty() ? cv::Mat() : image(side_);
  for (size_t r = std::min(ranked_.size(), size_t(std::max(options_.top_fates, 0))); r-- > 0;) {
    const FateGroup& g = report.groups[ranked_[r]];
    const bool stays = g.fate.kind == FateKind::Field;
    const cv::Vec3b& shade = group_colour_[ranked_[r]];
    const cv::Scalar c = cv::Scalar(shade[0], shade[1], shade[2]) * (stays ? 0.6 : 1.0);
    const int thickness = r < 3 && !stays ? 3 : 1;
    const std::vector<Vec3> path = world.predict_path(g.representative, report.horizon);
    for (size_t k = 1; k < path.size(); ++k) {
      cv::line(top, to_pixel({path[k - 1].x, path[k - 1].y}) - top_.tl(), to_pixel({path[k].x, path[k].y}) - top_.tl(), c,
               thickness, cv::LINE_AA);
      if (!side.empty()) cv::line(side, px_side(path[k - 1]) - side_.tl(), px_side(path[k]) - side_.tl(), c, thickness, cv::LINE_AA);
    }
    if (!path.empty()) path_ends_.push_back({to_pixel({path.back().x, path.back().y}), percent(g.tweaked_mass), c});
  }
  std::reverse(path_ends_.begin(), path_ends_.end());  // the likeliest first: labelled first, it gets the better place
}

// The players as discs in their team's colour, the ball in a holder's hands as a white ball on
// it, the player a person drives ringed; then their names, so no disc hides one.
void Picture::draw_bodies(const World& world, int hand, cv::Mat& image) {
  obstacles_.clear();
  for (size_t k = 0; k < field_.bodies.size(); ++k) {
    const cv::Point at = to_pixel(world.body_positions()[k]);
    const int r = std::max(4, int(field_.bodies[k].radius * scale_));
    cv::circle(image, at, r, team_colour(field_.bodies[k].team), cv::FILLED, cv::LINE_AA);
    cv::circle(image, at, r, kText, 1, cv::LINE_AA);
    obstacles_.push_back({at.x - r, at.y - r, 2 * r + 1, 2 * r + 1});
  }
  if (world.holder() >= 0) {
    const cv::Point at = to_pixel(world.body_positions()[size_t(world.holder())]);
    const int r = std::max(4, int(field_.ball_radius * scale_));
    cv::circle(image, at, r, kText, cv::FILLED, cv::LINE_AA);
    cv::circle(image, at, r, kBackground, 1, cv::LINE_AA);
  }
  const bool handed = hand >= 0 && size_t(hand) < field_.bodies.size();
  if (handed) {
    const cv::Point at = to_pixel(world.body_positions()[size_t(hand)]);
    const int r = std::max(4, int(field_.bodies[size_t(hand)].radius * scale_)) + 4;
    cv::circle(image, at, r + 1, kBackground, 3, cv::LINE_AA);
    cv::circle(image, at, r, kText, 2, cv::LINE_AA);
    obstacles_[size_t(hand)] = {at.x - r - 2, at.y - r - 2, 2 * r + 5, 2 * r + 5};
  }
  auto name = [&](size_t k) {
    const cv::Point at = to_pixel(world.body_positions()[k]);
    const int r = std::max(4, int(field_.bodies[k].radius * scale_)) + (int(k) == hand ? 6 : 0);
    const cv::Scalar c = team_colour(field_.bodies[k].team) * 0.5 + kText * 0.5;
    if (int(k) == hand) place_label(field_.bodies[k].name + " (you)", at, r, kText, image);
    else place_label(field_.bodies[k].name, at, r, c, image);
  };
  if (handed) name(size_t(hand));
  for (size_t k = 0; k < field_.bodies.size(); ++k)
    if (int(k) != hand) name(k);
}

// Writes `text` near `at` (a disc of radius `clearance` there), in the first of the places around
// it that costs least: one inside the view from above counts before one that covers no other
// label, and that before one that covers no disc; nearer places before farther ones.
void Picture::place_label(const std::string& s, cv::Point at, int clearance, const cv::Scalar& colour, cv::Mat& image) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(s, kFont, font_, 1, &baseline);
  const int w = size.width + 2, h = size.height + baseline + 2, gap = 3;
  cv::Rect best;
  long best_cost = -1;
  for (int ring = 0; ring < 3; ++ring) {
    const int c = clearance + gap + ring * h, d = int(c * 0.7);
    const cv::Point corners[] = {
        {at.x + c, at.y - h / 2},     {at.x - c - w, at.y - h / 2}, {at.x - w / 2, at.y - c - h}, {at.x - w / 2, at.y + c},
        {at.x + d, at.y - d - h},     {at.x + d, at.y + d},         {at.x - d - w, at.y - d - h}, {at.x - d - w, at.y + d}};
    for (size_t k = 0; k < std::size(corners); ++k) {
      const cv::Rect box(corners[k], cv::Size(w, h));
      long cost = long(ring) * 8 + long(k);
      cost += 1'000'000L * outside(box, top_);
      for (const FieldLabel& l : labels_) cost += 10'000L * overlap(box, l.box);
      for (const cv::Rect& o : obstacles_) cost += 100L * overlap(box, o);
      if (best_cost < 0 || cost < best_cost) best_cost = cost, best = box;
    }
  }
  const cv::Point origin(best.x + 1, best.y + 1 + size.height);
  cv::putText(image, s, origin, kFont, font_, kBackground, 3, cv::LINE_AA);  // a dark edge: legible on the cloud
  text(image, s, origin, colour);
  labels_.push_back({s, best});
}

// The next piece of the header line: on the next line when it does not fit on this one and the
// legend has another for the header (beside the field), else cut.
void Picture::header(cv::Mat& image, const std::string& s, const cv::Scalar& colour) {
  constexpr double kHeader = 4.0 / 3;  // the header's text is a third larger
  if (s.empty()) return;
  const int width = text_width(s, kHeader), room = legend_.header.x + legend_.room - header_.x;
  if (width > room && header_.x > legend_.header.x && header_.y < legend_.header.y + (legend_.header_lines - 1) * line_)
    header_ = {legend_.header.x, header_.y + line_ * 4 / 3};
  text(image, s, header_, colour, kHeader);
  header_.x += width + line_;
}

void Picture::draw(const game::Match& match, const Overlay& overlay, cv::Mat& image) {
  draw_frame(match.world(), match.report(), overlay, image);
  // The score and the power-ups go on in the header line, then the desk's status.
  for (const auto& [team, goals] : match.score()) header(image, team + " " + std::to_string(goals), team_colour(team));
  for (const game::ActivePowerup& p : match.powerups()) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%s: %s %.1f s", match.players()[size_t(p.player)].name.c_str(), p.name.c_str(),
                  std::max(0.0, p.until - match.time()));
    header(image, buf, kOut);
  }
  header(image, overlay.status, kWarning);
}

void Picture::draw(const World& world, const FateReport& report, const Overlay& overlay, cv::Mat& image) {
  draw_frame(world, report, overlay, image);
  header(image, overlay.status, kWarning);
}

void Picture::draw_frame(const World& world, const FateReport& report, const Overlay& overlay, cv::Mat& image) {
  image.create(size_, CV_8UC3);
  layer_.copyTo(image);
  labels_.clear();
  // The report describes this cloud only when it has a group for every particle.
  const bool fated = world.live() && report.group_of.size() == world.cloud().size();
  ranked_.resize(fated ? report.groups.size() : 0);
  for (size_t g = 0; g < ranked_.size(); ++g) ranked_[g] = g;
  std::sort(ranked_.begin(), ranked_.end(),
            [&](size_t a, size_t b) { return report.groups[a].tweaked_mass > report.groups[b].tweaked_mass; });
  // Each group's colour: its kind's, darker for each likelier group of its kind and target.
  group_colour_.resize(ranked_.size());
  std::map<std::pair<int, int>, size_t> seen;
  for (size_t g : ranked_) {
    const Fate& f = report.groups[g].fate;
    group_colour_[g] = pixel(fate_colour(f, seen[{int(f.kind), f.target}]++));
  }
  draw_cloud(world, report, image);
  if (side_axis_ >= 0) draw_side(world, report, image);
  for (const Wormhole& w : world.wormholes())
    for (Vec2 m : {w.a, w.b}) cv::circle(image, to_pixel(m), int(w.radius * scale_), kOut, 2, cv::LINE_AA);
  path_ends_.clear();
  if (options_.paths && fated) draw_paths(world, report, image);
  draw_bodies(world, overlay.hand, image);
  for (const PathEnd& end : path_ends_) place_label(end.probability, end.at, 3, end.colour, image);
  draw_legend(world, report, overlay, image);
}

std::string Picture::fit(const std::string& s, int room) const {
  if (text_width(s) <= room) return s;
  std::string cut = s;
  while (!cut.empty() && text_width(cut + "...") > room) cut.pop_back();
  return cut + "...";
}

// Writes `s` from `at` on, on at most `lines` lines of `room` pixels, broken at spaces; what does
// not fit is cut, marked "...".
void Picture::write(cv::Mat& image, const std::string& s, cv::Point at, int room, int lines, const cv::Scalar& colour) const {
  size_t from = 0;
  for (int k = 0; k < lines && from < s.size(); ++k, at.y += line_) {
    const std::string rest = s.substr(from);
    // Broken between the widest spaces that leave a line that fits: the keys' "s step   m slow".
    size_t cut = std::string::npos;
    for (const char* gap : {"   ", " "}) {
      for (cut = rest.size(); k + 1 < lines && cut != std::string::npos && text_width(rest.substr(0, cut)) > room;)
        cut = cut == 0 ? std::string::npos : rest.rfind(gap, cut - 1);
      if (cut != std::string::npos && cut > 0) break;
    }
    if (cut == std::string::npos || cut == 0) cut = rest.size();
    text(image, fit(rest.substr(0, cut), room), at, colour);
    from = s.find_first_not_of(' ', from + cut);
  }
}

// The legend's figures of this frame: the header line's sport and time, the outcomes' totals, the
// likeliest paths, the announcer's last phrases, the last draw and the keys.
void Picture::draw_legend(const World& world, const FateReport& report, const Overlay& overlay, cv::Mat& image) {
  header_ = legend_.header;
  header(image, overlay.title, kText);
  header(image, clock(world.time()), kText);
  const int numbers = line_ + text_width(newtonian_to_tweaked(1, 1)) + line_ / 2;  // where a row's name starts
  auto row = [&](cv::Point at, const cv::Scalar& colour, double mass, double tweaked, const std::string& name, int room) {
    cv::rectangle(image, cv::Rect(at + cv::Point(0, -line_ / 2), swatch()), colour, cv::FILLED);
    text(image, newtonian_to_tweaked(mass, tweaked), at + cv::Point(line_, 0), kText);
    text(image, fit(name, room - numbers), at + cv::Point(numbers, 0), kText);
  };
  // Every outcome with its totals, the likeliest first; those without a cell of their own share the last.
  const std::vector<OutcomeTotal> totals = ranked_.empty() ? std::vector<OutcomeTotal>{} : outcome_totals(report, world.field());
  const size_t cells = size_t(legend_.outcome_rows * legend_.outcome_columns);
  for (size_t k = 0; k < totals.size() && k < cells; ++k) {
    const cv::Point at = legend_.outcomes + cv::Point(int(k) % legend_.outcome_columns * outcome_width_,
                                                      (1 + int(k) / legend_.outcome_columns) * line_);
    if (k + 1 == cells && totals.size() > cells) {
      double mass = 0, tweaked = 0;
      for (size_t rest = k; rest < totals.size(); ++rest) mass += totals[rest].mass, tweaked += totals[rest].tweaked_mass;
      row(at, kDim, mass, tweaked, std::to_string(totals.size() - k) + " rarer outcomes", outcome_width_);
    } else {
      row(at, fate_colour(totals[k].fate, 0), totals[k].mass, totals[k].tweaked_mass, totals[k].name, outcome_width_);
    }
  }
  // The likeliest paths, in the colours they are drawn in.
  for (size_t r = 0; r < ranked_.size() && r < size_t(std::max(options_.top_fates, 0)); ++r) {
    const FateGroup& g = report.groups[ranked_[r]];
    const cv::Vec3b& c = group_colour_[ranked_[r]];
    row(legend_.paths + cv::Point(0, int(r + 1) * line_), cv::Scalar(c[0], c[1], c[2]), g.mass, g.tweaked_mass,
        describe(g.fate, world.field()), legend_.paths_room);
  }
  if (ranked_.empty()) {
    const std::string why = world.live()           ? "(no prediction yet)"
                            : world.holder() >= 0 ? "(the ball is in " + world.field().bodies[size_t(world.holder())].name + "'s hands)"
                                                  : "(no ball in play)";
    text(image, fit(why, legend_.room), legend_.outcomes + cv::Point(0, line_), kDim);
  }
  // The announcer's last phrases, and what became of them.
  if (overlay.ticker) {
    text(image, "announcer", legend_.announcer, kDim);
    const std::deque<Ticker::Line>& lines = overlay.ticker->lines();
    cv::Point at = legend_.announcer;
    const int room = legend_.room - (at.x - legend_.key.x);
    for (size_t k = lines.size() > kTickerRows ? lines.size() - kTickerRows : 0; k < lines.size(); ++k) {
      const Ticker::Line& line = lines[k];
      at.y += line_;
      std::string s = clock(line.t) + "  " + line.text;
      if (line.fate == Ticker::Line::Fate::Cut) s += "  (cut)";
      if (line.fate == Ticker::Line::Fate::Dropped) s += "  (dropped)";
      text(image, fit(s, room), at, line.fate == Ticker::Line::Fate::Said ? kText : kWarning);
    }
  }
  write(image, overlay.last_draw, legend_.last_draw, legend_.room, legend_.last_draw_lines, kDim);
  write(image, overlay.help, legend_.help, legend_.room, legend_.help_lines, kDim);
}

void check_snapshot_file(const std::string& path) {
  check_output_file("--snapshot", path);
  if (!cv::haveImageWriter(path))
    throw std::runtime_error("--snapshot " + path + ": not a picture file OpenCV writes (name it .png or .jpg)");
}

void write_snapshot(const std::string& path, const cv::Mat& image) {
  bool written = false;
  try {
    written = cv::imwrite(path, image);
  } catch (const cv::Exception&) {
  }
  if (!written) throw std::runtime_error("--snapshot " + path + ": cannot be written");
}

}  // namespace quantum::runtime

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

constexpr int kLine = 20;  // pixels between text lines
const cv::Scalar kBackground(28, 28, 28), kText(235, 235, 235), kDim(150, 150, 150), kWall(230, 230, 230);
const cv::Scalar kGoal(40, 215, 255), kOwnGoal(0, 140, 255), kOut(210, 90, 210), kStays(165, 165, 165);
const cv::Scalar kWarning(60, 170, 255);  // cut or dropped phrases
// Teams in the order the field names them: blue and red first, as the shipped sports use them.
const cv::Scalar kTeams[] = {{235, 140, 45}, {70, 70, 235}, {90, 200, 90}, {50, 200, 230}, {200, 110, 200}};

void text(cv::Mat& img, const std::string& s, cv::Point at, const cv::Scalar& colour, double size = 0.5) {
  cv::putText(img, s, at, cv::FONT_HERSHEY_SIMPLEX, size, colour, 1, cv::LINE_AA);
}

std::string clock(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%d:%05.2f", int(t / 60), std::fmod(t, 60.0));
  return buf;
}

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

Picture::Picture(const Field& field, PictureOptions options) : field_(field), options_(options) {
  const float w = field_.bounds_max.x - field_.bounds_min.x, h = field_.bounds_max.y - field_.bounds_min.y;
  scale_ = double(options_.width - 2 * margin_) / w;
  field_height_ = top_height_ = int(h * scale_) + 2 * margin_;
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
    float top = 4;
    for (const Goal& g : field_.goals) top = std::max(top, g.rim_height + 1);
    for (const Board& b : field_.boards) top = std::max(top, b.top + 0.5f);
    for (size_t k = 0; k < field_.bodies.size(); ++k) top = std::max(top, field_.reach_of(int(k)) + 1);
    if (field_.ceiling > 0) top = field_.ceiling;
    floor_row_ = field_height_ + int(top * scale_) + margin_;
    field_height_ = floor_row_ + margin_;
  }
  size_t k = 0;
  for (const std::string& team : field_.teams()) team_colours_[team] = kTeams[k++ % std::size(kTeams)];
}

cv::Point Picture::px(Vec2 p) const {
  // Field y points to the left of a player facing +x; image rows go down.
  return {margin_ + int((p.x - field_.bounds_min.x) * scale_), margin_ + int((field_.bounds_max.y - p.y) * scale_)};
}

cv::Point Picture::px_side(Vec3 p) const {
  const float u = side_axis_ == 0 ? p.x : p.y, u0 = side_axis_ == 0 ? field_.bounds_min.x : field_.bounds_min.y;
  return {margin_ + int((u - u0) * scale_), floor_row_ - int(p.z * scale_)};
}

Vec2 Picture::to_field(int x, int y) const {
  return {float(field_.bounds_min.x + (x - margin_) / scale_), float(field_.bounds_max.y - (y - margin_) / scale_)};
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

void Picture::draw_field(const World& world, const FateReport& report, cv::Mat& whole) {
  // The view from above keeps to its own rows; with height the side view is drawn under it.
  cv::Mat img = side_axis_ >= 0 ? whole(cv::Rect(0, 0, whole.cols, top_height_)) : whole;
  const Cloud& cloud = world.cloud();
  // The report describes this cloud only when it has a group for every particle.
  const bool fated = world.live() && report.group_of.size() == cloud.size();
  ranked_.resize(fated ? report.groups.size() : 0);
  for (size_t g = 0; g < ranked_.size(); ++g) ranked_[g] = g;
  std::sort(ranked_.begin(), ranked_.end(),
            [&](size_t a, size_t b) { return report.groups[a].tweaked_mass > report.groups[b].tweaked_mass; });
  std::vector<size_t> rank(ranked_.size());
  for (size_t r = 0; r < ranked_.size(); ++r) rank[ranked_[r]] = r;
  // Ranks among fates of one kind (and body), for their shades.
  std::vector<size_t> shade(ranked_.size());
  std::map<std::pair<int, int>, size_t> seen;
  for (size_t g : ranked_) shade[g] = seen[{int(report.groups[g].fate.kind), report.groups[g].fate.target}]++;

  // The cloud: every particle's weight and fate colour gathered per pixel, so that a million
  // particles cost one pass, and drawn with an alpha that grows with the weight there. A lone
  // particle still shows, as a dot of three pixels.
  density_.create(img.rows, img.cols, CV_32F);
  tint_.create(img.rows, img.cols, CV_32FC3);
  density_.setTo(0);
  tint_.setTo(cv::Scalar::all(0));
  float most = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const cv::Point p = px({cloud.x[i], cloud.y[i]});
    if (p.x < 0 || p.y < 0 || p.x >= img.cols || p.y >= img.rows) continue;
    const float w = float(cloud.weight(i));
    const size_t g = fated ? report.group_of[i] : 0;
    const cv::Scalar c = fated ? fate_colour(report.groups[g].fate, shade[g]) : kStays;
    float& d = density_.at<float>(p);
    d += w;
    most = std::max(most, d);
    cv::Vec3f& t = tint_.at<cv::Vec3f>(p);
    t += cv::Vec3f(float(c[0]), float(c[1]), float(c[2])) * w;
  }
  if (most > 0) {
    cv::Mat spread, colour;
    cv::dilate(density_, spread, cv::Mat::ones(3, 3, CV_8U));
    cv::dilate(tint_, colour, cv::Mat::ones(3, 3, CV_8U));
    for (int y = 0; y < img.rows; ++y)
      for (int x = 0; x < img.cols; ++x) {
        const float d = spread.at<float>(y, x);
        if (d <= 0) continue;
        const cv::Vec3f c = colour.at<cv::Vec3f>(y, x) / d;
        const float alpha = 0.35f + 0.65f * std::sqrt(std::min(1.0f, d / most));
        cv::Vec3b& out = img.at<cv::Vec3b>(y, x);
        for (int k = 0; k < 3; ++k) out[k] = cv::saturate_cast<uint8_t>(out[k] * (1 - alpha) + c[k] * alpha);
      }
  }
  // The likeliest fates' ways: each one's heaviest particle's path, the likeliest three bold.
  // Staying in the field is drawn faint: it is where the ball goes when nothing happens.
  if (options_.paths && fated) {
    for (size_t r = ranked_.size() < size_t(options_.top_fates) ? ranked_.size() : size_t(options_.top_fates); r-- > 0;) {
      const size_t g = ranked_[r];
      const bool stays = report.groups[g].fate.kind == FateKind::Field;
      const cv::Scalar c = fate_colour(report.groups[g].fate, shade[g]) * (stays ? 0.6 : 1.0);
      const std::vector<Vec3> path = world.predict_path(report.groups[g].representative, report.horizon);
      for (size_t k = 1; k < path.size(); ++k) {
        cv::line(img, px({path[k - 1].x, path[k - 1].y}), px({path[k].x, path[k].y}), c, r < 3 && !stays ? 3 : 1, cv::LINE_AA);
        if (side_axis_ >= 0) cv::line(whole, px_side(path[k - 1]), px_side(path[k]), c, r < 3 && !stays ? 3 : 1, cv::LINE_AA);
      }
    }
  }
  if (side_axis_ >= 0) draw_side(world, report, fated, shade, whole);
  // A court's lines are its bounds; its areas (goal areas) are outlined in their team's colour.
  if (field_.has_bounds) cv::rectangle(img, px(field_.bounds_min), px(field_.bounds_max), kDim, 1, cv::LINE_AA);
  for (const Area& a : field_.areas) {
    if (a.box) {
      cv::rectangle(img, px(a.a), px(a.b), team_colour(a.team) * 0.6, 1, cv::LINE_AA);
      continue;
    }
    std::vector<cv::Point> outline;
    const float heading = std::atan2(a.b.y - a.a.y, a.b.x - a.a.x);
    for (int end = 0; end < 2; ++end)
      for (int k = 0; k <= 16; ++k) {
        const float angle = heading + float(std::numbers::pi) * (0.5f + float(end) + float(k) / 16);
        const Vec2 c = end == 0 ? a.a : a.b;
        outline.push_back(px({c.x + a.radius * std::cos(angle), c.y + a.radius * std::sin(angle)}));
      }
    cv::polylines(img, outline, true, team_colour(a.team) * 0.6, 1, cv::LINE_AA);
  }
  for (const Segment& s : field_.segments) cv::line(img, px(s.a), px(s.b), kWall, 3, cv::LINE_AA);
  for (const Goal& g : field_.goals) {
    if (g.hoop()) cv::circle(img, px(g.a), std::max(3, int(g.rim_radius * scale_)), kGoal, 2, cv::LINE_AA);
    else cv::line(img, px(g.a), px(g.b), team_colour(g.team), 5, cv::LINE_AA);
  }
  for (const Board& b : field_.boards) cv::line(img, px(b.a), px(b.b), kWall, 3, cv::LINE_AA);
  for (const Spot& s : field_.spots) cv::drawMarker(img, px(s.at), kDim, cv::MARKER_CROSS, 12, 1);
  for (const Wormhole& w : world.wormholes())
    for (Vec2 m : {w.a, w.b}) cv::circle(img, px(m), int(w.radius * scale_), kOut, 2, cv::LINE_AA);
  for (size_t k = 0; k < field_.bodies.size(); ++k) {
    const BodySpec& b = field_.bodies[k];
    const cv::Point at = px(world.body_positions()[k]);
    const cv::Scalar c = team_colour(b.team);
    cv::circle(img, at, std::max(4, int(b.radius * scale_)), c, cv::FILLED, cv::LINE_AA);
    cv::circle(img, at, std::max(4, int(b.radius * scale_)), kText, 1, cv::LINE_AA);
    text(img, b.name, at + cv::Point(int(b.radius * scale_) + 4, -4), c * 0.5 + kText * 0.5, 0.45);
  }
  // The ball in a player's hands: a white ball on the holder.
  if (world.holder() >= 0) {
    const cv::Point at = px(world.body_positions()[size_t(world.holder())]);
    const int r = std::max(4, int(field_.ball_radius * scale_));
    cv::circle(img, at, r, kText, cv::FILLED, cv::LINE_AA);
    cv::circle(img, at, r, kBackground, 1, cv::LINE_AA);
  }
}

// Fields with height: the view from the side, under the top view. The floor, the boards and the
// rings edge-on, the players as high as they reach, every particle at its height in its fate's
// colour (the predicted paths are drawn with the top view's).
void Picture::draw_side(const World& world, const FateReport& report, bool fated, const std::vector<size_t>& shade,
                        cv::Mat& img) {
  const Vec2 lo = field_.bounds_min, hi = field_.bounds_max;
  cv::line(img, px_side({lo.x, lo.y, 0}), px_side({hi.x, hi.y, 0}), kDim, 2, cv::LINE_AA);
  text(img, side_axis_ == 0 ? "from the side (across x)" : "from the side (across y)", px_side({lo.x, lo.y, 0}) + cv::Point(0, 20),
       kDim, 0.45);
  if (field_.ceiling > 0)
    cv::line(img, px_side({lo.x, lo.y, field_.ceiling}), px_side({hi.x, hi.y, field_.ceiling}), kDim, 1, cv::LINE_AA);
  for (const Board& b : field_.boards)
    cv::rectangle(img, px_side({std::min(b.a.x, b.b.x), std::min(b.a.y, b.b.y), b.bottom}),
                  px_side({std::max(b.a.x, b.b.x), std::max(b.a.y, b.b.y), b.top}), kWall, 2, cv::LINE_AA);
  for (size_t k = 0; k < field_.bodies.size(); ++k) {
    const Vec2 p = world.body_positions()[k];
    const float r = field_.bodies[k].radius;
    cv::rectangle(img, px_side({p.x - r, p.y - r, 0}), px_side({p.x + r, p.y + r, world.reach(int(k))}),
                  team_colour(field_.bodies[k].team) * 0.7, 1, cv::LINE_AA);
  }
  const Cloud& cloud = world.cloud();
  for (size_t i = 0; i < cloud.size() && cloud.tall(); ++i) {
    const size_t g = fated ? report.group_of[i] : 0;
    const cv::Point p = px_side({cloud.x[i], cloud.y[i], cloud.z[i]});
    if (p.x < 0 || p.y < 0 || p.x >= img.cols || p.y >= img.rows) continue;
    const cv::Scalar c = fated ? fate_colour(report.groups[g].fate, shade[g]) : kStays;
    img.at<cv::Vec3b>(p) = {cv::saturate_cast<uint8_t>(c[0]), cv::saturate_cast<uint8_t>(c[1]), cv::saturate_cast<uint8_t>(c[2])};
  }
  for (const Goal& g : field_.goals)
    if (g.hoop())
      cv::line(img, px_side({g.a.x - g.rim_radius, g.a.y - g.rim_radius, g.rim_height}),
               px_side({g.a.x + g.rim_radius, g.a.y + g.rim_radius, g.rim_height}), kGoal, 3, cv::LINE_AA);
  if (world.holder() >= 0) {
    const Vec2 p = world.body_positions()[size_t(world.holder())];
    cv::circle(img, px_side({p.x, p.y, world.reach(world.holder())}), std::max(4, int(field_.ball_radius * scale_)), kText,
               cv::FILLED, cv::LINE_AA);
  }
}

std::string outcome_summary(const FateReport& report, const Field& field) {
  // Kept in first-seen order of the likeliest fates, so the line reads from the likeliest.
  std::vector<std::pair<std::string, std::pair<double, double>>> rows;
  auto add = [&](const std::string& what, const FateGroup& g) {
    auto it = std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.first == what; });
    if (it == rows.end()) it = rows.insert(rows.end(), {what, {0, 0}});
    it->second.first += g.mass, it->second.second += g.tweaked_mass;
  };
  std::vector<const FateGroup*> order;
  for (const FateGroup& g : report.groups) order.push_back(&g);
  std::stable_sort(order.begin(), order.end(), [](const FateGroup* a, const FateGroup* b) { return a->tweaked_mass > b->tweaked_mass; });
  for (const FateGroup* g : order) {
    const Fate& f = g->fate;
    const bool bounced = f.path_len > 0;
    if (f.kind == FateKind::Goal || f.kind == FateKind::OwnGoal) add(field.goals[size_t(f.target)].name, *g);
    else if (f.kind == FateKind::Out) add("out", *g);
    else if (f.kind == FateKind::Field) add("in play", *g);
    else if (f.kind == FateKind::Landing) add(describe(f, field), *g);
    else if (bounced) add("rebound " + field.bodies[size_t(f.target)].name, *g);
    else if (f.kind == FateKind::Intercept) add("blocked by " + field.bodies[size_t(f.target)].name, *g);
    else add("caught by " + field.bodies[size_t(f.target)].name, *g);
  }
  std::string line;
  for (const auto& [what, p] : rows) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s%s %.1f%% -> %.1f%%", line.empty() ? "" : " | ", what.c_str(), 100 * p.first,
                  100 * p.second);
    line += buf;
  }
  return line;
}

void Picture::header(cv::Mat& image, const std::string& s, const cv::Scalar& colour) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, 0.6, 1, &baseline);
  text(image, s, {header_x_, field_height_ + 22}, colour, 0.6);
  header_x_ += size.width + 24;
}

void Picture::draw(const game::Match& match, const Overlay& overlay, cv::Mat& image) {
  draw(match.world(), match.report(), overlay, image);
  // The score and the power-ups go on in the header line.
  for (const auto& [team, goals] : match.score()) header(image, team + " " + std::to_string(goals), team_colour(team));
  for (const game::ActivePowerup& p : match.powerups()) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%s: %s %.1f s", match.players()[size_t(p.player)].name.c_str(), p.name.c_str(),
                  std::max(0.0, p.until - match.time()));
    header(image, buf, kOut);
  }
}

void Picture::draw(const World& world, const FateReport& report, const Overlay& overlay, cv::Mat& image) {
  const size_t ticker = overlay.ticker ? 6 : 0;
  const int outcomes = side_axis_ >= 0 ? 2 : 0;  // fields with height: the outcomes line, two rows
  const int rows = int(std::max<size_t>(size_t(options_.top_fates) + 3 + size_t(outcomes), ticker + 1)) + 4;
  image.create(field_height_ + rows * kLine + 10, options_.width, CV_8UC3);
  image.setTo(kBackground);
  cv::Mat field_area = image(cv::Rect(0, 0, image.cols, field_height_));
  draw_field(world, report, field_area);

  int y = field_height_ + 22;
  header_x_ = margin_;
  header(image, overlay.title, kText);
  header(image, clock(world.time()), kText);
  // The likeliest fates, with the colour each is drawn in.
  y += kLine + 6;
  text(image, "Newtonian  tweaked   fate", {margin_ + 22, y}, kDim, 0.45);
  const bool fated = !ranked_.empty();
  double rest_mass = 0, rest_tweaked = 0;
  for (size_t r = 0; r < ranked_.size(); ++r) {
    const FateGroup& g = report.groups[ranked_[r]];
    if (r >= size_t(options_.top_fates)) {
      rest_mass += g.mass, rest_tweaked += g.tweaked_mass;
      continue;
    }
    y += kLine;
    size_t shade = 0;
    for (size_t q = 0; q < r; ++q)
      shade += report.groups[ranked_[q]].fate.kind == g.fate.kind && report.groups[ranked_[q]].fate.target == g.fate.target;
    cv::rectangle(image, cv::Rect(margin_, y - 11, 14, 12), fate_colour(g.fate, shade), cv::FILLED);
    std::string name = describe(g.fate, world.field());
    if (name.size() > 44) name = name.substr(0, 43) + "...";
    char buf[160];
    std::snprintf(buf, sizeof buf, "%6.1f%%   %6.1f%%   %s", 100 * g.mass, 100 * g.tweaked_mass, name.c_str());
    text(image, buf, {margin_ + 22, y}, kText, 0.45);
  }
  if (ranked_.size() > size_t(options_.top_fates)) {
    y += kLine;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%6.1f%%   %6.1f%%   %zu rarer fates together", 100 * rest_mass, 100 * rest_tweaked,
                  ranked_.size() - size_t(options_.top_fates));
    text(image, buf, {margin_ + 22, y}, kDim, 0.45);
  }
  if (outcomes > 0 && fated) {
    std::string line = outcome_summary(report, world.field());
    const size_t cut = line.size() > 110 ? line.rfind(" | ", 110) : std::string::npos;
    text(image, line.substr(0, cut), {margin_ + 22, y + kLine}, kText, 0.45);
    if (cut != std::string::npos) text(image, line.substr(cut + 3), {margin_ + 22, y + 2 * kLine}, kText, 0.45);
  }
  if (!fated) {
    const std::string why = world.live()           ? "(no prediction yet)"
                            : world.holder() >= 0 ? "(the ball is in " + world.field().bodies[size_t(world.holder())].name + "'s hands)"
                                                  : "(no ball in play)";
    text(image, why, {margin_ + 22, y + kLine}, kDim, 0.45);
  }
  // Every colour the picture uses, the rarer fates' included.
  int x = margin_;
  const int key_y = field_height_ + 22 + kLine * (options_.top_fates + 3 + outcomes) + 6;
  auto key = [&](const std::string& name, const cv::Scalar& c) {
    cv::rectangle(image, cv::Rect(x, key_y - 11, 14, 12), c, cv::FILLED);
    text(image, name, {x + 20, key_y}, kDim, 0.45);
    int baseline = 0;
    x += 20 + cv::getTextSize(name, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &baseline).width + 18;
  };
  for (const auto& [team, colour] : team_colours_) key(team + " player", colour);
  key("goal", kGoal);
  key("own goal", kOwnGoal);
  key("out", kOut);
  key("stays in field", kStays);
  // The announcer's last phrases, and what became of them.
  if (overlay.ticker) {
    const int x = image.cols / 2 + 40;
    int ty = field_height_ + 22 + kLine + 6;
    text(image, "announcer", {x, ty}, kDim, 0.45);
    for (const Ticker::Line& line : overlay.ticker->lines()) {
      ty += kLine;
      const bool lost = line.fate != Ticker::Line::Fate::Said;
      std::string s = clock(line.t) + "  " + line.text;
      if (line.fate == Ticker::Line::Fate::Cut) s += "  (cut)";
      if (line.fate == Ticker::Line::Fate::Dropped) s += "  (dropped)";
      text(image, s, {x, ty}, lost ? kWarning : kText, 0.45);
    }
  }
  const int bottom = image.rows - 10;
  if (!overlay.last_draw.empty()) text(image, overlay.last_draw, {margin_, bottom - kLine}, kDim, 0.45);
  if (!overlay.status.empty()) text(image, overlay.status, {margin_, bottom}, kWarning, 0.5);
  if (!overlay.help.empty()) text(image, overlay.help, {image.cols / 2 + 40, bottom}, kDim, 0.4);
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

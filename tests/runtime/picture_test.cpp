// The desk's picture (runtime/desk/picture.h): a legend whose outcomes add up to 100 % in every
// sport, a picture that fits the box it is given with the field's aspect kept, names that stay on
// the field and apart, areas drawn only on the field, the player a person drives marked, and the
// paths' probabilities where they end.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <sstream>

#include "picture.h"
#include "scenes.h"
#include "session.h"
#include "../shipped_sports.h"
#include "lua_sport.h"

namespace quantum {
namespace {

std::string sport_folder(const std::string& sport) { return QUANTUM_SOURCE_DIR "/rules/" + sport; }

// Pixels of `image` within `rect` within 10 of colour (B, G, R) on every channel.
int pixels_of(const cv::Mat& image, cv::Rect rect, cv::Scalar colour) {
  int n = 0;
  rect &= cv::Rect({}, image.size());
  for (int y = rect.y; y < rect.br().y; ++y)
    for (int x = rect.x; x < rect.br().x; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      n += std::abs(p[0] - colour[0]) < 10 && std::abs(p[1] - colour[1]) < 10 && std::abs(p[2] - colour[2]) < 10;
    }
  return n;
}

// The world's players standing at `at`, a frame later.
void stand(World& world, const std::vector<Vec2>& at) {
  std::vector<BodyInput> input;
  for (Vec2 p : at) input.push_back({p, {0, 0}});
  std::vector<Event> events;
  world.step(1.0f / 60, input, events);
}

std::vector<Vec2> starts(const Field& field) {
  std::vector<Vec2> at;
  for (const BodySpec& b : field.bodies) at.push_back(b.start);
  return at;
}

TEST(DeskPicture, TheOutcomesAddUpToAHundredPercentInEverySport) {
  for (const std::string sport : test::kShippedSports) {
    runtime::SessionOptions o;
    o.sport = sport_folder(sport);
    o.seconds = 30;
    o.particles = 2000;
    std::ostringstream errors;
    runtime::Session session(o, tools::lua_sport, nullptr, errors);
    const Field& field = session.match().field();
    const size_t possible = 2 * field.goals.size() + field.bodies.size() + 2 + (field.landings ? field.areas.size() + 1 : 0);
    int predicted = 0;
    size_t grouped = 0, totalled = 0;
    for (int frame = 0; frame < 30 * 60 && predicted < 60; ++frame) {
      session.frame();
      const World& world = session.match().world();
      const FateReport& report = session.match().report();
      if (!world.live() || report.group_of.size() != world.cloud().size()) continue;
      ++predicted;
      const std::vector<runtime::OutcomeTotal> totals = runtime::outcome_totals(report, field);
      double mass = 0, tweaked = 0;
      std::set<uint64_t> outcomes;
      for (size_t k = 0; k < totals.size(); ++k) {
        mass += totals[k].mass, tweaked += totals[k].tweaked_mass;
        EXPECT_TRUE(outcomes.insert(totals[k].fate.key()).second) << sport << ": " << totals[k].name << " twice";
        EXPECT_EQ(totals[k].fate.path_len, 0) << sport << ": an outcome is not a way";
        if (k > 0) {
          EXPECT_GE(totals[k - 1].tweaked_mass, totals[k].tweaked_mass) << sport << ": likeliest first";
        }
      }
      EXPECT_NEAR(mass, 1.0, 1e-6) << sport << " at " << world.time() << " s";
      EXPECT_NEAR(tweaked, 1.0, 1e-6) << sport << " at " << world.time() << " s";
      EXPECT_LE(totals.size(), possible) << sport;
      grouped += report.groups.size(), totalled += totals.size();
    }
    EXPECT_GT(predicted, 10) << sport << ": the ball was hardly ever in flight";
    EXPECT_EQ(errors.str(), "") << sport;
    // Fates that differ only in their way (via which walls) are one outcome.
    if (sport == "airhockey") {
      EXPECT_LT(totalled, grouped) << sport;
    }
  }
}

TEST(DeskPicture, ThePictureFitsItsBoxWithTheFieldsAspect) {
  const cv::Size boxes[] = {{1280, 800}, {1920, 1080}, {800, 600}, {1100, 0}};
  for (const std::string sport : test::kShippedSports) {
    const lua::ScriptedRules loaded(sport_folder(sport));
    const Field& field = loaded.spec().field;
    World world(field, WorldConfig{});
    stand(world, starts(field));
    for (const cv::Size box : boxes) {
      const std::string where = sport + " in " + std::to_string(box.width) + " x " + std::to_string(box.height);
      runtime::Picture picture(field, {.width = box.width, .height = box.height});
      cv::Mat image;
      picture.draw(world, FateReport{}, runtime::Overlay{field.name, "", "q quit", nullptr, ""}, image);
      EXPECT_EQ(image.cols, box.width) << where;
      if (box.height > 0) {
        EXPECT_EQ(image.rows, box.height) << where;
      }
      const cv::Point lo = picture.to_pixel(field.bounds_min), hi = picture.to_pixel(field.bounds_max);
      const cv::Rect on_screen(0, 0, image.cols, picture.field_height());
      EXPECT_TRUE(on_screen.contains(lo) && on_screen.contains(hi)) << where << ": the field is off its area";
      // As many pixels per metre across as down.
      const double across = (hi.x - lo.x) / double(field.bounds_max.x - field.bounds_min.x);
      const double down = (lo.y - hi.y) / double(field.bounds_max.y - field.bounds_min.y);
      EXPECT_NEAR(across, down, 2 * std::max(1 / double(hi.x - lo.x), 1 / double(lo.y - hi.y)) * across) << where;
      // On a screen, the field takes a quarter of the picture or more (an eighth with the legend
      // under it and a side view under the view from above in basketball).
      if (box.width >= 1280) {
        EXPECT_GE(double(hi.x - lo.x) * (lo.y - hi.y), 0.25 * double(box.width) * box.height) << where;
      }
      // Every name written whole, in letters at least 12 pixels high.
      EXPECT_EQ(picture.labels().size(), field.bodies.size()) << where;
      for (const runtime::FieldLabel& label : picture.labels()) {
        EXPECT_TRUE(on_screen.contains(label.box.tl()) && on_screen.contains(label.box.br() - cv::Point(1, 1)))
            << where << ": " << label.text;
        EXPECT_GE(label.box.height, 14) << where << ": " << label.text;
      }
      // Looking at the pixel of a place on the field finds that place again, within a pixel.
      const Vec2 back = picture.to_field(picture.to_pixel(field.bodies[0].start).x, picture.to_pixel(field.bodies[0].start).y);
      EXPECT_NEAR(back.x, field.bodies[0].start.x, 1.5 / across) << where;
      EXPECT_NEAR(back.y, field.bodies[0].start.y, 1.5 / across) << where;
    }
  }
}

// Players in the corners, against the lines, and three of them on top of one another in the
// middle (handball's six, soccer's ten): every name is on the field, whole, on no other name and
// on no disc.
TEST(DeskPicture, NamesStayOnTheFieldApartAndOffTheDiscs) {
  for (const std::string sport : {"handball", "soccer"}) {
    const lua::ScriptedRules loaded(sport_folder(sport));
    const Field& field = loaded.spec().field;
    const Vec2 lo = field.bounds_min, hi = field.bounds_max;
    std::vector<Vec2> at = {lo, {hi.x, 0}, {0, 0}, {0, 0}, {0.3f, 0}, hi, {lo.x, hi.y}, {0, lo.y}, {0, 0.3f}, {hi.x, lo.y}};
    ASSERT_LE(field.bodies.size(), at.size());
    at.resize(field.bodies.size());
    World world(field, WorldConfig{});
    stand(world, at);
    for (const cv::Size box : {cv::Size{1100, 0}, cv::Size{1280, 800}, cv::Size{800, 600}}) {
      runtime::Picture picture(field, {.width = box.width, .height = box.height});
      cv::Mat image;
      picture.draw(world, FateReport{}, runtime::Overlay{}, image);
      const std::vector<runtime::FieldLabel>& labels = picture.labels();
      ASSERT_EQ(labels.size(), field.bodies.size());
      const cv::Rect on_screen(0, 0, image.cols, picture.field_height());
      const double scale = picture.to_pixel({1, 0}).x - picture.to_pixel({0, 0}).x;
      for (size_t k = 0; k < labels.size(); ++k) {
        const std::string where = sport + ": " + labels[k].text + " in " + std::to_string(box.width) + " x " + std::to_string(box.height);
        EXPECT_EQ((labels[k].box & on_screen), labels[k].box) << where << ": cut off at the edge";
        for (size_t j = 0; j < k; ++j) EXPECT_EQ((labels[k].box & labels[j].box).area(), 0) << where << " on " << labels[j].text;
        for (size_t b = 0; b < field.bodies.size(); ++b) {
          const cv::Point c = picture.to_pixel(world.body_positions()[b]);
          const cv::Rect& l = labels[k].box;
          const int dx = std::max({l.x - c.x, 0, c.x - (l.br().x - 1)}), dy = std::max({l.y - c.y, 0, c.y - (l.br().y - 1)});
          EXPECT_GT(std::hypot(dx, dy), field.bodies[b].radius * scale) << where << " on " << field.bodies[b].name << "'s disc";
        }
      }
      std::set<std::string> names;
      for (const runtime::FieldLabel& l : labels) names.insert(l.text);
      for (const BodySpec& b : field.bodies) EXPECT_EQ(names.count(b.name), 1u) << sport << ": " << b.name;
    }
  }
}

// Handball's goal areas reach past the goal lines, basketball's three-point line past the
// baseline: neither is drawn off the court.
TEST(DeskPicture, AreasAreDrawnOnlyOnTheField) {
  for (const std::string sport : {"handball", "basketball"}) {
    const lua::ScriptedRules loaded(sport_folder(sport));
    const Field& field = loaded.spec().field;
    runtime::Picture picture(field);
    cv::Mat image;
    World world(field, WorldConfig{});
    stand(world, starts(field));
    picture.draw(world, FateReport{}, runtime::Overlay{}, image);
    const cv::Point lo = picture.to_pixel(field.bounds_min), hi = picture.to_pixel(field.bounds_max);
    // The bands just outside the field's lines, beyond the lines' own width.
    const cv::Rect beyond[] = {{hi.x + 4, hi.y, 24, lo.y - hi.y}, {lo.x - 28, hi.y, 24, lo.y - hi.y},
                               {lo.x, lo.y + 4, hi.x - lo.x, 24}, {lo.x, hi.y - 28, hi.x - lo.x, 24}};
    int inside = 0;
    for (const Area& a : field.areas) {
      const cv::Scalar colour = (a.team.empty() ? cv::Scalar(165, 165, 165) : a.team == "blue" ? cv::Scalar(235, 140, 45)
                                                                                              : cv::Scalar(70, 70, 235)) * 0.6;
      for (const cv::Rect& band : beyond) EXPECT_EQ(pixels_of(image, band, colour), 0) << sport << ": " << a.name << " off the field";
      inside += pixels_of(image, cv::Rect(lo.x, hi.y, hi.x - lo.x, lo.y - hi.y), colour);
    }
    EXPECT_GT(inside, 100) << sport << ": the areas are drawn on the field";
  }
}

TEST(DeskPicture, ThePlayerAPersonDrivesIsRingedAndCalledYou) {
  const lua::ScriptedRules loaded(sport_folder("airhockey"));
  const Field& field = loaded.spec().field;
  World world(field, WorldConfig{});
  stand(world, starts(field));
  runtime::Picture picture(field);
  for (const int hand : {-1, 1}) {
    runtime::Overlay overlay;
    overlay.hand = hand;
    cv::Mat image;
    picture.draw(world, FateReport{}, overlay, image);
    int yours = 0;
    for (const runtime::FieldLabel& l : picture.labels()) yours += l.text == field.bodies[1].name + " (you)";
    EXPECT_EQ(yours, hand == 1 ? 1 : 0);
    // A white ring just outside Red's mallet, none around Blue's.
    const cv::Point red = picture.to_pixel(world.body_positions()[1]), blue = picture.to_pixel(world.body_positions()[0]);
    const int r = picture.to_pixel({field.bodies[1].radius, 0}).x - picture.to_pixel({0, 0}).x;
    const cv::Rect ring(red.x - r - 6, red.y - 2, 3, 5), none(blue.x - r - 6, blue.y - 2, 3, 5);
    if (hand == 1) EXPECT_GT(pixels_of(image, ring, {235, 235, 235}), 2);
    else EXPECT_EQ(pixels_of(image, ring, {235, 235, 235}), 0);
    EXPECT_EQ(pixels_of(image, none, {235, 235, 235}), 0);
  }
}

// Each drawn path is labelled with its tweaked probability where it ends, and no other.
TEST(DeskPicture, EachPathEndsWithItsProbability) {
  const lua::ScriptedRules loaded(sport_folder("airhockey"));
  const Field& field = loaded.spec().field;
  World world(field, WorldConfig{});
  world.set_cloud(tools::spread_cloud(field, 3000, 7));
  std::vector<Event> events;
  world.step(1.0f / 60, tools::scripted_mallets(field, 1.0 / 60), events);
  const FateReport report = world.predict();
  ASSERT_GT(report.groups.size(), 6u);
  std::vector<double> tweaked;
  for (const FateGroup& g : report.groups) tweaked.push_back(g.tweaked_mass);
  std::sort(tweaked.rbegin(), tweaked.rend());
  std::multiset<std::string> likeliest;
  for (size_t k = 0; k < 6; ++k) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f%%", 100 * tweaked[k]);
    likeliest.insert(buf);
  }
  runtime::Picture picture(field);
  cv::Mat image;
  auto probabilities = [&] {
    std::multiset<std::string> written;
    for (const runtime::FieldLabel& l : picture.labels())
      if (l.text.back() == '%') written.insert(l.text);
    return written;
  };
  picture.draw(world, report, runtime::Overlay{}, image);
  EXPECT_EQ(probabilities(), likeliest);
  picture.set_paths(false);
  picture.draw(world, report, runtime::Overlay{}, image);
  EXPECT_TRUE(probabilities().empty());
}

}  // namespace
}  // namespace quantum

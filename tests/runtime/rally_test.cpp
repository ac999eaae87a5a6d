// Handball played from real inputs: a synthetic overhead video of a rally with its players'
// accelerometers (tools/synthetic.h), played as a tracked match by `quantum play`. The engine
// decides every catch and the goal; a rally thrown straight at unmarked teammates and past the
// goalkeeper must come out as its truth says it was thrown.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "field_loader.h"
#include "session.h"
#include "synthetic.h"
#include "lua_sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The rally on rules/handball's hall, written into a fresh folder.
fs::path film_rally(const std::string& name, const std::vector<tools::HatSceneOptions::Away>& away = {}) {
  const fs::path dir = fs::temp_directory_path() / ("quantum_rally_" + name);
  fs::remove_all(dir);
  tools::HatSceneOptions o;
  o.away = away;
  tools::write_rally_video(dir.string(), o, lua::load_field(QUANTUM_SOURCE_DIR "/rules/handball"));
  return dir;
}

// The events the truth's rally should make, each as the fields that must match: the throw-off to
// the first thrower, then per throw the throw and the pass to the teammate aimed at, or the goal.
std::vector<json> expected_events(const json& truth) {
  std::vector<json> out{{{"type", "give"}, {"actor", truth["throws"][0]["name"]}}};
  for (const json& th : truth["throws"]) {
    out.push_back({{"type", "throw"}, {"actor", th["name"]}});
    if (th.contains("to")) out.push_back({{"type", "pass"}, {"actor", th["to_name"]}, {"previous", th["name"]}});
    else out.push_back({{"type", "goal"}, {"actor", th["at"]}, {"by", truth["goal"]["name"]}});
  }
  return out;
}

// The seed is one: the rally is thrown so that every particle of each pass meets its catcher and
// every particle of the shot the goal, so any seed plays it the same (seeds 1 to 5 were tried).
TEST(Rally, AFilmedRallyIsPlayedAsItWasThrown) {
  const fs::path dir = film_rally("played"), events = dir / "events.jsonl";
  const std::string command = QUANTUM_BINARY " play " QUANTUM_SOURCE_DIR "/rules/handball --input video:" +
                              (dir / "hats.avi").string() + " --accel " + (dir / "accel.csv").string() +
                              " --events " + events.string() + " --pace fast --audio none --quiet --seed 1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const json truth = json::parse(std::ifstream(dir / "truth.json"));
  std::vector<json> played;
  std::ifstream in(events);
  for (std::string line; std::getline(in, line);) played.push_back(json::parse(line));
  const std::vector<json> want = expected_events(truth);
  ASSERT_GE(played.size(), want.size());
  // Event by event up to the goal: nothing else happened in between (no intercept, no ball out).
  for (size_t k = 0; k < want.size(); ++k)
    for (const auto& [key, value] : want[k].items())
      EXPECT_EQ(played[k].value(key, ""), value) << "event " << k << ": " << played[k].dump();
  // Each throw when its thrower's arm whipped (the accelerometer's time), to a frame.
  for (size_t k = 0, n = 0; k < want.size(); ++k) {
    if (want[k]["type"] != "throw") continue;
    EXPECT_NEAR(played[k]["t"].get<double>(), truth["throws"][n++]["t"].get<double>(), 0.04);
  }
  fs::remove_all(dir);
}

// A player who walks in after the first frame is followed from when the tracker finds them:
// Red's goalkeeper comes in over the side line at his goal, so the video starts with red 1 and
// red 2 only, and his hat becomes red 3, which is his (rules/handball/field.lua). Until then his
// body stands at its place; after it, where his hat is; and the rally goes on as before.
TEST(Rally, AGoalkeeperWhoWalksInLateTakesHisPlace) {
  const fs::path dir = film_rally("late_keeper", {{3, 0, 3.0}});
  std::vector<json> truth;
  {
    std::ifstream in(dir / "truth.jsonl");
    for (std::string line; std::getline(in, line);) truth.push_back(json::parse(line));
  }
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/handball";
  o.input = "video:" + (dir / "hats.avi").string();
  o.accel = (dir / "accel.csv").string();
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  std::ostringstream warnings;
  runtime::Session session(o, tools::lua_sport, nullptr, warnings);
  const int hugo = 3;
  ASSERT_EQ(session.match().players()[hugo].name, "Hugo");
  const Vec2 place = session.match().field().bodies[hugo].start;
  std::string scorer;
  session.watch([&](const runtime::News& news) {
    for (const game::GameEvent& e : news.events)
      if (e.type == game::EventKind::Goal) scorer = e.by;
  });
  double in_picture = -1;  // when the truth first shows his hat
  int followed = 0;
  while (session.frame()) {
    // The video frame this match frame shows: a recording's 0 s plays at the end of the first step.
    const size_t f = size_t(std::lround((session.match().time() - 1 / session.match().fps()) * 30));
    if (f >= truth.size()) break;
    const Vec2 at = session.match().players()[hugo].position;
    for (const json& p : truth[f]["players"])
      if (p["id"] == "red 3" && in_picture < 0) in_picture = truth[f]["t"].get<double>();
    if (in_picture < 0) {
      EXPECT_EQ(at.x, place.x) << "at " << session.match().time() << " s";
      EXPECT_EQ(at.y, place.y) << "at " << session.match().time() << " s";
    } else if (truth[f]["t"].get<double>() > in_picture + 0.5) {
      // Within the filter's lag as he sets off at 4 m/s, and a frame's step.
      for (const json& p : truth[f]["players"]) {
        if (p["id"] != "red 3") continue;
        EXPECT_LT(std::hypot(at.x - p["x"].get<double>(), at.y - p["y"].get<double>()), 0.3)
            << "at " << session.match().time() << " s";
        ++followed;
      }
    }
  }
  session.finish();
  EXPECT_GT(in_picture, 0.5) << "he was not there at the start";
  EXPECT_GT(followed, 100);
  EXPECT_EQ(scorer, "Clara");
  EXPECT_EQ(warnings.str(), "");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace quantum

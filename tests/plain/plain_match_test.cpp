// A whole match with no Lua at all: a field built in C++, the plain rules (game::PlainRules) and
// simulated players, through the game engine alone and through a runtime session. This test's
// program links no Lua library (tests/CMakeLists.txt): that it links is half of what it checks.
#include <gtest/gtest.h>

#include <memory>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "game/bots.h"
#include "game/game.h"
#include "game/plain_rules.h"
#include "game/sport_spec.h"
#include "session.h"
#include "sport_source.h"

namespace quantum {
namespace {

// The air hockey table of rules/airhockey/field.lua, written out: two mallets, two goals.
Field table() {
  Field f;
  f.name = "plain table";
  f.ball_radius = 0.0315f;
  f.body_restitution = 0.8f;
  const float x = 1.0f, y = 0.5f, m = 0.13f;
  auto wall = [&](const std::string& name, Vec2 a, Vec2 b) { f.segments.push_back({a, b, f.wall_id(name)}); };
  wall("left wall", {-x, y}, {x, y});
  wall("right wall", {-x, -y}, {x, -y});
  wall("Blue's end", {-x, y}, {-x, m});
  wall("Blue's end", {-x, -m}, {-x, -y});
  wall("Red's end", {x, y}, {x, m});
  wall("Red's end", {x, -m}, {x, -y});
  f.goals.push_back({"Blue's goal", "blue", {-x, -m}, {-x, m}});
  f.goals.push_back({"Red's goal", "red", {x, -m}, {x, m}});
  f.spots.push_back({"in front of Blue's goal", "blue", {-0.5f, 0}});
  f.spots.push_back({"in front of Red's goal", "red", {0.5f, 0}});
  for (const auto& [name, team, x_start] : {std::tuple{"Blue's mallet", "blue", -0.85f}, {"Red's mallet", "red", 0.85f}}) {
    BodySpec mallet;
    mallet.name = name, mallet.team = team, mallet.radius = 0.048f, mallet.start = {x_start, 0};
    f.bodies.push_back(mallet);
  }
  finish_field(f);
  return f;
}

struct Played {
  std::vector<std::string> events;  // "12.3 goal blue", in order
  int goals = 0;
  double time = 0;
};

// A match of `seconds` between two simulated players, on the game engine alone.
Played play(uint64_t seed, double seconds) {
  const Field field = table();
  game::MatchConfig config;
  config.seed = seed;
  config.seconds = seconds;
  config.particles = 300;
  game::PlainRules rules;
  game::Match match(field, config, rules);
  const auto bots = game::make_bots(field, {0.8, 0.8}, seed, config.throw_speed);
  Played out;
  while (!match.finished()) {
    match.step(bots->move(match.time(), 1 / match.fps(), match.players()));
    for (const game::GameEvent& e : match.events()) {
      bots->hear(e);
      std::ostringstream line;
      line << e.t << ' ' << game::to_string(e.type) << ' ' << e.team;
      out.events.push_back(line.str());
      out.goals += e.type == game::EventKind::Goal || e.type == game::EventKind::OwnGoal;
    }
    match.clear_news();
  }
  out.time = match.time();
  return out;
}

TEST(PlainMatch, SimulatedPlayersScoreUnderThePlainRulesWithoutLua) {
  const Played p = play(7, 60);
  EXPECT_NEAR(p.time, 60, 0.05) << "the match runs to its time limit";
  EXPECT_GT(p.goals, 0) << "a minute of air hockey without a goal";
  EXPECT_GT(p.events.size(), size_t(p.goals) * 2) << "shots and bounces too, not only goals";
}

TEST(PlainMatch, TheSameSeedPlaysTheSameMatch) {
  const Played a = play(11, 20), b = play(11, 20), c = play(12, 20);
  EXPECT_EQ(a.events, b.events);
  EXPECT_NE(a.events, c.events) << "another seed, another match";
}

// A sport of plain data and plain rules: what a session asks of a loader, without one in Lua.
class PlainSport final : public runtime::SportSource {
 public:
  PlainSport() {
    spec_.name = "plain air hockey";
    spec_.field = table();
    spec_.match.particles = 300;
    spec_.match.seconds = 30;
    spec_.handicaps.assign(spec_.field.bodies.size(), 1.0);
    spec_.phrases["paused"] = "Wait";
  }
  const game::SportSpec& spec() const override { return spec_; }
  game::Rules& rules() override { return rules_; }
  void changed(const std::filesystem::path&) override {}
  int reload(game::Match&, std::ostream&, std::vector<std::filesystem::path>*) override { return 0; }
  const std::map<std::string, std::string>& failures() const override { return failures_; }

 private:
  game::SportSpec spec_;
  game::PlainRules rules_;
  std::map<std::string, std::string> failures_;
};

TEST(PlainSession, ARuntimeSessionPlaysASportOfPlainRules) {
  runtime::SessionOptions o;
  o.seed = 3;
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  std::ostringstream transcript, errors;
  runtime::SportRequest asked;
  const runtime::SportLoader plain = [&](const runtime::SportRequest& r) {
    asked = r;
    return std::make_unique<PlainSport>();
  };
  int goals = 0;
  {
    runtime::Session session(o, plain, &transcript, errors);
    session.watch([&](const runtime::News& news) {
      for (const game::GameEvent& e : news.events) goals += e.type == game::EventKind::Goal || e.type == game::EventKind::OwnGoal;
    });
    session.run();
    EXPECT_NEAR(session.match().time(), 30, 0.05) << "the sport's own time limit";
    EXPECT_EQ(session.sport().name, "plain air hockey");
  }
  EXPECT_EQ(asked.sport, "airhockey") << "the options' sport is what the loader is asked for";
  EXPECT_EQ(asked.reloads, runtime::SportRequest::Reloads::None);
  EXPECT_GT(goals, 0);
  EXPECT_EQ(transcript.str().rfind("plain air hockey: plain table, seed 3\n", 0), 0u) << transcript.str();
  EXPECT_EQ(errors.str(), "");
}

}  // namespace
}  // namespace quantum

// Restarts: a rule places players (a formation, a kick-off) and gives the ball at a place (a
// corner, the spot where it went out). Simulated players walk there and wait; the ball waits
// for its taker, not for ever; the places are freed once the ball is played. On the handball
// hall (rules/handball/field.lua), whose players catch.
#include <gtest/gtest.h>

#include <cmath>

#include "field_loader.h"
#include "game/bots.h"
#include "game/game.h"
#include "recorder.h"

namespace quantum {
namespace {

using test::Recorder;

constexpr double kFps = 60;

game::MatchConfig config() {
  game::MatchConfig c;
  c.particles = 200;
  c.seed = 3;
  c.seconds = 120;
  return c;
}

float distance(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

// A formation: every player a few metres from where it starts, mirrored across the hall, so
// everyone has a walk of its own to make.
std::vector<Vec2> formation(const Field& f) {
  std::vector<Vec2> at;
  for (const BodySpec& b : f.bodies) at.push_back({-0.5f * b.start.x, -b.start.y});
  return at;
}

// One frame of simulated players: they move, and the holder's throw goes.
void play_frame(game::Match& match, game::SimulatedPlayers& bots) {
  const std::vector<BodyInput>& moves = bots.move(match.time(), 1 / kFps, match.players());
  for (const game::Throw& t : bots.throws()) match.let_go(t);
  match.step(moves);
}

TEST(Restart, SimulatedPlayersWalkToTheirPlacesAndTheBallWaitsForItsTaker) {
  const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/rules/handball");
  Recorder rules;
  game::Match match(field, config(), rules);
  const std::unique_ptr<game::SimulatedPlayers> bots =
      game::make_bots(field, std::vector<double>(field.bodies.size(), 0.6), 7, 10);
  rules.act = [&](const game::GameEvent& e, game::Match&) { bots->hear(e); };
  const std::vector<Vec2> places = formation(field);
  const int taker = 1;
  const Vec2 corner{field.bounds_max.x - 0.5f, field.bounds_max.y - 0.5f};
  for (size_t k = 0; k < places.size(); ++k)
    if (int(k) != taker) match.place(int(k), places[k]);
  // The ball waits 6 s at least: long enough for a goalkeeper's side steps to get it home.
  match.give(taker, 6, corner);
  EXPECT_EQ(match.holder(), -1);
  const Recorder::Seen* given = nullptr;
  for (int frame = 0; frame < int(12 * kFps) && !given; ++frame) {
    play_frame(match, *bots);
    given = rules.first(game::EventKind::Give);
  }
  ASSERT_NE(given, nullptr) << "the taker got to the corner";
  EXPECT_EQ(given->event.actor_index, taker);
  EXPECT_LE(distance(match.players()[taker].position, corner), game::Match::kTakePlace + 1e-3);
  for (size_t k = 0; k < places.size(); ++k) {
    if (int(k) == taker) continue;
    EXPECT_LE(distance(match.players()[k].position, places[k]), 0.1) << field.bodies[k].name << " waits at its place";
    ASSERT_TRUE(match.players()[k].place.has_value());
  }
  // The taker plays the ball: everyone is free again.
  const Recorder::Seen* played = nullptr;
  for (int frame = 0; frame < int(5 * kFps) && !played; ++frame) {
    play_frame(match, *bots);
    played = rules.first(game::EventKind::Throw);
  }
  ASSERT_NE(played, nullptr);
  EXPECT_EQ(played->event.actor_index, taker);
  for (const game::Player& p : match.players()) EXPECT_FALSE(p.place.has_value()) << p.name;
  rules.act = [](const game::GameEvent&, game::Match&) {};  // the bots go with this scope
}

TEST(Restart, AGiveAtAPlaceWaitsForAPersonButNotForEver) {
  const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/rules/handball");
  for (const bool walks : {true, false}) {
    Recorder rules;
    game::Match match(field, config(), rules);
    std::vector<BodyInput> input = test::standing(field);
    const int taker = 2;
    const Vec2 start = field.bodies[taker].start, spot{start.x > 0 ? start.x - 6 : start.x + 6, start.y};
    match.give(taker, 0.5, spot);
    for (int frame = 0; frame < int(3 * kFps); ++frame) match.step(input);
    EXPECT_EQ(rules.count(game::EventKind::Give), 0u) << "after 3 s, the taker still away";
    // The person walks there at 4 m/s (or stays), and the ball is given once they stand within
    // kTakePlace of it; never there, it is given where they stand once the wait is over.
    double arrived = -1;
    for (int frame = 0; frame < int(9 * kFps) && !rules.first(game::EventKind::Give); ++frame) {
      Vec2& at = input[taker].position;
      const float left = distance(at, spot), stride = float(4 / kFps);
      if (walks && left > 0.2f) {
        at = {at.x + (spot.x - at.x) * stride / left, at.y + (spot.y - at.y) * stride / left};
        input[taker].velocity = {float((spot.x - at.x) / left * 4), float((spot.y - at.y) / left * 4)};
      } else {
        input[taker].velocity = {0, 0};
      }
      match.step(input);
      if (arrived < 0 && distance(at, spot) <= game::Match::kTakePlace) arrived = match.time();
    }
    const Recorder::Seen* given = rules.first(game::EventKind::Give);
    ASSERT_NE(given, nullptr);
    if (walks) {
      EXPECT_GE(given->event.t, arrived - 1e-9);
      EXPECT_LE(given->event.t, arrived + 2 / kFps);
    } else {
      EXPECT_NEAR(given->event.t, 0.5 + game::Match::kMostPlaceWait, 1 / kFps + 1e-6);
    }
    EXPECT_EQ(match.holder(), taker);
  }
}

TEST(Restart, PlacesOutsideTheBoundsOrNotFiniteAreRefused) {
  const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/rules/handball");
  Recorder rules;
  game::Match match(field, config(), rules);
  for (const Vec2 bad : {Vec2{field.bounds_max.x + 1, 0}, Vec2{NAN, 0}, Vec2{0, INFINITY}}) {
    EXPECT_THROW(match.place(0, bad), std::invalid_argument);
    EXPECT_THROW(match.give(0, 0, bad), std::invalid_argument);
  }
  EXPECT_THROW(match.place(int(field.bodies.size()), Vec2{0, 0}), std::invalid_argument);
  match.place(0, Vec2{1, 1});
  match.place(0, std::nullopt);
  EXPECT_FALSE(match.players()[0].place.has_value());
}

}  // namespace
}  // namespace quantum

// Simulated team players on courts of their sport: players who kick play the ball along the
// ground, a keeper throws. On the futsal test pitch (tests/sports/futsal/field.lua).
#include <gtest/gtest.h>

#include "field_loader.h"
#include "game/bots.h"
#include "game/game.h"
#include "../quantum/test_scenes.h"
#include "recorder.h"

namespace quantum {
namespace {

using test::Recorder;

TEST(TeamBots, PlayersWhoKickPlayAlongTheGroundAndTheKeeperThrows) {
  const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/tests/sports/futsal");
  game::MatchConfig config;
  config.particles = 300;
  config.seed = 4;
  config.seconds = 60;
  for (const char* who : {"Ann", "Kim"}) {
    Recorder rules;
    game::Match match(field, config, rules);
    const std::unique_ptr<game::SimulatedPlayers> bots =
        game::make_bots(field, std::vector<double>(field.bodies.size(), 0.6), 7, config.throw_speed);
    rules.act = [&](const game::GameEvent& e, game::Match&) { bots->hear(e); };
    const int k = test::body_named(field, who);
    match.give(k);
    const Recorder::Seen* released = nullptr;
    for (int frame = 0; frame < 5 * 60 && !released; ++frame) {
      const std::vector<BodyInput>& moves = bots->move(match.time(), 1.0 / 60, match.players());
      for (const game::Throw& t : bots->throws()) match.let_go(t);
      match.step(moves);
      for (const Recorder::Seen& s : rules.seen)
        if (s.event.type == game::EventKind::Kick || s.event.type == game::EventKind::Throw) released = &s;
    }
    ASSERT_NE(released, nullptr) << who << " let go within 5 s";
    EXPECT_EQ(released->actor, who);
    const bool kicks = field.bodies[size_t(k)].kicks;
    EXPECT_EQ(released->event.type, kicks ? game::EventKind::Kick : game::EventKind::Throw) << who;
    const Cloud& c = match.world().cloud();
    ASSERT_GT(c.size(), 0u);
    size_t on_floor = 0;
    for (size_t i = 0; i < c.size(); ++i) on_floor += c.z[i] == field.ball_radius && c.vz[i] == 0;
    if (kicks) EXPECT_EQ(on_floor, c.size()) << "a kick along the ground: every particle rolls";
    else EXPECT_EQ(on_floor, 0u) << "a keeper's throw leaves the hand";
    rules.act = [](const game::GameEvent&, game::Match&) {};
  }
}

}  // namespace
}  // namespace quantum

// No match goes silent: a ball that rolls dead is told `loose`, simulated players go for it, and
// when nothing is played for the sport's bound (match.stall) the rules hear `stalled` and, unless
// they restart play themselves, the match does.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "field_loader.h"
#include "game/bots.h"
#include "game/game.h"
#include "session.h"
#include "recorder.h"
#include "scripted_rules.h"
#include "lua_sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;
using test::Recorder;
using test::standing;

constexpr double kFps = 60;
constexpr double kStall = 5;

// A ball of `n` particles at `at`, all rolling at `velocity`.
Cloud rolling(Vec2 at, Vec2 velocity, int n = 200) {
  Cloud c;
  for (int i = 0; i < n; ++i) c.push(at.x, at.y, velocity.x, velocity.y, 1, 1);
  return c;
}

game::MatchConfig config(uint64_t seed = 1) {
  game::MatchConfig c;
  c.particles = 200;
  c.seed = seed;
  c.seconds = 60;
  c.stall = kStall;
  return c;
}

// The handball hall with nobody moving, and a ball rolling along the side line where nobody
// stands: it rolls dead in about two seconds, out of everyone's reach.
struct DeadBall {
  Field field = lua::load_field(QUANTUM_SOURCE_DIR "/rules/handball");
  Recorder rules;
  game::Match match{field, config(), rules};
  std::vector<BodyInput> still = standing(field);

  DeadBall() { match.set_scene(still, rolling({0, 4.2f}, {1.2f, 0})); }
  void play(double seconds) {
    for (int k = 0; k < int(seconds * kFps); ++k) match.step(still);
  }
};

int nearest_catcher(const Field& f, Vec2 at) {
  int nearest = -1;
  for (size_t k = 0; k < f.bodies.size(); ++k)
    if (f.bodies[k].catches &&
        (nearest < 0 || std::hypot(f.bodies[k].start.x - at.x, f.bodies[k].start.y - at.y) <
                            std::hypot(f.bodies[size_t(nearest)].start.x - at.x, f.bodies[size_t(nearest)].start.y - at.y)))
      nearest = int(k);
  return nearest;
}

TEST(Stall, ABallThatRollsDeadIsToldLooseThenStalledAtTheBoundAndGivenToTheNearestCatcher) {
  DeadBall s;
  s.play(kStall + 1);
  const Recorder::Seen* loose = s.rules.first(game::EventKind::Loose);
  ASSERT_NE(loose, nullptr);
  // 1.2 m/s falls below kLooseSpeed (0.5) after ln(2.4) / 0.45 s of the hall's friction.
  EXPECT_NEAR(loose->event.t, std::log(1.2 / kLooseSpeed) / s.field.friction, 0.05);
  EXPECT_NEAR(loose->event.at.x, 1.2 / s.field.friction * (1 - kLooseSpeed / 1.2), 0.2);
  EXPECT_NEAR(loose->event.at.y, 4.2, 0.2);
  const Recorder::Seen* stalled = s.rules.first(game::EventKind::Stalled);
  ASSERT_NE(stalled, nullptr);
  EXPECT_NEAR(stalled->event.t, kStall, 1 / kFps + 1e-6);
  EXPECT_NEAR(stalled->event.at.x, 1.2 / s.field.friction * (1 - std::exp(-s.field.friction * kStall)), 0.2);
  EXPECT_EQ(s.match.stats().stalls, 1);
  // Before the stall the engine said nothing but `loose`; after it, the ball is dead and given.
  ASSERT_EQ(s.rules.seen.size(), 4u);
  EXPECT_EQ(s.rules.seen[2].event.type, game::EventKind::Dead);
  EXPECT_EQ(s.rules.seen[3].event.type, game::EventKind::Give);
  EXPECT_EQ(s.rules.seen[3].actor, s.field.bodies[size_t(nearest_catcher(s.field, stalled->event.at))].name);
  EXPECT_EQ(s.match.holder(), nearest_catcher(s.field, stalled->event.at));
}

TEST(Stall, AHeldBallThatIsNeverThrownGoesToAnotherPlayerAtTheBound) {
  DeadBall s;
  s.match.give(0);
  s.play(kStall + 0.5);
  const Recorder::Seen* stalled = s.rules.first(game::EventKind::Stalled);
  ASSERT_NE(stalled, nullptr);
  EXPECT_EQ(stalled->actor, s.field.bodies[0].name);  // who kept it
  ASSERT_NE(s.match.holder(), -1);
  EXPECT_NE(s.match.holder(), 0);
}

TEST(Stall, RulesThatRestartPlayThemselvesAreLeftToIt) {
  DeadBall s;
  s.rules.act = [](const game::GameEvent& e, game::Match& m) {
    if (e.type == game::EventKind::Stalled) m.give(2, 1.0);
  };
  s.play(kStall + 2);
  EXPECT_EQ(s.rules.count(game::EventKind::Stalled), 1u);
  EXPECT_EQ(s.rules.count(game::EventKind::Give), 1u);
  EXPECT_EQ(s.match.holder(), 2);
}

TEST(Stall, RulesThatOnlySpeakStillSeePlayRestarted) {
  DeadBall s;
  s.rules.act = [](const game::GameEvent& e, game::Match& m) {
    if (e.type == game::EventKind::Stalled) m.say("Nobody wants it");
  };
  s.play(kStall + 0.5);
  EXPECT_EQ(s.rules.count(game::EventKind::Give), 1u);
}

// Air hockey: nobody catches, so a dead puck drops again at the spot nearest where it lay.
TEST(Stall, WithoutCatchersTheBallDropsAtTheNearestSpot) {
  const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/rules/airhockey");
  Recorder rules;
  game::Match match(field, config(), rules);
  std::vector<BodyInput> still = standing(field);
  const Vec2 at = field.spots.back().at;
  match.set_scene(still, rolling(at, {0, 0}));
  for (int k = 0; k < int((kStall + 0.5) * kFps); ++k) match.step(still);
  const Recorder::Seen* stalled = rules.first(game::EventKind::Stalled);
  ASSERT_NE(stalled, nullptr);
  const Recorder::Seen* drop = rules.first(game::EventKind::Drop);
  ASSERT_NE(drop, nullptr);
  EXPECT_GT(drop->event.t, stalled->event.t - 1e-9);
  EXPECT_EQ(drop->event.actor_index, int(field.spots.size()) - 1);
}

TEST(Stall, ABoundOutsideItsRangeIsRefusedWithItsValue) {
  const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/rules/handball");
  Recorder rules;
  game::MatchConfig c = config();
  c.stall = 0.5;
  try {
    game::Match match(field, c, rules);
    ADD_FAILURE() << "a stall bound of 0.5 s was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("stall bound must be in [1, 3600] s, got 0.5"), std::string::npos) << e.what();
  }
  for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
           {"0", "match.stall: must be a number of seconds in [1, 3600] (how long a match may go without play), got 0"},
           {"1e9", "got 1e+09"},
           {"'long'", "match.stall"}}) {
    const fs::path dir = fs::temp_directory_path() / "quantum_stall_bound";
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(QUANTUM_SOURCE_DIR "/rules/handball/field.lua", dir / "field.lua");
    std::ofstream(dir / "sport.lua") << "return { match = { stall = " << text << " } }\n";
    try {
      lua::ScriptedRules sport(dir.string());
      ADD_FAILURE() << "match.stall = " << text << " was taken";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
}

// Simulated players act only on what is said: told where the ball lies loose, the nearest of
// each team runs to it and it is caught long before the bound; not told, nobody goes and the
// match stalls.
void play_with_bots(bool hear_loose, Recorder& rules, game::Match& match, const Field& field) {
  const std::unique_ptr<game::SimulatedPlayers> bots =
      game::make_bots(field, std::vector<double>(field.bodies.size(), 0.6), 7, 10);
  rules.act = [&, hear_loose](const game::GameEvent& e, game::Match&) {
    if (hear_loose || e.type != game::EventKind::Loose) bots->hear(e);
  };
  match.set_scene(standing(field), rolling({0, 4.2f}, {1.2f, 0}));
  for (int k = 0; k < int((kStall + 0.5) * kFps); ++k) match.step(bots->move(match.time(), 1 / kFps, match.players()));
  rules.act = [](const game::GameEvent&, game::Match&) {};  // the bots go with this scope
}

TEST(Stall, SimulatedPlayersGoForALooseBall) {
  const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/rules/handball");
  Recorder told, untold;
  game::Match with(field, config(), told), without(field, config(), untold);
  play_with_bots(true, told, with, field);
  play_with_bots(false, untold, without, field);
  const Recorder::Seen* loose = told.first(game::EventKind::Loose);
  ASSERT_NE(loose, nullptr);
  const Recorder::Seen* caught = told.first(game::EventKind::Catch);
  ASSERT_NE(caught, nullptr);
  EXPECT_LT(caught->event.t, loose->event.t + 3);
  EXPECT_EQ(told.count(game::EventKind::Stalled), 0u);
  EXPECT_EQ(untold.count(game::EventKind::Catch), 0u);
  EXPECT_EQ(untold.count(game::EventKind::Stalled), 1u);
}

// Every shipped sport between simulated players, ten minutes a match over 20 seeds: no two
// events of play (counts_as_play) are further apart than the sport's bound (and a frame). Label
// `long` (about two minutes a sport in the optimized build).
class Silence : public testing::TestWithParam<const char*> {};

TEST_P(Silence, NoMatchGoesLongerThanItsBoundWithoutPlay) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    runtime::SessionOptions o;
    o.sport = std::string(QUANTUM_SOURCE_DIR "/rules/") + GetParam();
    o.seconds = 600;
    o.seed = seed;
    std::ostringstream errors;
    runtime::Session session(o, tools::lua_sport, nullptr, errors);
    double last = 0, longest = 0;
    session.watch([&](const runtime::News& news) {
      for (const game::GameEvent& e : news.events)
        if (game::counts_as_play(e.type)) longest = std::max(longest, e.t - last), last = e.t;
    });
    session.run();
    const double bound = session.match().config().stall + 1 / session.match().fps() + 1e-6;
    EXPECT_LE(std::max(longest, session.match().time() - last), bound) << GetParam() << " seed " << seed;
    RecordProperty("stalls_seed_" + std::to_string(seed), session.match().stats().stalls);
  }
}

INSTANTIATE_TEST_SUITE_P(Sport, Silence, testing::Values("handball", "basketball", "keepaway", "airhockey", "soccer", "volleyball"),
                         [](const testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

}  // namespace
}  // namespace quantum

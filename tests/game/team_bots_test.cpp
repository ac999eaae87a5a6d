// Simulated team players on courts of their sport: players who kick play the ball along the
// ground, a keeper throws (on the futsal test pitch, tests/sports/futsal/field.lua), a lob is run
// after; players keep to their side of a court (tests/sports/court); markers of players who kick
// leave their passes a chance (rules/soccer).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>
#include <span>

#include "field_loader.h"
#include "game/bots.h"
#include "game/game.h"
#include "game/team_bots.h"
#include "../quantum/test_scenes.h"
#include "recorder.h"
#include "session.h"
#include "lua_sport.h"

namespace quantum {
namespace {

using test::Recorder;

// A match on a sport's field (a folder under the source tree, such as tests/sports/futsal)
// between simulated players of skill 0.6 who hear its events; the test steps it.
struct BotsMatch {
  explicit BotsMatch(const std::string& sport)
      : field(lua::load_field(QUANTUM_SOURCE_DIR "/" + sport)), match(field, config(), rules),
        bots(game::make_bots(field, std::vector<double>(field.bodies.size(), 0.6), 7, config().throw_speed)) {
    rules.act = [this](const game::GameEvent& e, game::Match&) { bots->hear(e); };
  }
  static game::MatchConfig config() {
    game::MatchConfig c;
    c.particles = 300;
    c.seed = 4;
    c.seconds = 60;
    return c;
  }
  // The match stops telling the bots before they go.
  ~BotsMatch() { rules.act = [](const game::GameEvent&, game::Match&) {}; }
  // A frame of the bots' moves; their throws are made when `let_go`, else only kept in throws().
  void step(bool let_go) {
    const std::vector<BodyInput>& moves = bots->move(match.time(), 1.0 / 60, match.players());
    if (let_go)
      for (const game::Throw& t : bots->throws()) match.let_go(t);
    match.step(moves);
  }

  Field field;
  Recorder rules;
  game::Match match;
  std::unique_ptr<game::SimulatedPlayers> bots;
};

TEST(TeamBots, PlayersWhoKickPlayAlongTheGroundAndTheKeeperThrows) {
  for (const char* who : {"Ann", "Kim"}) {
    BotsMatch m("tests/sports/futsal");
    const int k = test::body_named(m.field, who);
    m.match.give(k);
    const Recorder::Seen* released = nullptr;
    for (int frame = 0; frame < 5 * 60 && !released; ++frame) {
      m.step(true);
      for (const Recorder::Seen& s : m.rules.seen)
        if (s.event.type == game::EventKind::Kick || s.event.type == game::EventKind::Throw) released = &s;
    }
    ASSERT_NE(released, nullptr) << who << " let go within 5 s";
    EXPECT_EQ(released->actor, who);
    const bool kicks = m.field.bodies[size_t(k)].kicks;
    EXPECT_EQ(released->event.type, kicks ? game::EventKind::Kick : game::EventKind::Throw) << who;
    const Cloud& c = m.match.world().cloud();
    ASSERT_GT(c.size(), 0u);
    size_t on_floor = 0;
    for (size_t i = 0; i < c.size(); ++i) on_floor += c.z[i] == m.field.ball_radius && c.vz[i] == 0;
    if (kicks) EXPECT_EQ(on_floor, c.size()) << "a kick along the ground: every particle rolls";
    else EXPECT_EQ(on_floor, 0u) << "a keeper's throw leaves the hand";
  }
}

// Under gravity a lob flies over the players under its path: the teammate under it runs on to
// where it comes down within reach (flat, it would have stopped to meet it where it passes
// overhead, 2 to 3 m behind its start). Ann lobs from (-3, 0) at 6 m/s across and 8 m/s up;
// Bo stands at (3, 2) and the ball passes over him at about 4.9 m, out of his 1.8 m reach,
// and comes down to it near x = 6.8.
TEST(TeamBots, ALobOverAPlayersHeadIsRunAfterToWhereItComesDown) {
  BotsMatch m("tests/sports/futsal");
  const int ann = test::body_named(m.field, "Ann"), bo = test::body_named(m.field, "Bo");
  m.match.give(ann);
  m.match.let_go({ann, {6, 0}, 8});
  ASSERT_EQ(m.rules.seen.back().event.type, game::EventKind::Kick);
  const float start = m.match.players()[size_t(bo)].position.x;
  for (int frame = 0; frame < 60; ++frame) m.step(false);
  EXPECT_GT(m.match.players()[size_t(bo)].position.x, start + 2.0f) << "Bo runs on under the lob";
}

// The sport's aim reads alike for every kind of simulated player (docs/lua-api.md): at a point
// the holder sends the ball to arrive there at passing pace, at a goal it shoots at its hardest.
// Kim, the futsal keeper, holds near (9, 0) and is aimed at a point 6 m off, then at the goal a
// metre behind him (his own: any goal is shot at hard, where a pass that near would be slow).
TEST(TeamBots, TheSportsAimIsAPassToAPointAndAShotAtAGoal) {
  const float shot = float(BotsMatch::config().throw_speed * game::team_skill(0.6).throw_speed);
  struct Case {
    game::Aim aim;
    Vec2 toward;
    bool hard;
  };
  const Case cases[] = {
      {{game::Aim::Kind::Point, -1, {5, 4}}, {5, 4}, false},
      {{game::Aim::Kind::Goal, 1, {}}, {10, 0}, true},
  };
  for (const Case& c : cases) {
    BotsMatch m("tests/sports/futsal");
    const int kim = test::body_named(m.field, "Kim");
    m.match.set_aim(kim, c.aim);
    m.match.give(kim);
    std::optional<game::Throw> thrown;
    for (int frame = 0; frame < 5 * 60 && !thrown; ++frame) {
      m.step(false);
      if (!m.bots->throws().empty()) thrown = m.bots->throws().front();
    }
    ASSERT_TRUE(thrown.has_value()) << "Kim lets go within 5 s";
    const Vec2 from = m.match.players()[size_t(kim)].position;
    const Vec2 want{c.toward.x - from.x, c.toward.y - from.y};
    const double off = std::abs(std::atan2(thrown->velocity.y, thrown->velocity.x) - std::atan2(want.y, want.x));
    EXPECT_LT(off, 0.15) << "thrown toward the aim";
    const float speed = std::hypot(thrown->velocity.x, thrown->velocity.y);
    if (c.hard) EXPECT_GT(speed, 0.8f * shot) << "a shot at the goal: nearly its hardest, only the arc's rise taken off";
    else EXPECT_LT(speed, 0.8f * shot) << "a pass to the point, not a shot";
  }
}

// A field that gives each team a side (a box area named after it, holding no goal) keeps that
// team's players in it: on tests/sports/court, a ball that lies loose on Red's side is Bo's
// (Red) to fetch, and Ada (Blue) waits on her side of the net however near she is.
TEST(TeamBots, PlayersKeepToTheirSideOfTheCourt) {
  BotsMatch m("tests/sports/court");
  const int ada = test::body_named(m.field, "Ada"), bo = test::body_named(m.field, "Bo");
  game::GameEvent loose;
  loose.type = game::EventKind::Loose;
  loose.at = {1.0f, 0};
  m.bots->hear(loose);
  float furthest = -1e9f;
  for (int frame = 0; frame < 180; ++frame) {
    m.step(false);
    furthest = std::max(furthest, m.match.players()[size_t(ada)].position.x);
  }
  EXPECT_LE(furthest, 0.0f) << "Ada stays on Blue's side";
  EXPECT_LT(std::abs(m.match.players()[size_t(bo)].position.x - 1.0f), 1.0f) << "Bo goes for the ball";
}

// The bots of `field` alone, told that the ball lies loose `at`, walking where they decide for
// `frames` (a match would put its own ball in play); `each` sees the players after every frame.
template <class Each>
void walk_after_a_loose_ball(const Field& field, Vec2 at, int frames, Each each) {
  const std::unique_ptr<game::SimulatedPlayers> bots =
      game::make_bots(field, std::vector<double>(field.bodies.size(), 0.6), 7, 8.0);
  std::vector<game::Player> players(field.bodies.size());
  for (size_t k = 0; k < players.size(); ++k) players[k].team = field.bodies[k].team, players[k].position = field.bodies[k].start;
  game::GameEvent loose;
  loose.type = game::EventKind::Loose;
  loose.at = at;
  bots->hear(loose);
  for (int frame = 0; frame < frames; ++frame) {
    const std::vector<BodyInput>& moves = bots->move(frame / 60.0, 1.0 / 60, players);
    for (size_t k = 0; k < players.size(); ++k) players[k].position = moves[k].position, players[k].velocity = moves[k].velocity;
    each(std::span<const game::Player>(players));
  }
}

// A body's zone is its role's part of the field. On tests/sports/futsal Ann, a back, keeps to her
// own half (x <= 0): while Cy holds the ball up in Red's half she marks him from its edge; without
// her zone she went to about x = 2.4. A loose ball is anyone's: one lying beyond her
// half, nearer her than Bo, she fetches (else it could lie where no zone reaches until the match
// stalls).
TEST(TeamBots, APlayerKeepsToItsZoneButFetchesALooseBall) {
  {
    BotsMatch m("tests/sports/futsal");
    const int ann = test::body_named(m.field, "Ann");
    ASSERT_TRUE(m.field.bodies[size_t(ann)].zoned);
    m.match.give(test::body_named(m.field, "Cy"), 0, Vec2{5, 0});
    float furthest = -1e9f;
    for (int frame = 0; frame < 3 * 60; ++frame) {
      m.step(false);
      furthest = std::max(furthest, m.match.players()[size_t(ann)].position.x);
    }
    EXPECT_LE(furthest, 0.0f) << "Ann holds her half while Red has the ball in theirs";
    EXPECT_GT(furthest, -1.0f) << "...up at its edge";
  }
  const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/tests/sports/futsal");
  const int ann = test::body_named(field, "Ann");
  float furthest = -1e9f;
  walk_after_a_loose_ball(field, {0.5f, -5.5f}, 3 * 60, [&](std::span<const game::Player> players) {
    furthest = std::max(furthest, players[size_t(ann)].position.x);
  });
  EXPECT_GT(furthest, 0.2f) << "Ann goes beyond her half for a loose ball";
}

// The area under a hoop is no goal area: its mouth is in the air. A ball lying loose inside
// basketball's arc, 2 m from the basket, is fetched (before, every player stayed outside the arc
// and the ball lay there until the match stalled).
TEST(TeamBots, ABallLyingUnderTheHoopIsFetched) {
  const Vec2 ball{0, 3.6f};
  float nearest = 1e9f;
  walk_after_a_loose_ball(lua::load_field(QUANTUM_SOURCE_DIR "/rules/basketball"), ball, 4 * 60,
                          [&](std::span<const game::Player> players) {
                            for (const game::Player& p : players)
                              nearest = std::min(nearest, std::hypot(p.position.x - ball.x, p.position.y - ball.y));
                          });
  EXPECT_LT(nearest, 0.5f) << "someone gets to the ball";
}

// A seeded match of `sport` (a folder under the source tree) between simulated players, played
// to its end without sound; `each` hears every event with the match's field.
template <class Each>
void play_seeded(const std::string& sport, double seconds, uint64_t seed, Each each) {
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/" + sport;
  o.seconds = seconds;
  o.seed = seed;
  o.audio = "none";
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  session.watch([&](const runtime::News& news) {
    for (const game::GameEvent& e : news.events) each(e, session.match().field());
  });
  session.run();
  EXPECT_EQ(errors.str(), "") << sport << " seed " << seed;
}

// With a goal at each end a team keeps the formation of its start places and moves it up the
// field with the ball (docs/lua-api.md, "Team players"). On rules/soccer, while Blue's keeper
// holds the ball in her area, Blue's outfield players keep to their own half (before, they ran
// to the edge of Red's area, about x = 8, and her throw met Red's striker); with Carla holding
// at x = 8 they go up, the backs (Bruno, Dario) past halfway but behind the other forward, Elena.
TEST(TeamBots, AFormationKeepsItsShapeAndFollowsTheBall) {
  const auto after_three_seconds = [](const char* holder, Vec2 at) {
    BotsMatch m("rules/soccer");
    const int k = test::body_named(m.field, holder);
    std::vector<BodyInput> places(m.field.bodies.size());
    for (size_t i = 0; i < places.size(); ++i) places[i].position = m.field.bodies[i].start;
    places[size_t(k)].position = at;
    m.match.place_players(places);
    m.match.give(k);
    for (int frame = 0; frame < 3 * 60; ++frame) m.step(false);
    std::map<std::string, float> x;
    for (const char* name : {"Bruno", "Carla", "Dario", "Elena"})
      x[name] = m.match.players()[size_t(test::body_named(m.field, name))].position.x;
    return x;
  };
  for (const auto& [name, x] : after_three_seconds("Alba", {-14, 0}))
    EXPECT_LT(x, 0.0f) << name << " keeps to Blue's half while Alba holds";
  std::map<std::string, float> x = after_three_seconds("Carla", {8, 0});
  for (const char* back : {"Bruno", "Dario"}) {
    EXPECT_GT(x[back], 0.0f) << back << " goes up with the ball";
    EXPECT_LT(x[back], x["Elena"]) << back << " stays behind the forwards";
  }
}

// A keeper's throw or kick after a save goes to a teammate, not to the striker who pressed her.
// Over six seeded ten-minute matches of soccer and of handball between simulated players, of the
// keepers' releases fewer than 15 % are intercepted and at least 45 % arrive as passes (measured:
// soccer 4 and 40 of 66, handball 29 and 298 of 421; before the formation moved with the ball,
// soccer's keepers lost 78 of 133 and passed 10).
TEST(TeamBots, AKeepersThrowFindsATeammate) {
  for (const char* sport : {"rules/soccer", "rules/handball"}) {
    int released = 0, passes = 0, cut_out = 0;
    bool by_keeper = false;
    for (uint64_t seed = 1; seed <= 6; ++seed)
      play_seeded(sport, 600, seed, [&](const game::GameEvent& e, const Field& field) {
        const bool keeper = e.actor_index >= 0 && field.bodies[size_t(e.actor_index)].role == "goalkeeper";
        if (e.type == game::EventKind::Kick || e.type == game::EventKind::Throw) {
          by_keeper = keeper;
          released += keeper;
        } else if (by_keeper && e.type != game::EventKind::Bounce) {
          by_keeper = false;
          passes += e.type == game::EventKind::Pass;
          cut_out += e.type == game::EventKind::Intercept;
        }
      });
    ASSERT_GT(released, 40) << sport;
    EXPECT_LT(double(cut_out) / released, 0.15) << sport << ": " << cut_out << " of " << released << " intercepted";
    EXPECT_GE(double(passes) / released, 0.45) << sport << ": " << passes << " of " << released << " passes";
  }
}

// A kick along the ground is taken by any foot on its line, so a marker who stood as close as a
// handball marker (1.3 m) took a pass for certain (Newtonian chance 1) after 10 % of kicks and
// cut out almost as many passes as arrived. Over four seeded 5-minute soccer matches between
// simulated players: fewer than 8 % of kicks are certain interceptions by a field player, and
// passes arrive at least 1.5 times as often as they are cut out (measured: 6 % and 2.4 times).
TEST(TeamBots, MarkersOfPlayersWhoKickLeaveTheirPassesAChance) {
  int kicks = 0, certain = 0, passes = 0, cut_out = 0;
  bool kicked = false;
  for (uint64_t seed = 1; seed <= 4; ++seed)
    play_seeded("rules/soccer", 300, seed, [&](const game::GameEvent& e, const Field& field) {
      if (e.type == game::EventKind::Kick) {
        ++kicks, kicked = true;
      } else if (kicked && e.type != game::EventKind::Bounce) {
        kicked = false;
        const bool field_player = field.bodies[size_t(std::max(e.actor_index, 0))].role == "field";
        passes += e.type == game::EventKind::Pass;
        if (e.type == game::EventKind::Intercept && field_player) {
          ++cut_out;
          certain += e.p_newtonian > 0.99;
        }
      }
    });
  ASSERT_GT(kicks, 400);
  EXPECT_LT(double(certain) / kicks, 0.08) << certain << " of " << kicks;
  EXPECT_GE(double(passes), 1.5 * cut_out) << passes << " passes, " << cut_out << " cut out";
}

}  // namespace
}  // namespace quantum

// The rules API of team sports, on the keep-away court (rules/keepaway): game.give, game.throw,
// game.holder, game.field and param() do what lua-api.md says, and every misuse is an error
// that names it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "session.h"
#include "scripted_rules.h"
#include "lua_sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

#define EXPECT_HAS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

// A sport on the keep-away court whose match starts in Ann's hands and whose `give` handler (the
// first give is the match's start) runs `body`.
// On another sport's field (`field_of`) the match starts with `starter` holding the ball.
std::string court_with(const std::string& name, const std::string& body, const std::string& more = "",
                       const std::string& field_of = "keepaway", const std::string& starter = "Ann") {
  const fs::path dir = fs::temp_directory_path() / ("quantum_team_rules_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/" + field_of + "/field.lua", dir / "field.lua");
  std::ofstream(dir / "sport.lua") << "local given = 0\nreturn { match = { start = '" << starter << "' }, " << more
                                   << " on = { give = function(game, e)\n  given = given + 1\n  if given > 1 then return end\n"
                                   << body << "\nend } }\n";
  return dir.string();
}

struct Played {
  std::string errors;
  std::vector<game::GameEvent> events;
  std::vector<std::string> actors, previous;  // the events' strings outlive the match
};

Played play(const std::string& folder, double seconds = 2, std::vector<std::string> params = {}) {
  runtime::SessionOptions o;
  o.sport = folder;
  o.seconds = seconds;
  o.particles = 300;
  o.params = std::move(params);
  std::ostringstream errors;
  Played out;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  session.watch([&](const runtime::News& news) {
    for (const game::GameEvent& e : news.events)
      out.events.push_back(e), out.actors.emplace_back(e.actor), out.previous.emplace_back(e.previous);
  });
  session.run();
  out.errors = errors.str();
  return out;
}

TEST(TeamRules, ARuleThrowsForTheHolderAtATeammate) {
  const Played p = play(court_with("throw", R"(
  assert(game.holder() == "Ann", "Ann holds the ball at the start")
  game.throw("Ann", "Bo", { speed = 9, spread = 0, speed_spread = 0 }))"));
  EXPECT_EQ(p.errors, "");
  size_t thrown = 0;
  while (thrown < p.events.size() && p.events[thrown].type != game::EventKind::Throw) ++thrown;
  ASSERT_LT(thrown, p.events.size());
  EXPECT_EQ(p.actors[thrown], "Ann");
  const game::GameEvent& e = p.events[thrown];
  EXPECT_NEAR(std::hypot(e.velocity.x, e.velocity.y), 9, 1e-3);
  EXPECT_GT(e.velocity.x, 0);  // toward Bo, up the court from Ann
  EXPECT_GT(e.velocity.y, 0);
}

TEST(TeamRules, MisusedCallsAreErrorsThatNameTheMistake) {
  EXPECT_HAS(play(court_with("not_holder", "game.throw('Bo', 'Ann')")).errors, "Bo does not hold the ball (Ann does)");
  EXPECT_HAS(play(court_with("bad_spread", "game.throw('Ann', 'Bo', { spread = 'wide' })")).errors, "spread");
  EXPECT_HAS(play(court_with("wide_spread", "game.throw('Ann', 'Bo', { spread = 120 })")).errors,
             "spread must be in [0, 90] degrees");
  EXPECT_HAS(play(court_with("bad_key", "game.throw('Ann', 'Bo', { sped = 9 })")).errors, "sped");
  EXPECT_HAS(play(court_with("nobody", "game.give('Nobody')")).errors, "unknown player 'Nobody'");
  EXPECT_HAS(play(court_with("not_hitter", "game.hit('Bo', 'Ann')")).errors, "Bo does not hit the ball");
  EXPECT_HAS(play(court_with("hit_key", "game.hit('Bo', 'Ann', { sped = 9 })")).errors, "sped");
  EXPECT_HAS(play(court_with("late", "game.give('Bo', 100)")).errors, "delay must be in [0, 60] s");
  EXPECT_HAS(play(court_with("flat_jump", "game.jump('Ann')")).errors, "jumping needs a field with height");
  EXPECT_HAS(play(court_with("flat_lob", "game.throw('Ann', 'Bo', { elevation = 40 })")).errors,
             "elevation needs a field with height");
}

// On the basketball court a rule's shot at the hoop arcs up to it: it ends at the ring (a
// basket, or off the rim or the board) within two seconds, and a jump is no error there.
TEST(TeamRules, AShotAtAHoopArcsToTheRing) {
  const Played p = play(court_with("shot", R"(
  game.jump("Pia", 0.5, 0.5)
  game.throw("Maya", "basket", { spread = 0, speed_spread = 0, elevation_spread = 0 }))", "", "basketball", "Maya"), 2.5);
  EXPECT_EQ(p.errors, "");
  bool at_ring = false;
  for (size_t k = 0; k < p.events.size(); ++k)
    at_ring |= p.events[k].type == game::EventKind::Goal ||
               (p.events[k].type == game::EventKind::Bounce && (p.actors[k] == "rim" || p.actors[k] == "backboard"));
  EXPECT_TRUE(at_ring);
}

TEST(TeamRules, AGiveWithADelayHandsTheBallOverLater) {
  const Played p = play(court_with("delay", "game.give('Dee', 1.0)"), 3);
  EXPECT_EQ(p.errors, "");
  std::vector<std::pair<double, std::string>> gives;
  for (size_t i = 0; i < p.events.size(); ++i)
    if (p.events[i].type == game::EventKind::Give) gives.push_back({p.events[i].t, p.actors[i]});
  ASSERT_GE(gives.size(), 2u);
  EXPECT_EQ(gives[0].second, "Ann");
  EXPECT_EQ(gives[1].second, "Dee");
  EXPECT_NEAR(gives[1].first - gives[0].first, 1.0, 1.5 / 60);
}

TEST(TeamRules, TheFieldIsReadableFromTheRules) {
  const Played p = play(court_with("field", R"(
  local f = game.field()
  assert(f.bounds[1][1] == -6 and f.bounds[2][2] == 4, "bounds from the court's lines")
  assert(math.abs(f.friction - 0.5) < 1e-6, "friction")
  assert(#f.players == 4 and f.players[4].name == "Cy" and f.players[4].catches, "players")
  assert(math.abs(f.players[4].reach - 0.6) < 1e-6, "Cy's reach")
  assert(game.area(0, 0) == nil, "no areas on a keep-away court"))"));
  EXPECT_EQ(p.errors, "");
}

TEST(TeamRules, APlayersZoneIsReadableFromTheRules) {
  const Played p = play(court_with("zone", R"(
  local ann, bo = game.field().players[1], game.field().players[2]
  assert(ann.name == "Ann" and ann.zone[1][1] == -10 and ann.zone[1][2] == -6, "Ann's zone from its first corner")
  assert(ann.zone[2][1] == 0 and ann.zone[2][2] == 6, "...to its second: Blue's half")
  assert(bo.zone == nil, "Bo has none: the whole field"))", "", "../tests/sports/futsal"));
  EXPECT_EQ(p.errors, "");
}

TEST(TeamRules, ParamsSizeTheFieldAndUnknownOnesAreRefused) {
  const std::string folder = court_with("params", R"(
  local f = game.field()
  assert(f.bounds[2][1] == 10, "length=20 makes the court 20 m long, got " .. f.bounds[2][1]))");
  EXPECT_EQ(play(folder, 1, {"length=20"}).errors, "");
  try {
    play(folder, 1, {"lenght=20"});
    ADD_FAILURE() << "an unknown param was accepted";
  } catch (const std::exception& e) {
    EXPECT_HAS(e.what(), "lenght");
  }
}

}  // namespace
}  // namespace quantum

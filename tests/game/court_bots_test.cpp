// Simulated players of a sport of hitting over a net (rules/volleyball): each side plays its own
// court, passes the ball up to a teammate before sending it over, and both sides win rallies.
#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "game/bots.h"
#include "session.h"
#include "lua_sport.h"

namespace quantum {
namespace {

// What seeded beach volleyball matches between simulated players showed, over every rally that
// began with a serve: its touches, the touches of a side in a row, and who won it.
struct Rallies {
  int rallies = 0, touches = 0;
  int digs = 0, passed_on = 0;  // a side's first touch after the ball came over, and those its own side touched next
  std::map<std::string, int> points;
};

Rallies play(const std::string& players, int matches, double seconds) {
  Rallies r;
  for (uint64_t seed = 1; seed <= uint64_t(matches); ++seed) {
    runtime::SessionOptions o;
    o.sport = QUANTUM_SOURCE_DIR "/rules/volleyball";
    o.params = {"players=" + players};
    o.seconds = seconds;
    o.seed = seed;
    o.audio = "none";
    std::ostringstream errors;
    runtime::Session session(o, tools::lua_sport, nullptr, errors);
    std::string side;  // the side that touched last, and whether its touch was a first one
    bool first_touch = false;
    session.watch([&](const runtime::News& news) {
      for (const game::GameEvent& e : news.events) {
        if (e.type == game::EventKind::Drop) side.clear(), first_touch = false;
        if (e.type != game::EventKind::Hit) continue;
        ++r.touches;
        const std::string team(e.team);
        if (first_touch) r.passed_on += team == side;
        first_touch = !side.empty() && team != side;
        r.digs += first_touch;
        side = team;
      }
    });
    session.run();
    EXPECT_EQ(errors.str(), "") << "seed " << seed;
    for (const auto& [team, points] : session.match().score()) r.points[team] += points;
    r.rallies += session.match().score().at("blue") + session.match().score().at("red");
  }
  return r;
}

// Over four 5-minute beach matches: a rally is more than a serve (at least 2.5 touches on average;
// measured 3.06 over 100 matches, about four standard errors of 200 rallies above the bound),
// a side that takes the ball from the other passes it on to a teammate more often than not
// instead of sending it straight back, and each side wins at least a third of the points.
TEST(CourtBots, EachSidePlaysItsCourtAndPassesTheBallUpBeforeSendingItOver) {
  Rallies r = play("2", 4, 300);
  ASSERT_GT(r.rallies, 60);
  const double per_rally = double(r.touches) / r.rallies;
  std::cout << r.rallies << " rallies, " << per_rally << " touches per rally; " << r.passed_on << " of " << r.digs
            << " first touches passed on; points blue " << r.points["blue"] << ", red " << r.points["red"] << "\n";
  EXPECT_GE(per_rally, 2.5);
  EXPECT_GT(r.passed_on, r.digs / 2) << r.passed_on << " of " << r.digs;
  for (const char* team : {"blue", "red"}) EXPECT_GE(3 * r.points[team], r.rallies) << team;
}

// Indoors, six a side, with the rotation's zones: over four 5-minute matches a rally has a touch
// besides the serve on average (measured 2.62 a rally over 100 matches; a rally's touches vary
// by about 2, so four matches' 200 rallies put 2.0 five standard errors below it), and more
// first touches are passed on than not.
TEST(CourtBots, SixASidePlayTheirZones) {
  const Rallies r = play("6", 4, 300);
  ASSERT_GT(r.rallies, 100);
  const double per_rally = double(r.touches) / r.rallies;
  std::cout << r.rallies << " rallies, " << per_rally << " touches per rally; " << r.passed_on << " of " << r.digs
            << " first touches passed on\n";
  EXPECT_GE(per_rally, 2.0);
  EXPECT_GT(r.passed_on, r.digs / 2);
}

}  // namespace
}  // namespace quantum

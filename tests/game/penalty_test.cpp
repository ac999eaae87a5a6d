// A factor of 0 for a player disables it, as the paper says of a penalty of strength 0 ("the
// mallet is essentially disabled, as it cannot interact with the ball anymore"): in every
// shipped sport, whatever its kind of touch (a mallet's, a catch, a pass, a hit, a pickup, a
// tackle), the penalized player never gets the ball while the penalty holds, however the players
// move onto particles predicted elsewhere. The same seeds without the penalty show that the
// player meets the ball and gets it, so the count of none is not for want of chances.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "session.h"
#include "../shipped_sports.h"
#include "lua_sport.h"

namespace quantum {
namespace {

constexpr uint64_t kSeeds = 200;
constexpr double kSeconds = 20;

struct Touches {
  int met = 0;       // options at the player with Newtonian chance > 0
  int realized = 0;  // of them, realized
};

// Seed `seed` of `sport` with player seed % players penalized at strength 0 for the whole match
// (or not): how often that player met the ball in a draw and got it.
Touches play(const std::string& sport, uint64_t seed, bool penalized) {
  runtime::SessionOptions o;
  o.sport = std::string(QUANTUM_SOURCE_DIR "/rules/") + sport;
  o.seconds = kSeconds;
  o.seed = seed;
  o.particles = 500;
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  game::Match& m = session.match();
  const int k = int(seed % m.players().size());
  if (penalized) m.grant(k, "penalty", 3600, {{"strength", 0}});
  Touches t;
  while (session.frame()) {
    const Decision* d = m.decision();
    if (!d) continue;
    for (size_t i = 0; i < d->options.size(); ++i) {
      const Decision::Option& option = d->options[i];
      const TargetKind kind = option.target.kind;
      if ((kind != TargetKind::Body && kind != TargetKind::Tackle) || option.target.index != k) continue;
      if (option.chance_newtonian > 0) ++t.met;
      if (d->realized == int(i)) ++t.realized;
    }
  }
  // A ball whose every fate ends at the penalized player makes the frame's fates' factors
  // skipped, which the rules report; nothing else may go wrong.
  std::istringstream lines(errors.str());
  for (std::string line; std::getline(lines, line);)
    EXPECT_NE(line.find("this frame's factors are skipped"), std::string::npos) << sport << " seed " << seed << ": " << line;
  return t;
}

class Penalty : public testing::TestWithParam<const char*> {};

TEST_P(Penalty, OfZeroThePlayerNeverGetsTheBall) {
  Touches with, without;
  for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
    const Touches p = play(GetParam(), seed, true), free = play(GetParam(), seed, false);
    with.met += p.met, with.realized += p.realized;
    without.met += free.met, without.realized += free.realized;
    ASSERT_EQ(p.realized, 0) << GetParam() << " seed " << seed << ": the penalized player got the ball";
  }
  RecordProperty("met_penalized", with.met);
  RecordProperty("met_free", without.met), RecordProperty("realized_free", without.realized);
  std::cout << GetParam() << ": penalized, met " << with.met << " times, got it 0; free, met " << without.met
            << ", got it " << without.realized << '\n';
  EXPECT_GT(with.met, 0) << "the penalized player never even met the ball: the test proves nothing";
  EXPECT_GT(without.realized, 0) << "without the penalty the player should get the ball";
}

INSTANTIATE_TEST_SUITE_P(Sport, Penalty, testing::ValuesIn(test::kShippedSports),
                         [](const testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

}  // namespace
}  // namespace quantum

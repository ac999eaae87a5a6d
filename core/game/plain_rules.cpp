#include "game/plain_rules.h"

#include <algorithm>

namespace quantum::game {

void plain_event(const GameEvent& e, Match& match) {
  if (e.type != EventKind::Goal && e.type != EventKind::OwnGoal) return;
  const std::string conceding(e.team);  // the team defending the goal the ball went into
  std::string scorer;
  for (const std::string& team : match.teams())
    if (team != conceding && scorer.empty()) scorer = team;
  if (scorer.empty()) return;  // a field of one team: nobody to award
  match.award(scorer);
  std::string score;
  for (const std::string& team : match.teams())
    score += (score.empty() ? "" : " to ") + std::to_string(match.score().at(team));
  match.say("Goal for " + scorer + ", " + score);
  const int spot = match.field().spot_of(conceding);
  match.respawn(spot < 0 ? 0 : spot, kPlainRespawnDelay);
}

void PlainRules::factors(std::span<const FateView> fates, Match&, std::span<double> out, FactorTerms&) {
  std::fill(out.begin(), out.begin() + std::ptrdiff_t(fates.size()), 1.0);
}

}  // namespace quantum::game

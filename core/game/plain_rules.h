// The rules a match falls back on when its sport's own cannot run (a script disabled for
// overrunning its budget, docs/lua-api.md): a goal counts for the team that did not defend it and
// the ball drops again in front of the conceding goal after a moment. The host already brings a
// ball back that went out or died, and ends the match on time with the leader winning.
#pragma once

#include "game/game.h"

namespace quantum::game {

// Seconds between a goal and the next drop.
inline constexpr double kPlainRespawnDelay = 1.5;

// What plain rules do with an event: a goal or own goal is awarded and announced.
void plain_event(const GameEvent& event, Match& match);

// Rules that are only the plain ones: every fate keeps its odds (factor 1), events go to
// plain_event.
class PlainRules final : public Rules {
 public:
  void factors(std::span<const FateView> fates, Match& match, std::span<double> out, FactorTerms& terms) override;
  void on_event(const GameEvent& event, Match& match) override { plain_event(event, match); }
};

}  // namespace quantum::game

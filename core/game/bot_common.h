// What every kind of simulated player shares: the checks of its inputs, and news that reaches it
// after its reaction time. Internal to core/game: the bots' headers include it for their private
// members, not for their callers.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "game/game.h"

namespace quantum::game {

// News of the ball as a simulated player heard it: the event's kind, who, where, and the ball's
// velocity (with height, how high and how fast rising) after it; acted on at `at`, once its
// reaction time has passed.
struct Heard {
  double at;
  EventKind type;
  int actor;
  Vec2 where, velocity;
  float height, up;
};
inline Heard heard(const GameEvent& e, double reaction) {
  return {e.t + reaction, e.type, e.actor_index, e.at, e.velocity, e.height, e.up};
}

// Throws std::invalid_argument "got 3 skills for 4 players" unless there are as many as wanted.
inline void check_count(size_t got, const char* what, size_t wanted, const char* of) {
  if (got != wanted)
    throw std::invalid_argument("got " + std::to_string(got) + " " + what + " for " + std::to_string(wanted) + " " + of);
}

// Acts on the news in `heard` that is due by time t (each item's `at`), in the order it was
// heard, and keeps the rest for later.
template <class Heard, class Act>
void act_on_due(std::vector<Heard>& heard, double t, Act act) {
  size_t kept = 0;
  for (const Heard& h : heard) {
    if (h.at > t) heard[kept++] = h;
    else act(h);
  }
  heard.resize(kept);
}

}  // namespace quantum::game

// What simulated players heard reaches them after their reaction time. Internal to core/game.
#pragma once

#include <cstddef>
#include <vector>

namespace quantum::game {

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

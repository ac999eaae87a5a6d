// Rules that record what they are told, for tests of the match (tests/game).
#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "game/game.h"

namespace quantum::test {

// Rules that keep every event (with its names, which live in the field) and may act on one.
struct Recorder final : game::Rules {
  struct Seen {
    game::GameEvent event;
    std::string actor;
  };
  std::vector<Seen> seen;
  std::function<void(const game::GameEvent&, game::Match&)> act = [](const game::GameEvent&, game::Match&) {};

  void factors(std::span<const game::FateView>, game::Match&, std::span<double>, game::FactorTerms&) override {}
  void on_event(const game::GameEvent& e, game::Match& m) override {
    seen.push_back({e, std::string(e.actor)});
    act(e, m);
  }
  const Seen* first(game::EventKind kind, size_t from = 0) const {
    for (size_t k = from; k < seen.size(); ++k)
      if (seen[k].event.type == kind) return &seen[k];
    return nullptr;
  }
  size_t count(game::EventKind kind) const {
    size_t n = 0;
    for (const Seen& s : seen) n += s.event.type == kind;
    return n;
  }
};

// Every body where the field starts it, still.
inline std::vector<BodyInput> standing(const Field& f) {
  std::vector<BodyInput> still;
  for (const BodySpec& b : f.bodies) still.push_back({b.start, {0, 0}});
  return still;
}

}  // namespace quantum::test

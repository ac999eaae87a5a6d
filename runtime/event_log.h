// A match told to the outside world: JSON lines for tools, a transcript for people.
#pragma once

#include <iosfwd>
#include <span>

#include "audio/audio.h"
#include "game/game.h"

namespace quantum::runtime {

// One JSON object per event: {"t", "type", "actor", "team", "by", "previous", "powerup", "p",
// "p_newtonian", "particles", "x", "y", "said", "phrases"}, where "said" lists the phrases that
// event's own handlers said (an event set off by another's handler keeps its own) and "phrases"
// what became of each, in the same order (`fates[i]` is `said[i]`'s; none given, no "phrases"):
// {"text", "fate": "spoken"|"cut"|"dropped"|"silent", "start", "end"} for what sounded, "why"
// and "by" for what was cut or dropped. Phrases said outside any event at one moment share a
// line of their own, {"t", "type", "said", "phrases"}, whose type says who spoke: "timer", or
// "said" (on_reload).
void write_events(std::ostream& out, std::span<const game::GameEvent> events, std::span<const game::Said> said,
                  std::span<const audio::PhraseFate> fates = {});

// What a draw's factors were made of: the terms of its fates' factors (Decision::fates, in
// order), of its contacts' from `contacts_from` (World::contact_fates' order), or of each
// tackle's; power-ups named by FactorTerm::index into `powerups`.
struct DrawTerms {
  const game::FactorTerms& terms;
  size_t contacts_from = 0;
  std::span<const std::string> powerups;
};

// One JSON object per draw the engine made, with everything its chances were made of
// (docs/decisions.md, "A draw"): {"t", "u", "draw": [{"kind", "actor", "p", "p_newtonian",
// "particles", "mass", "factor", "factors", "weight", "groups"}, ...], "rest", "all_met",
// "outcome", "factors_skipped", "fates": [{"kind", "actor", "via", "mass", "tweaked", "particles",
// "factor", "factors"}, ...]}. Numbers in full.
void write_decision(std::ostream& out, const Decision& d, const DrawTerms& terms, const Field& field);

// "   0:03.42  Blue shoots", one line per phrase; with fates, one not heard in full is marked:
// "   0:03.42  Blue shoots  [cut after 0.31 of 0.72 s by: Goal for Red!]".
void write_transcript(std::ostream& out, std::span<const game::Said> said,
                      std::span<const audio::PhraseFate> fates = {});

}  // namespace quantum::runtime

// What a field file and an announcer phrase may hold. Fields and sports are written by designers
// and shared between venues, so the work the engine does on their behalf (a contact grid over the
// bounds, a phrase filled in) must stay bounded whatever they say. Each limit is checked before
// anything is allocated for it; docs/field-files.md and docs/lua-api.md state them.
#pragma once

#include <cstddef>

namespace quantum::limits {

// Field coordinates beyond this are typos (centimetres for metres), not fields: a football
// pitch is 105 m long.
inline constexpr float kMaxCoordinate = 1000.0f;

// Wall pieces (segments) in all. The contact grid numbers them (and their end points) in 16 bits,
// and every piece is tested in the largest-clear-box search; a round court drawn with a piece
// every 5 cm round a ring 30 m across is 1,900 pieces.
inline constexpr size_t kMaxSegments = 10'000;
// Walls by name: paths and bounces name them, the fate search keeps their numbers in 16 bits.
inline constexpr size_t kMaxWalls = 1'000;
// Goal lines and hoops (together: both are goals), boards, respawn spots, bodies and areas. The
// rules search them by name and the simulated players look through them every frame; a
// thousand is far beyond any hall and keeps those searches within microseconds.
inline constexpr size_t kMaxGoals = 1'000;
inline constexpr size_t kMaxBoards = 1'000;
inline constexpr size_t kMaxSpots = 1'000;
inline constexpr size_t kMaxBodies = 1'000;
inline constexpr size_t kMaxAreas = 1'000;

// The contact grid's memory while it is built, whatever the bounds: its cells grow coarser until
// it fits. Every shipped field keeps its 5 cm cells (basketball's court, the largest, 1.1 MB);
// bounds of +-1000 m get 1.6 m cells and 20 MB.
inline constexpr size_t kMaxGridBytes = size_t(64) << 20;

// Text one phrase says, filled in (and so its template too): a minute of speech, far more than
// an announcer says at once, and what `print` keeps of a line.
inline constexpr size_t kMaxPhraseBytes = 1'000;
// A sport's phrases: each is parsed and kept, so a table of a million keys naming one long text
// would take a gigabyte outside the script's 64 MiB. The shipped sports have a dozen or two.
inline constexpr size_t kMaxPhrases = 1'000;

}  // namespace quantum::limits

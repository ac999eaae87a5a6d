// The engine's limits, in one table: what a field file and an announcer phrase may hold, and the
// ranges of the numbers a sport, a Lua call, the command line or a network message may give.
//
// Fields and sports are written by designers and shared between venues, so the work the engine
// does on their behalf (a contact grid over the bounds, a phrase filled in) must stay bounded
// whatever they say. Each size limit is checked before anything is allocated for it.
//
// A range is checked where its value enters (the file's reader, the Lua call, the command line,
// the network message), and its message is built from the range (must_be_in), so that what the
// check takes and what the message says cannot drift apart. docs/field-files.md, docs/lua-api.md
// and the --help texts state the same ranges (tests/docs/docs_test.cpp holds the docs to them).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

namespace quantum::limits {

// The numbers a value may take: lo to hi, each end in or out, in `unit` ("m/s"; "" for a plain
// number). `name` says what it bounds, for the tests and the docs' check.
struct Range {
  const char* name;
  double lo, hi;
  bool lo_open = false, hi_open = false;
  const char* unit = "";

  // False for NaN: no comparison with it is true.
  constexpr bool contains(double v) const { return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi); }
};

// The range as the engine writes it: "(0, 1000]" and, with its unit, "(0, 1000] m/s".
std::string interval(const Range& r);
std::string stated(const Range& r);
// "must be in (0, 1000] m/s, got 2000": the end of a message that names the value first.
std::string must_be_in(const Range& r, double got);
// Throws std::invalid_argument("<what> must be in ..., got ...") unless `r` contains `v`.
void check(const Range& r, double v, std::string_view what);
// A number as the messages write it: "0.5", "1e+09", "nan".
std::string number_text(double v);

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

// --- Ranges of what a sport, a rule, the command line or a device gives.

// A match's time limit (match.seconds, --seconds): a day is longer than any event runs.
inline constexpr Range kMatchSeconds{"match time limit", 0, 24 * 3600, true, false, "s"};
// Frames a second (--fps): below 10 a fast ball crosses a player between two looks; above 1000
// the frames are shorter than the step's numbers can tell.
inline constexpr Range kFps{"frame rate", 10, 1000};
// Particles in the cloud (particles, --particles): one is a Newtonian ball; ten million take a
// gigabyte and seconds a frame.
inline constexpr Range kParticles{"particles", 1, 10'000'000};
// A throw's or a hit's speed (throws.speed, game.throw's speed, an accelerometer's throw): far
// beyond any arm (a baseball pitch is 45 m/s), and a ball that fast still crosses a 1000 m field
// in more than one frame.
inline constexpr Range kThrowSpeed{"throw speed", 0, 1000, true, false, "m/s"};
// How a throw scatters (throws.spread and elevation_spread; a throw's options): a standard
// deviation of the direction, and of the angle above the horizontal, up to a right angle.
inline constexpr Range kSpreadDegrees{"throw spread", 0, 90, false, false, "degrees"};
// The same in the core's radians: a little above 90 degrees, so that a spread given in degrees
// is never refused after its conversion's rounding.
inline constexpr Range kSpreadRadians{"throw spread in radians", 0, 1.6, false, false, "rad"};
// The scatter of a throw's speed, as a share of it (throws.speed_spread).
inline constexpr Range kSpeedSpread{"speed spread", 0, 1};
// The angle a throw leaves at, above the horizontal (a throw's elevation): upward and forward.
inline constexpr Range kElevationDegrees{"throw elevation", 0, 90, true, true, "degrees"};
// A player's handicap (handicaps, --handicap, game.handicap): a thousand times likelier is as
// good as certain already, and more overflows the fate factors' product.
inline constexpr Range kHandicap{"handicap", 0, 1000, true, false};
// Automatic balance (balance.per_goal, --auto-balance): the boost a goal behind gives...
inline constexpr Range kBalancePerGoal{"balance per goal", 0, 10};
// ...and the most it may multiply a handicap by (balance.most): at most a handicap's own bound,
// so a handicap and its balance never overflow a fate's factor.
inline constexpr Range kBalanceMost{"balance most", 1, kHandicap.hi};
// A fate factor, and each term of it (a factor by kind, a modifier's or a power-up's result): a
// million times likelier is certain already, and the product of a few terms stays far from
// overflowing the particles' weights.
inline constexpr Range kFactor{"factor", 0, 1e6};
// Seconds a match may go without play before the rules hear `stalled` (match.stall).
inline constexpr Range kStall{"stall bound", 1, 3600, false, false, "s"};
// Tackles a second an opponent within reach makes (tackles.rate): 100 takes the ball within a
// frame or two; 0 is none.
inline constexpr Range kTackleRate{"tackle rate", 0, 100, false, false, "per second"};
// A restart's wait (game.respawn's and game.give's delay): a celebration, not a pause.
inline constexpr Range kRestartDelay{"restart delay", 0, 60, false, false, "s"};
// A power-up's or a timer's seconds (game.grant, game.after): an hour outlasts any match phase.
inline constexpr Range kPowerupSeconds{"power-up seconds", 0, 3600, true, false};
// A jump (game.jump): a jump's height above the player's reach, and how long it stays up.
inline constexpr Range kJumpHeight{"jump height", 0, 3, true, false, "m"};
inline constexpr Range kJumpSeconds{"jump time", 0, 2, true, false, "s"};
// A simulated player's skill (--skill, a scenario's skills): 0 plays blind, 1 as well as it can.
inline constexpr Range kSkill{"skill", 0, 1};
// A camera's horizontal field of view (--fov): a pinhole sees less than half a turn.
inline constexpr Range kFieldOfView{"field of view", 1, 179, false, false, "degrees"};
// A video's frames a second (--video-fps): a slide show to a slow-motion camera's.
inline constexpr Range kVideoFps{"video frame rate", 1, 240};

// Every range above, for the tests and the docs' check.
inline constexpr const Range* kRanges[] = {
    &kMatchSeconds, &kFps,      &kParticles,     &kThrowSpeed, &kSpreadDegrees, &kSpreadRadians,
    &kSpeedSpread,  &kElevationDegrees, &kHandicap, &kBalancePerGoal, &kBalanceMost, &kFactor,
    &kStall,        &kTackleRate, &kRestartDelay, &kPowerupSeconds, &kJumpHeight, &kJumpSeconds, &kSkill, &kFieldOfView, &kVideoFps};

}  // namespace quantum::limits

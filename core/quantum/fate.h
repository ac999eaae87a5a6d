// Fate prediction: where every particle's trajectory ends and how it gets there.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "quantum/field.h"

namespace quantum {

// Where a particle's flight ends. A body that strikes the ball is Body; one that catches it is
// Pass when a teammate of the last player to touch the ball (the thrower) catches it, Intercept
// when an opponent does, and Catch otherwise (nobody threw it, or the thrower catches it again).
// Landing: on a field of landings (Field::landings), the ball comes down on the floor; the target
// is the area it lands in, -1 outside every area. Hit: a body that hits (BodySpec::hits) meets it
// and sends it on. Pickup: a body that catches reaches a loose ball (World::loose) that someone
// touched; a loose ball nobody touched since its drop is a Catch. Tackle: no flight's end but a
// player's chance to take the held ball from its holder (World::challenge); the target is that
// player.
enum class FateKind : uint8_t { Goal, OwnGoal, Body, Out, Field, Catch, Pass, Intercept, Landing, Hit, Pickup, Tackle };
constexpr FateKind kFateKinds[] = {FateKind::Goal,    FateKind::OwnGoal, FateKind::Body,   FateKind::Out,
                                   FateKind::Field,   FateKind::Catch,   FateKind::Pass,   FateKind::Intercept,
                                   FateKind::Landing, FateKind::Hit,     FateKind::Pickup, FateKind::Tackle};
constexpr int kFateKindCount = 12;
// "goal", "own_goal", "body", "out", "field", "catch", "pass", "intercept", "landing", "hit",
// "pickup", "tackle"
const char* to_string(FateKind kind);
std::vector<std::string> fate_kind_names();  // every kind's name, in order
// Whether the fate ends at a body (Fate::target is a body index).
constexpr bool at_body(FateKind k) {
  return k == FateKind::Body || k == FateKind::Catch || k == FateKind::Pass || k == FateKind::Intercept ||
         k == FateKind::Hit || k == FateKind::Pickup || k == FateKind::Tackle;
}
// The kind of body `catcher` catching a ball last touched by `thrower` (-1: nobody): Catch,
// Pass or Intercept as above. The prediction and the match's events name catches alike by it.
FateKind catch_kind(const Field& field, int thrower, int catcher);

constexpr int kMaxPath = 4;

struct Fate {
  FateKind kind = FateKind::Field;
  int target = -1;         // goal index (Goal, OwnGoal), body index (at_body(kind)) or area index (Landing)
  uint8_t path_len = 0;    // walls touched before the end, in order, repeats folded
  bool path_more = false;  // more than kMaxPath walls
  uint16_t path[kMaxPath] = {};

  uint64_t key() const;  // equal keys, equal fates
};

struct FateGroup {
  Fate fate;
  double mass = 0;          // Newtonian probability: the untweaked weight of the group
  double tweaked_mass = 0;  // probability after fate factors; equals mass until tweaked
  uint32_t count = 0;
  uint32_t representative = 0;  // heaviest particle of the group: World::predict_path draws its way
};

// Fate groups a busy moment may have: buffers of groups (the prediction's, the tweak's, a draw's,
// the rules' views) are made this large up front, so that a match does not allocate in the frame
// of a busier moment than any before. A 20,000-particle air hockey match passed 256.
inline constexpr size_t kBusyFateGroups = 1024;

struct FateReport {
  float horizon = 0;
  uint64_t cloud_version = 0;       // the cloud this report describes; tweak() checks it
  std::vector<FateGroup> groups;    // in order of first appearance in the cloud
  std::vector<uint32_t> group_of;   // group index of every live particle
};

// "goal (red goal) via left wall", "blue mallet", "stays in field", "lands in blue court", ...
std::string describe(const Fate& fate, const Field& field);
// Who or what the fate ends at, by the field's names: the body, the goal, the area a landing is
// in; "" for the rest (out, stays in the field, a landing outside every area).
std::string_view fate_actor(const Fate& fate, const Field& field);
// "via left wall, Red's end" ("" when direct) into `out`, cut to fit; returns its length. No
// allocation: the rules read it every frame.
size_t write_via(const Fate& fate, const Field& field, char* out, size_t size);

// Per-kind fate factors, the paper's example as defaults (catches, pickups and tackles among them,
// and hits count as body contacts, and a landing, which ends a flight as going out does, as out).
struct KindFactors {
  double goal = 5, own_goal = 0.1, body = 5, out = 1, field = 1, catches = 5, hits = 5;
};
double factor_by_kind(FateKind kind, const KindFactors& factors);
std::vector<double> factors_by_kind(const FateReport& report, const KindFactors& factors);
std::vector<double> factors_by_kind(std::span<const Fate> fates, const KindFactors& factors);  // contacts

}  // namespace quantum

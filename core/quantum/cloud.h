// The ball as a cloud of weighted particles, stored as structure of arrays so the step loop
// streams through plain float arrays.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "quantum/field.h"

namespace quantum {

// Weights are kept unnormalized: `mass` is the sum of `w`, so removing particles costs
// O(removed) instead of a pass over the whole cloud. weight(i) is the normalized value.
// `tw` is the tweaked weight (w times the fate factors), `tmass` its sum; decisions draw from it.
// `fate` is the fate group of the tweak in force each particle was weighed by (World::tweak), or
// kNoFate for a particle no tweak has weighed yet (the decision log names the groups behind a draw).
// On a field with height every particle also has `z` (its centre above the floor) and `vz`;
// on a flat field both stay empty, and the flat step never touches them.
struct Cloud {
  std::vector<float> x, y, vx, vy;
  std::vector<float> z, vz;
  std::vector<double> w, tw;
  std::vector<uint32_t> fate;
  double mass = 0, tmass = 0;
  static constexpr uint32_t kNoFate = ~0u;

  size_t size() const { return x.size(); }
  bool empty() const { return x.empty(); }
  double weight(size_t i) const { return w[i] / mass; }
  double tweaked(size_t i) const { return tw[i] / tmass; }

  bool tall() const { return !z.empty(); }

  void reserve(size_t n, bool height = false);
  void clear();
  // A particle of no fate yet (kNoFate).
  void push(float px, float py, float pvx, float pvy, double pw, double ptw);
  void push(Vec3 p, Vec3 v, double pw, double ptw);
  void push_from(const Cloud& other, size_t i);
  // Removes the particles whose indices are listed (ascending, unique) by moving the last live
  // particles into the holes: O(removed), and the same order on every run.
  void remove_sorted(const std::vector<uint32_t>& indices);
  // Recomputes mass and tmass exactly and rescales both by the same number, so that the weights
  // sum to 1 and every particle keeps its factor (tw / w). Returns that number (0 for no weight).
  double normalize();
  // Forgets the fate factors: tw = w, and no particle has a fate.
  void reset_tweak();
};

}  // namespace quantum

// The random sources of the quantum core.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace quantum {

// Counter-based bits for Brownian motion: a pure function of (particle index, step key), so the
// step loop vectorizes (no generator state carried from particle to particle) and any backend
// can reproduce the same offsets. murmur3's finalizer: two multiplies, full avalanche.
inline uint32_t noise_bits(uint32_t index, uint32_t key) {
  uint32_t h = (index * 0x9E3779B1u) ^ key;
  h ^= h >> 16;
  h *= 0x85EBCA6Bu;
  h ^= h >> 13;
  h *= 0xC2B2AE35u;
  h ^= h >> 16;
  return h;
}

// Two offsets, each uniform in [-amplitude, amplitude], from the two halves of the bits.
// Uniform steps with the right variance sum to Gaussian diffusion within a few frames
// (central limit), at a fraction of the cost of a normal sampler.
inline void noise_offsets(uint32_t bits, float amplitude, float& dx, float& dy) {
  constexpr float kScale = 2.0f / 65535.0f;
  dx = amplitude * (float(bits & 0xFFFFu) * kScale - 1.0f);
  dy = amplitude * (float(bits >> 16) * kScale - 1.0f);
}

// Half-width of the uniform offset whose standard deviation is brownian * sqrt(dt).
inline float noise_amplitude(float brownian, float dt) { return brownian * std::sqrt(3.0f * dt); }

// One step key per frame, from the seed: splitmix64, so neighbouring frames are unrelated.
inline uint32_t step_key(uint64_t seed, uint64_t step) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ull * (step + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return uint32_t((z ^ (z >> 31)) >> 16);
}

// Decisions and split jitter: the standard generator (its output sequence is fixed by the
// standard), turned into doubles by hand because std::uniform_real_distribution is not.
class DecisionRng {
 public:
  explicit DecisionRng(uint64_t seed) : engine_(seed) {}
  double uniform() { return double(engine_() >> 11) * 0x1.0p-53; }  // [0, 1)

 private:
  std::mt19937_64 engine_;
};

}  // namespace quantum

// How particles move through one step. The fast backend (hand-written structure-of-arrays loop)
// is the engine; the Box2D backend in core/reference replays the same scene for comparison.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "quantum/cloud.h"
#include "quantum/field.h"

namespace quantum {

// Where a body goes during one step, from the frame's input.
struct BodyMotion {
  Vec2 from, to;  // positions at the start and the end of the step
  Vec2 velocity;  // the tracked velocity, handed to the ball on contact
  float radius;
  float top = 0;  // fields with height: how high the body reaches (its reach, raised by a jump)
  bool passes = false;  // the ball passes through it this step (a hitter right after its hit)
};

struct StepContext {
  float dt;
  const BodyMotion* bodies;
  int n_bodies;
  uint32_t noise_key;     // noise_bits(particle index, noise_key) drives the Brownian offsets
  float noise_amplitude;  // see noise_amplitude()
};

// Something a particle ran into during a step: a body, a goal line, the bounds (Out), a wall it
// bounced off at an audible speed (and met nothing else), no valid place left (Crushed), or on a
// field of landings the floor, audibly (Landing). Tackle is no particle's: a player taking the held
// ball from its holder (World::challenge), an option of that draw; its index is the player.
enum class TargetKind : uint8_t { Body, Goal, Out, Wall, Crushed, Landing, Tackle };
struct Target {
  TargetKind kind;
  uint16_t index;  // the body, goal or wall; a landing's area + 1 (0: outside every area); 0 for Out and Crushed

  bool operator==(const Target&) const = default;
};

struct Contact {
  uint32_t particle;
  Target target;
};

class Backend {
 public:
  virtual ~Backend() = default;
  // Moves every particle of `cloud` through one step in place and appends one Contact per
  // particle that touched a body, crossed a goal line, left the bounds or bounced audibly off a
  // wall (the first such thing), in any order. Particles hold their state after the bounce.
  virtual void advance(Cloud& cloud, const StepContext& ctx, std::vector<Contact>& contacts) = 0;
  // Opens these wormholes (none closes them). Throws std::logic_error where there are none.
  virtual void set_wormholes(const std::vector<Wormhole>& wormholes) = 0;
};

std::unique_ptr<Backend> make_fast_backend(const Field& field);
// The step of a field with height (Field::has_height()).
std::unique_ptr<Backend> make_height_backend(const Field& field);

}  // namespace quantum

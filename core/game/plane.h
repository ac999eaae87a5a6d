// Plane geometry for the simulated players: Vec2 arithmetic and the few distances they judge by.
// Internal to core/game.
#pragma once

#include <algorithm>
#include <cmath>

#include "quantum/field.h"

namespace quantum::game {

inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(float s, Vec2 a) { return {s * a.x, s * a.y}; }
inline float dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline float length(Vec2 a) { return std::hypot(a.x, a.y); }
inline Vec2 unit(Vec2 a) {
  const float l = length(a);
  return l > 0 ? (1 / l) * a : Vec2{1, 0};
}
inline Vec2 rotated(Vec2 a, double angle) {
  const float c = float(std::cos(angle)), s = float(std::sin(angle));
  return {c * a.x - s * a.y, s * a.x + c * a.y};
}
// p moved the least way into the rectangle of corners lo and hi.
inline Vec2 clamped(Vec2 p, Vec2 lo, Vec2 hi) { return {std::clamp(p.x, lo.x, hi.x), std::clamp(p.y, lo.y, hi.y)}; }
inline Vec2 centre(const Goal& g) { return {0.5f * (g.a.x + g.b.x), 0.5f * (g.a.y + g.b.y)}; }

// The point of segment a-b nearest p.
inline Vec2 nearest_on_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const float l2 = dot(ab, ab);
  const float t = l2 > 0 ? std::clamp(dot(p - a, ab) / l2, 0.0f, 1.0f) : 0.0f;
  return a + t * ab;
}
inline float distance_to_segment(Vec2 p, Vec2 a, Vec2 b) { return length(p - nearest_on_segment(p, a, b)); }

// The point of the field's wall `wall` (all its segments) nearest `from`, kept off each
// segment's ends: a corner sends the ball anywhere. `from` itself when the wall has no segment.
inline Vec2 nearest_on_wall(const Field& field, int wall, Vec2 from) {
  Vec2 best = from;
  float nearest = 1e30f;
  for (const Segment& seg : field.segments) {
    if (seg.wall != wall) continue;
    const Vec2 ab = seg.b - seg.a, ap = from - seg.a;
    const float l2 = ab.x * ab.x + ab.y * ab.y;
    const float f = l2 > 0 ? std::clamp((ap.x * ab.x + ap.y * ab.y) / l2, 0.2f, 0.8f) : 0.5f;
    const Vec2 p = seg.a + f * ab;
    if (length(p - from) < nearest) nearest = length(p - from), best = p;
  }
  return best;
}

}  // namespace quantum::game

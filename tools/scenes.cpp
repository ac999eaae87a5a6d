#include "scenes.h"

#include <algorithm>
#include <cmath>

#include "quantum/noise.h"

namespace quantum::tools {

std::vector<BodyInput> scripted_mallets(const Field& field, double t) {
  std::vector<BodyInput> out;
  const float cx = 0.5f * (field.bounds_min.x + field.bounds_max.x);
  const float half_width = 0.5f * (field.bounds_max.y - field.bounds_min.y);
  // The sweep and the lunge each stay under this, so a body stays under half the field's limit:
  // a scripted player is never mistaken for a tracking fault.
  const double fastest = 0.5 * field.max_body_speed / std::sqrt(2.0);
  const double lunge_peak = 2 / std::sqrt(3.0);  // the fastest of sin^3, per unit of reach and rate
  for (size_t k = 0; k < field.bodies.size(); ++k) {
    const BodySpec& b = field.bodies[k];
    const double phase = 1.7 * double(k);
    // Sideways sweep over most of the width, forward lunge of up to 45 cm; a player who catches
    // lunges all the way to the middle, where a ball is dropped, and one who hits (a net game,
    // whose ball lies at its first spot, a serve) to that spot, as slowly as that takes.
    const bool to_spot = b.hits && !field.spots.empty();
    const Vec2 spot = to_spot ? field.spots[0].at : Vec2{cx, b.start.y};
    const float dx = spot.x - b.start.x, dy = to_spot ? spot.y - b.start.y : 0.0f, far = std::hypot(dx, dy);
    const Vec2 way = far > 0 && (to_spot || b.catches) ? Vec2{dx / far, dy / far} : Vec2{b.start.x < cx ? 1.0f : -1.0f, 0};
    const double reach = to_spot || b.catches ? far : 0.45;
    // A lunge at a slant is not square to the sweep: each keeps to half of the sum then.
    const double most = to_spot ? fastest / std::sqrt(2.0) : fastest;
    const double sweep_w = 2.1 + 0.3 * double(k), lunge_w = std::min(1.3 + 0.2 * double(k), most / (lunge_peak * reach));
    // A body that starts off the middle sweeps only as far as its nearer side line allows.
    const float room = std::min(b.start.y - field.bounds_min.y, field.bounds_max.y - b.start.y) - b.radius;
    const double sweep = std::min(double(std::max(0.0f, std::min(0.6f * (half_width - b.radius), room))), most / sweep_w);
    const double s = std::sin(sweep_w * t + phase), ds = sweep_w * std::cos(sweep_w * t + phase);
    const double l = std::sin(lunge_w * t + phase), dl = lunge_w * std::cos(lunge_w * t + phase);
    const double lunge = l > 0 ? l * l * l : 0, dlunge = l > 0 ? 3 * l * l * dl : 0;
    BodyInput in;
    in.position = {float(b.start.x + way.x * reach * lunge), float(b.start.y + way.y * reach * lunge + sweep * s)};
    in.velocity = {float(way.x * reach * dlunge), float(way.y * reach * dlunge + sweep * ds)};
    out.push_back(in);
  }
  return out;
}

Cloud spread_cloud(const Field& f, uint32_t n, uint64_t seed) {
  DecisionRng rng(seed);
  // Keep clear of walls and goal lines by a ball radius: the cloud starts in valid places.
  float x0 = f.bounds_max.x, x1 = f.bounds_min.x, y0 = f.bounds_max.y, y1 = f.bounds_min.y;
  for (const Segment& s : f.segments)
    for (Vec2 p : {s.a, s.b}) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  const float m = 2 * f.ball_radius;
  Cloud c;
  c.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    const float x = float(x0 + m + (x1 - x0 - 2 * m) * rng.uniform());
    const float y = float(y0 + m + (y1 - y0 - 2 * m) * rng.uniform());
    const double angle = 2 * M_PI * rng.uniform(), speed = 0.5 + 2.5 * rng.uniform();
    c.push(x, y, float(speed * std::cos(angle)), float(speed * std::sin(angle)), 1.0 / n, 1.0 / n);
  }
  return c;
}

}  // namespace quantum::tools

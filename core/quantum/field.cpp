#include "quantum/field.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace quantum {

FieldError::FieldError(std::string where, std::string what)
    : std::runtime_error(where.empty() ? what : where + ": " + what), place(std::move(where)), message(std::move(what)) {}

int Field::spot_of_team(const std::string& team) const {
  for (size_t i = 0; i < spots.size(); ++i)
    if (spots[i].team == team) return int(i);
  return -1;
}

int Field::spot_of(const std::string& key) const {
  for (size_t i = 0; i < spots.size(); ++i)
    if (spots[i].name == key) return int(i);
  return spot_of_team(key);
}

float Field::flight_time(float seconds) const {
  return friction > 0 ? float(-std::expm1(-double(friction) * seconds) / friction) : seconds;
}

double Field::travel_time(double distance, double speed) const {
  if (friction <= 0) return distance / speed;
  return friction * distance < speed ? -std::log1p(-friction * distance / speed) / friction
                                     : std::numeric_limits<double>::infinity();
}

std::vector<std::string> Field::teams() const {
  std::vector<std::string> out;
  auto add = [&](const std::string& t) {
    if (!t.empty() && std::find(out.begin(), out.end(), t) == out.end()) out.push_back(t);
  };
  for (const BodySpec& b : bodies) add(b.team);
  for (const Goal& g : goals) add(g.team);
  return out;
}

bool Field::catching() const {
  return std::any_of(bodies.begin(), bodies.end(), [](const BodySpec& b) { return b.catches; });
}

bool Area::contains(Vec2 p) const {
  const float dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
  const float t = len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0f, 1.0f) : 0.0f;
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy)) <= radius;
}

int Field::area_at(Vec2 p) const {
  for (size_t i = 0; i < areas.size(); ++i)
    if (areas[i].contains(p)) return int(i);
  return -1;
}

namespace {

// Coordinates beyond this are typos (centimetres for metres), not fields.
constexpr float kMaxCoordinate = 1000.0f;

void check_point(const Vec2& p, const std::string& place) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y))
    throw FieldError(place, "coordinates must be finite numbers");
  if (std::fabs(p.x) > kMaxCoordinate || std::fabs(p.y) > kMaxCoordinate)
    throw FieldError(place, "coordinates beyond +-1000 m; the field is in metres");
}

void check_range(float v, float lo, float hi, const std::string& place) {
  if (!(v >= lo && v <= hi))
    throw FieldError(place, "must be between " + std::to_string(lo) + " and " + std::to_string(hi) +
                                ", got " + std::to_string(v));
}

float length(Vec2 a, Vec2 b) { return std::hypot(b.x - a.x, b.y - a.y); }

}  // namespace

void finish_field(Field& f) {
  check_range(f.ball_radius, 1e-4f, 10.0f, "ball.radius");
  check_range(f.wall_restitution, 0.0f, 1.0f, "ball.wall_restitution");
  check_range(f.body_restitution, 0.0f, 1.0f, "ball.body_restitution");
  check_range(f.audible_bounce, 0.0f, 1000.0f, "ball.audible_bounce");
  check_range(f.brownian, 0.0f, 10.0f, "brownian");
  check_range(f.max_body_speed, 0.1f, 1000.0f, "max_body_speed");
  check_range(f.friction, 0.0f, 100.0f, "ball.friction");
  for (size_t i = 0; i < f.segments.size(); ++i) {
    const Segment& s = f.segments[i];
    const std::string place = "walls[" + std::to_string(s.wall + 1) + "] (" + f.wall_names.at(s.wall) + ")";
    check_point(s.a, place);
    check_point(s.b, place);
    if (length(s.a, s.b) < 1e-4f) throw FieldError(place, "a wall piece is shorter than 0.1 mm");
  }
  for (size_t i = 0; i < f.goals.size(); ++i) {
    const std::string place = "goals[" + std::to_string(i + 1) + "] (" + f.goals[i].name + ")";
    check_point(f.goals[i].a, place);
    check_point(f.goals[i].b, place);
    if (length(f.goals[i].a, f.goals[i].b) < 1e-3f) throw FieldError(place, "a goal mouth is shorter than 1 mm");
    if (f.goals[i].team.empty()) throw FieldError(place, "a goal needs the team that defends it");
  }
  if (f.spots.empty()) throw FieldError("spots", "a field needs at least one respawn spot");
  for (size_t i = 0; i < f.spots.size(); ++i)
    check_point(f.spots[i].at, "spots[" + std::to_string(i + 1) + "] (" + f.spots[i].name + ")");
  for (size_t i = 0; i < f.bodies.size(); ++i) {
    const std::string place = "bodies[" + std::to_string(i + 1) + "] (" + f.bodies[i].name + ")";
    check_point(f.bodies[i].start, place);
    check_range(f.bodies[i].radius, 1e-3f, 10.0f, place + ".radius");
  }
  if (f.bodies.size() > 1000) throw FieldError("bodies", "more than 1000 bodies");
  for (size_t i = 0; i < f.bodies.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if ((!f.bodies[i].track.empty() || !f.bodies[j].track.empty()) && f.bodies[i].tracked_as() == f.bodies[j].tracked_as())
        throw FieldError("bodies[" + std::to_string(i + 1) + "] (" + f.bodies[i].name + ")",
                         "tracked as '" + f.bodies[i].tracked_as() + "', like bodies[" + std::to_string(j + 1) +
                             "]: each tracking id moves one body");
  for (size_t i = 0; i < f.areas.size(); ++i) {
    const std::string place = "areas[" + std::to_string(i + 1) + "] (" + f.areas[i].name + ")";
    check_point(f.areas[i].a, place);
    check_point(f.areas[i].b, place);
    check_range(f.areas[i].radius, 0.0f, kMaxCoordinate, place + ".radius");
  }
  if (f.wall_names.size() > 1000) throw FieldError("walls", "more than 1000 named walls");

  if (!f.has_bounds) {
    // Everything the ball can reach lies inside the walls; a margin of two ball radii keeps a
    // ball that grazes the outermost wall from counting as out.
    Vec2 lo{kMaxCoordinate, kMaxCoordinate}, hi{-kMaxCoordinate, -kMaxCoordinate};
    auto grow = [&](Vec2 p) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
    };
    for (const Segment& s : f.segments) grow(s.a), grow(s.b);
    for (const Goal& g : f.goals) grow(g.a), grow(g.b);
    for (const Spot& s : f.spots) grow(s.at);
    const float m = 2 * f.ball_radius;
    f.bounds_min = {lo.x - m, lo.y - m};
    f.bounds_max = {hi.x + m, hi.y + m};
  }
  check_point(f.bounds_min, "bounds");
  check_point(f.bounds_max, "bounds");
  if (!(f.bounds_min.x < f.bounds_max.x && f.bounds_min.y < f.bounds_max.y))
    throw FieldError("bounds", "the first corner must be below and left of the second");
  for (size_t i = 0; i < f.spots.size(); ++i) {
    const Vec2 p = f.spots[i].at;
    if (p.x <= f.bounds_min.x || p.x >= f.bounds_max.x || p.y <= f.bounds_min.y || p.y >= f.bounds_max.y)
      throw FieldError("spots[" + std::to_string(i + 1) + "] (" + f.spots[i].name + ")", "lies outside the bounds");
  }
  // Without walls or goals around them, the bounds are only the spots': players who stand
  // beyond them are on no field at all (a field of players who catch needs `bounds`).
  for (size_t i = 0; i < f.bodies.size(); ++i) {
    const Vec2 p = f.bodies[i].start;
    if (p.x < f.bounds_min.x || p.x > f.bounds_max.x || p.y < f.bounds_min.y || p.y > f.bounds_max.y)
      throw FieldError("bodies[" + std::to_string(i + 1) + "] (" + f.bodies[i].name + ")",
                       f.has_bounds ? "starts outside the bounds"
                                    : "starts outside the field (give the field `bounds`, the lines beyond which the ball is out)");
  }
}

}  // namespace quantum

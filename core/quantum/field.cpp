#include "quantum/field.h"

#include "quantum/limits.h"

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

Vec3 Field::arc_velocity(Vec3 from, Vec3 to, float elevation) const {
  const float dx = to.x - from.x, dy = to.y - from.y, d = std::hypot(dx, dy), rise = to.z - from.z;
  const float c = std::cos(elevation), s = std::sin(elevation);
  // z(t) = s v t - g t^2 / 2 at t = d / (c v): v^2 = g d^2 / (2 c^2 (d tan - rise)).
  const float above = d * s / c - rise;
  if (!(d > 0 && c > 0 && above > 0)) return {};
  const float v = std::sqrt(gravity * d * d / (2 * c * c * above));
  return {v * c * dx / d, v * c * dy / d, v * s};
}

Vec3 Field::throw_at(Vec3 from, Vec3 to, float speed) const {
  const float dx = to.x - from.x, dy = to.y - from.y, d = std::hypot(dx, dy), rise = to.z - from.z;
  if (!(d > 0)) return {0, 0, speed};
  if (!(gravity > 0)) return {speed * dx / d, speed * dy / d, 0};
  const float v2 = speed * speed, disc = v2 * v2 - gravity * (gravity * d * d + 2 * rise * v2);
  const float elevation = disc >= 0 ? std::atan((v2 - std::sqrt(disc)) / (gravity * d)) : 0.785398f;
  const float c = std::cos(elevation);
  return {speed * c * dx / d, speed * c * dy / d, speed * std::sin(elevation)};
}

int Field::wall_id(const std::string& wall) {
  const auto [it, added] = wall_ids_.try_emplace(wall, int(wall_names.size()));
  if (added) wall_names.push_back(wall);
  return it->second;
}

Vec2 Field::release_point(int body, Vec2 at, Vec2 toward) const {
  const float dx = toward.x - at.x, dy = toward.y - at.y, d = std::hypot(dx, dy);
  const float arm = bodies[size_t(body)].radius + ball_radius + 1e-3f;
  return d > 0 ? Vec2{at.x + arm * dx / d, at.y + arm * dy / d} : at;
}

float Field::reach_of(int body) const {
  const float r = bodies[size_t(body)].reach;
  return r > 0 ? r : kDefaultReach;
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
  if (box) return p.x >= a.x && p.x <= b.x && p.y >= a.y && p.y <= b.y;
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

using limits::kMaxCoordinate;

void check_point(const Vec2& p, const std::string& place) {
  if (std::isnan(p.x) || std::isnan(p.y)) throw FieldError(place, "coordinates must be numbers, not NaN");
  // An infinity (or a file's 1e300, narrowed to one) is as far beyond as any typo.
  if (!(std::fabs(p.x) <= kMaxCoordinate && std::fabs(p.y) <= kMaxCoordinate))
    throw FieldError(place, "coordinates beyond +-1000 m; the field is in metres");
}

// A rectangle given as two corners (bounds, a box area, a zone): both points, lowest first.
void check_corners(const Vec2& low, const Vec2& high, const std::string& place) {
  check_point(low, place);
  check_point(high, place);
  if (!(low.x < high.x && low.y < high.y))
    throw FieldError(place, "the first corner must be below and left of the second ({x0, y0}, {x1, y1})");
}

void check_range(float v, float lo, float hi, const std::string& place) {
  if (!(v >= lo && v <= hi))
    throw FieldError(place, "must be between " + std::to_string(lo) + " and " + std::to_string(hi) +
                                ", got " + std::to_string(v));
}

float length(Vec2 a, Vec2 b) { return std::hypot(b.x - a.x, b.y - a.y); }

// Height, hoops and boards: checked, and their surfaces named as walls so a fate's path and a
// bounce say "rim", "backboard" or "floor".
void finish_height(Field& f) {
  check_range(f.gravity, 0.0f, 100.0f, "gravity");
  const bool tall = f.has_height();
  for (size_t i = 0, nth = 0; i < f.goals.size(); ++i) {
    Goal& g = f.goals[i];
    if (!g.hoop()) continue;
    const std::string place = "hoops[" + std::to_string(++nth) + "] (" + g.name + ")";
    if (!tall) throw FieldError(place, "a hoop needs height: give the field `gravity` (9.81)");
    check_range(g.rim_radius, 0.01f, 10.0f, place + ".radius");
    check_range(g.rim_thickness, 0.0f, g.rim_radius, place + ".thickness");
    check_range(g.rim_height, 0.0f, 100.0f, place + ".height");
    check_range(g.rim_restitution, 0.0f, 1.0f, place + ".restitution");
    if (g.rim_radius - g.rim_thickness / 2 <= f.ball_radius)
      throw FieldError(place, "the ring is too narrow for the ball to pass");
    if (g.rim_wall < 0) g.rim_wall = f.wall_id(g.name + " rim");
  }
  for (size_t i = 0; i < f.boards.size(); ++i) {
    const Board& b = f.boards[i];
    const std::string place = "boards[" + std::to_string(i + 1) + "] (" + f.wall_names.at(b.wall) + ")";
    if (!tall) throw FieldError(place, "a board needs height: give the field `gravity` (9.81)");
    check_point(b.a, place);
    check_point(b.b, place);
    if (length(b.a, b.b) < 1e-3f) throw FieldError(place, "a board is narrower than 1 mm");
    check_range(b.bottom, 0.0f, 100.0f, place + ".bottom");
    check_range(b.top, b.bottom + 1e-3f, 100.0f, place + ".top");
    check_range(b.restitution, 0.0f, 1.0f, place + ".restitution");
  }
  if (!tall) {
    if (f.ceiling != 0) throw FieldError("ceiling", "a ceiling needs height: give the field `gravity` (9.81)");
    if (f.landings) throw FieldError("landings", "a ball lands only on a field with height: give the field `gravity` (9.81)");
    return;
  }
  check_range(f.floor_restitution, 0.0f, 1.0f, "ball.floor_restitution");
  if (f.ceiling != 0) check_range(f.ceiling, 2 * f.ball_radius + 0.01f, 1000.0f, "ceiling");
  for (size_t i = 0; i < f.bodies.size(); ++i)
    check_range(f.bodies[i].reach, 0.0f, 100.0f, "bodies[" + std::to_string(i + 1) + "] (" + f.bodies[i].name + ").reach");
  if (f.floor_wall < 0) f.floor_wall = f.wall_id("floor");
  if (f.ceiling > 0 && f.ceiling_wall < 0) f.ceiling_wall = f.wall_id("ceiling");
}

// What limits.h allows a field to hold, checked before any per-item work: a field built in C++
// comes here as a loaded one does (whose loader refused a longer list before reading it).
void check_counts(const Field& f) {
  const auto check = [](size_t count, size_t most, const char* place, const char* what) {
    if (count > most)
      throw FieldError(place, std::to_string(count) + " " + what + ", more than the " + std::to_string(most) + " allowed");
  };
  check(f.segments.size(), limits::kMaxSegments, "walls", "wall pieces");
  check(f.goals.size(), limits::kMaxGoals, "goals", "goals and hoops");
  check(f.boards.size(), limits::kMaxBoards, "boards", "boards");
  check(f.spots.size(), limits::kMaxSpots, "spots", "spots");
  check(f.bodies.size(), limits::kMaxBodies, "bodies", "bodies");
  check(f.areas.size(), limits::kMaxAreas, "areas", "areas");
}

}  // namespace

void finish_field(Field& f) {
  check_counts(f);
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
  finish_height(f);
  for (size_t i = 0, lines = 0, hoops = 0; i < f.goals.size(); ++i) {
    // The field file lists goal lines and hoops apart: number each in its own list.
    const size_t nth = ++(f.goals[i].hoop() ? hoops : lines);
    const std::string place = (f.goals[i].hoop() ? "hoops[" : "goals[") + std::to_string(nth) + "] (" + f.goals[i].name + ")";
    check_point(f.goals[i].a, place);
    check_point(f.goals[i].b, place);
    if (f.goals[i].hoop()) continue;  // a hoop both teams shoot at defends no team
    if (f.goals[i].team.empty()) throw FieldError(place, "a goal needs the team that defends it");
    if (length(f.goals[i].a, f.goals[i].b) < 1e-3f) throw FieldError(place, "a goal mouth is shorter than 1 mm");
  }
  if (f.spots.empty()) throw FieldError("spots", "a field needs at least one respawn spot");
  for (size_t i = 0; i < f.spots.size(); ++i)
    check_point(f.spots[i].at, "spots[" + std::to_string(i + 1) + "] (" + f.spots[i].name + ")");
  for (size_t i = 0; i < f.bodies.size(); ++i) {
    const std::string place = "bodies[" + std::to_string(i + 1) + "] (" + f.bodies[i].name + ")";
    check_point(f.bodies[i].start, place);
    check_range(f.bodies[i].radius, 1e-3f, 10.0f, place + ".radius");
    if (f.bodies[i].catches && f.bodies[i].hits)
      throw FieldError(place, "a body either catches or hits the ball, not both (one touch holds it, the other sends it on)");
    if (f.bodies[i].kicks && !f.bodies[i].catches)
      throw FieldError(place, "a body that kicks must catch: it holds the ball at its feet until it kicks");
    if (f.bodies[i].zoned) check_corners(f.bodies[i].zone_min, f.bodies[i].zone_max, place + ".zone");
  }
  check_range(f.rehit, 0.0f, 10.0f, "rehit");
  for (size_t i = 0; i < f.bodies.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if ((!f.bodies[i].track.empty() || !f.bodies[j].track.empty()) && f.bodies[i].tracked_as() == f.bodies[j].tracked_as())
        throw FieldError("bodies[" + std::to_string(i + 1) + "] (" + f.bodies[i].name + ")",
                         "tracked as '" + f.bodies[i].tracked_as() + "', like bodies[" + std::to_string(j + 1) +
                             "]: each tracking id moves one body");
  for (size_t i = 0; i < f.areas.size(); ++i) {
    const std::string place = "areas[" + std::to_string(i + 1) + "] (" + f.areas[i].name + ")";
    if (f.areas[i].box) {
      check_corners(f.areas[i].a, f.areas[i].b, place + ".box");
    } else {
      check_point(f.areas[i].a, place);
      check_point(f.areas[i].b, place);
    }
    check_range(f.areas[i].radius, 0.0f, kMaxCoordinate, place + ".radius");
  }
  if (f.wall_names.size() > limits::kMaxWalls)
    throw FieldError("walls", "more than " + std::to_string(limits::kMaxWalls) + " named walls");

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
    for (const Board& b : f.boards) grow(b.a), grow(b.b);
    // Spots lie on the field, never widen it: a spot beyond the walls is a mistake, refused
    // below, not a ball dropped where nothing can reach it. With nothing else, they are the field.
    const bool enclosed = !f.segments.empty() || !f.goals.empty() || !f.boards.empty();
    if (!enclosed)
      for (const Spot& s : f.spots) grow(s.at);
    const float m = 2 * f.ball_radius;
    f.bounds_min = {lo.x - m, lo.y - m};
    f.bounds_max = {hi.x + m, hi.y + m};
  }
  check_corners(f.bounds_min, f.bounds_max, "bounds");
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

// The field a quantum ball lives on: walls, goal mouths, respawn spots and player bodies.
// Fields are data (rules/<sport>/field.lua); this is their in-memory form.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace quantum {

struct Vec2 {
  float x = 0, y = 0;
};

// One straight piece of wall. Chains in the field file become several segments that share the
// chain's wall id, so a fate's path reads "via left wall" whichever piece was touched.
struct Segment {
  Vec2 a, b;
  int wall = 0;  // index into Field::wall_names
};

// A goal mouth is the line the ball's centre must cross; `team` is the team defending it.
struct Goal {
  std::string name, team;
  Vec2 a, b;
};

// Two round mouths on the field: a ball whose centre enters one leaves the other, at the same
// offset from its centre and with the same velocity (the wormhole power-up).
struct Wormhole {
  Vec2 a, b;
  float radius = 0.1f;
};

struct Spot {
  std::string name, team;
  Vec2 at;
};

// A circle moved every frame from input: a mallet, or a player seen from above. A body that
// catches holds the ball it meets (its radius is the player's reach) instead of striking it.
struct BodySpec {
  std::string name, team;
  float radius = 0;
  Vec2 start;
  bool catches = false;
  std::string role;   // the sport's word for the player's part ("goalkeeper"); the core ignores it
  std::string track;  // the tracking id that moves this body ("blue 1" for a hat); "" for its name

  const std::string& tracked_as() const { return track.empty() ? name : track; }
};

// A named region of the floor: every point within `radius` of the segment a-b (a circle when a
// and b are the same point). Rules and simulated players read it (a handball goal area); the
// ball does not notice it.
struct Area {
  std::string name, team;
  Vec2 a, b;
  float radius = 0;

  bool contains(Vec2 p) const;
};

struct Field {
  std::string name;
  float ball_radius = 0.03f;
  float wall_restitution = 0.9f;
  float body_restitution = 0.9f;
  // m/s: a wall bounce whose normal speed is below this is too soft to hear. It is neither
  // announced nor decided: the particles just bounce.
  float audible_bounce = 0.3f;
  float brownian = 0.0f;        // diffusion of the players' knowledge of the ball, m/sqrt(s)
  float max_body_speed = 30.0f;  // m/s; faster input is a tracking fault, not a player
  // 1/s: a rolling or flying ball's speed falls as e^(-friction t). 0 (an air table) is none.
  float friction = 0.0f;
  std::vector<std::string> wall_names;
  std::vector<Segment> segments;
  std::vector<Goal> goals;
  std::vector<Spot> spots;
  std::vector<BodySpec> bodies;
  std::vector<Area> areas;
  Vec2 bounds_min, bounds_max;  // leaving this box is "out"
  bool has_bounds = false;      // given by the field; false: derived from the geometry by finish_field()

  int spot_of_team(const std::string& team) const;  // -1 when the team has none
  // The spot of that name, else the first of that team; -1 when there is none.
  int spot_of(const std::string& name_or_team) const;
  // Every team the field names, bodies' first, then goals' (in their order).
  std::vector<std::string> teams() const;
  // Whether any body catches: a sport of holding, throwing and catching.
  bool catching() const;
  // The first area containing p, or -1.
  int area_at(Vec2 p) const;

  // Friction slows a ball alike at any speed, v(t) = v0 e^(-kt), so in t seconds it covers
  // v0 (1 - e^(-kt)) / k: the frictionless path, travelled for this "flight time" instead of t
  // (without friction, t itself). The core's step and prediction, the simulated players'
  // imagined ball and the rules' aimed throws all fly by it.
  float flight_time(float seconds) const;
  // Seconds a ball thrown at `speed` takes to cover `distance`; infinity when it stops short.
  double travel_time(double distance, double speed) const;
};

// A field that is not usable. `place` says where, e.g. "walls[2].points[3]".
struct FieldError : std::runtime_error {
  FieldError(std::string place, std::string message);
  std::string place, message;
};

// Checks every number and reference and derives the bounds when none were given.
// Throws FieldError naming the first problem.
void finish_field(Field& field);

}  // namespace quantum

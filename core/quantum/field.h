// The field a quantum ball lives on: walls, goal mouths, respawn spots and player bodies.
// Fields are data (rules/<sport>/field.lua); this is their in-memory form.
#pragma once

#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace quantum {

struct Vec2 {
  float x = 0, y = 0;
};

struct Vec3 {
  float x = 0, y = 0, z = 0;
};

// One straight piece of wall. Chains in the field file become several segments that share the
// chain's wall id, so a fate's path reads "via left wall" whichever piece was touched.
struct Segment {
  Vec2 a, b;
  int wall = 0;  // index into Field::wall_names
};

// A goal mouth is the line the ball's centre must cross; `team` is the team defending it.
// A hoop (fields with height) is a goal too: a rim ring of `rim_radius` (to the middle of the
// rod, `rim_thickness` thick) at `rim_height` around a = b, scored when the ball's centre comes
// down through the ring; touching the rod bounces the ball (the wall `rim_wall`, for paths).
struct Goal {
  std::string name, team;
  Vec2 a, b;
  float rim_height = 0, rim_radius = 0, rim_thickness = 0.02f, rim_restitution = 0.6f;
  int rim_wall = -1;

  bool hoop() const { return rim_radius > 0; }
};

// A vertical rectangle standing on the floor line a-b between `bottom` and `top` (fields with
// height): a backboard. The ball bounces off its faces; past its edges it flies on.
struct Board {
  Vec2 a, b;
  float bottom = 0, top = 0, restitution = 0.7f;
  int wall = 0;  // index into Field::wall_names
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
// catches holds the ball it meets (its radius is the player's reach) instead of striking it. A
// body that hits redirects it at once without holding it (a dig, a header): the ball leaves as
// the body's planned hit says (World::plan_hit) or else off its motion as off a mallet, and the
// ball passes through the hitter for Field::rehit seconds afterwards.
struct BodySpec {
  std::string name, team;
  float radius = 0;
  Vec2 start;
  bool catches = false;
  bool hits = false;  // never both: a touch either holds the ball or sends it on
  // A body that catches and kicks holds the ball at its feet: its own throws (a simulated
  // player's, an accelerometer's) leave as kicks (World::Release::Kick). A keeper's hands don't.
  bool kicks = false;
  std::string role;   // the sport's word for the player's part ("goalkeeper"); the core ignores it
  std::string track;  // the tracking id that moves this body ("blue 1" for a hat); "" for its name
  // Fields with height: the body is a vertical cylinder up to this height (m), the highest its
  // hands get standing; a throw leaves its hand there. 0 takes kDefaultReach.
  float reach = 0;
  // The rectangle a simulated team player keeps to (its role's part of the field: a back's own
  // two thirds), corners zone_min and zone_max; the core ignores it.
  bool zoned = false;
  Vec2 zone_min, zone_max;

  const std::string& tracked_as() const { return track.empty() ? name : track; }
};

// A named region of the floor: every point within `radius` of the segment a-b (a circle when a
// and b are the same point), or with `box` the rectangle of corners a and b (a court). Rules and
// simulated players read it (a handball goal area); the ball notices it only where it lands on a
// field of landings.
struct Area {
  std::string name, team;
  Vec2 a, b;
  float radius = 0;
  bool box = false;  // a, b: the lowest and the highest corner

  bool contains(Vec2 p) const;
};

// How high a player reaches standing, arms up, when the field does not say (m).
constexpr float kDefaultReach = 2.3f;
// Aimed throws on a field with height: a pass arrives at this share of the catcher's reach (the
// chest), and a shot at a hoop leaves the hand this steeply (rad; a usual jump shot's arc).
constexpr float kChestShare = 0.6f;
constexpr float kShotElevation = 0.9f;

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
  // 1/s: a sliding or flying ball's speed falls as e^(-friction t). 0 (an air table) is none. With
  // height it is the floor's rolling friction: only a ball rolling on the floor slows, one in the
  // air flies its arc unslowed.
  float friction = 0.0f;
  // Height. A field with gravity (m/s^2) gives the ball a height above the floor: it flies in
  // arcs, bounces off the floor (the wall "floor") with `floor_restitution` and off a ceiling
  // (the wall "ceiling") when one is given (> 0 m). Without gravity the field is flat.
  float gravity = 0.0f;
  float floor_restitution = 0.8f;
  float ceiling = 0.0f;
  // With height: every audible touch of the floor is a landing, a fate and a decision of its own
  // with the area it lands in (a volleyball court), not a bounce the flight goes on from.
  bool landings = false;
  // s: after a body that hits has hit the ball, the ball passes through it this long (one
  // swing is one touch; the hitter may touch the ball again once it is gone).
  float rehit = 0.3f;
  int floor_wall = -1, ceiling_wall = -1;  // set by finish_field()
  std::vector<Board> boards;
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
  bool has_height() const { return gravity > 0; }
  // The wall of that name, added to wall_names when there is none yet (pieces of one wall, a
  // rim or a board share the name's index).
  int wall_id(const std::string& wall);
  // Where a body's throw leaves its hand, and how high it catches: BodySpec::reach, or the default.
  float reach_of(int body) const;

  // Friction slows a ball alike at any speed, v(t) = v0 e^(-kt), so in t seconds it covers
  // v0 (1 - e^(-kt)) / k: the frictionless path, travelled for this "flight time" instead of t
  // (without friction, t itself). The core's step and prediction, the simulated players'
  // imagined ball and the rules' aimed throws all fly by it; with height, only a rolling ball.
  float flight_time(float seconds) const;
  // Seconds a ball thrown at `speed` takes to cover `distance`; infinity when it stops short.
  double travel_time(double distance, double speed) const;
  // Fields with height: the velocity that throws a ball from `from` at `elevation` rad above the
  // horizontal through `to` (a shot at a hoop, a lob to a player's hands); {0, 0, 0} when no
  // throw at that elevation gets there (`to` lies above the launch line).
  Vec3 arc_velocity(Vec3 from, Vec3 to, float elevation) const;
  // Where body `body`, standing at `at`, lets go of a throw toward `toward`: at arm's length, just
  // outside its reach (World::release starts a throw there; aim from here, not from the body).
  Vec2 release_point(int body, Vec2 at, Vec2 toward) const;
  // Fields with height: the flattest throw at `speed` from `from` through `to` (a pass); where
  // no throw that fast gets there, the one at 45 degrees toward it, which gets furthest.
  Vec3 throw_at(Vec3 from, Vec3 to, float speed) const;

 private:
  // wall_names' indices by name: a field of thousands of wall pieces finds each name at once.
  std::unordered_map<std::string, int> wall_ids_;
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

#include "field_loader.h"

#include "engine_paths.h"
#include "lua_reader.h"
#include "lua_sandbox.h"
#include "quantum/limits.h"
#include "quantum/narrow.h"

#include <filesystem>
#include <string>

namespace quantum::lua {
namespace {

// A field file is data: a runaway loop or a memory bomb in it is a mistake to report, not a hang.
// It runs once, when a match is set up: a whole second of CPU for its geometry, and the hundred
// million instructions a sport's loading gets (a list of a million walls is charged 16 million
// for its array alone, and is refused by its count, not the budget).
constexpr Limits kFieldLimits{64u << 20, 100'000'000, 1.0};

// The two corners { {x0, y0}, {x1, y1} } on top of the stack (bounds, a box area, a zone), popped.
void read_corners(const Reader& r, const std::string& place, Vec2& low, Vec2& high) {
  lua_State* L = r.L;
  if (!lua_istable(L, -1) || lua_objlen(L, -1) != 2) r.fail(place, "expected two corners { {x0, y0}, {x1, y1} }");
  const int corners = lua_gettop(L);
  lua_rawgeti(L, corners, 1);
  low = r.point(place + "[1]");
  lua_rawgeti(L, corners, 2);
  high = r.point(place + "[2]");
  lua_pop(L, 1);
}

// "3" of "walls[3]": an unnamed wall, spot or area is called by its number in the list.
std::string number_of(const std::string& place) {
  const size_t open = place.find('[');
  return place.substr(open + 1, place.find(']') - open - 1);
}

Field read_field(Reader& r, int top) {
  lua_State* L = r.L;
  Field f;
  r.only_keys(top, "field",
              {"name", "ball", "brownian", "max_body_speed", "walls", "goals", "spots", "bodies", "areas", "bounds",
               "gravity", "ceiling", "hoops", "boards", "landings", "rehit"});
  f.name = r.string(top, "name", "field", "unnamed field", false);
  f.brownian = r.number(top, "brownian", "field", f.brownian, false);
  f.max_body_speed = r.number(top, "max_body_speed", "field", f.max_body_speed, false);
  f.gravity = r.number(top, "gravity", "field", f.gravity, false);
  f.ceiling = r.number(top, "ceiling", "field", f.ceiling, false);
  f.landings = r.boolean(top, "landings", "field", false);
  f.rehit = to_float(r.number(top, "rehit", "field", f.rehit, false));
  if (r.field(top, "ball")) {
    r.expect(LUA_TTABLE, "ball");
    const int b = lua_gettop(L);
    r.only_keys(b, "ball", {"radius", "wall_restitution", "body_restitution", "audible_bounce", "friction",
                            "floor_restitution"});
    f.floor_restitution = r.number(b, "floor_restitution", "ball", f.floor_restitution, false);
    f.ball_radius = r.number(b, "radius", "ball", f.ball_radius, false);
    f.wall_restitution = r.number(b, "wall_restitution", "ball", f.wall_restitution, false);
    f.body_restitution = r.number(b, "body_restitution", "ball", f.body_restitution, false);
    f.audible_bounce = r.number(b, "audible_bounce", "ball", f.audible_bounce, false);
    f.friction = r.number(b, "friction", "ball", f.friction, false);
    lua_pop(L, 1);
  }
  r.array(top, "walls", "", limits::kMaxSegments, [&](int w, const std::string& place) {
    r.only_keys(w, place, {"name", "points"});
    const std::string name = r.string(w, "name", place, "wall " + number_of(place), false);
    const int id = f.wall_id(name);
    if (!r.field(w, "points")) r.fail(place, "missing 'points'");
    r.expect(LUA_TTABLE, place + ".points", "a list of points");
    const int pts = lua_gettop(L);
    const size_t n = lua_objlen(L, pts);
    if (n < 2) r.fail(place + ".points", "a wall needs at least 2 points, got " + std::to_string(n));
    if (f.segments.size() + n - 1 > limits::kMaxSegments)
      r.fail(place + ".points", std::to_string(n) + " points make " + std::to_string(f.segments.size() + n - 1) +
                                    " wall pieces in all, more than the " + std::to_string(limits::kMaxSegments) +
                                    " allowed");
    Vec2 prev;
    for (size_t i = 1; i <= n; ++i) {
      lua_rawgeti(L, pts, int(i));
      const Vec2 p = r.point(place + ".points[" + std::to_string(i) + "]");
      if (i > 1) f.segments.push_back({prev, p, id});
      prev = p;
    }
    lua_pop(L, 1);
  });
  r.array(top, "goals", "", limits::kMaxGoals - f.goals.size(), [&](int g, const std::string& place) {
    r.only_keys(g, place, {"name", "team", "from", "to"});
    Goal goal;
    goal.team = r.string(g, "team", place, "", true);
    goal.name = r.string(g, "name", place, goal.team + " goal", false);
    goal.a = r.point_at(g, "from", place);
    goal.b = r.point_at(g, "to", place);
    f.goals.push_back(goal);
  });
  r.array(top, "hoops", "", limits::kMaxGoals - f.goals.size(), [&](int h, const std::string& place) {
    r.only_keys(h, place, {"name", "team", "at", "height", "radius", "thickness", "restitution", "rim"});
    Goal hoop;
    hoop.team = r.string(h, "team", place, "", false);
    hoop.name = r.string(h, "name", place, hoop.team.empty() ? "hoop " + number_of(place) : hoop.team + " hoop", false);
    hoop.a = hoop.b = r.point_at(h, "at", place);
    hoop.rim_height = to_float(r.number(h, "height", place, 0, true));
    hoop.rim_radius = to_float(r.number(h, "radius", place, 0, true));
    hoop.rim_thickness = to_float(r.number(h, "thickness", place, hoop.rim_thickness, false));
    hoop.rim_restitution = to_float(r.number(h, "restitution", place, hoop.rim_restitution, false));
    const std::string rim = r.string(h, "rim", place, hoop.name + " rim", false);
    hoop.rim_wall = f.wall_id(rim);
    f.goals.push_back(hoop);
  });
  r.array(top, "boards", "", limits::kMaxBoards, [&](int b, const std::string& place) {
    r.only_keys(b, place, {"name", "from", "to", "bottom", "top", "restitution"});
    Board board;
    const std::string name = r.string(b, "name", place, "board " + number_of(place), false);
    board.wall = f.wall_id(name);
    board.a = r.point_at(b, "from", place);
    board.b = r.point_at(b, "to", place);
    board.bottom = to_float(r.number(b, "bottom", place, 0, true));
    board.top = to_float(r.number(b, "top", place, 0, true));
    board.restitution = to_float(r.number(b, "restitution", place, board.restitution, false));
    f.boards.push_back(board);
  });
  r.array(top, "spots", "", limits::kMaxSpots, [&](int s, const std::string& place) {
    r.only_keys(s, place, {"name", "team", "at"});
    Spot spot;
    spot.team = r.string(s, "team", place, "", false);
    spot.name = r.string(s, "name", place, "spot " + number_of(place), false);
    spot.at = r.point_at(s, "at", place);
    f.spots.push_back(spot);
  });
  r.array(top, "bodies", "", limits::kMaxBodies, [&](int b, const std::string& place) {
    r.only_keys(b, place, {"name", "team", "radius", "at", "catches", "hits", "kicks", "role", "track", "reach", "zone"});
    BodySpec body;
    body.team = r.string(b, "team", place, "", true);
    body.name = r.string(b, "name", place, body.team + " body", false);
    body.radius = r.number(b, "radius", place, 0, true);
    body.start = r.point_at(b, "at", place);
    body.catches = r.boolean(b, "catches", place, false);
    body.hits = r.boolean(b, "hits", place, false);
    body.kicks = r.boolean(b, "kicks", place, false);
    body.role = r.string(b, "role", place, "", false);
    body.track = r.string(b, "track", place, "", false);
    body.reach = to_float(r.number(b, "reach", place, 0, false));
    if (r.field(b, "zone")) {
      read_corners(r, place + ".zone", body.zone_min, body.zone_max);
      body.zoned = true;
    }
    f.bodies.push_back(body);
  });
  r.array(top, "areas", "", limits::kMaxAreas, [&](int a, const std::string& place) {
    r.only_keys(a, place, {"name", "team", "from", "to", "at", "radius", "box"});
    Area area;
    area.team = r.string(a, "team", place, "", false);
    area.name = r.string(a, "name", place, "area " + number_of(place), false);
    if (r.field(a, "box")) {
      if (r.field(a, "at") || r.field(a, "from") || r.field(a, "to") || r.field(a, "radius"))
        r.fail(place, "give either 'box' (a rectangle) or 'at' / 'from' and 'to' with 'radius'");
      read_corners(r, place + ".box", area.a, area.b);
      area.box = true;
      f.areas.push_back(area);
      return;
    }
    if (r.field(a, "at")) {
      area.a = area.b = r.point(place + ".at");
      if (r.field(a, "from") || r.field(a, "to")) r.fail(place, "give either 'at' (a circle) or 'from' and 'to'");
    } else {
      area.a = r.point_at(a, "from", place);
      area.b = r.point_at(a, "to", place);
    }
    area.radius = to_float(r.number(a, "radius", place, 0, true));
    f.areas.push_back(area);
  });
  if (r.field(top, "bounds")) {
    read_corners(r, "bounds", f.bounds_min, f.bounds_max);
    f.has_bounds = true;
  }
  return f;
}

}  // namespace

std::string field_file(const std::string& path) {
  namespace fs = std::filesystem;
  if (fs::is_directory(path)) return (fs::path(path) / "field.lua").string();
  // A bare name is a sport's, found as `quantum play` finds it; a path that is not there is
  // said by load_field.
  const bool name = is_sport_name(path) && fs::path(path).extension() != ".lua" && !fs::exists(path);
  return name ? (find_sport(path) / "field.lua").string() : path;
}

Field load_field(const std::string& path, Params* params) {
  const std::string file = field_file(path);
  if (!std::filesystem::exists(file)) throw FieldError(file, "no such field file");
  const Sandbox::Ptr sandbox = Sandbox::make(kFieldLimits, false);
  lua_State* L = sandbox->L();
  Params none;
  sandbox->push_environment();
  (params ? *params : none).install(L);
  lua_pop(L, 1);
  Field f;
  try {
    // Protected: the engine's reads of the returned table may run out of the script's memory.
    sandbox->protect([&] {
      sandbox->run_file(file);
      if (!lua_istable(L, -1)) throw FieldError(file, std::string("must return a table, returned ") + luaL_typename(L, -1));
      Reader reader(L);
      try {
        f = read_field(reader, lua_gettop(L));
        finish_field(f);
      } catch (const ReadError& e) {
        throw FieldError(e.place.empty() ? file : file + ": " + e.place, e.message);
      } catch (const FieldError& e) {
        throw FieldError(e.place.empty() ? file : file + ": " + e.place, e.message);
      }
    });
  } catch (const ScriptError& e) {
    // Lua's own messages start with "file:line:".
    throw FieldError("", e.what());
  }
  return f;
}

}  // namespace quantum::lua

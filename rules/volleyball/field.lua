-- The court of Quantum volleyball, seen from above: two square courts either side of a net.
-- Beach volleyball by default (2 v 2, 8 x 8 m a side, on sand); indoor volleyball from the same
-- file with `--param players=6` (6 v 6, 9 x 9 m a side). `--param net=2.24` lowers the net to the
-- women's height. Field coordinates: x from Blue's end line (x = -L) to Red's (x = +L), the net
-- along x = 0, y to the left as Blue faces the net. Lengths in metres, speeds in m/s.
local per_team = param("players", 2)
assert(per_team == 2 or per_team == 6, "players must be 2 (beach) or 6 (indoor)")
local beach = per_team == 2
local net = param("net", 2.43)
assert(net >= 1.5 and net <= 3, "net must be in [1.5, 3] m")
local L = beach and 8 or 9   -- a side's depth and width
local W = L

-- Names for the announcer. The hats (docs/tracking.md) are "blue 1", "blue 2", ... in the order
-- below: indoor, the rotation's positions 1 to 6 (1 serves: right back).
local names = {
  blue = { "Ana", "Bea", "Carla", "Dora", "Elsa", "Fay" },
  red = { "Holly", "Iris", "Jade", "Kira", "Lucy", "Mia" },
}
-- Where each player starts as Blue stands (x < 0); Red's places are Blue's turned half a turn
-- about the centre, so neither side has the better ones. Indoor, positions 1 to 6: back right,
-- front right, front middle, front left, back left, back middle.
local places = beach and { { -4.5, -2 }, { -4.5, 2 } }
  or { { -7, -3 }, { -2, -3 }, { -2, 0 }, { -2, 3 }, { -7, 3 }, { -7, 0 } }
local roles = beach and { "player", "player" } or { "back", "front", "front", "front", "back", "back" }

local bodies = {}
for _, team in ipairs({ "blue", "red" }) do
  local side = team == "blue" and 1 or -1
  for i = 1, per_team do
    bodies[#bodies + 1] = {
      name = names[team][i], team = team, role = roles[i], track = team .. " " .. i,
      at = { side * places[i][1], side * places[i][2] },
      -- A player seen from above: how far the hands get around the body, and how high standing.
      radius = beach and 0.7 or 0.6, reach = 2.4, hits = true,
    }
  end
end

return {
  name = beach and "Beach volleyball court, 2 v 2" or "Volleyball court, 6 v 6",
  gravity = 9.81,
  -- Where the ball comes down decides a rally: every audible touch of the floor is a landing in a
  -- court or outside both.
  landings = true,
  rehit = 0.3,  -- s: one swing is one touch
  ball = { radius = 0.105, floor_restitution = beach and 0.3 or 0.6, audible_bounce = 0.5 },
  max_body_speed = 9,
  -- The hall (or the beach) around the courts: a serve is taken behind the end line, and a ball
  -- played from outside the lines is still in play until it lands.
  bounds = { { -L - 6, -W / 2 - 5 }, { L + 6, W / 2 + 5 } },
  areas = {
    { name = "Blue court", team = "blue", box = { { -L, -W / 2 }, { 0, W / 2 } } },
    { name = "Red court", team = "red", box = { { 0, -W / 2 }, { L, W / 2 } } },
  },
  -- The net: a metre of mesh from the floor line across the court and half a metre past each
  -- side line (the antennae), its top at `net`.
  boards = {
    { name = "net", from = { 0, -W / 2 - 0.5 }, to = { 0, W / 2 + 0.5 }, bottom = net - 1, top = net, restitution = 0.15 },
  },
  spots = {
    { name = "Blue's serve", team = "blue", at = { -L - 1, beach and 0 or -3 } },
    { name = "Red's serve", team = "red", at = { L + 1, beach and 0 or 3 } },
  },
  bodies = bodies,
}

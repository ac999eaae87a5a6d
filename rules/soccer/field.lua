-- The pitch of Quantum soccer, 5-a-side: a 30 x 18 m hard pitch filmed from above, the ball
-- with height. It rolls on the floor and slows by the floor's friction, or flies when lofted.
-- As in indoor 5-a-side, each goal has its area (a half circle of 5 m around the mouth) that
-- only its goalkeeper may enter, and the goalkeeper may not leave it.
--
-- `--param length=40 --param width=20 --param players=6` makes another size from the same file.
-- Field coordinates: origin at the centre spot, x from Blue's goal line (x = -L/2) to Red's
-- (x = +L/2), y to the left as Blue's goalkeeper sees it; metres and m/s.
local L = param("length", 30)
local W = param("width", 18)
local per_team = param("players", 5)   -- a team's players, its goalkeeper included: 2 to 7
local area = param("area", 5)          -- the goal area: everything within this of the goal mouth
local mouth = 3.66                     -- a 5-a-side goal is 12 feet wide
assert(L >= 16 and L <= 60 and W >= 10 and W <= 40, "length must be in [16, 60] m and width in [10, 40] m")
assert(per_team >= 2 and per_team <= 7 and per_team % 1 == 0, "players must be a whole number from 2 to 7")
assert(area > mouth / 2 and area < L / 4, "the goal area must hold the goal's mouth and leave the middle of the pitch open")

local x, m = L / 2, mouth / 2

-- Names for the announcer; the first of each team keeps goal. Places: the outfield players in two
-- lines across their own half, Red's places Blue's turned half a turn about the centre spot, so
-- neither team has the better ones. A hat's tracking id follows x from Blue's goal, as in
-- handball (docs/tracking.md).
local names = {
  blue = { "Alba", "Bruno", "Carla", "Dario", "Elena", "Fabio", "Gina" },
  red = { "Hector", "Iris", "Jorge", "Katia", "Luca", "Mara", "Nico" },
}
local REACH, KEEPER_REACH = 0.6, 0.9   -- m: a foot's reach from the body's centre; a keeper dives

local bodies = {}
for _, team in ipairs({ "blue", "red" }) do
  local side = team == "blue" and -1 or 1   -- the end this team defends
  local places = {}
  for i = 1, per_team do
    local at
    if i == 1 then
      at = { side * (x - 1), 0 }
    else
      local k, n = i - 1, per_team - 1
      local back = k % 2 == 1                        -- alternate: a back, a forward
      local depth = back and x * 0.6 or x * 0.25       -- from the centre line
      at = { side * depth, side * W * 0.7 * ((k - 0.5) / n - 0.5) }
    end
    places[i] = {
      name = names[team][i], team = team, at = at, catches = true, kicks = i > 1,
      radius = i == 1 and KEEPER_REACH or REACH, reach = 1.8,
      role = i == 1 and "goalkeeper" or "field",
    }
  end
  local order = {}
  for i = 1, per_team do order[i] = i end
  table.sort(order, function(a, b) return places[a].at[1] < places[b].at[1] end)
  for rank, i in ipairs(order) do places[i].track = team .. " " .. rank end
  for i = 1, per_team do bodies[#bodies + 1] = places[i] end
end

return {
  name = string.format("5-a-side pitch, %g x %g m", L, W),
  gravity = 9.81,
  -- A size 4 ball on a hard pitch: it rolls a long way (friction 0.35 a second) and bounces
  -- lively; the posts send it back.
  ball = { radius = 0.1, friction = 0.35, floor_restitution = 0.6, wall_restitution = 0.5, audible_bounce = 1.0 },
  brownian = 0.1,
  max_body_speed = 10,
  bounds = { { -x, -W / 2 }, { x, W / 2 } },
  walls = {
    { name = "Blue's post", points = { { -x, m }, { -x, m + 0.1 } } },
    { name = "Blue's post", points = { { -x, -m }, { -x, -m - 0.1 } } },
    { name = "Red's post", points = { { x, m }, { x, m + 0.1 } } },
    { name = "Red's post", points = { { x, -m }, { x, -m - 0.1 } } },
  },
  goals = {
    { name = "Blue's goal", team = "blue", from = { -x, -m }, to = { -x, m } },
    { name = "Red's goal", team = "red", from = { x, -m }, to = { x, m } },
  },
  areas = {
    { name = "Blue's area", team = "blue", from = { -x, -m }, to = { -x, m }, radius = area },
    { name = "Red's area", team = "red", from = { x, -m }, to = { x, m }, radius = area },
  },
  -- Restart places: the centre spot (also where the engine drops a ball the rules did not
  -- restart), where each keeper takes a goal kick, and the corners, half a metre in from both
  -- lines so that the kick starts inside the pitch (left and right as that end's keeper sees them).
  spots = {
    { name = "centre spot", at = { 0, 0 } },
    { name = "Blue's goal kick", at = { -x + 1.5, 0 } },
    { name = "Red's goal kick", at = { x - 1.5, 0 } },
    { name = "Blue's left corner", at = { -x + 0.5, W / 2 - 0.5 } },
    { name = "Blue's right corner", at = { -x + 0.5, -W / 2 + 0.5 } },
    { name = "Red's left corner", at = { x - 0.5, -W / 2 + 0.5 } },
    { name = "Red's right corner", at = { x - 0.5, W / 2 - 0.5 } },
  },
  bodies = bodies,
}

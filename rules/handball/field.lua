-- The hall of Quantum team handball (the paper's section 2.1), seen from the ceiling camera. The
-- ball flies at chest height, as in the paper: the game is 2D.
--
-- A school gym by default (20 x 10 m, 3 v 3); a full court from the same file with
-- `--param length=40 --param width=20 --param players=7`. Field coordinates: origin at the
-- centre, x from Blue's goal line (x = -L/2) to Red's (x = +L/2), y to the left as Blue's
-- goalkeeper sees it. Lengths in metres, speeds in m/s.
local L = param("length", 20)
local W = param("width", 10)
local per_team = param("players", 3)   -- a team's players, its goalkeeper included: 1 to 7
local area = param("area", 6)          -- the goal area: everything within this of the goal mouth
local mouth = 3                        -- a handball goal is 3 m wide
assert(L >= 10 and L <= 60 and W >= 5 and W <= 40, "length must be in [10, 60] m and width in [5, 40] m")
assert(per_team >= 1 and per_team <= 7 and per_team % 1 == 0, "players must be a whole number from 1 to 7")
assert(area > 0 and area < L / 2, "the goal areas must not meet")

local x, m = L / 2, mouth / 2
local post = 0.08  -- a post's width

-- The players: names for the announcer, the first of each team in goal. Hats are tracked as
-- "blue 1", "blue 2", ... in order along the hall (from Blue's goal) as the players stand at the
-- first frame: players take their places before the match starts, and each hat's number is the
-- place it takes (docs/tracking.md).
local names = {
  blue = { "Anna", "Ben", "Clara", "David", "Eva", "Felix", "Greta" },
  red = { "Hugo", "Ida", "Jonas", "Kim", "Lena", "Max", "Nora" },
}
local KEEPER_REACH, REACH = 0.9, 0.7   -- how far a player's hands get to the ball, m: a goalkeeper dives

local bodies = {}
for _, team in ipairs({ "blue", "red" }) do
  local side = team == "blue" and -1 or 1   -- the end this team defends
  local places = {}
  for i = 1, per_team do
    local at
    if i == 1 then
      at = { side * (x - 1), 0 }   -- in goal
    else
      -- Field players spread across their own half, between the goal area and the centre; Red's
      -- places are Blue's turned half a turn about the centre, so neither team has the better ones.
      local k, n = i - 1, per_team - 1
      local depth = area + 1 + (x - area - 2) * ((k - 1) % 2) * 0.5
      at = { side * (x - depth), side * W * 0.8 * ((k - 0.5) / n - 0.5) }
    end
    places[i] = {
      name = names[team][i], team = team, at = at, catches = true,
      radius = i == 1 and KEEPER_REACH or REACH, role = i == 1 and "goalkeeper" or "field",
    }
  end
  -- Hat numbers follow x, from Blue's goal toward Red's.
  local order = {}
  for i = 1, per_team do order[i] = i end
  table.sort(order, function(a, b) return places[a].at[1] < places[b].at[1] end)
  for rank, i in ipairs(order) do places[i].track = team .. " " .. rank end
  for i = 1, per_team do bodies[#bodies + 1] = places[i] end
end

return {
  name = string.format("Handball hall, %g x %g m", L, W),
  -- A size 2 handball; the ball slows as it flies and rolls, and a post sends it back.
  ball = { radius = 0.09, wall_restitution = 0.6, audible_bounce = 1.0, friction = 0.45 },
  -- How fast the players' idea of a loose ball blurs.
  brownian = 0.1,
  max_body_speed = 10,
  bounds = { { -x, -W / 2 }, { x, W / 2 } },   -- the court's lines: beyond them the ball is out
  walls = {
    { name = "Blue's post", points = { { -x, m }, { -x, m + post } } },
    { name = "Blue's post", points = { { -x, -m }, { -x, -m - post } } },
    { name = "Red's post", points = { { x, m }, { x, m + post } } },
    { name = "Red's post", points = { { x, -m }, { x, -m - post } } },
  },
  goals = {
    { name = "Blue's goal", team = "blue", from = { -x, -m }, to = { -x, m } },
    { name = "Red's goal", team = "red", from = { x, -m }, to = { x, m } },
  },
  areas = {
    { name = "Blue's goal area", team = "blue", from = { -x, -m }, to = { -x, m }, radius = area },
    { name = "Red's goal area", team = "red", from = { x, -m }, to = { x, m }, radius = area },
  },
  spots = {
    { name = "at the centre", at = { 0, 0 } },
  },
  bodies = bodies,
}

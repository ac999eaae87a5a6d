-- A wall game on a table, seen from above: one front wall, two side walls, an open back line.
-- x from the open back (x = -1) to the front wall (x = +1); y to the left, looking at the wall.
local L, W = 2.0, 1.2
local x, y = L / 2, W / 2

return {
  name = "Wall court",
  ball = { radius = 0.03, wall_restitution = 0.85, body_restitution = 0.8 },
  brownian = 0.04,
  walls = {
    { name = "front wall", points = { { x, -y }, { x, y } } },
    { name = "left wall",  points = { { -x, y }, { x, y } } },
    { name = "right wall", points = { { -x, -y }, { x, -y } } },
  },
  -- Past the back line the ball is out.
  bounds = { { -x, -y }, { x, y } },
  spots = {
    { name = "Blue's serve", team = "blue", at = { -0.3, 0.25 } },
    { name = "Red's serve",  team = "red",  at = { -0.3, -0.25 } },
  },
  bodies = {
    { name = "Blue", team = "blue", radius = 0.05, at = { -0.7, 0.3 } },
    { name = "Red",  team = "red",  radius = 0.05, at = { -0.7, -0.3 } },
  },
}

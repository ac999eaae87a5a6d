-- The Quantum air hockey table, seen from above (the paper's Figure 1).
-- Field coordinates: origin at the table's centre, x from Blue's end (x = -L/2) to Red's end
-- (x = +L/2), y to Blue's left. Lengths in metres, speeds in m/s.
local L, W = 2.0, 1.0       -- a 7-foot table
local mouth = 0.26          -- goal mouth width
local x, y, m = L / 2, W / 2, mouth / 2

return {
  name = "Quantum air hockey table",
  ball = { radius = 0.0315, wall_restitution = 0.9, body_restitution = 0.8 },  -- a 63 mm puck
  -- How fast the players' idea of where the puck is blurs: about 16 cm after 10 s unseen.
  brownian = 0.05,
  walls = {
    { name = "left wall",  points = { { -x, y }, { x, y } } },
    { name = "right wall", points = { { -x, -y }, { x, -y } } },
    { name = "Blue's end", points = { { -x, y }, { -x, m } } },
    { name = "Blue's end", points = { { -x, -m }, { -x, -y } } },
    { name = "Red's end",  points = { { x, y }, { x, m } } },
    { name = "Red's end",  points = { { x, -m }, { x, -y } } },
  },
  goals = {
    { name = "Blue's goal", team = "blue", from = { -x, -m }, to = { -x, m } },
    { name = "Red's goal",  team = "red",  from = { x, -m },  to = { x, m } },
  },
  spots = {
    { name = "in front of Blue's goal", team = "blue", at = { -0.5, 0 } },
    { name = "in front of Red's goal",  team = "red",  at = { 0.5, 0 } },
  },
  bodies = {
    { name = "Blue's mallet", team = "blue", radius = 0.048, at = { -0.85, 0 } },
    { name = "Red's mallet",  team = "red",  radius = 0.048, at = { 0.85, 0 } },
  },
}

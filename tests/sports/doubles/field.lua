-- Doubles air hockey: the 7-foot table with two mallets a side, a forward and a back.
local L, W = 2.0, 1.0
local mouth = 0.26
local x, y, m = L / 2, W / 2, mouth / 2

return {
  name = "Doubles table",
  ball = { radius = 0.0315, wall_restitution = 0.9, body_restitution = 0.8 },
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
    { name = "on Blue's side", team = "blue", at = { -0.5, 0 } },
    { name = "on Red's side",  team = "red",  at = { 0.5, 0 } },
  },
  bodies = {
    { name = "Blue back",    team = "blue", radius = 0.048, at = { -0.85, 0.15 } },
    { name = "Blue forward", team = "blue", radius = 0.048, at = { -0.35, -0.2 } },
    { name = "Red back",     team = "red",  radius = 0.048, at = { 0.85, -0.15 } },
    { name = "Red forward",  team = "red",  radius = 0.048, at = { 0.35, 0.2 } },
  },
}

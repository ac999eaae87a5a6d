-- Shooting practice: half an air hockey table, one goal at the far end, one player.
-- x from the shooter's end (x = -0.5) to the goal (x = +0.5); y to the shooter's left.
local L, W, mouth = 1.0, 1.0, 0.26
local x, y, m = L / 2, W / 2, mouth / 2

return {
  name = "Practice half table",
  ball = { radius = 0.0315, wall_restitution = 0.9, body_restitution = 0.8 },
  brownian = 0.05,   -- how fast the players' idea of the ball blurs, m/sqrt(s)
  walls = {
    { name = "left wall",  points = { { -x, y }, { x, y } } },
    { name = "right wall", points = { { -x, -y }, { x, -y } } },
    { name = "back wall",  points = { { -x, -y }, { -x, y } } },
    { name = "goal end",   points = { { x, y }, { x, m } } },
    { name = "goal end",   points = { { x, -m }, { x, -y } } },
  },
  goals = {
    { name = "the goal", team = "target", from = { x, -m }, to = { x, m } },
  },
  spots = {
    { name = "on the practice spot", team = "blue", at = { -0.1, 0 } },
  },
  bodies = {
    { name = "Shooter", team = "blue", radius = 0.048, at = { -0.35, 0 } },
  },
}

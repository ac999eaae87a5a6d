-- A beach volleyball court seen from above, 2 v 2: two 8 m courts either side of a net, players
-- who hit the ball on (a dig, a set, a spike) instead of holding it. x from Blue's end line
-- (x = -8) to Red's (x = +8), the net along x = 0 with its top at 2.43 m; y to the left.
local half, W = 8, 8

return {
  name = "Rally court, 2 v 2",
  gravity = 9.81,
  landings = true,
  rehit = 0.3,  -- s: one swing is one touch
  ball = { radius = 0.105, floor_restitution = 0.3, audible_bounce = 0.5 },  -- sand
  max_body_speed = 9,
  bounds = { { -half - 6, -W / 2 - 6 }, { half + 6, W / 2 + 6 } },
  areas = {
    { name = "Blue court", team = "blue", box = { { -half, -W / 2 }, { 0, W / 2 } } },
    { name = "Red court", team = "red", box = { { 0, -W / 2 }, { half, W / 2 } } },
  },
  boards = {
    { name = "net", from = { 0, -W / 2 - 1 }, to = { 0, W / 2 + 1 }, bottom = 1.43, top = 2.43, restitution = 0.15 },
  },
  spots = {
    { name = "Blue's serve", team = "blue", at = { -half - 1, 0 } },
    { name = "Red's serve", team = "red", at = { half + 1, 0 } },
  },
  bodies = {
    { name = "Ada", team = "blue", at = { -4, 2 }, radius = 0.7, reach = 2.4, hits = true },
    { name = "Cy", team = "blue", at = { -4, -2 }, radius = 0.7, reach = 2.4, hits = true },
    { name = "Bo", team = "red", at = { 4, 2 }, radius = 0.7, reach = 2.4, hits = true },
    { name = "Di", team = "red", at = { 4, -2 }, radius = 0.7, reach = 2.4, hits = true },
  },
}

-- A court of landings, seen from above: two courts either side of a net, as in volleyball. Where
-- the ball comes down decides a rally, so the field declares `landings`: every audible touch of
-- the floor is a landing in one of the courts (box areas) or outside both.
-- x from Blue's end line (x = -6) to Red's (x = +6), the net along x = 0; y to the left.
local half, W = 6, 6

return {
  name = "Landing court, 1 v 1",
  gravity = 9.81,
  landings = true,
  ball = { radius = 0.1, floor_restitution = 0.6, audible_bounce = 0.8 },
  brownian = 0,
  max_body_speed = 10,
  -- Past these the ball has gone out of the hall.
  bounds = { { -half - 8, -W / 2 - 4 }, { half + 8, W / 2 + 4 } },
  areas = {
    { name = "Blue court", team = "blue", box = { { -half, -W / 2 }, { 0, W / 2 } } },
    { name = "Red court", team = "red", box = { { 0, -W / 2 }, { half, W / 2 } } },
  },
  -- The net: a board from the floor line across the court, 1 m deep, its top at 2.24 m.
  boards = {
    { name = "net", from = { 0, -W / 2 - 0.5 }, to = { 0, W / 2 + 0.5 }, bottom = 1.24, top = 2.24, restitution = 0.2 },
  },
  spots = {
    { name = "Blue's serve", team = "blue", at = { -half - 1, 0 } },
    { name = "Red's serve", team = "red", at = { half + 1, 0 } },
  },
  bodies = {
    { name = "Ada", team = "blue", at = { -3, 0 }, radius = 0.6, reach = 2.3, catches = true },
    { name = "Bo", team = "red", at = { 3, 0 }, radius = 0.6, reach = 2.3, catches = true },
  },
}

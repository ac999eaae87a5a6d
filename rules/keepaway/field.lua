-- rules/keepaway/field.lua
-- Keep-away: three passers on a triangle throw an imagined ball to each other; the player in the
-- middle tries to catch it. Seen from above, x along the court, y to its left; metres.
local L, W = param("length", 12), param("width", 8)

return {
  name = "Keep-away court",
  -- A ball that slows as it flies and rolls (1/s): a long throw arrives softer than it left.
  ball = { radius = 0.1, friction = 0.5 },
  brownian = 0.1,   -- how fast the players' idea of a loose ball blurs, m/sqrt(s)
  bounds = { { -L / 2, -W / 2 }, { L / 2, W / 2 } },   -- beyond the lines the ball is out
  spots = {
    { name = "in the middle", at = { 0, 0 } },
  },
  -- Players who catch: their radius is their reach, how near the ball must pass their hands.
  bodies = {
    { name = "Ann", team = "blue", catches = true, radius = 0.7, at = { -3.5, 0 } },
    { name = "Bo", team = "blue", catches = true, radius = 0.7, at = { 1.75, 3 } },
    { name = "Dee", team = "blue", catches = true, radius = 0.7, at = { 1.75, -3 } },
    { name = "Cy", team = "red", catches = true, radius = 0.6, at = { 0, 0 } },
  },
}

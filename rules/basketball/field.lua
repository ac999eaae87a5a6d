-- A half court of Quantum basketball (the paper's section 6; Imaginary Reality Basketball,
-- CHI 2014): one basket, both teams shooting at it, 3 v 3 by default (`--param players=1` for
-- 1 v 1). The ball has height: it flies in arcs, bounces off the floor, the backboard and the
-- rim, and drops through the hoop.
--
-- Field coordinates: x across the court (the sidelines at x = -7.5 and 7.5), y from the
-- baseline (y = 0) to the half-court line (y = 14), z up from the floor. FIBA sizes, in metres.
local per_team = param("players", 3)
assert(per_team >= 1 and per_team <= 5 and per_team % 1 == 0, "players must be a whole number from 1 to 5")
local W, L = 15, 14
local basket = { 0, 1.575 }   -- the ring's centre: 1.2 m to the board, 0.375 m to the ring's middle
local ARC = 6.75              -- the three-point line, from the basket's centre

-- Players: names for the announcer. Hats are tracked as "home 1", "home 2", ... (how a hat gets
-- its number: docs/tracking.md); TUIO and accelerometers use the same ids.
local names = {
  home = { "Maya", "Noah", "Omar", "Lena", "Ivo" },
  away = { "Pia", "Quinn", "Rosa", "Sven", "Tara" },
}
local bodies = {}
for t, team in ipairs({ "home", "away" }) do
  for i = 1, per_team do
    -- Around the basket inside the arc; Away's places are Home's mirrored across the court's
    -- middle line, so neither team has the better ones (the simulated players keep to them).
    local angle = math.rad(35 + 110 * (i - 0.5) / per_team)
    local side = t == 1 and 1 or -1
    bodies[#bodies + 1] = {
      name = names[team][i], team = team, catches = true, track = team .. " " .. i,
      at = { side * (ARC - 0.75) * math.cos(angle), basket[2] + (ARC - 0.75) * math.sin(angle) },
      radius = 0.5,    -- how far the hands get around a player
      reach = 2.4,     -- how high they get standing, arms up (a jump adds to it)
    }
  end
end

return {
  name = string.format("Half court, %d v %d", per_team, per_team),
  gravity = 9.81,
  -- A size 7 basketball; a good one comes back from the floor at about 0.8 of its speed.
  ball = { radius = 0.12, floor_restitution = 0.78, audible_bounce = 0.8 },
  brownian = 0.05,
  max_body_speed = 10,
  bounds = { { -W / 2, 0 }, { W / 2, L } },   -- the lines: beyond them the ball is out
  hoops = {
    { name = "basket", at = basket, height = 3.05, radius = 0.234, thickness = 0.018, restitution = 0.55,
      rim = "rim" },
  },
  boards = {
    { name = "backboard", from = { -0.9, 1.2 }, to = { 0.9, 1.2 }, bottom = 2.9, top = 3.95, restitution = 0.7 },
  },
  areas = {
    -- Inside the arc a basket counts two, beyond it three (the corners' straight lines, 0.9 m in
    -- from the sidelines, are taken as part of the arc: at most 15 cm apart).
    { name = "two-point area", at = basket, radius = ARC },
  },
  spots = {
    { name = "check", at = { 0, basket[2] + ARC + 1.5 } },   -- where the ball is checked after a basket
  },
  bodies = bodies,
}

local n = param("players", 3)
local bodies = {}
for i = 1, n do bodies[i] = { name = "p" .. i, team = i % 2 == 0 and "red" or "blue", radius = 0.3, at = { i - n / 2, 0 } } end
return { walls = { { points = { { -5, 3 }, { 5, 3 } } } }, bodies = bodies, spots = { { at = { 0, 0 } } } }

-- Black ice: a penalty unless the holder keeps the direction and speed it had when the ice came,
-- within `slip` m/s.
return {
  name = "black ice",
  duration = 5,
  defaults = { strength = 0.2, slip = 0.3 },
  phrases = { start = "Black ice under {player}: keep going", over = "{player} is off the ice" },
  start = function(holder, game, p)
    p.vx, p.vy = holder.vx, holder.vy
  end,
  factor = function(fate, holder, game, p)
    local dvx, dvy = holder.vx - p.vx, holder.vy - p.vy
    if fate.player == holder.name and math.sqrt(dvx * dvx + dvy * dvy) > p.slip then
      return p.strength
    end
  end,
}

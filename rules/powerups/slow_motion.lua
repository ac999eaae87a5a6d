-- Slow motion: a penalty while the holder moves faster than `limit` m/s.
return {
  name = "slow motion",
  duration = 10,
  defaults = { strength = 0.2, limit = 1.0 },
  phrases = { start = "Slow motion for {player}", over = "{player} is back to full speed" },
  factor = function(fate, holder, game, p)
    if fate.player == holder.name and holder.speed > p.limit then return p.strength end
  end,
}

-- Penalty: the holder's chance to touch the ball shrinks; at strength 0 the mallet cannot meet it.
return {
  name = "penalty",
  duration = 10,
  defaults = { strength = 0.3 },
  phrases = { start = "Penalty for {player}", over = "{player}'s penalty is over" },
  factor = function(fate, holder, game, p)
    if fate.kind == "body" and fate.actor == holder.name then return p.strength end
  end,
}

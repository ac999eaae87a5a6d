-- Penalty: the holder's chance to get the ball shrinks, whatever the sport's kind of touch (a
-- mallet's, a catch, a hit, a tackle); at strength 0 the holder never gets it.
return {
  name = "penalty",
  duration = 10,
  defaults = { strength = 0.3 },
  phrases = { start = "Penalty for {player}", over = "{player}'s penalty is over" },
  factor = function(fate, holder, game, p)
    if fate.player == holder.name then return p.strength end
  end,
}

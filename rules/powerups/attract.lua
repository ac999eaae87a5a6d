-- Attract: the holder's chance to get the ball grows (a mallet's touch, a catch, a hit, a tackle),
-- which helps receiving and intercepting.
return {
  name = "attract",
  duration = 10,                       -- seconds, unless the grant says otherwise
  defaults = { strength = 3 },         -- numbers the grant may override
  phrases = { start = "{player} attracts the ball", over = "{player} no longer attracts the ball" },
  factor = function(fate, holder, game, p)
    if fate.player == holder.name then return p.strength end
  end,
}

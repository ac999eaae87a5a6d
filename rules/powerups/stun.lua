-- Stun: a penalty unless the holder stays put (slower than `still` m/s).
return {
  name = "stun",
  duration = 5,
  defaults = { strength = 0.2, still = 0.1 },
  phrases = { start = "{player} is stunned: stay put", over = "{player} can move again" },
  factor = function(fate, holder, game, p)
    if fate.player == holder.name and holder.speed > p.still then return p.strength end
  end,
}

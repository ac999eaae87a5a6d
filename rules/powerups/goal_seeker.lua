-- Goal seeker: the holder's shots favour the opposing goal.
return {
  name = "goal seeker",
  duration = 10,
  defaults = { strength = 3 },
  phrases = { start = "{player}'s shots seek the goal", over = "{player}'s shots are ordinary again" },
  factor = function(fate, holder, game, p)
    if fate.kind == "goal" and fate.favours == holder.team and game.last_touch() == holder.name then
      return p.strength
    end
  end,
}

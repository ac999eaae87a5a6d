-- Tackles, written from docs/lua-api.md: an opponent whose body touches the holder's takes the
-- ball at `tackles.rate` per second, made likelier by `factors.tackle` and ruled out by a
-- modifier (a keeper may not tackle out of the box here). It exercises the `tackle` event and
-- fate kind.
local sport = {
  name = "Tackles",
  particles = 200,
  match = { seconds = 600, start = "Ann" },
  tackles = { rate = 1.5 },
  factors = { tackle = 2 },
  teams = { blue = "Blue", red = "Red" },
  phrases = {
    tackle = "{player} takes it off {previous}",
  },
}

sport.on = {
  tackle = function(game, e)
    game.say("tackle", { player = e.actor, previous = e.previous })
  end,
}

sport.modifiers = {
  function(fate, game)
    if fate.kind ~= "tackle" then return end
    for _, p in ipairs(game.players()) do
      if p.name == fate.actor and p.role == "keeper" then return 0 end
    end
  end,
}

return sport

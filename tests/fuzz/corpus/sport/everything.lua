local sport = { name = "everything", match = { seconds = 1, particles = 50 } }
sport.factors = { goal = 2, own_goal = 0.5, body = 1 }
sport.handicaps = { ["Red's mallet"] = 2 }
sport.modifiers = { function(game, fate) return fate.kind == "goal" and 1.5 or 1 end }
sport.phrases = { goal = { "{player} scores", "Goal by {player}" } }
sport.audio = { voice = "en-us", priorities = { goal = 3 } }
sport.state = { n = 0 }
sport.on = {
  drop = function(game, e)
    sport.state.n = sport.state.n + 1
    game.after(0.2, function() game.say("later") end)
    game.grant("Red's mallet", "attract", { seconds = 5 })
  end,
  goal = function(game, e) game.award("red"); game.say("goal", { player = e.by }) end,
  time_up = function(game, e) game.finish("") end,
}
return setmetatable(sport, { __index = function(t, k) return rawget(t, k) end })

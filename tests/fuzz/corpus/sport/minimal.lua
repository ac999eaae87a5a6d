local sport = { name = "minimal", field = "field.lua" }
sport.on = {
  goal = function(game, e) game.award(e.team == "blue" and "red" or "blue"); game.say("Goal, " .. e.by) end,
  drop = function(game, e) game.say("drop") end,
}
return sport

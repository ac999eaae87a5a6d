-- Futsal kicks, written from docs/lua-api.md: `game.kick` along the ground or lofted, the `kick`
-- event, and a rolling ball that slows to a stop and is told `loose`. With --param opening=chip
-- the player given the ball chips it over the defender to Bo; whoever Bo gets it from, he
-- shoots along the ground at the Red goal. opening=wrong kicks for someone without the ball.
local opening = param("opening", "none")

local sport = {
  name = "Futsal kicks",
  particles = 300,
  match = { seconds = 600, start = "Ann" },
  factors = { pass = 3, intercept = 3, pickup = 2 },
  teams = { blue = "Blue", red = "Red" },
  phrases = {
    kick = "{player} kicks",
    pass = "to {player}",
    loose = "loose ball",
    goal = "goal",
  },
}

sport.on = {
  give = function(game, e)
    if opening == "chip" then game.kick(e.actor, "Bo", { elevation = 60 }) end
    if opening == "wrong" then game.kick("Cy", "Bo") end
  end,
  kick = function(game, e) game.say("kick", { player = e.actor }) end,
  pass = function(game, e)
    game.say("pass", { player = e.actor })
    if e.actor == "Bo" then game.kick("Bo", "Red goal", { speed = 10 }) end
  end,
  loose = function(game) game.say("loose") end,
  goal = function(game) game.say("goal") end,
}

return sport

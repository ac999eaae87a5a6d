-- Futsal kicks and restarts, written from docs/lua-api.md: `game.kick` along the ground or
-- lofted, the `kick` event, a rolling ball that slows to a stop and is told `loose`, kick-ins
-- given where the ball went out and a kick-off formation (`game.give` at a place, `game.place`). With --param opening=chip
-- the player given the ball chips it over the defender to Bo; whoever Bo gets it from, he
-- shoots along the ground at the Red goal. opening=wrong kicks for someone without the ball;
-- opening=nowhere places a player on a spot the pitch does not have.
local opening = param("opening", "none")

-- Where each stands for a kick-off; the taker is given the ball at the centre.
local kickoff = { Ann = { x = -1, y = 0 }, Bo = { x = -4, y = 3 }, Cy = { x = 1, y = 0 }, Kim = { x = 9, y = 0 } }

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
    place = "{player}, to {place}",
  },
}

sport.on = {
  give = function(game, e)
    if opening == "chip" then game.kick(e.actor, "Bo", { elevation = 60 }) end
    if opening == "wrong" then game.kick("Cy", "Bo") end
    if opening == "nowhere" then game.place("Bo", "penalty mark") end
  end,
  kick = function(game, e) game.say("kick", { player = e.actor }) end,
  pass = function(game, e)
    game.say("pass", { player = e.actor })
    if e.actor == "Bo" then game.kick("Bo", "Red goal", { speed = 10 }) end
  end,
  loose = function(game) game.say("loose") end,
  -- A kick-in where the ball went out, by the other team's nearest player, who is placed there
  -- (a person is told where to go) and gets the ball when they stand there.
  out = function(game, e)
    local f = game.field()
    local at = { x = math.max(f.bounds[1][1], math.min(f.bounds[2][1], e.x)),
                 y = math.max(f.bounds[1][2], math.min(f.bounds[2][2], e.y)) }
    local taker, best
    for _, p in ipairs(game.players()) do
      local d = math.sqrt((p.x - at.x) ^ 2 + (p.y - at.y) ^ 2)
      if p.team ~= e.by_team and (not best or d < best) then taker, best = p.name, d end
    end
    game.give(taker, 1, { at = at })
  end,
  -- Kick-off: everyone to their place, the team that conceded at the centre.
  goal = function(game, e)
    game.say("goal")
    for name, at in pairs(kickoff) do game.place(name, at) end
    game.give(e.team == "blue" and "Ann" or "Cy", 1, { at = "centre" })
  end,
}

return sport

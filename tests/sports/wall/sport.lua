-- A turn-based wall game, written from docs/lua-api.md: the two players hit the ball in turn
-- against the front wall. Whoever hits out of turn, or before the ball has been to the wall,
-- loses the point; so does a player who lets the ball die (no hit within three seconds).
-- It exercises timers, dead balls, hints to simulated players, the previous toucher and
-- formatted phrases.
local two_teams = require "two_teams"

local POINTS = 5           -- to win the game
local DIES_AFTER = 3.0     -- seconds without a hit: the ball is dead

local sport = {
  name = "Quantum wall",
  particles = 600,
  match = { seconds = 120, start = "blue" },
  teams = { blue = "Blue", red = "Red" },
  factors = { body = 3 },
  phrases = {
    serve = "{team} to serve",
    hit = "{team}",
    front = "Front wall, {speed:%.1f} metres a second",
    point = "Point {team}: {why}",
    score = "{blue} to {red}",
    dead = "The ball is dead",
    match_end = "{team} wins the game",
  },
}

-- The rally: whose turn it is to hit, whether the ball has reached the front wall since the last
-- hit, and the timer that ends a rally nobody plays on.
local turn, reached, dies

local function point(game, winner, why)
  if dies then game.cancel(dies) end
  dies = nil
  game.say("point", { team = game.team_name(winner), why = why })
  two_teams.goal(game, winner, "score", POINTS, winner, 1.5)
end

local function hit(game, e)
  if e.team ~= turn then return point(game, two_teams.other(game, e.team), "out of turn") end
  if e.previous ~= "" and not reached then return point(game, two_teams.other(game, e.team), "no front wall") end
  game.say("hit", { team = game.team_name(e.team) })
  turn, reached = two_teams.other(game, e.team), false
  game.turn(turn)
  if dies then game.cancel(dies) end
  dies = game.after(DIES_AFTER, function(game)
    dies = nil
    game.dead_ball()
    point(game, e.team, "no return")
  end)
end

sport.on = {
  drop = function(game, e)
    turn, reached = e.team, false
    game.turn(turn)
    game.aim("blue", "front wall")
    game.aim("red", "front wall")
    game.say("serve", { team = game.team_name(e.team) })
  end,

  shot = hit,
  intercept = hit,

  bounce = function(game, e)
    if e.actor == "front wall" then
      reached = true
      game.say("front", { speed = e.speed })
    end
  end,

  -- Past the back line: the player whose turn it was missed it, or the hit never reached the wall.
  out = function(game, e)
    if reached then point(game, two_teams.other(game, turn), "missed")
    else point(game, two_teams.other(game, e.by_team ~= "" and e.by_team or turn), "no front wall") end
  end,

  dead = function(game, e)
    game.say("dead")
  end,

  match_end = function(game, e)
    if e.team ~= "" then game.say("match_end", { team = game.team_name(e.team) }) end
  end,
}

return sport

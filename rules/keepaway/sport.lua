-- rules/keepaway/sport.lua
-- Keep-away: Ann, Bo and Dee (the passers) score a point for every five passes in a row; Cy (in
-- the middle) scores one for every pass caught, and hands the ball back. docs/writing-a-team-sport.md
-- builds this file step by step.
local two_teams = require "two_teams"

local sport = {
  name = "Keep-away",
  field = "field.lua",
  particles = 500,
  match = { seconds = 120, start = "Ann" },   -- the match starts with the ball in Ann's hands

  -- "A vs B vs out": a catch by either side is likelier than the ball going out, a pass likelier
  -- still; never more than the player's reach allows.
  factors = { pass = 4, intercept = 2, out = 0.5 },

  -- A throw that says no speed leaves the hand at 8 m/s, scattered by 4 degrees and 10 %.
  throws = { speed = 8, spread = 4, speed_spread = 0.1 },

  teams = { blue = "the passers", red = "Cy" },

  phrases = {
    pass = "{thrower} to {catcher}",
    streak = "{count} in a row, point to {team}",
    caught = "Caught by {player}",
    out = "Out",
    back = "{player} has it",
    match_end = "Time. {blue} to {red} for {winner}",
    draw = "A draw, {blue} to {red}",
  },
}

local PASSES_FOR_A_POINT = 5
local GIVE_BACK_AFTER = 1.5   -- s: a moment to hear the news before play goes on

sport.state = { passes = 0 }

-- The passer nearest (x, y): the ball goes back to the passers after a catch or out.
local function nearest_passer(game, x, y)
  local best, best_d
  for _, p in ipairs(game.players()) do
    local d = (p.x - x) ^ 2 + (p.y - y) ^ 2
    if p.team == "blue" and (not best_d or d < best_d) then best, best_d = p, d end
  end
  return best
end

sport.on = {
  pass = function(game, e)
    game.say("pass", { thrower = e.previous, catcher = e.actor })
    sport.state.passes = sport.state.passes + 1
    if sport.state.passes == PASSES_FOR_A_POINT then
      sport.state.passes = 0
      game.award("blue")
      game.say("streak", { count = PASSES_FOR_A_POINT, team = game.team_name("blue") })
    end
  end,

  intercept = function(game, e)
    sport.state.passes = 0
    game.award("red")
    game.say("caught", { player = e.actor })
    local p = nearest_passer(game, e.x, e.y)
    game.give(p.name, GIVE_BACK_AFTER)
  end,

  out = function(game, e)
    sport.state.passes = 0
    game.say("out")
    local p = nearest_passer(game, e.x, e.y)
    game.give(p.name, GIVE_BACK_AFTER)
  end,

  give = function(game, e)
    game.say("back", { player = e.actor })
  end,

  -- A ball that rolled loose is no pass: the streak starts again, and Cy picking it up has
  -- caught it.
  pickup = function(game, e)
    if e.team == "red" then return sport.on.intercept(game, e) end
    sport.state.passes = 0
    game.say("back", { player = e.actor })
  end,

  match_end = two_teams.announce_end,
}

return sport

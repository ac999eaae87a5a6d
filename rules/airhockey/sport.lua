-- Quantum air hockey (the paper's game): rules, fate factors and the announcer's phrases.
-- The table itself is data in field.lua. The engine's Lua API: docs/lua-api.md.
local sport = {
  name = "Quantum air hockey",
  field = "field.lua",
  particles = 1000,
  -- The puck first drops in Blue's half, in front of Blue's goal (as in the paper). The first to
  -- seven goals wins; after a goal the puck drops again in a second and a half.
  match = { seconds = 180, first_to = 7, respawn_delay = 1.5, start = "blue" },

  -- The paper's fate factors: goals and mallet contacts are made likelier, own goals rarer.
  factors = { goal = 5, own_goal = 0.1, body = 5, out = 1, field = 1 },

  -- 1 is even; above 1 helps that player (its intercepts and its shots on goal get likelier).
  handicaps = { ["Blue's mallet"] = 1, ["Red's mallet"] = 1 },

  -- The announcer's voice (espeak-ng), and where the listener stands: the table's centre,
  -- facing Red's end as Blue does, so a bounce off the left wall is heard on the left.
  audio = {
    voice = "en-us", rate = 170, volume = 100,
    listener = { 0, 0 }, facing = { 1, 0 },
    sounds = { shot = "hit.wav", intercept = "hit.wav", bounce = "wall.wav", goal = "goal.wav", drop = "whistle.wav" },
  },

  -- How the announcer names the teams (also in the power-ups' phrases).
  teams = { blue = "Blue", red = "Red" },

  phrases = {
    drop = "Puck to {team}",  -- short: a goal often comes a second after the drop
    shot = "{team} shoots",
    intercept = "intercepted by {team}",
    goal = "Goal for {team}!",
    own_goal = "Own goal by {team}!",
    out = "The puck is off the table",
    score = "{blue} to {red}",
    match_end = "{winner} wins the match, {blue} to {red}",
    draw = "It's a draw, {blue} to {red}",
  },
}

local two_teams = require "two_teams"  -- rules/lib/two_teams.lua

-- A goal for the team that did not defend it; the puck drops again in front of the conceding goal.
local function goal_for(game, scorer, conceding)
  two_teams.goal(game, scorer, "score", sport.match.first_to, conceding, sport.match.respawn_delay)
end

sport.on = {
  drop = function(game, e)
    game.say("drop", { team = game.team_name(e.team) })
  end,

  shot = function(game, e)
    game.say("shot", { team = game.team_name(e.team) })
  end,

  intercept = function(game, e)
    game.say("intercept", { team = game.team_name(e.team) })
  end,

  -- e.team defends the goal the puck went into; the other team scores.
  goal = function(game, e)
    local scorer = two_teams.other(game, e.team)
    game.say("goal", { team = game.team_name(scorer) })
    goal_for(game, scorer, e.team)
  end,

  own_goal = function(game, e)
    game.say("own_goal", { team = game.team_name(e.team) })
    goal_for(game, two_teams.other(game, e.team), e.team)
  end,

  out = function(game, e)
    game.say("out")
    -- The side that did not shoot it off gets the puck.
    game.respawn(two_teams.other(game, e.by_team) or "blue", sport.match.respawn_delay)
  end,

  match_end = two_teams.announce_end,
}

return sport

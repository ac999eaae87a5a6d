-- Quantum air hockey (the paper's game): rules, fate factors and the announcer's phrases.
-- The table itself is data in field.lua. The engine's Lua API: docs/lua-api.md.
local sport = {
  name = "Quantum air hockey",
  field = "field.lua",
  particles = 1000,
  -- The puck first drops in Blue's half, in front of Blue's goal (as in the paper).
  match = { seconds = 180, first_to = 7, respawn_delay = 1.5, start = "blue" },

  -- The paper's fate factors: goals and mallet contacts are made likelier, own goals rarer.
  factors = { goal = 5, own_goal = 0.1, body = 5, out = 1, field = 1 },

  -- 1 is even; above 1 helps that player (its intercepts and its shots on goal get likelier).
  handicaps = { ["Blue's mallet"] = 1, ["Red's mallet"] = 1 },

  -- The announcer's voice (espeak-ng), and where the listener stands: the table's centre,
  -- facing Red's end as Blue does, so a bounce off the left wall is heard on the left.
  audio = {
    voice = "en", rate = 170, volume = 100,
    listener = { 0, 0 }, facing = { 1, 0 },
    sounds = { shot = "hit.wav", intercept = "hit.wav", bounce = "wall.wav", goal = "goal.wav", drop = "whistle.wav" },
  },

  phrases = {
    drop = "The puck was dropped {spot}",
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

local names = { blue = "Blue", red = "Red" }
local other = { blue = "red", red = "blue" }

local function score_line(game)
  local s = game.score()
  return { blue = s.blue, red = s.red }
end

sport.on = {
  drop = function(game, e)
    game.say("drop", { spot = e.actor })
  end,

  shot = function(game, e)
    game.say("shot", { team = names[e.team] })
  end,

  intercept = function(game, e)
    game.say("intercept", { team = names[e.team] })
  end,

  -- e.team defends the goal the puck went into; the other team scores.
  goal = function(game, e)
    local scorer = other[e.team]
    game.award(scorer)
    game.say("goal", { team = names[scorer] })
    game.say("score", score_line(game))
    if game.score()[scorer] >= sport.match.first_to then
      game.finish(scorer)
    else
      game.respawn(e.team, sport.match.respawn_delay)  -- dropped in front of the conceding goal
    end
  end,

  own_goal = function(game, e)
    local scorer = other[e.team]
    game.award(scorer)
    game.say("own_goal", { team = names[e.team] })
    game.say("score", score_line(game))
    if game.score()[scorer] >= sport.match.first_to then
      game.finish(scorer)
    else
      game.respawn(e.team, sport.match.respawn_delay)
    end
  end,

  out = function(game, e)
    game.say("out")
    -- The side that did not shoot it off gets the puck.
    game.respawn(other[e.by_team] or "blue", sport.match.respawn_delay)
  end,

  match_end = function(game, e)
    local s = score_line(game)
    if e.team == "" then
      game.say("draw", s)
    else
      s.winner = names[e.team]
      game.say("match_end", s)
    end
  end,
}

return sport

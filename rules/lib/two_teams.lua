-- Helpers for sports of two teams, for any sport to require: local two_teams = require "two_teams"
-- (rules/lib is on every sport's require path; docs/lua-api.md, "Modules").
local two_teams = {}

-- The other team of a field with two teams ("blue" -> "red").
function two_teams.other(game, team)
  for _, t in ipairs(game.teams()) do
    if t ~= team then return t end
  end
end

-- A goal for `scorer`: awarded, announced by `phrase` with the score as its values ({blue},
-- {red}, ...), then the match ends when the scorer has `first_to` goals, or the next ball drops
-- at `restart` (a spot or team) after `delay` seconds.
function two_teams.goal(game, scorer, phrase, first_to, restart, delay)
  game.award(scorer)
  game.say(phrase, game.score())
  if game.score()[scorer] >= first_to then
    game.finish(scorer)
  else
    game.respawn(restart, delay)
  end
end

-- A match_end handler: says `draw` when nobody won, else `match_end`, each with the score as its
-- values ({blue}, {red}, ...) and the winner's team name as {winner}:
--   sport.on.match_end = two_teams.announce_end
function two_teams.announce_end(game, e)
  local s = game.score()
  if e.team == "" then
    game.say("draw", s)
  else
    s.winner = game.team_name(e.team)
    game.say("match_end", s)
  end
end

return two_teams

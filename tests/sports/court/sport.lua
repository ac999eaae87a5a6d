-- A net game of landings, written from docs/lua-api.md and docs/field-files.md: the server
-- throws the ball over the net; where it comes down decides the point. A landing in a team's
-- court is a point for the other team, a landing outside both courts one against the thrower's
-- team. It exercises the `landing` event and fate kind: e.actor and e.team name the court, and
-- `factors.landing` weighs where the ball comes down.
local two_teams = require "two_teams"

local sport = {
  name = "Landing court",
  particles = 400,
  match = { seconds = 120, start = "Ada" },
  teams = { blue = "Blue", red = "Red" },
  -- Landings in a court are likelier than landings outside both: gameflow, not a sure point.
  factors = { landing = 1, out = 0.5 },
  phrases = {
    serve = "{player} to serve",
    in_court = "In, {court}",
    outside = "Out",
    score = "{blue} to {red}",
  },
}

-- Who served the rally, so a ball landing outside both courts counts against their team.
sport.state = { server = "Ada" }

local function serve(game, who)
  sport.state.server = who
  game.give(who, 1.0)
end

sport.on = {
  give = function(game, e)
    game.say("serve", { player = e.actor })
  end,

  landing = function(game, e)
    local winner
    if e.actor ~= "" then
      game.say("in_court", { court = e.actor })
      winner = two_teams.other(game, e.team)
    else
      game.say("outside")
      winner = two_teams.other(game, e.by_team)
    end
    game.award(winner)
    game.say("score", game.score())
    serve(game, winner == "blue" and "Ada" or "Bo")
  end,

  out = function(game, e)
    game.award(two_teams.other(game, e.by_team))
    serve(game, sport.state.server)
  end,
}

-- Landings outside both courts are rarer still when the sport says so: a modifier reads the
-- fate's actor, "" outside every area.
sport.modifiers = {
  function(fate, game)
    if fate.kind == "landing" and fate.actor == "" then return 0.5 end
  end,
}

return sport

-- A net game of hits, written from docs/lua-api.md: nobody holds the ball. Each player's next
-- touch is aimed by the rules (game.hit) at the middle of the other court, lobbed over the net;
-- where the ball comes down decides the point, as on the landing court. It exercises the `hit`
-- event, the `hit` fate kind and game.hit.
local two_teams = require "two_teams"

local sport = {
  name = "Rally court",
  particles = 400,
  match = { seconds = 120, start = "Blue's serve" },
  teams = { blue = "Blue", red = "Red" },
  factors = { hit = 2, landing = 1, out = 0.5 },
  phrases = {
    hit = "{player}",
    in_court = "In, {court}",
    outside = "Out",
  },
}

local middle = { blue = { x = -4, y = 0 }, red = { x = 4, y = 0 } }

-- Every player's next touch goes to the middle of the other court, 45 degrees up: a rule's aim.
local function aim_everyone(game)
  for _, p in ipairs(game.players()) do
    game.hit(p.name, middle[two_teams.other(game, p.team)], { elevation = 45 })
  end
end

local function point_to(game, team)
  game.award(team)
  game.respawn(team == "blue" and "Blue's serve" or "Red's serve", 1.0)
end

sport.on = {
  drop = aim_everyone,

  hit = function(game, e)
    game.say("hit", { player = e.actor })
    aim_everyone(game)  -- a plan is for one touch: the hitter's is used up
  end,

  landing = function(game, e)
    if e.actor ~= "" then
      game.say("in_court", { court = e.actor })
      point_to(game, two_teams.other(game, e.team))
    else
      game.say("outside")
      point_to(game, two_teams.other(game, e.by_team))
    end
  end,

  out = function(game, e)
    point_to(game, two_teams.other(game, e.by_team))
  end,
}

return sport

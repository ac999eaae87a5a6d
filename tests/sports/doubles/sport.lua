-- Doubles air hockey, written from docs/lua-api.md and docs/writing-a-powerup.md: four mallets,
-- two a side. A pass between teammates is called, and its receiver attracts the puck for a few
-- seconds (the engine's own attract power-up: this sport lives outside rules/). It exercises
-- the previous toucher, modules, team names in power-up phrases and formatted numbers.
local two_teams = require "two_teams"
local calls = require "calls"

return {
  name = "Doubles air hockey",
  match = { seconds = 180, start = "blue" },
  factors = { goal = 5, own_goal = 0.1, body = 5 },
  teams = { blue = "Blue", red = "Red" },
  phrases = {
    drop = "Puck down {spot}",
    shot = "{player} shoots, {speed:%.1f}",
    pass = "{from} to {player}",
    intercept = "{player} cuts it off",
    attract_start = "{team} attracts the puck",
    goal = "Goal for {team}, {blue} to {red}",
  },
  on = {
    drop = function(game, e) game.say("drop", { spot = e.actor }) end,
    shot = function(game, e)
      local call = calls.of_touch(e)
      game.say(call, { player = e.actor, from = e.previous, speed = e.speed })
      if call == "pass" then game.grant(e.actor, "attract", { seconds = 3 }) end
    end,
    intercept = function(game, e) game.say("intercept", { player = e.actor }) end,
    goal = function(game, e)
      local scorer = two_teams.other(game, e.team)
      game.award(scorer)
      local score = game.score()
      game.say("goal", { team = game.team_name(scorer), blue = score.blue, red = score.red })
      game.respawn(e.team, 1.5)
    end,
  },
}

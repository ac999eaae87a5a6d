-- Shooting practice: one player, one goal, as many goals as possible before time runs out.
-- A second sport written in Lua only (no C++ changes): see docs/writing-a-sport.md.
local sport = {
  name = "Shooting practice",
  field = "field.lua",
  particles = 1000,
  match = { seconds = 60, start = "blue" },

  -- Practice rewards a shot that scores, and does not punish a miss: the puck stays in play.
  factors = { goal = 3, body = 2, field = 1 },

  -- The listener stands behind the shooter, facing the goal.
  audio = { voice = "en-us", rate = 160, listener = { -0.5, 0 }, facing = { 1, 0 } },

  phrases = {
    goal_seeker_start = "Hat trick! Your shots seek the goal",
    goal_seeker_over = "The goal seeker is gone",
    drop = "New puck",
    shot = "Shot {n}",
    goal = "Goal! {goals} from {shots}",
    time_up = "Time! {goals} goals from {shots} shots",
  },
}

-- Every third goal earns the goal seeker (rules/powerups/goal_seeker.lua) for ten seconds.
local streak_reward = { every = 3, powerup = "goal_seeker", seconds = 10 }

local shots, goals = 0, 0

sport.on = {
  drop = function(game, e)
    game.say("drop")
  end,

  shot = function(game, e)
    shots = shots + 1
    game.say("shot", { n = shots })
  end,

  goal = function(game, e)
    goals = goals + 1
    game.award("blue")
    game.say("goal", { goals = goals, shots = shots })
    if goals % streak_reward.every == 0 then
      game.grant(e.by, streak_reward.powerup, { seconds = streak_reward.seconds })
    end
    game.respawn("blue", 1.0)
  end,

  time_up = function(game, e)
    game.say("time_up", { goals = goals, shots = shots })
    game.finish("blue")
  end,
}

return sport

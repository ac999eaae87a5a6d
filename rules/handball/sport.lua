-- Quantum team handball (the paper's section 2.1): two teams throw and catch an imagined ball in a
-- hall; the announcer says who has it, who passes to whom, who intercepts and who scores. The
-- hall, the goals, the goal areas and the players are in field.lua (its --param's too). The
-- engine's Lua API: docs/lua-api.md; how this file came about: docs/writing-a-team-sport.md.
local two_teams = require "two_teams"

local sport = {
  name = "Quantum team handball",
  field = "field.lua",
  particles = 1000,
  -- Blue throws off; a match is two short halves' worth, ten minutes in all.
  -- The match starts with the ball in the hands of Blue's player nearest the centre.
  match = { seconds = param("minutes", 10) * 60, start = "blue", throw_off_delay = 2.0 },

  -- "A vs B vs out" (the paper's section 4): either team catching the ball is much likelier than
  -- the ball going out or rolling dead, and passes likelier still, so skilful play keeps its team
  -- the ball and poor play hands it to the other team rather than out of the game.
  factors = { goal = 3, own_goal = 0.2, pass = 6, intercept = 4, catch = 3, pickup = 3, out = 0.5, field = 1 },

  -- A throw leaves the hand at 10 m/s unless it says otherwise, scattered by 3 degrees and 8 %.
  throws = { speed = 10, spread = 3, speed_spread = 0.08 },

  teams = { blue = "Blue", red = "Red" },

  audio = {
    voice = "en-us", rate = 175,
    listener = { 0, 0 }, facing = { 1, 0 },
    sounds = { pass = "hit.wav", intercept = "hit.wav", catch = "hit.wav", pickup = "hit.wav", bounce = "wall.wav", goal = "goal.wav",
               give = "whistle.wav" },
    -- A goal or an intercept cuts a pass that is still being read out; passes wait their turn.
    priorities = { goal = 3, own_goal = 3, intercept = 2, pass = 1, catch = 1, pickup = 1, out = 2, give = 1, throw = 0 },
  },

  phrases = {
    throw_off = "Throw-off, {player}",
    throw_in = "Out. Throw-in {team}, {player}",
    keeper_throw = "Out. Goalkeeper throw, {player}",
    free_throw = "Free throw {team}, {player}",
    pass = "{thrower} to {catcher}",
    intercept = "Intercepted by {player}",
    save = "Saved by {player}",
    catch = "{player} has it",
    shot = "{player} shoots",
    post = "Off the post",
    goal = "Goal, {player}!",
    own_goal = "Own goal, {player}",
    score = "{blue} to {red}",
    in_area = "{player} stepped into the goal area",
    match_end = "{winner} wins, {blue} to {red}",
    draw = "It's a draw, {blue} to {red}",
  },
}

-- The players as they are this frame (read once a frame: the modifiers ask for every fate).
local players, players_at
local function player(game, name)
  if players_at ~= game.time() then players, players_at = game.players(), game.time() end
  for _, p in ipairs(players) do
    if p.name == name then return p end
  end
end

-- The player of `team` nearest (x, y); the goalkeeper only if `keeper`, else a field player
-- (a goalkeeper alone in its team takes everything).
local function nearest(game, team, x, y, keeper)
  local best, best_d
  for _, p in ipairs(game.players()) do
    if p.team == team and (p.role == "goalkeeper") == keeper then
      local d = (p.x - x) ^ 2 + (p.y - y) ^ 2
      if not best_d or d < best_d then best, best_d = p, d end
    end
  end
  return best or (not keeper and nearest(game, team, x, y, true)) or nil
end

-- The goal a team attacks: the one the other team defends.
local function attacked_goal(game, team)
  for _, g in ipairs(game.field().goals) do
    if g.team ~= team then return g end
  end
end

-- Whether a throw from (x, y) at (vx, vy) heads for the goal's mouth (with a post's margin).
local function at_goal(goal, x, y, vx, vy)
  local gx = goal.from[1]
  if vx == 0 or (gx - x) / vx <= 0 then return false end
  local cross = y + vy * (gx - x) / vx
  local lo, hi = math.min(goal.from[2], goal.to[2]), math.max(goal.from[2], goal.to[2])
  return cross > lo - 0.5 and cross < hi + 0.5
end

-- What the rules remember across events, and a reload: who is to throw off (nobody yet has: the
-- first give is the match's throw-off).
sport.state = { started = false, throw_off_by = nil }

local function throw_off(game, team)
  local p = nearest(game, team, 0, 0, false)
  game.give(p.name, sport.match.throw_off_delay)
  sport.state.throw_off_by = p.name
end

local function scored(game, scorer_team, conceding, phrase, who)
  game.say(phrase, { player = who })
  game.award(scorer_team)
  game.say("score", game.score())
  throw_off(game, conceding)
end

sport.on = {
  give = function(game, e)
    if e.actor == sport.state.throw_off_by or not sport.state.started then
      sport.state.started, sport.state.throw_off_by = true, nil
      game.say("throw_off", { player = e.actor })
    end
  end,

  -- A ball dropped (the engine brings one back when the rules did not): Blue's nearest player
  -- throws off.
  drop = function(game, e)
    throw_off(game, "blue")
  end,

  throw = function(game, e)
    local thrower = player(game, e.actor)
    -- Field players throw from outside the goal areas; from inside, the ball goes to the others.
    if thrower.role ~= "goalkeeper" and thrower.area ~= "" then
      local other = two_teams.other(game, e.team)
      local p = nearest(game, other, e.x, e.y, false)
      game.say("in_area", { player = e.actor })
      game.give(p.name)
      game.say("free_throw", { team = game.team_name(other), player = p.name })
      return
    end
    if at_goal(attacked_goal(game, e.team), e.x, e.y, e.vx, e.vy) then game.say("shot", { player = e.actor }) end
  end,

  pass = function(game, e)
    game.say("pass", { thrower = e.previous, catcher = e.actor })
  end,

  intercept = function(game, e)
    local p = player(game, e.actor)
    game.say(p.role == "goalkeeper" and "save" or "intercept", { player = e.actor })
  end,

  catch = function(game, e)
    game.say("catch", { player = e.actor })
  end,

  -- A ball that rolled loose, taken by whoever got to it.
  pickup = function(game, e)
    game.say("catch", { player = e.actor })
  end,

  bounce = function(game, e)
    game.say("post")
  end,

  -- e.team defends the goal the ball went into.
  goal = function(game, e)
    scored(game, two_teams.other(game, e.team), e.team, "goal", e.by)
  end,

  own_goal = function(game, e)
    scored(game, two_teams.other(game, e.team), e.team, "own_goal", e.by)
  end,

  -- Out over a side line: a throw-in for the team that did not touch it last, where it went out.
  -- Over a goal line: the goalkeeper of that end throws it in when the attackers put it there.
  out = function(game, e)
    local other = two_teams.other(game, e.by_team) or "blue"
    local f = game.field()
    local over_end = math.abs(e.x) >= f.bounds[2][1] - 0.01
    local p
    if over_end then
      local defender = e.x < 0 and "blue" or "red"
      if defender == other then
        p = nearest(game, other, e.x, e.y, true)
        game.give(p.name)
        game.say("keeper_throw", { player = p.name })
        return
      end
    end
    p = nearest(game, other, e.x, e.y, false)
    game.give(p.name)
    game.say("throw_in", { team = game.team_name(other), player = p.name })
  end,

  match_end = two_teams.announce_end,
}

-- A field player inside a goal area may not catch the ball, nor pick up a loose one: those catches
-- are no outcome at all.
-- A pass to a teammate on the run (into space) is the skilful play the engine favours more.
sport.modifiers = {
  function(fate, game)
    if fate.kind == "pass" or fate.kind == "intercept" or fate.kind == "catch" or fate.kind == "pickup" then
      local p = player(game, fate.actor)
      if p.role ~= "goalkeeper" and p.area ~= "" then return 0 end
      if fate.kind == "pass" and p.speed > 2 then return 1.5 end
    end
  end,
}

return sport

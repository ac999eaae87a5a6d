-- Quantum soccer, 5-a-side: two teams kick an imagined ball about a pitch; the announcer says who
-- has it, who passes to whom, who tackles, who shoots, who saves and who scores. The pitch, the
-- goals, the goal areas and the players are in field.lua (its --param's too). The engine's Lua
-- API: docs/lua-api.md; how a sport of kicking is written: docs/writing-a-team-sport.md.
--
-- The rules of indoor 5-a-side, outdoors: the outfield players control the ball at their feet and
-- kick it; only the goalkeeper handles, and only in the goal area, which nobody else may enter.
-- Over a side line: a kick-in where it went out. Over a goal line: a goal kick by the keeper
-- when the attackers put it there, a corner when the defenders did. After a goal: kick-off.
local two_teams = require "two_teams"

local sport = {
  name = "Quantum soccer",
  field = "field.lua",
  particles = 1000,
  -- Two halves of five minutes; Blue kicks off from the centre spot, and at half time Red does.
  match = { seconds = param("minutes", 10) * 60, start = "centre spot" },

  -- "A vs B vs out" (the paper's section 4): either team getting the ball is likelier than the
  -- ball going out, passes likelier still; a tackle is the defenders' fair chance.
  factors = { goal = 3, own_goal = 0.2, pass = 4, intercept = 3, catch = 2, pickup = 2, tackle = 1.5, out = 0.5, field = 1 },

  -- An opponent whose foot reaches the holder's takes the ball about once a second in three.
  tackles = { rate = 0.35 },

  -- A kick leaves the foot at 11 m/s unless it says otherwise, scattered by 3 degrees and 8 %.
  throws = { speed = 11, spread = 3, speed_spread = 0.08 },

  teams = { blue = "Blue", red = "Red" },

  audio = {
    voice = "en-us", rate = 175,
    listener = { 0, 0 }, facing = { 1, 0 },
    sounds = { pass = "hit.wav", intercept = "hit.wav", catch = "hit.wav", pickup = "hit.wav", tackle = "hit.wav",
               bounce = "wall.wav", goal = "goal.wav", give = "whistle.wav" },
    priorities = { goal = 3, own_goal = 3, tackle = 2, intercept = 2, pass = 1, catch = 1, pickup = 1, out = 2, give = 1,
                   kick = 0, throw = 0 },
  },

  phrases = {
    kick_off = "Kick-off, {player}",
    kick_in = "Kick-in {team}, {player}",
    corner = "Corner {team}, {player}",
    goal_kick = "Goal kick, {player}",
    place = "{player}, to {place}",
    pass = "{from} to {player}",
    intercept = "Cut out by {player}",
    save = "Saved by {player}",
    tackle = "{player} wins it off {previous}",
    control = "{player} has it",
    shot = "{player} shoots",
    post = "Off the post",
    goal = "Goal, {player}!",
    own_goal = "Own goal, {player}",
    score = "{blue} to {red}",
    half_time = "Half time, {blue} to {red}",
    match_end = "{winner} wins, {blue} to {red}",
    draw = "It's a draw, {blue} to {red}",
  },
}

local function player(game, name)
  for _, p in ipairs(game.players()) do
    if p.name == name then return p end
  end
end

local function keeper_of(game, team)
  for _, p in ipairs(game.players()) do
    if p.team == team and p.role == "goalkeeper" then return p end
  end
end

-- The outfield player of `team` nearest (x, y) (its keeper when it has nobody else).
local function nearest(game, team, x, y)
  local best, best_d
  for _, p in ipairs(game.players()) do
    if p.team == team and p.role ~= "goalkeeper" then
      local d = (p.x - x) ^ 2 + (p.y - y) ^ 2
      if not best_d or d < best_d then best, best_d = p, d end
    end
  end
  return best or keeper_of(game, team)
end

-- Whether a kick from (x, y) at (vx, vy) heads for the mouth of the goal `team` attacks (with a
-- post's margin).
local function at_goal(game, team, x, y, vx, vy)
  for _, g in ipairs(game.field().goals) do
    if g.team ~= team then
      local gx = g.from[1]
      if vx == 0 or (gx - x) / vx <= 0 then return false end
      local cross = y + vy * (gx - x) / vx
      return cross > math.min(g.from[2], g.to[2]) - 0.5 and cross < math.max(g.from[2], g.to[2]) + 0.5
    end
  end
  return false
end

-- What the rules remember across events and a reload: the restart being taken (its phrase and
-- taker, told when the taker gets the ball), and whether the match has started.
sport.state = { restart = nil, taker = nil, started = false }

-- A restart: `taker` gets the ball at `where` (a spot's name or a point) once there, told with
-- `phrase`. Everyone else keeps playing from where they stand.
local function restart(game, phrase, taker, where)
  sport.state.restart, sport.state.taker = phrase, taker
  game.give(taker, 1, { at = where })
end

-- Kick-off: everyone back to their starting place in their own half, the taker at the centre.
local function kick_off(game, team)
  for _, p in ipairs(game.field().players) do game.place(p.name, { x = p.at[1], y = p.at[2] }) end
  restart(game, "kick_off", nearest(game, team, 0, 0).name, "centre spot")
end

local function scored(game, scorer_team, conceding, phrase, who)
  game.say(phrase, { player = who })
  game.award(scorer_team)
  game.say("score", game.score())
  kick_off(game, conceding)
end

-- Half time falls at half the match's real length (game.length(): --seconds too), wherever the
-- ball is: Red kicks off the second half.
local function half_time(game)
  game.say("half_time", game.score())
  kick_off(game, "red")
end

sport.on = {
  -- The first ball of the match (and any ball the engine drops itself): Blue kicks off.
  drop = function(game)
    if not sport.state.started then
      sport.state.started = true
      game.after(game.length() / 2, half_time)
    end
    kick_off(game, "blue")
  end,

  give = function(game, e)
    if e.actor == sport.state.taker then
      game.say(sport.state.restart, { player = e.actor, team = game.team_name(e.team) })
      sport.state.restart, sport.state.taker = nil, nil
    end
  end,

  kick = function(game, e)
    if at_goal(game, e.team, e.x, e.y, e.vx, e.vy) then game.say("shot", { player = e.actor }) end
  end,

  throw = function(game, e)
    if at_goal(game, e.team, e.x, e.y, e.vx, e.vy) then game.say("shot", { player = e.actor }) end
  end,

  pass = function(game, e)
    game.say("pass", { from = e.previous, player = e.actor })
  end,

  intercept = function(game, e)
    game.say(player(game, e.actor).role == "goalkeeper" and "save" or "intercept", { player = e.actor })
  end,

  catch = function(game, e)
    game.say("control", { player = e.actor })
  end,

  pickup = function(game, e)
    game.say("control", { player = e.actor })
  end,

  tackle = function(game, e)
    game.say("tackle", { player = e.actor, previous = e.previous })
  end,

  bounce = function(game, e)
    if e.actor:find("post") then game.say("post") end
  end,

  -- e.team defends the goal the ball went into.
  goal = function(game, e)
    scored(game, two_teams.other(game, e.team), e.team, "goal", e.by)
  end,

  own_goal = function(game, e)
    scored(game, two_teams.other(game, e.team), e.team, "own_goal", e.by)
  end,

  -- Over a side line: a kick-in for the team that did not touch it last, where it went out, half
  -- a metre in. Over a goal line: a goal kick when the attackers put it there, a corner when the
  -- defenders did (at the corner on the side it went out).
  out = function(game, e)
    local f = game.field()
    local lo, hi = f.bounds[1], f.bounds[2]
    local other = two_teams.other(game, e.by_team) or "blue"
    local over_end = e.x <= lo[1] + 0.01 or e.x >= hi[1] - 0.01
    if not over_end then
      local at = { x = math.max(lo[1] + 0.5, math.min(hi[1] - 0.5, e.x)), y = e.y < 0 and lo[2] + 0.5 or hi[2] - 0.5 }
      restart(game, "kick_in", nearest(game, other, at.x, at.y).name, at)
      return
    end
    local defender = e.x < 0 and "blue" or "red"
    local name = game.team_name(defender)
    if defender == other then
      restart(game, "goal_kick", keeper_of(game, defender).name, name .. "'s goal kick")
    else
      local left = (e.y > 0) == (defender == "blue")
      local corner = name .. (left and "'s left corner" or "'s right corner")
      local spot
      for _, s in ipairs(f.spots) do
        if s.name == corner then spot = s end
      end
      restart(game, "corner", nearest(game, other, spot.at[1], spot.at[2]).name, corner)
    end
  end,

  -- The rules restart a match that stalled: the ball to the nearest outfield player of the team
  -- that did not touch it last.
  stalled = function(game, e)
    local team = two_teams.other(game, e.by_team) or "blue"
    restart(game, "kick_in", nearest(game, team, e.x, e.y).name, { x = e.x, y = e.y })
  end,

  match_end = two_teams.announce_end,
}

-- Only a goalkeeper may play the ball in a goal area, and only in its own: a field player there,
-- or a keeper out of it, gets no catch, pickup, tackle or save. A pass into a teammate's run is
-- the skilful play the engine favours more.
sport.modifiers = {
  function(fate, game)
    local k = fate.kind
    if k == "pass" or k == "intercept" or k == "catch" or k == "pickup" or k == "tackle" then
      local p = player(game, fate.actor)
      if p.role == "goalkeeper" then
        if p.area == "" then return 0 end
      elseif p.area ~= "" then
        return 0
      end
      if k == "pass" and p.speed > 2 then return 1.5 end
    end
  end,
}

return sport

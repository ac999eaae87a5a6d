-- Quantum basketball (the paper's section 6): half court, one basket, 3 v 3 (field.lua; 1 v 1
-- with --param players=1). The ball has height: shots fly in arcs, drop through the ring or come
-- off the rim and the backboard, and whoever is under it takes the rebound. Two points from
-- inside the arc, three from beyond it; after a basket the other team checks the ball at the top.
-- The engine's Lua API: docs/lua-api.md; how a sport of throws and catches is built:
-- docs/writing-a-team-sport.md.
local two_teams = require "two_teams"

local sport = {
  name = "Quantum basketball",
  field = "field.lua",
  particles = 1000,
  match = { seconds = param("minutes", 10) * 60, start = "home", check_delay = 2.0 },

  -- Baskets are favoured, and a ball off the rim is much likelier to be rebounded by someone
  -- than to roll out ("A vs B vs out", the paper's section 4); never beyond what a throw's
  -- scatter and the players' reach make possible.
  factors = { goal = 3, pass = 3, intercept = 2, catch = 2, pickup = 2, out = 0.4, field = 1 },

  -- A pass leaves the hand at 8 m/s unless it says otherwise; every throw scatters by 1.5 degrees
  -- of direction and of elevation and by 2 % of its speed (a shot's length is its hardest part:
  -- 2 % is 15 cm over 7 m, about what a good shooter misses by).
  throws = { speed = 8, spread = 1.5, speed_spread = 0.02, elevation_spread = 1.5 },

  teams = { home = "Home", away = "Away" },

  audio = {
    voice = "en-us", rate = 180,
    listener = { 0, 7 }, facing = { 0, -1 },
    sounds = { pass = "hit.wav", intercept = "hit.wav", catch = "hit.wav", pickup = "hit.wav", bounce = "wall.wav", goal = "goal.wav",
               give = "whistle.wav" },
    priorities = { goal = 3, intercept = 2, bounce = 1, pass = 1, catch = 1, pickup = 1, out = 2, give = 1, throw = 1 },
  },

  phrases = {
    shot = "{player} shoots",
    downtown = "{player} shoots from downtown",
    basket = "and it's in!",
    points = "{points} for {team}. {home} to {away}",
    rim = "off the rim",
    board = "off the glass",
    rebound = "rebound {player}",
    blocked = "blocked by {player}",
    steal = "stolen by {player}",
    pass = "{thrower} to {catcher}",
    catch = "{player} has it",
    check = "{team} ball, {player} checks it",
    out = "Out. {team} ball",
    match_end = "{winner} wins, {home} to {away}",
    draw = "It's a draw, {home} to {away}",
  },
}

local BASKET = "basket"
local CONTEST = 1.5   -- m: a defender this near the shot jumps at it

-- What the rules remember across events and a reload: the shot in the air (who, from where, and
-- whether it has touched the rim or the board yet).
sport.state = { shot = nil }

local function basket(game)
  for _, g in ipairs(game.field().goals) do
    if g.name == BASKET then return g end
  end
end

-- The player of `team` nearest (x, y).
local function nearest(game, team, x, y)
  local best, best_d
  for _, p in ipairs(game.players()) do
    local d = (p.x - x) ^ 2 + (p.y - y) ^ 2
    if p.team == team and (not best_d or d < best_d) then best, best_d = p, d end
  end
  return best
end

-- A throw heading for the basket (within 15 degrees of it) is a shot.
local function at_basket(game, e)
  local b = basket(game).from
  local dx, dy = b[1] - e.x, b[2] - e.y
  local d, v = math.sqrt(dx * dx + dy * dy), math.sqrt(e.vx * e.vx + e.vy * e.vy)
  return d < 0.3 or (v > 0 and (dx * e.vx + dy * e.vy) / (d * v) > math.cos(math.rad(15)))
end

-- The ball to `team` at the top of the arc after `delay` seconds: its player nearest the check spot.
local function check_ball(game, team, delay)
  local spot = game.field().spots[1].at
  local p = nearest(game, team, spot[1], spot[2])
  game.give(p.name, delay)
  game.say("check", { team = game.team_name(team), player = p.name })
end

sport.on = {
  -- A ball dropped (the engine brings one back when the rules did not): Home checks it.
  drop = function(game, e)
    check_ball(game, "home", 1.0)
  end,

  throw = function(game, e)
    sport.state.shot = nil
    if not at_basket(game, e) then return end
    -- Beyond the arc a basket counts three: where the ball left the hand decides.
    local three = game.area(e.x, e.y) == nil
    sport.state.shot = { by = e.actor, team = e.team, points = three and 3 or 2, touched = false }
    game.say(three and "downtown" or "shot", { player = e.actor })
    -- The nearest opponent within CONTEST of the ball contests the shot: a jump, hands 0.5 m
    -- higher for 0.6 s. (Tracked players' jumps have no input yet: the rules assume this one.)
    local d = nearest(game, two_teams.other(game, e.team), e.x, e.y)
    if d and (d.x - e.x) ^ 2 + (d.y - e.y) ^ 2 < CONTEST ^ 2 then game.jump(d.name, 0.5, 0.6) end
  end,

  bounce = function(game, e)
    if sport.state.shot then sport.state.shot.touched = true end
    if e.actor == "floor" then return end   -- heard as a bounce; nothing to say
    game.say(e.actor == "backboard" and "board" or "rim")
  end,

  goal = function(game, e)
    local shot = sport.state.shot
    local team = shot and shot.team or e.by_team
    sport.state.shot = nil
    game.say("basket")
    game.award(team, shot and shot.points or 2)
    local s = game.score()
    game.say("points", { points = shot and shot.points or 2, team = game.team_name(team), home = s.home, away = s.away })
    check_ball(game, two_teams.other(game, team), sport.match.check_delay)
  end,

  -- A catch after the rim or the board is a rebound; an opponent's catch of a shot before it got
  -- there is a block, of a pass a steal.
  intercept = function(game, e)
    local shot = sport.state.shot
    sport.state.shot = nil
    if shot and shot.touched then game.say("rebound", { player = e.actor })
    elseif shot then game.say("blocked", { player = e.actor })
    else game.say("steal", { player = e.actor }) end
  end,

  pass = function(game, e)
    local shot = sport.state.shot
    sport.state.shot = nil
    if shot and shot.touched then game.say("rebound", { player = e.actor })
    else game.say("pass", { thrower = e.previous, catcher = e.actor }) end
  end,

  catch = function(game, e)
    local shot = sport.state.shot
    sport.state.shot = nil
    game.say(shot and shot.touched and "rebound" or "catch", { player = e.actor })
  end,

  -- A loose ball (it rolled to a stop) is a rebound after a shot, else whoever gets to it has it.
  pickup = function(game, e)
    sport.on.catch(game, e)
  end,

  -- Out: the ball goes to the team that did not touch it last, from where it went out.
  out = function(game, e)
    sport.state.shot = nil
    local other = two_teams.other(game, e.by_team) or "home"
    local p = nearest(game, other, e.x, e.y)
    game.say("out", { team = game.team_name(other) })
    game.give(p.name, 1.0)
  end,

  match_end = two_teams.announce_end,
}

-- A shot caught before it touched the rim or the board is a block: as likely as the players'
-- reach and height make it, neither favoured (as the factors favour a pass or a steal) nor damped.
sport.modifiers = {
  function(fate, game)
    if (fate.kind == "pass" or fate.kind == "intercept") and fate.via == "" and sport.state.shot then
      return 1 / sport.factors[fate.kind]
    end
  end,
}

return sport

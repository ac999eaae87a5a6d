-- Quantum volleyball: two teams hit an imagined ball over a net; the announcer says who serves,
-- who digs, sets and attacks, who blocks, where the ball came down and the score. Beach
-- volleyball (2 v 2) by default, indoor (6 v 6) with `--param players=6`; the court, the net
-- and the players are in field.lua. The engine's Lua API: docs/lua-api.md; how a sport of
-- hitting is written: docs/writing-a-team-sport.md.
--
-- The rules: rally point scoring (every rally is a point, to whichever side did not lose it); a
-- side has three touches to send the ball back over, and nobody touches it twice in a row; a
-- touch at the net just after the other side's is a block, which indoors is not one of the
-- three. The side that wins a rally serves the next; indoors a side that wins the serve back
-- rotates, so the next player serves, and on the beach the two partners take turns. A set goes
-- to the first to `points` (21 on the beach, 25 indoors) two clear; the match to the first to
-- win `sets` of them (2, or 3 indoors). When time runs out first, the side ahead in sets wins,
-- else the one ahead in the set being played.
local two_teams = require "two_teams"

local per_team = param("players", 2)
local beach = per_team == 2
local set_points = param("points", beach and 21 or 25)
local sets_to_win = param("sets", beach and 2 or 3)
assert(set_points >= 1 and set_points % 1 == 0, "points must be a whole number >= 1")
assert(sets_to_win >= 1 and sets_to_win % 1 == 0, "sets must be a whole number >= 1")

local sport = {
  name = beach and "Quantum beach volleyball" or "Quantum volleyball",
  field = "field.lua",
  particles = 1000,
  match = { seconds = param("minutes", 20) * 60, start = "Blue's serve" },

  -- "A vs B vs out": a player's touch, which keeps the rally going, is likelier than the ball
  -- coming down, and the ball going out of the hall least likely of all.
  factors = { hit = 2, landing = 1, out = 0.5, field = 1 },

  -- A hit that says no speed (a rule's aim at a point) leaves at 9 m/s; an expert's attack twice
  -- that. Every touch scatters by 2 degrees and 3 % (a serve's length by twice that).
  throws = { speed = 9, spread = 2, speed_spread = 0.03 },

  teams = { blue = "Blue", red = "Red" },

  audio = {
    voice = "en-us", rate = 170,
    listener = { 0, -6 }, facing = { 0, 1 },  -- the referee's stand beside the net
    sounds = { landing = "wall.wav" },
    priorities = { landing = 3, out = 3, hit = 1, drop = 2 },
  },

  phrases = {
    to_serve = "Service {team}, {player}",
    serve = "{player} serves",
    dig = "{player} digs",
    set = "{player} sets",
    attack = "{player} attacks",
    block = "Blocked by {player}",
    in_court = "In, point {team}",
    outside = "Out, point {team}",
    four_touches = "Four touches, point {team}",
    fault = "Fault by {player}, point {team}",
    double_touch = "Double touch by {player}, point {team}",
    score = "{serving} to {receiving}",
    set_won = "Set {team}, {won} to {lost}",
    match_end = "{winner} wins the match, sets {sets_won} to {sets_lost}",
    draw = "It's a draw",
  },
}

-- What the rules remember across events and a reload: the set's points and the sets won, who
-- serves (a team, and each team's next server), and this rally's touches.
sport.state = {
  points = { blue = 0, red = 0 }, sets = { blue = 0, red = 0 },
  serving = "blue", server = { blue = 1, red = 0 },  -- Red's first serve is its first player's
  touching = nil, touches = 0, served = false, serve_only = false, blocker = nil,
}
local state = sport.state

-- The players of `team` in the field's order (indoors: the rotation's positions 1 to 6).
local function team_players(game, team)
  local out = {}
  for _, p in ipairs(game.field().players) do
    if p.team == team then out[#out + 1] = p.name end
  end
  return out
end

local function server_of(game, team)
  local players = team_players(game, team)
  return players[(state.server[team] - 1) % #players + 1]
end

local TOUCHES = { "dig", "set", "attack" }  -- a side's touches, as the announcer calls them

-- The net is the line x = 0 (field.lua); a touch within this of it, just after the other side's,
-- is a block.
local NET_REACH = 1.0

local function new_rally(game, delay)
  state.touching, state.touches, state.served, state.serve_only, state.blocker = nil, 0, false, false, nil
  game.respawn(state.serving == "blue" and "Blue's serve" or "Red's serve", delay)
end

-- The match's winner when it ends before a side has won its sets: ahead in sets, else ahead in
-- the set being played; "" for a draw.
local function leader()
  for _, key in ipairs({ "sets", "points" }) do
    if state[key].blue ~= state[key].red then return state[key].blue > state[key].red and "blue" or "red" end
  end
  return ""
end

-- A rally won by `team`: the point (the score keeps every point of the match), the set when it is
-- won, and the next serve, by the winner. A side that wins the serve back takes its next server.
local function point_to(game, team, phrase, values)
  values = values or {}
  values.team = game.team_name(team)
  game.say(phrase, values)
  game.award(team)
  state.points[team] = state.points[team] + 1
  if team ~= state.serving then
    state.serving = team
    state.server[team] = state.server[team] + 1
  end
  local other = two_teams.other(game, team)
  local won, lost = state.points[team], state.points[other]
  if won >= set_points and won - lost >= 2 then
    state.sets[team] = state.sets[team] + 1
    state.points = { blue = 0, red = 0 }
    game.say("set_won", { team = game.team_name(team), won = won, lost = lost })
    if state.sets[team] >= sets_to_win then return game.finish(team) end
  else
    game.say("score", { serving = state.points[team], receiving = state.points[other] })
  end
  new_rally(game, 2.0)
end

-- A ball coming down outside both courts is as unlikely as one leaving the hall: the engine
-- favours the rally over the error.
sport.modifiers = {
  function(fate)
    if fate.kind == "landing" and fate.actor == "" then return 0.5 end
  end,
}

sport.on = {
  -- A ball at a serve spot: only the server goes for it.
  drop = function(game)
    local server = server_of(game, state.serving)
    game.turn(server)
    game.say("to_serve", { player = server, team = game.team_name(state.serving) })
  end,

  hit = function(game, e)
    local other = two_teams.other(game, e.team)
    -- The first touch of a ball nobody has touched: the serve, which must go over as it is.
    local serve = not state.served and e.previous == ""
    state.served = true
    if serve then
      game.turn(nil)  -- from the serve on, anyone plays the ball
      state.touching, state.touches, state.serve_only = e.team, 3, true
      return game.say("serve", { player = e.actor })
    end
    if e.team ~= state.touching then
      -- The ball came over: a block when met at the net at once, else the side's first touch.
      local block = math.abs(e.x) < NET_REACH
      state.touching, state.touches, state.serve_only = e.team, (block and not beach) and 0 or 1, false
      state.blocker = block and e.actor or nil
      if block then return game.say("block", { player = e.actor }) end
      return game.say("dig", { player = e.actor })
    end
    -- A blocker may play the ball again at once; nobody else touches it twice in a row.
    if e.by == e.previous and e.actor ~= state.blocker then
      return point_to(game, other, "double_touch", { player = e.actor })
    end
    state.blocker = nil
    if state.touches >= 3 then
      -- A side's fourth touch, or a serve its own side touched.
      if state.serve_only then return point_to(game, other, "fault", { player = e.actor }) end
      return point_to(game, other, "four_touches")
    end
    state.touches = state.touches + 1
    game.say(TOUCHES[state.touches], { player = e.actor })
  end,

  -- Down in a court: the point to the side that did not defend it. Down outside both: the point
  -- against the side that touched it last.
  landing = function(game, e)
    if e.actor ~= "" then
      point_to(game, two_teams.other(game, e.team), "in_court")
    elseif e.by_team ~= "" then
      point_to(game, two_teams.other(game, e.by_team), "outside")
    else
      new_rally(game, 1.0)
    end
  end,

  -- Out of the hall: against the side that touched it last; a ball nobody touched is served again.
  out = function(game, e)
    if e.by_team ~= "" then point_to(game, two_teams.other(game, e.by_team), "outside")
    else new_rally(game, 1.0) end
  end,

  -- A serve nobody took, a ball lying where nobody plays it: served again.
  stalled = function(game)
    new_rally(game, 1.0)
  end,

  time_up = function(game)
    game.finish(leader())
  end,

  match_end = function(game, e)
    if e.team == "" then return game.say("draw") end
    local other = two_teams.other(game, e.team)
    game.say("match_end", { winner = game.team_name(e.team), sets_won = state.sets[e.team], sets_lost = state.sets[other] })
  end,
}

return sport

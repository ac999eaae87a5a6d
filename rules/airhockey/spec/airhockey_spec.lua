-- Rule specs for Quantum air hockey: run with `build/quantum test rules/airhockey`.
-- Field coordinates: Blue defends x = -1, Red defends x = +1; the table is 2 m x 1 m.
local SPORT = "airhockey"  -- by name: found here, in QUANTUM_PATH or among the engine's sports

local helpers = require "spec_helpers"
local first = helpers.first
local outcome = helpers.outcome

describe("Quantum air hockey", function()
  it("drops the puck in front of Blue's goal and says so", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    local events = s:run(0.1)
    assert.are.equal("drop", events[1].type)
    assert.are.equal("in front of Blue's goal", events[1].actor)
    assert.are.same({ "Puck to Blue" }, s:said())
  end)

  it("scores a clean shot at an empty goal most of the time", function()
    local goals = 0
    for seed = 1, 20 do
      local s = quantum.scenario(SPORT, { seed = seed })
      s:place("Red's mallet", 0.6, 0.4)  -- out of the way
      s:ball { x = 0.2, y = 0.0, vx = 3.0, vy = 0.0, turn = 0.02 }
      local goal = first(s:run(2.0, "goal"), "goal")
      if goal then
        goals = goals + 1
        assert.are.equal("Red's goal", goal.actor)
        assert.are.equal(1, s:score().blue)
      end
    end
    -- Straight down the middle of a 26 cm mouth: nothing but Brownian blur can miss.
    assert.is_true(goals >= 18, goals .. " of 20 shots scored")
  end)

  it("lets a mallet parked on the goal line intercept a straight shot", function()
    local intercepted = 0
    for seed = 1, 20 do
      local s = quantum.scenario(SPORT, { seed = seed })
      s:place("Red's mallet", 0.9, 0.0)
      s:ball { x = 0.0, y = 0.0, vx = 3.0, vy = 0.0, turn = 0.02, by = "Blue's mallet" }
      local events = s:run(2.0, "intercept")
      local e = first(events, "intercept")
      if e then
        intercepted = intercepted + 1
        assert.are.equal("Red's mallet", e.actor)
        assert.are.equal("intercepted by Red", s:said()[1])
      end
    end
    -- The mallet covers the shot's whole width: only Brownian blur could slip past it.
    assert.is_true(intercepted >= 18, intercepted .. " of 20 shots intercepted")
  end)

  local function outcomes_follow_the_tweaked_fates(opts, setup, category, classify)
    return helpers.outcomes_follow_the_tweaked_fates(SPORT, opts, setup, category, classify)
  end

  -- A shot at Red's goal with Red's mallet half in the way.
  local function half_blocked(s)
    s:place("Red's mallet", 0.88, 0.06)
    s:ball { x = 0.5, y = 0.0, vx = 2.5, vy = 0.0, turn = 0.1, count = 400 }
  end
  local shot_or_goal = helpers.shot_or_goal

  it("realizes a handicapped intercept as often as its factors compute", function()
    local opts = { particles = 400, handicaps = { ["Red's mallet"] = 4 } }
    local expected, newtonian = outcomes_follow_the_tweaked_fates(opts, half_blocked, shot_or_goal)
    assert.is_true(expected.shot > newtonian.shot + 0.1, "the handicap raises Red's intercept")
  end)

  it("realizes goals and intercepts as often as its fate factors compute", function()
    outcomes_follow_the_tweaked_fates({ particles = 400 }, half_blocked, shot_or_goal)
  end)

  it("makes an own goal as rare as its factor of 0.1 computes", function()
    -- Red just touched the puck, which heads for Red's own goal past Red's mallet.
    local function own_goal_chance(s)
      s:place("Red's mallet", 0.9, 0.1)
      s:ball { x = 0.5, y = 0.0, vx = 2.5, vy = 0.0, turn = 0.1, count = 400, by = "Red's mallet" }
    end
    local expected, newtonian = outcomes_follow_the_tweaked_fates({ particles = 400 }, own_goal_chance,
      shot_or_goal)
    assert.is_true(expected.own_goal < newtonian.own_goal / 4, "the own goal factor makes it rarer")
  end)

  it("hears the puck bounce off the wall it really bounced off, as often as the fates say", function()
    -- A fan toward Red's left corner: part of it meets the left wall first, part Red's end.
    local function corner(s)
      s:place("Red's mallet", 0.6, -0.4)  -- out of the way
      s:ball { x = 0.5, y = 0.2, vx = 2.2, vy = 1.2, turn = 0.25, count = 400, by = "Blue's mallet" }
    end
    local function first_wall(fate) return fate.path[1] or "no bounce" end
    local function first_heard(events)
      local e = events[1]
      if e and e.type == "bounce" then
        assert.are.equal("Blue's mallet", e.by)
        return e.actor
      end
      return "no bounce"
    end
    local expected = outcomes_follow_the_tweaked_fates({ particles = 400 }, corner, first_wall, first_heard)
    assert.is_true(expected["left wall"] > 0.1 and expected["Red's end"] > 0.1, "both walls are in play")
  end)

  it("stays silent about a bounce too soft to hear", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    s:ball { x = 0.0, y = 0.4, vx = 0.0, vy = 0.2, turn = 0.0 }  -- 0.2 m/s into the left wall
    local events = s:run(1.5)
    assert.is_nil(first(events, "bounce"))
    local loud = quantum.scenario(SPORT, { seed = 1 })
    loud:ball { x = 0.0, y = 0.4, vx = 0.0, vy = 0.6, turn = 0.0 }  -- 0.6 m/s: heard
    local bounce = first(loud:run(1.5), "bounce")
    assert.are.equal("left wall", bounce.actor)
    assert.is_true(math.abs(bounce.y - (0.5 - 0.0315)) < 0.02, "placed at the wall, y = " .. bounce.y)
  end)

  it("ends the match when a team reaches first_to", function()
    local s = quantum.scenario(SPORT, { seed = 3 })
    s:place("Red's mallet", 0.6, 0.4)
    for _ = 1, 7 do
      s:ball { x = 0.2, y = 0.0, vx = 3.0, vy = 0.0, turn = 0.0 }
      s:run(2.0, "goal")
    end
    local last = s:events()[#s:events()]
    assert.are.equal("match_end", last.type)
    assert.are.equal("blue", last.actor)
    assert.are.equal(7, s:score().blue)
    local said = s:said()
    assert.are.equal("Blue wins the match, 7 to 0", said[#said])
  end)
end)

-- Rule specs for Quantum team handball: run with `build/quantum test rules/handball`.
-- The default hall: 20 x 10 m, Blue defends x = -10, Red x = +10, goals 3 m wide, goal areas
-- of 6 m. Blue: Anna (goalkeeper), Ben, Clara; Red: Hugo (goalkeeper), Ida, Jonas.
local SPORT = "handball"  -- by name: found here, in QUANTUM_PATH or among the engine's sports

local helpers = require "spec_helpers"
local first = helpers.first
local outcome = helpers.outcome
local heard = helpers.heard

-- Everyone but the named players out of the way, by the far side line and away from any line
-- of play the specs use.
local function clear(s, except)
  local parked = {
    Anna = { -9, 0 }, Ben = { -6, -4.5 }, Clara = { -4, -4.5 },
    Hugo = { 9, 0 }, Ida = { 4, -4.5 }, Jonas = { 2, -4.5 },
  }
  for name, at in pairs(parked) do
    if not except[name] then s:place(name, at[1], at[2]) end
  end
end

describe("Quantum team handball", function()
  it("throws off from Blue's field player nearest the centre", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    local give = first(s:run(3.0, "give"), "give")
    assert.are.equal("Clara", give.actor)   -- at (-2, -2): nearer the centre than Ben at (-3, 2)
    assert.are.equal("Clara", s:holder())
    assert.are.equal("Throw-off, Clara", heard(s, "Throw-off"))
  end)

  it("catches a pass to an unmarked teammate", function()
    local caught = 0
    for seed = 1, 20 do
      local s = quantum.scenario(SPORT, { seed = seed })
      clear(s, { Ben = true, Clara = true })
      s:place("Ben", -3, 2)
      s:place("Clara", 2, 2)
      s:give("Ben")
      s:throw("Ben", 9, 0)
      local e = outcome(s:run(3.0, "pass"))
      if e and e.type == "pass" then
        caught = caught + 1
        assert.are.equal("Clara", e.actor)
        assert.are.equal("Ben", e.previous)
        assert.are.equal("Clara", s:holder())
        assert.are.equal("Ben to Clara", heard(s, "to Clara"))
      end
    end
    -- 5 m at 9 m/s, scattered by 3 degrees (26 cm at Clara): well within her reach every time.
    assert.are.equal(20, caught)
  end)

  it("intercepts a pass as often as the fates say", function()
    -- Ida stands just off the line of Ben's pass to Clara: part of the cloud passes within her
    -- reach first. Chi-square over 400 seeds, rejected below p = 0.001 (spec_helpers).
    local function marked(s)
      clear(s, { Ben = true, Clara = true, Ida = true })
      s:place("Ben", -4, 2)
      s:place("Ida", -1.5, 2.75)
      s:place("Clara", 2, 2)
      s:give("Ben")
      s:throw("Ben", 9, 0)
    end
    local function intercepted(fate) return fate.kind == "intercept" and "intercept" or "not intercepted" end
    local function first_catch(events)
      local e = outcome(events)
      return e and e.type == "intercept" and "intercept" or "not intercepted"
    end
    local expected, newtonian = helpers.outcomes_follow_the_tweaked_fates(SPORT, { particles = 400 }, marked,
      intercepted, first_catch)
    assert.is_true(expected.intercept > 0.1 and expected["not intercepted"] > 0.1, "both outcomes are in play")
    -- Passes weigh 6 and intercepts 4: the factors favour the pass over the intercept.
    assert.is_true(expected.intercept < newtonian.intercept, "the sport's factors favour the pass")
  end)

  it("gives the goalkeeper a longer reach than a field player", function()
    -- The same tight ball, passing 0.9 m from whoever stands at (0, 0): within Hugo's reach
    -- (0.9 m, and the ball's radius of 0.09 m), beyond Ida's (0.7 m). The fates say so before
    -- any draw; Brownian blur could still bring a few particles to Ida, so her side is checked on
    -- the fates alone.
    local function pass_by(who)
      local s = quantum.scenario(SPORT, { seed = 1 })
      clear(s, { Ben = true, [who] = true })
      s:place("Ben", -2, 0.9)
      s:place(who, 0, 0)
      s:ball { x = -1, y = 0.9, vx = 8, vy = 0, spread = 0.01, turn = 0, by = "Ben" }
      local caught = 0
      for _, f in ipairs(s:fates()) do
        if f.kind == "intercept" and f.actor == who then caught = caught + f.mass end
      end
      return s, caught
    end
    local keeper, keeper_caught = pass_by("Hugo")
    assert.is_true(keeper_caught > 0.99, "Hugo reaches " .. keeper_caught .. " of the ball")
    local saved = outcome(keeper:run(1.0, "intercept"))
    assert.are.equal("intercept", saved.type)
    assert.are.equal("Hugo", saved.actor)
    local _, field_caught = pass_by("Ida")
    assert.are.equal(0, field_caught)
  end)

  it("says a goalkeeper's catch is a save", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    clear(s, { Ben = true, Hugo = true })
    s:place("Ben", 3, 0)
    s:place("Hugo", 9, 0)
    s:give("Ben")
    s:throw("Ben", 10, 0)
    local e = outcome(s:run(2.0, "intercept"))
    assert.are.equal("intercept", e.type)
    assert.are.equal("Hugo", e.actor)
    assert.are.equal("Ben shoots", heard(s, "shoots"))
    assert.are.equal("Saved by Hugo", heard(s, "Saved"))
  end)

  it("scores past a goalkeeper who is out of the way, and Red throws off", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    clear(s, { Ben = true, Hugo = true })
    s:place("Ben", 3, 0.5)
    s:place("Hugo", 9, -3)
    s:give("Ben")
    s:throw("Ben", 10, 0)
    local goal = first(s:run(2.0, "goal"), "goal")
    assert.are.equal("red", goal.team)   -- the team whose goal it went into
    assert.are.equal(1, s:score().blue)
    assert.are.equal("Goal, Ben!", heard(s, "Goal"))
    assert.are.equal("1 to 0", heard(s, "1 to 0"))
    -- The throw-off goes to Red's field player nearest the centre after the throw-off delay.
    local give = first(s:run(3.0, "give"), "give")
    assert.are.equal("red", give.team)
    assert.are.equal("Throw-off, " .. give.actor, heard(s, "Throw-off, " .. give.actor))
  end)

  it("refuses a throw from inside the goal area by a field player: a free throw to the others", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    clear(s, { Ben = true })
    s:place("Ben", 6, 1)   -- 4 m from Red's goal mouth: inside its 6 m area
    s:give("Ben")
    s:throw("Ben", 10, 0)
    assert.are.equal("Ben stepped into the goal area", heard(s, "goal area"))
    local holder = s:holder()
    assert.is_not_nil(holder)
    local red = {}
    for _, p in ipairs(s:players()) do red[p.name] = p.team == "red" end
    assert.is_true(red[holder], holder .. " holds the ball")
    assert.is_not_nil(heard(s, "Free throw Red, " .. holder))
  end)

  it("never lets a field player catch inside a goal area", function()
    for seed = 1, 10 do
      local s = quantum.scenario(SPORT, { seed = seed })
      clear(s, { Ben = true, Clara = true })
      s:place("Ben", 0, 3)
      s:place("Clara", 6, 3.2)   -- in Red's goal area, right on the line of the pass
      s:give("Ben")
      s:throw("Ben", 9, 0)
      for _, e in ipairs(s:run(3.0)) do
        assert.is_false((e.type == "pass" or e.type == "catch") and e.actor == "Clara", "Clara caught in the area")
      end
    end
  end)

  it("plays a full court of 40 x 20 m, 7 a side, from the same files", function()
    local s = quantum.scenario(SPORT, { seed = 1, params = { length = 40, width = 20, players = 7 } })
    local names = {}
    for _, p in ipairs(s:players()) do names[#names + 1] = p.name end
    assert.are.equal(14, #names)
    assert.are.equal("Greta", names[7])   -- Blue's seventh
    s:place("Ben", -5, 6)
    s:place("Clara", 5, 6)
    for _, name in ipairs(names) do
      if name ~= "Ben" and name ~= "Clara" and name ~= "Anna" and name ~= "Hugo" then s:place(name, 0, -9) end
    end
    s:give("Ben")
    s:throw("Ben", 12, 0)
    local e = outcome(s:run(3.0, "pass"))
    assert.are.equal("pass", e.type)
    assert.are.equal("Clara", e.actor)
  end)

  it("gives a throw-in to the other team where the ball went out over a side line", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    clear(s, { Ben = true })
    s:place("Ben", -2, 3)
    s:give("Ben")
    s:throw("Ben", 0, 9)
    local out = first(s:run(2.0, "out"), "out")
    assert.is_not_nil(out)
    local holder = s:holder()
    assert.is_not_nil(holder)
    assert.are.equal("Out. Throw-in Red, " .. holder, heard(s, "Throw-in"))
  end)
end)

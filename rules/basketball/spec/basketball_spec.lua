-- Rule specs for Quantum basketball: run with `build/quantum test rules/basketball`.
-- The half court: x across (-7.5 to 7.5), y from the baseline (0) to the half-court line (14);
-- the ring's centre at (0, 1.575), 3.05 m up; the three-point arc 6.75 m from it. Home: Maya,
-- Noah, Omar; Away: Pia, Quinn, Rosa; each reaches 2.4 m standing.
local SPORT = "basketball"  -- by name: found here, in QUANTUM_PATH or among the engine's sports

local helpers = require "spec_helpers"
local outcome = helpers.outcome
local heard = helpers.heard

local G, HAND, RIM = 9.81, 2.4, 3.05
local RING = { 0, 1.575 }

-- Everyone but the named players by the half-court line, out of every line of play.
local function clear(s, except)
  local x = -6
  for _, name in ipairs({ "Maya", "Noah", "Omar", "Pia", "Quinn", "Rosa" }) do
    if not except[name] then s:place(name, x, 13.5) end
    x = x + 2.4
  end
end

-- The velocity of a shot by a player standing at (x, y) that drops through the ring's centre,
-- leaving the hand at `elevation` degrees. The ball leaves at arm's length toward the ring: the
-- player's reach, 0.5 m, plus the ball's radius.
local ARM = 0.5 + 0.12 + 0.001
local function shot_from(x, y, elevation)
  local dx, dy = RING[1] - x, RING[2] - y
  local full = math.sqrt(dx * dx + dy * dy)
  local d, a = full - ARM, math.rad(elevation or 52)
  local v = math.sqrt(G * d * d / (2 * math.cos(a) ^ 2 * (d * math.tan(a) - (RIM - HAND))))
  return v * math.cos(a) * dx / full, v * math.cos(a) * dy / full, v * math.sin(a)
end

-- Maya shoots from (x, y): the scene set up in s.
local function shoot(s, x, y, others)
  local keep = { Maya = true }
  for name in pairs(others or {}) do keep[name] = true end
  clear(s, keep)
  s:place("Maya", x, y)
  for name, at in pairs(others or {}) do s:place(name, at[1], at[2]) end
  s:give("Maya")
  s:throw("Maya", shot_from(x, y))
end

-- The tweaked and Newtonian probability of the fates of kind `kind` in s's current prediction.
local function chance(s, kind)
  local tweaked, newtonian = 0, 0
  for _, f in ipairs(s:fates()) do
    if f.kind == kind then tweaked, newtonian = tweaked + f.tweaked, newtonian + f.mass end
  end
  return tweaked, newtonian
end

describe("Quantum basketball", function()
  it("makes a shot from close likelier than one from downtown, and the factor favours baskets", function()
    local near = quantum.scenario(SPORT, { seed = 1 })
    shoot(near, 0, 4.5)
    local far = quantum.scenario(SPORT, { seed = 1 })
    shoot(far, 0, 9)
    local near_t, near_n = chance(near, "goal")
    local far_t, far_n = chance(far, "goal")
    assert.is_true(near_n > far_n, string.format("Newtonian: %.3f from 3 m, %.3f from 7.4 m", near_n, far_n))
    assert.is_true(near_t > near_n and far_t > far_n, "the goal factor of 3 raises both")
  end)

  it("realizes shots as often as the tweaked fates say", function()
    local setup = function(s)
      shoot(s, -3, 5.5, { Pia = { 1.2, 2.2 }, Noah = { -1.3, 2.4 } })
    end
    -- A basket, a rebound by Pia (an opponent's catch), or anything else (Noah's rebound, Maya's
    -- own, out, still bouncing after 3 s): each cell common enough for the chi-square.
    local category = function(f)
      return (f.kind == "goal" or f.kind == "intercept") and f.kind or "other"
    end
    local classify = function(events)
      local e = outcome(events)
      return e and (e.type == "goal" or e.type == "intercept") and e.type or "other"
    end
    local expected = helpers.outcomes_follow_the_tweaked_fates(SPORT, {}, setup, category, classify)
    assert.is_true(expected.goal > 0.05 and expected.intercept > 0.05, "baskets and rebounds both happen")
  end)

  it("blocks a shot only with a defender within reach and height", function()
    local blocks = function(at)
      local s = quantum.scenario(SPORT, { seed = 3 })
      shoot(s, 0, 6, { Pia = at })
      local p = 0
      for _, f in ipairs(s:fates()) do
        if f.kind == "intercept" and f.actor == "Pia" and f.via == "" then p = p + f.mass end
      end
      return p
    end
    -- Right in front of the shooter the ball is still below her reach; 2 m further it is over her.
    assert.is_true(blocks({ 0, 5.2 }) > 0.5)
    assert.are.equal(0, blocks({ 0, 3.4 }))
  end)

  it("gives the rebound to the player who is there", function()
    -- The chance that Quinn catches the ball after it came off the rim, the board or the floor.
    local rebounds = function(at)
      local s = quantum.scenario(SPORT, { seed = 1 })
      shoot(s, -3, 5.5, { Quinn = at })
      local p = 0
      for _, f in ipairs(s:fates()) do
        if f.kind == "intercept" and f.actor == "Quinn" and f.via ~= "" then p = p + f.mass end
      end
      return p
    end
    local under, away = rebounds({ 1.2, 2.2 }), rebounds({ 5, 10 })
    assert.is_true(under > 0.1, "under the basket, on the far side of the shot: " .. under)
    assert.is_true(away < 0.02, "by the arc, only a ball that rolled all the way: " .. away)
  end)

  it("counts three from beyond the arc and checks the ball after a basket", function()
    for seed = 1, 40 do
      local s = quantum.scenario(SPORT, { seed = seed })
      shoot(s, 0, 9)
      local e = outcome(s:run(3.0))
      if e and e.type == "goal" then
        assert.are.equal(3, s:score().home)
        assert.is_not_nil(heard(s, "Maya shoots from downtown"))
        assert.is_not_nil(heard(s, "and it's in!"))
        local give = helpers.first(s:run(3.0, "give"), "give")
        assert.are.equal("away", give.team)
        return
      end
    end
    error("no basket from downtown in 40 shots")
  end)
end)

-- rules/keepaway/spec/keepaway_spec.lua
-- Rule specs for keep-away: run with `build/quantum test rules/keepaway`.
local SPORT = "keepaway"  -- by name: found here, in QUANTUM_PATH or among the engine's sports

local helpers = require "spec_helpers"
local outcome = helpers.outcome

-- Ann and Bo 8 m apart along the court, Dee out of the way, Cy where the spec says.
local function scene(cy_x, cy_y)
  local s = quantum.scenario(SPORT)
  s:place("Ann", -4, 0)
  s:place("Bo", 4, 0)
  s:place("Dee", 0, 3.5)
  s:place("Cy", cy_x, cy_y)
  return s
end

describe("Keep-away", function()
  it("starts with the ball in Ann's hands", function()
    local s = quantum.scenario(SPORT)
    s:run(0.1)
    assert.are.equal("Ann", s:holder())
  end)

  it("catches a pass with Cy out of the way", function()
    local s = scene(0, -3.5)
    s:give("Ann")
    s:throw("Ann", 8, 0)   -- straight at Bo, 8 m away
    local e = outcome(s:run(3.0, "pass"))
    assert.are.equal("pass", e.type)
    assert.are.equal("Bo", e.actor)
    assert.are.equal("Ann", e.previous)
    assert.are.equal("Bo", s:holder())
    assert.are.same({ "Ann to Bo" }, e.said)
  end)

  it("gives the passers a point for five passes in a row", function()
    local s = scene(0, -3.5)
    local from, to = "Ann", "Bo"
    s:give(from)
    for _ = 1, 5 do
      s:throw(from, from == "Ann" and 8 or -8, 0)
      assert.are.equal("pass", outcome(s:run(3.0, "pass")).type)
      from, to = to, from
    end
    assert.are.equal(1, s:score().blue)
    local said = s:said()
    assert.are.equal("5 in a row, point to the passers", said[#said])
  end)

  it("gives Cy a point for a pass caught, and the ball back to the nearest passer", function()
    local s = scene(0, 0)
    s:give("Ann")
    s:throw("Ann", 8, 0)   -- Cy stands in the middle of the line
    local e = outcome(s:run(3.0, "intercept"))
    assert.are.equal("intercept", e.type)
    assert.are.equal("Cy", e.actor)
    assert.are.equal(1, s:score().red)
    local back = helpers.first(s:run(2.0, "give"), "give")
    assert.are.equal("blue", back.team)
  end)
end)

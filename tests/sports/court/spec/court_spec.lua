-- Rule specs of the landing court (tests/sports/court): where the ball comes down is a `landing`
-- event naming the court, and decides the point. Ada serves from Blue's court (x < 0); the net
-- stands along x = 0, Red's court ends at x = 6.
local SPORT = "tests/sports/court"
local first = require("spec_helpers").first

-- Ada, standing at (-3, 0), throws at (vx, 0, vz) over the net; returns the rally's landing.
local function serve(seed, vx, vz)
  local s = quantum.scenario(SPORT, { seed = seed })
  s:place("Ada", -3, 0)
  s:place("Bo", 9, 6)   -- out of the ball's way
  s:give("Ada")
  s:throw("Ada", vx, 0, vz)
  return s, first(s:run(3.0, "landing"), "landing")
end

describe("The landing court", function()
  it("tells where the ball comes down, and the team whose court it is loses the point", function()
    local s, landing = serve(1, 5, 4)
    assert.is_truthy(landing, "the serve came down")
    assert.are.equal("Red court", landing.actor)
    assert.are.equal("red", landing.team)
    assert.are.equal("Ada", landing.by)
    assert.is_true(landing.x > 0 and landing.x < 6, "in Red's court, at " .. landing.x)
    assert.are.same({ "In, Red court", "1 to 0" }, landing.said)
    assert.are.equal(1, s:score().blue)
  end)

  it("counts a ball landing beyond the lines against the thrower's team", function()
    local s, landing = serve(2, 10, 4)
    assert.is_truthy(landing)
    assert.are.equal("", landing.actor)
    assert.is_true(landing.x > 6, "beyond Red's end line, at " .. landing.x)
    assert.are.equal(1, s:score().red)
  end)

  it("shows the landing as a fate the rules weigh, with the court as its actor", function()
    local s = quantum.scenario(SPORT, { seed = 3 })
    s:place("Ada", -3, 0)
    s:place("Bo", 9, 6)
    s:give("Ada")
    s:throw("Ada", 5, 0, 4)
    local courts = {}
    for _, f in ipairs(s:fates()) do
      assert.are.equal("landing", f.kind)
      courts[f.actor] = (courts[f.actor] or 0) + f.mass
    end
    assert.is_true((courts["Red court"] or 0) > 0.5, "most of a serve at 5 m/s lands in Red's court")
  end)
end)

-- Rule specs of the rally court (tests/sports/rally): players who hit send the ball on at once,
-- where the rules aim them (game.hit) or a swing says (s:hit), and the rally is told as `hit`
-- events. Ada and Cy play Blue's court (x < 0), Bo and Di Red's; the net stands along x = 0.
local SPORT = "tests/sports/rally"
local first = require("spec_helpers").first

-- A ball dropping onto Ada at (-4, 0) from Blue's end of the court.
local function onto_ada(seed)
  local s = quantum.scenario(SPORT, { seed = seed })
  s:place("Ada", -4, 0)
  s:place("Cy", -6, 5)  -- the others out of the ball's way
  s:place("Bo", 6, 5)
  s:place("Di", 6, -5)
  s:run(0.1)            -- the drop: the rules aim everyone
  s:ball { x = -6, y = 0, z = 2, vx = 3, vy = 0, vz = 1 }
  return s
end

describe("The rally court", function()
  it("sends the ball on at once where the rules aim it, and names the hitter", function()
    local s = onto_ada(5)
    local hit = first(s:run(1.0, "hit"), "hit")
    assert.is_truthy(hit, "Ada met the ball")
    assert.are.equal("Ada", hit.actor)
    assert.are.equal("Ada", hit.by)
    assert.is_nil(s:holder(), "nobody holds a hit ball")
    assert.is_true(hit.vx > 0, "toward Red's court")
    assert.are.same({ "Ada" }, hit.said)
    local red = 0
    for _, f in ipairs(s:fates()) do
      if f.kind == "landing" and f.actor == "Red court" then red = red + f.mass end
    end
    assert.is_true(red > 0.7, "most of the lob comes down in Red's court, not " .. red)
    local landing = first(s:run(3.0, "landing"), "landing")
    assert.is_truthy(landing, "the hit came down")
    assert.are.equal("Red court", landing.actor)
    assert.are.equal(1, s:score().blue)
  end)

  it("lets a swing overrule the rules' aim: straight down into the hitter's own court", function()
    local s = onto_ada(2)
    s:hit("Ada", -1, 0, -2)
    local landing = first(s:run(3.0, "landing"), "landing")
    assert.is_truthy(landing)
    assert.are.equal("Blue court", landing.actor)
    assert.are.equal(1, s:score().red)
  end)

  it("shows a hit as a fate the rules weigh, with the hitter as its actor", function()
    local s = onto_ada(3)
    local hitters = {}
    for _, f in ipairs(s:fates()) do
      if f.kind == "hit" then hitters[f.actor] = (hitters[f.actor] or 0) + f.mass end
    end
    assert.is_true((hitters.Ada or 0) > 0.5, "most of the ball meets Ada")
  end)

  it("refuses a plan for a player who does not hit, and a bad aim", function()
    local s = onto_ada(4)
    assert.has_error(function() s:hit("Nobody", 1, 0) end)
    assert.has_error(function() s:hit("Ada", 0, 0, 0) end)
  end)
end)

-- Rule specs for Quantum air hockey: run with `build/quantum test rules/airhockey`.
-- Field coordinates: Blue defends x = -1, Red defends x = +1; the table is 2 m x 1 m.
local SPORT = "rules/airhockey"

-- The first event of `kind` in a list, or nil.
local function first(events, kind)
  for _, e in ipairs(events) do
    if e.type == kind then return e end
  end
end

describe("Quantum air hockey", function()
  it("drops the puck in front of Blue's goal and says so", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    local events = s:run(0.1)
    assert.are.equal("drop", events[1].type)
    assert.are.equal("in front of Blue's goal", events[1].actor)
    assert.are.same({ "The puck was dropped in front of Blue's goal" }, s:said())
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

  -- The sport's factors {goal 5, own goal 0.1, mallet 5, field 1} move what is realized: over
  -- 400 seeded fanned shots with Red's mallet partly in the way, the first outcome is a mallet
  -- touch far more often than its Newtonian probability. One-sided binomial z-test, rejected
  -- only when z < 3.09 (p < 0.001).
  it("realizes mallet touches more often than Newtonian odds, as its factors ask", function()
    local probe = quantum.scenario(SPORT, { seed = 1 })
    probe:place("Red's mallet", 0.8, 0.1)
    local shot = { x = 0.45, y = 0.0, vx = 2.5, vy = 0.0, turn = 0.6, count = 400 }
    probe:ball(shot)
    local tweaked, newtonian = 0, 0
    for _, f in ipairs(probe:fates()) do
      if f.kind == "body" then tweaked, newtonian = tweaked + f.tweaked, newtonian + f.mass end
    end
    assert.is_true(tweaked > newtonian + 0.1, string.format("the mallet factor raises the touch: %.3f -> %.3f", newtonian, tweaked))

    local n, touched = 400, 0
    for seed = 1, n do
      local s = quantum.scenario(SPORT, { seed = seed })
      s:place("Red's mallet", 0.8, 0.1)
      s:ball(shot)
      local e = s:run(3.0, "shot")[1]
      if e and e.type == "shot" then touched = touched + 1 end
    end
    local z = (touched - n * newtonian) / math.sqrt(n * newtonian * (1 - newtonian))
    assert.is_true(z > 3.09, string.format("%d of %d touched; Newtonian %.3f, tweaked %.3f, z = %.2f",
      touched, n, newtonian, tweaked, z))
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

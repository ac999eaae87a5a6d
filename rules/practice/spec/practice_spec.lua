-- Rule specs for shooting practice: run with `build/quantum test rules/practice`.
local SPORT = "practice"  -- by name: found here, in QUANTUM_PATH or among the engine's sports

local count = require("spec_helpers").count

describe("Shooting practice", function()
  it("counts a strike through the puck as a shot, and a shot into the goal as a goal", function()
    local scored = 0
    for seed = 1, 10 do
      local s = quantum.scenario(SPORT, { seed = seed })
      s:place("Shooter", -0.3, 0.0)
      s:run(0.05)                              -- the puck drops at (-0.1, 0)
      s:move("Shooter", 0.05, 0.0, 0.15)       -- strike straight at the goal
      local events = s:run(2.0, "goal")
      local shots = count(events, "shot")
      assert.is_true(shots >= 1, "seed " .. seed)
      assert.are.equal("Shot 1", s:said()[2])
      if count(events, "goal") == 1 then
        scored = scored + 1
        local said = s:said()
        assert.are.equal("Goal! 1 from " .. shots, said[#said])  -- a rebound may be shot again first
        assert.are.equal(1, s:score().blue)
      end
    end
    assert.is_true(scored >= 7, scored .. " of 10 straight shots scored")
  end)

  it("gives the goal seeker for every third goal", function()
    local s = quantum.scenario(SPORT, { seed = 3 })
    local goals = 0
    for _ = 1, 3 do
      s:place("Shooter", -0.3, 0.0)
      s:run(goals == 0 and 0.05 or 1.05)        -- the puck drops at (-0.1, 0), 1 s after a goal
      s:move("Shooter", 0.05, 0.0, 0.15)        -- strike straight at the goal
      goals = goals + count(s:run(2.0, "goal"), "goal")
    end
    local granted = 0
    for _, e in ipairs(s:events()) do
      if e.type == "powerup" then
        granted = granted + 1
        assert.are.equal("goal_seeker", e.powerup)
        assert.are.equal("Shooter", e.actor)
      end
    end
    assert.are.equal(3, goals, "straight shots; this seed scores all three")
    assert.are.equal(1, granted)
    local said = table.concat(s:said(), " | ")
    assert.is_truthy(said:find("Hat trick! Your shots seek the goal", 1, true), said)
  end)

  it("tells the tally when time is up, and ends the session", function()
    local s = quantum.scenario(SPORT, { seed = 2 })
    s:place("Shooter", -0.45, 0.4)  -- in a corner, never touching the puck
    s:run(61.0)
    local said = s:said()
    assert.are.equal("Time! 0 goals from 0 shots", said[#said])
    local events = s:events()
    assert.are.equal("match_end", events[#events].type)
  end)
end)

-- Rule specs of doubles air hockey (tests/sports/doubles): passes named by the previous toucher,
-- the engine's power-ups found from a sport outside rules/, team names in their phrases, each
-- event with its own phrases, and the sport's own Lua module.
local SPORT = "tests/sports/doubles"

local first = require("spec_helpers").first

describe("Doubles air hockey", function()
  it("calls a pass between teammates and gives the receiver the engine's attract power-up", function()
    local passes = 0
    for seed = 1, 10 do
      local s = quantum.scenario(SPORT, { seed = seed })
      s:run(0.05)
      -- From Blue's back mallet toward Blue's forward.
      s:ball { x = -0.7, y = 0.05, vx = 2.0, vy = -1.4, turn = 0.02, by = "Blue back" }
      local events = s:run(1.0, "powerup")
      local pass = first(events, "shot")
      if pass and pass.actor == "Blue forward" then
        passes = passes + 1
        assert.are.equal("Blue back", pass.previous)
        assert.are.equal("blue", pass.previous_team)
        -- The pass's own phrase; the power-up it set off keeps its own.
        assert.are.same({ "Blue back to Blue forward" }, pass.said)
        local granted = first(events, "powerup")
        assert.are.equal("attract", granted.powerup)
        assert.are.same({ "Blue attracts the puck" }, granted.said)  -- the team's name, not "blue"
      end
    end
    assert.is_true(passes >= 8, passes .. " of 10 passes reached the forward")
  end)

  it("formats a shot's speed with one decimal", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    s:run(0.05)
    s:ball { x = -0.2, y = -0.2, vx = -1.5, vy = 0, turn = 0.02 }
    local shot = first(s:run(1.0, "shot"), "shot")
    assert.is_truthy(shot)
    assert.is_truthy(shot.said[1]:match("^Blue forward shoots, %d%.%d$"), shot.said[1])
  end)
end)

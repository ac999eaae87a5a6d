-- Rule specs of the wall game (tests/sports/wall): timers, dead balls, turns for simulated
-- players, the previous toucher and formatted phrases. The court: front wall at x = +1, open
-- back line at x = -1; Blue serves from (-0.3, 0.25).
local SPORT = "tests/sports/wall"

local function types(events)
  local out = {}
  for _, e in ipairs(events) do out[#out + 1] = e.type end
  return table.concat(out, " ")
end

local first = require("spec_helpers").first

-- Blue serves: a strike through the dropped ball toward the front wall. Returns the shot.
local function serve(s)
  s:place("Blue", -0.55, 0.25)
  s:run(0.05)
  s:move("Blue", -0.15, 0.25, 0.5)
  local shot = first(s:run(0.5, "shot"), "shot")
  assert.is_truthy(shot, "Blue served")
  s:move("Blue", -0.7, 0.55, 0.3)  -- and steps out of the way
  return shot
end

describe("The wall game", function()
  it("gives the turn to the other player after a hit, for the simulated players to hear", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    local before = s:players()
    assert.is_true(before[1].turn and before[2].turn, "everyone's turn before the first drop")
    serve(s)
    local players = s:players()
    assert.are.equal("Blue", players[1].name)
    assert.is_false(players[1].turn)
    assert.is_true(players[2].turn)
  end)

  it("ends a rally nobody plays on with a timer: the ball is dead and nothing more is heard", function()
    local s = quantum.scenario(SPORT, { seed = 2 })
    local shot = serve(s)
    -- A slow ball that takes longer than the rule's three seconds to come back.
    s:ball { x = 0.5, y = 0.3, vx = 0.3, vy = 0, by = "Blue" }
    local events = s:run(6, "drop")
    local dead = first(events, "dead")
    assert.is_truthy(dead, types(events))
    assert.is_true(math.abs(dead.t - (shot.t + 3)) < 0.05, "dead at " .. dead.t .. ", the serve at " .. shot.t)
    for _, e in ipairs(events) do
      assert.is_true(e.t <= dead.t or e.type == "drop", "after the dead ball: " .. e.type .. " at " .. e.t)
    end
    assert.are.equal(1, s:score().blue)
    assert.are.same({ "The ball is dead" }, dead.said)
    local said = table.concat(s:said(), " | ")
    assert.is_truthy(said:find("Point Blue: no return", 1, true), said)
  end)

  it("names the player who hit before in the receiver's hit, and formats the speed", function()
    local s = quantum.scenario(SPORT, { seed = 3 })
    serve(s)
    s:place("Red", -0.3, 0.0)
    s:ball { x = 0.7, y = 0.0, vx = 1.0, vy = 0, turn = 0.01, by = "Blue" }
    local events = s:run(4, "intercept")
    local front = first(events, "bounce")
    assert.are.equal("front wall", front.actor)
    assert.is_truthy(front.said[1]:match("^Front wall, %d+%.%d metres a second$"), front.said[1])
    local back = first(events, "intercept")
    assert.is_truthy(back, types(events))
    assert.are.equal("Red", back.actor)
    assert.are.equal("Blue", back.previous)
    assert.are.equal("blue", back.previous_team)
    assert.are.same({ "Red" }, back.said)
  end)

  it("gives the point away for a hit out of turn", function()
    local s = quantum.scenario(SPORT, { seed = 4 })
    serve(s)
    s:place("Blue", -0.3, 0.0)
    s:ball { x = 0.7, y = 0.0, vx = 1.0, vy = 0, turn = 0.01, by = "Blue" }
    local events = s:run(4, "dead")
    local again = first(events, "shot")
    assert.is_truthy(again, types(events))
    assert.are.equal("Blue", again.previous)  -- a second touch of the same player
    assert.are.same({ "Point Red: out of turn", "0 to 1" }, again.said)
    assert.are.equal(1, s:score().red)
    -- The serve's timer was cancelled with the point: nothing dies three seconds after it.
    s:run(4)
    assert.are.equal(0, s:score().blue)
    assert.is_falsy(table.concat(s:said(), " | "):find("no return", 1, true))
  end)
end)

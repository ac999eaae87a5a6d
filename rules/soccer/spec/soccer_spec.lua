-- Rule specs for Quantum soccer: run with `build/quantum test rules/soccer`.
-- The default pitch: 30 x 18 m, Blue defends x = -15, Red x = +15, goals 3.66 m wide, goal
-- areas of 5 m. Blue: Alba (goalkeeper), Bruno, Carla, Dario, Elena; Red: Hector (goalkeeper),
-- Iris, Jorge, Katia, Luca. The spec's players are people: they stand where they are placed.
local SPORT = "soccer"  -- by name: found here, in QUANTUM_PATH or among the engine's sports

local helpers = require "spec_helpers"
local first = helpers.first
local heard = helpers.heard

-- Everyone but the named players out of the way: the keepers in their goals, the others along
-- the side lines, away from every line of play the specs use.
local function clear(s, except)
  local parked = {
    Alba = { -14, 0 }, Bruno = { -12, -8.5 }, Carla = { -9, -8.5 }, Dario = { -6, -8.5 }, Elena = { -3, -8.5 },
    Hector = { 14, 0 }, Iris = { 3, -8.5 }, Jorge = { 6, -8.5 }, Katia = { 9, -8.5 }, Luca = { 12, -8.5 },
  }
  for name, at in pairs(parked) do
    if not except[name] then s:place(name, at[1], at[2]) end
  end
end

local function said_all(events)
  local all = {}
  for _, e in ipairs(events) do
    for _, p in ipairs(e.said) do all[#all + 1] = p end
  end
  return table.concat(all, " / ")
end

describe("Quantum soccer", function()
  it("kicks off from the centre spot once Blue's nearest outfield player stands there, everyone in formation", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    local events = s:run(2.5, "give")
    assert.is_nil(first(events, "give"), "no kick-off before the taker is at the centre spot")
    local said = said_all(events)
    assert.is_truthy(said:find("Carla, to centre spot", 1, true), said)   -- (-3.75, 1.6): the nearest
    assert.is_truthy(said:find("Iris, to 9.0, -4.7", 1, true), said)       -- back to her own place
    s:place("Carla", 0.2, 0)
    local give = first(s:run(1.5, "give"), "give")
    assert.is_truthy(give)
    assert.are.equal("Carla", give.actor)
    assert.are.same({ "Kick-off, Carla" }, give.said)
  end)

  it("gives a kick-in to the other team's nearest outfield player where the ball crossed the side line", function()
    local s = quantum.scenario(SPORT, { seed = 2 })
    clear(s, { Carla = true, Jorge = true })
    s:place("Carla", 0, 6)
    s:place("Jorge", 3, 6)
    s:give("Carla")
    s:kick("Carla", 0, 9)
    local out = first(s:run(2.0, "out"), "out")
    assert.is_truthy(out)
    assert.is_truthy(heard(s, "Jorge, to"), "Jorge is sent to the line")
    s:place("Jorge", out.x, 8.5)
    local give = first(s:run(2.0, "give"), "give")
    assert.is_truthy(give)
    assert.are.equal("Jorge", give.actor)
    assert.are.same({ "Kick-in Red, Jorge" }, give.said)
    assert.is_true(math.abs(give.y - 8.5) < 0.01, "at the line, half a metre in: y " .. give.y)
  end)

  it("gives a goal kick to the keeper when the attackers put the ball over the goal line", function()
    local s = quantum.scenario(SPORT, { seed = 3 })
    clear(s, { Carla = true })
    s:place("Carla", 10, 6)
    s:give("Carla")
    s:kick("Carla", 8, 3)   -- wide of the goal: over Red's line at y = 7.9
    local out = first(s:run(2.0, "out"), "out")
    assert.is_truthy(out)
    assert.is_true(out.x > 14.9, "over the goal line: x " .. out.x)
    local give = first(s:run(2.5, "give"), "give")
    assert.is_truthy(give, "Hector stands within a metre of his goal kick's place")
    assert.are.equal("Hector", give.actor)
    assert.are.same({ "Goal kick, Hector" }, give.said)
  end)

  it("gives a corner to the attackers when a defender put the ball over its own goal line", function()
    local s = quantum.scenario(SPORT, { seed = 4 })
    clear(s, { Katia = true, Carla = true })
    s:place("Katia", 10, 4)
    s:place("Carla", 8, 7)
    s:give("Katia")
    s:kick("Katia", 8, 2)   -- over her own goal line at y = 5.3, on the left as Blue attacks
    assert.is_truthy(first(s:run(2.0, "out"), "out"))
    assert.is_truthy(heard(s, "Carla, to Red's right corner"), "Carla is sent to the corner")
    s:place("Carla", 14.5, 8.5)
    local give = first(s:run(2.5, "give"), "give")
    assert.is_truthy(give)
    assert.are.equal("Carla", give.actor)
    assert.are.same({ "Corner Blue, Carla" }, give.said)
  end)

  it("scores a goal, says the score and has the team that conceded kick off", function()
    local s = quantum.scenario(SPORT, { seed = 5 })
    clear(s, { Carla = true, Hector = true })
    s:place("Hector", 13.5, 4.5)   -- in his area, beside the goal
    s:place("Carla", 9, 0)
    s:give("Carla")
    s:kick("Carla", 12, 0)
    local goal = first(s:run(2.0, "goal"), "goal")
    assert.is_truthy(goal)
    local said = table.concat(goal.said, " / ")
    assert.is_truthy(said:find("^Goal, Carla! / 1 to 0"), said)
    assert.is_truthy(said:find("to centre spot", 1, true), said)
    assert.are.same({ blue = 1, red = 0 }, s:score())
    -- Red's outfield player nearest the centre takes it: Iris, parked at (3, -8.5).
    s:place("Iris", 0.2, 0)
    local give = first(s:run(2.0, "give"), "give")
    assert.is_truthy(give)
    assert.are.same({ "Kick-off, Iris" }, give.said)
  end)

  -- A fate that is the ball's only one cannot be ruled out (docs/lua-api.md: factors never leave
  -- the ball nowhere), so each player stands half in the kick's path: the rule shows in the fates.
  local function ruled_out(fates, name)
    for _, f in ipairs(fates) do
      if f.actor == name then return f.mass > 0.1 and f.tweaked == 0 end
    end
    return false
  end

  it("lets the keeper save a shot in his area, and no field player take the ball in a goal area", function()
    local s = quantum.scenario(SPORT, { seed = 6 })
    clear(s, { Carla = true, Jorge = true, Hector = true })
    s:place("Jorge", 12, 0.7)   -- a defender inside his own goal area, half in the shot's path
    s:place("Hector", 14, 0)
    s:place("Carla", 8, 0)
    s:give("Carla")
    s:kick("Carla", 12, 0)
    assert.is_true(ruled_out(s:fates(), "Jorge"), "Jorge may not play the ball in the area")
    local save = first(s:run(2.0, "intercept"), "intercept")
    assert.is_truthy(save, "the keeper behind him got it")
    assert.are.equal("Hector", save.actor)
    assert.are.same({ "Saved by Hector" }, save.said)
  end)

  it("keeps the goalkeeper from handling outside his area", function()
    local s = quantum.scenario(SPORT, { seed = 7 })
    clear(s, { Carla = true, Hector = true, Luca = true })
    s:place("Hector", 5, 0.7)   -- out of his area, half in the pass's path
    s:place("Luca", 9, 0)
    s:place("Carla", 0, 0)
    s:give("Carla")
    s:kick("Carla", 8, 0)
    assert.is_true(ruled_out(s:fates(), "Hector"), "Hector may not handle out here")
    local e = first(s:run(3.0, "intercept"), "intercept")
    assert.is_true(e == nil or e.actor == "Luca", "Luca's, or nobody's")
  end)

  it("tells a tackle: an opponent whose foot reaches the holder wins the ball", function()
    local s = quantum.scenario(SPORT, { seed = 8 })
    clear(s, { Carla = true, Jorge = true })
    s:place("Carla", 0, 0)
    s:place("Jorge", 1.0, 0)   -- bodies of 0.6 m: touching
    s:give("Carla")
    local tackle = first(s:run(20.0, "tackle"), "tackle")
    assert.is_truthy(tackle, "at 0.35 a second (x 1.5), 20 s give a tackle all but surely")
    assert.are.equal("Jorge", tackle.actor)
    assert.are.equal("Carla", tackle.previous)
    assert.are.same({ "Jorge wins it off Carla" }, tackle.said)
    assert.are.equal("Jorge", s:holder())
  end)

  it("calls half time at half the match's real length, and Red kicks off the second half", function()
    local s = quantum.scenario(SPORT, { seed = 9, seconds = 60 })
    s:run(0.1)
    s:place("Carla", 0, 0)
    assert.is_truthy(first(s:run(2.0, "give"), "give"), "Blue kicked off")
    local function half_time_called() return table.concat(s:said(), " / "):find("Half time, %d+ to %d+") ~= nil end
    s:run(29.8 - s:time())
    assert.is_false(half_time_called(), "not before 30 s")
    s:run(0.4)
    assert.is_true(half_time_called(), "at 30 s")
    assert.is_truthy(heard(s, "Jorge, to centre spot"), "Red's nearest outfield player kicks off")
  end)
end)

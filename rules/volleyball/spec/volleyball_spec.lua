-- Rule specs for Quantum volleyball: run with `build/quantum test rules/volleyball`.
-- Beach by default: 8 x 8 m a side, the net along x = 0 (Blue's court x < 0); Blue: Ana, Bea;
-- Red: Holly, Iris; serves from (-9, 0) and (9, 0). Indoors (params players = 6): 9 x 9 m a side;
-- Blue: Ana, Bea, Carla, Dora, Elsa, Fay (Carla in the front middle); Red: Holly, Iris, Jade,
-- Kira, Lucy, Mia. The spec's players are people: they stand where they are placed.
local SPORT = "volleyball"  -- by name: found here, in QUANTUM_PATH or among the engine's sports

local helpers = require "spec_helpers"
local first = helpers.first
local heard = helpers.heard

local function player(s, name)
  for _, p in ipairs(s:players()) do
    if p.name == name then return p end
  end
end

-- A ball dropping from 2.5 m at (x, y), last touched by `by`.
local function down_at(s, x, y, by)
  s:ball { x = x, y = y, z = 2.5, vx = 0, vy = 0, vz = 0, by = by }
  return first(s:run(2.0, "landing"), "landing")
end

-- Runs until the next hit, which must be by `who`, and returns it.
local function hit_by(s, who)
  local hit = first(s:run(2.0, "hit"), "hit")
  assert.is_truthy(hit, who .. " meets the ball")
  assert.are.equal(who, hit.actor)
  return hit
end

describe("Quantum volleyball", function()
  it("asks Blue's first server to serve, and only her", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    local drop = first(s:run(0.2), "drop")
    assert.is_truthy(drop)
    assert.are.equal("Blue's serve", drop.actor)
    assert.are.same({ "Service Blue, Ana" }, drop.said)
    assert.is_true(player(s, "Ana").turn)
    assert.is_false(player(s, "Bea").turn)
    assert.is_false(player(s, "Holly").turn)
  end)

  it("gives the point to the side that did not defend the court the ball came down in; its server serves again", function()
    local s = quantum.scenario(SPORT, { seed = 2 })
    s:run(0.2)
    local landing = down_at(s, 4, 0, "Ana")
    assert.is_truthy(landing)
    assert.are.equal("Red court", landing.actor)
    assert.are.same({ "In, point Blue", "1 to 0" }, landing.said)
    assert.are.equal(1, s:score().blue)
    local drop = first(s:run(3.0, "drop"), "drop")
    assert.are.equal("Blue's serve", drop.actor)
    assert.are.same({ "Service Blue, Ana" }, drop.said)
  end)

  it("gives a ball down outside both courts to the side that did not touch it last, who serves next", function()
    local s = quantum.scenario(SPORT, { seed = 3 })
    s:run(0.2)
    local landing = down_at(s, 11, 0, "Ana")
    assert.is_truthy(landing)
    assert.are.equal("", landing.actor)
    assert.are.same({ "Out, point Red", "1 to 0" }, landing.said)
    local drop = first(s:run(3.0, "drop"), "drop")
    assert.are.equal("Red's serve", drop.actor)
    assert.are.same({ "Service Red, Holly" }, drop.said)
  end)

  it("lets the partners take turns to serve each time their side wins the serve back", function()
    local s = quantum.scenario(SPORT, { seed = 4 })
    s:run(0.2)
    down_at(s, -4, 0, "Holly")  -- Red's point: Holly serves
    down_at(s, 4, 0, "Iris")   -- Blue's point: Blue's next server
    local drop = first(s:run(3.0, "drop"), "drop")
    assert.are.same({ "Service Blue, Bea" }, drop.said)
  end)

  it("calls a serve, then a side's three touches, and gives the point away at its fourth", function()
    local s = quantum.scenario(SPORT, { seed = 5 })
    s:run(0.2)
    s:place("Holly", 6, 3)
    s:place("Iris", 6, -3)
    s:place("Ana", -6, 0)
    s:place("Bea", -4.5, 0)
    -- Ana and Bea, 1.5 m apart, lob the ball to each other: up and 1.6 m along.
    s:ball { x = -6, y = 0, z = 4, vx = 0, vy = 0, vz = 0, by = "Holly" }
    local names = { "Ana", "Bea", "Ana" }
    local calls = { "Ana digs", "Bea sets", "Ana attacks" }
    for i, who in ipairs(names) do
      s:hit(who, who == "Ana" and 1.3 or -1.3, 0, 6)
      assert.are.same({ calls[i] }, hit_by(s, who).said)
    end
    s:hit("Bea", -1.3, 0, 6)
    assert.are.same({ "Four touches, point Red", "1 to 0" }, hit_by(s, "Bea").said)
    assert.are.equal(1, s:score().red)
  end)

  it("gives the point away when a player touches the ball twice in a row", function()
    local s = quantum.scenario(SPORT, { seed = 6 })
    s:run(0.2)
    s:place("Ana", -6, 0)
    s:ball { x = -6, y = 0, z = 4, vx = 0, vy = 0, vz = 0, by = "Holly" }
    s:hit("Ana", 0, 0, 6)  -- straight up: it comes back down on her
    assert.are.same({ "Ana digs" }, hit_by(s, "Ana").said)
    assert.are.same({ "Double touch by Ana, point Red", "1 to 0" }, hit_by(s, "Ana").said)
  end)

  it("makes the serve the server's side's only touch", function()
    local s = quantum.scenario(SPORT, { seed = 7 })
    s:run(0.2)
    s:place("Ana", -6, 0)
    s:place("Bea", -4.5, 0)
    s:ball { x = -6, y = 0, z = 4, vx = 0, vy = 0, vz = 0 }  -- nobody's ball: Ana's touch serves it
    s:hit("Ana", 1.3, 0, 6)
    assert.are.same({ "Ana serves" }, hit_by(s, "Ana").said)
    assert.are.same({ "Fault by Bea, point Red", "1 to 0" }, hit_by(s, "Bea").said)
  end)

  it("indoors, lets a block at the net not count as a touch, and the blocker play the ball again", function()
    local s = quantum.scenario(SPORT, { seed = 8, params = { players = 6 } })
    s:run(0.2)
    s:place("Carla", -0.7, 0)
    s:place("Jade", 3, 0)
    s:jump("Carla", 0.6, 1.0)
    s:ball { x = 0.8, y = 0, z = 2.6, vx = -4, vy = 0, vz = 0, by = "Jade" }
    s:hit("Carla", -0.6, 0, 6)
    assert.are.same({ "Blocked by Carla" }, hit_by(s, "Carla").said)
    assert.are.same({ "Carla digs" }, hit_by(s, "Carla").said)
  end)

  it("wins a set at its points with two clear, and the match at its sets", function()
    local s = quantum.scenario(SPORT, { seed = 9, params = { points = 3, sets = 1 } })
    s:run(0.2)
    down_at(s, -4, 0, "Holly")
    down_at(s, -4, 0, "Holly")
    for _ = 1, 3 do down_at(s, 4, 0, "Ana") end
    assert.is_truthy(heard(s, "3 to 2"), "3 to 2 is no set")
    local landing = down_at(s, 4, 0, "Ana")
    assert.are.same({ "In, point Blue", "Set Blue, 4 to 2" }, landing.said)
    local events = s:events()
    local ended = first(events, "match_end")
    assert.is_truthy(ended, "one set to win: the match is over")
    assert.are.same({ "Blue wins the match, sets 1 to 0" }, ended.said)
  end)

  it("gives the match to the side ahead in the set being played when time runs out", function()
    local s = quantum.scenario(SPORT, { seed = 10, seconds = 6 })
    s:run(0.2)
    down_at(s, -4, 0, "Holly")
    s:run(6)
    local ended = first(s:events(), "match_end")
    assert.is_truthy(ended)
    assert.are.equal("red", ended.team)
    assert.are.same({ "Red wins the match, sets 0 to 0" }, ended.said)
  end)
end)

-- The rule-spec API itself (quantum.scenario and its methods): a typo in a spec is an error that
-- names it, never a silent default.
local SPORT = "tests/sports/wall"

local function error_of(f)
  local ok, err = pcall(f)
  assert.is_false(ok, "no error")
  return tostring(err)
end

local function has(text, part)
  assert.is_truthy(text:find(part, 1, true), text)
end

describe("The scenario API", function()
  it("names an unknown option of a scenario with the nearest known one", function()
    local err = error_of(function() quantum.scenario(SPORT, { sead = 3 }) end)
    has(err, "quantum.scenario")
    has(err, "unknown key 'sead' (did you mean 'seed'?")
    has(error_of(function() quantum.scenario(SPORT, { handicaps = { Bleu = 2 } }) end), "did you mean 'Blue'?")
  end)

  it("refuses a seed, a cloud or a count it cannot honour, naming the option", function()
    has(error_of(function() quantum.scenario(SPORT, { seed = -1 }) end), "seed: expected a whole number from 0 to 2^64 - 1, got -1")
    has(error_of(function() quantum.scenario(SPORT, { seed = 2^64 }) end), "seed: expected a whole number")
    has(error_of(function() quantum.scenario(SPORT, { seed = 0/0 }) end), "seed: expected a whole number")
    has(error_of(function() quantum.scenario(SPORT, { particles = 1e300 }) end), "particles: expected a whole number")
    local s = quantum.scenario(SPORT, { seed = 2^53 })
    has(error_of(function() s:ball { x = 0, y = 0, count = 2.5 } end), "count: expected a whole number from 1 to 10000000")
    -- Beyond a float's range is refused, not narrowed to an infinity the cloud cannot hold.
    has(error_of(function() s:ball { x = 1e300, y = 0 } end), "scenario:ball")
    has(error_of(function() s:place("Red", 1e300, 0) end), "is not finite")
  end)

  it("names an unknown key of a ball", function()
    local s = quantum.scenario(SPORT)
    local err = error_of(function() s:ball { x = 0, y = 0, cout = 3 } end)
    has(err, "scenario_api_spec.lua:")  -- the spec's own line
    has(err, "scenario:ball")
    has(err, "unknown key 'cout' (did you mean 'count'?")
  end)

  it("names a misspelled event type to stop at", function()
    local s = quantum.scenario(SPORT)
    has(error_of(function() s:run(1, "gaol") end), "unknown event type 'gaol' (did you mean 'goal'?")
  end)

  it("leaves a player where it was when a place is refused", function()
    local s = quantum.scenario(SPORT)
    s:place("Red", -0.5, -0.2)
    has(error_of(function() s:place("Red", 50, 0) end), "far outside the field")
    local function red_is_still_there()
      local red = s:players()[2]
      assert.is_true(math.abs(red.x + 0.5) < 1e-6 and math.abs(red.y + 0.2) < 1e-6, red.x .. ", " .. red.y)
    end
    red_is_still_there()
    s:run(0.1)  -- and the match runs on with it there
    red_is_still_there()
  end)

  it("gives every event the phrases its own handlers said", function()
    local s = quantum.scenario(SPORT)
    local events = s:run(0.1)
    assert.are.equal("drop", events[1].type)
    assert.are.same({ "Blue to serve" }, events[1].said)
  end)

  it("reads each player's skill: none for the spec's own, the one its options give", function()
    local s = quantum.scenario(SPORT)
    assert.is_nil(s:players()[1].skill)
    s = quantum.scenario(SPORT, { skills = { Red = 0.3 } })
    assert.is_nil(s:players()[1].skill)
    assert.are.equal(0.3, s:players()[2].skill)
    has(error_of(function() quantum.scenario(SPORT, { skills = { Red = 1.5 } }) end), "Red's skill must be in [0, 1], got 1.5")
    has(error_of(function() quantum.scenario(SPORT, { skills = { Redd = 0.5 } }) end), "did you mean 'Red'?")
  end)

  it("refuses a height, a vertical speed or a jump on a flat field", function()
    local s = quantum.scenario(SPORT)
    has(error_of(function() s:ball { x = 0, y = 0, z = 1 } end), "z, vz: ")
    has(error_of(function() s:ball { x = 0, y = 0, vz = 1 } end), "is flat (no gravity): a ball has no height there")
    has(error_of(function() s:jump("Red") end), "jumping needs a field with height")
    assert.is_nil(s:players()[2].reach_height)
  end)

  it("says which way to call a method or a function", function()
    local s = quantum.scenario(SPORT)
    has(error_of(function() s.run(1) end), "call it with a colon")
    has(error_of(function() quantum:scenario(SPORT) end), "call it with a dot")
    has(error_of(function() s:place("Green", 0, 0) end), "unknown player 'Green'")
  end)
end)

describe("A ball and a jump with height", function()
  local COURT = "rules/basketball"

  it("drops a ball set above the floor, and leaves one on the floor at rest", function()
    -- Far from every player (they stand around the basket), 3 m up: it falls and bounces.
    local s = quantum.scenario(COURT)
    s:ball { x = 6, y = 12, z = 3, count = 50 }
    local bounce = s:run(1.0, "bounce")
    assert.are.equal("bounce", bounce[#bounce].type)
    assert.are.equal("floor", bounce[#bounce].actor)
    -- By default the ball rests on the floor: nothing to hear.
    s = quantum.scenario(COURT)
    s:ball { x = 6, y = 12, count = 50 }
    for _, e in ipairs(s:run(1.0)) do assert.are_not.equal("bounce", e.type) end
  end)

  it("throws a ball up with vz", function()
    local s = quantum.scenario(COURT)
    s:ball { x = 6, y = 12, z = 0.5, vz = 6, count = 50 }
    -- Up 1.8 m and down again: the floor is met only after about 1.3 s.
    for _, e in ipairs(s:run(1.0)) do assert.are_not.equal("bounce", e.type) end
    local later = s:run(1.0, "bounce")
    assert.are.equal("floor", later[#later].actor)
  end)

  it("refuses a height or a vertical speed out of range, naming it", function()
    local s = quantum.scenario(COURT)
    has(error_of(function() s:ball { x = 6, y = 12, z = -1 } end), "z: expected a height from 0.12 m (the ball on the floor) up, got -1")
    has(error_of(function() s:ball { x = 6, y = 12, z = 0 / 0 } end), "nan")
    has(error_of(function() s:ball { x = 6, y = 12, z = math.huge } end), "got inf")
    has(error_of(function() s:ball { x = 6, y = 12, vz = 1e4 } end), "vz: expected a vertical speed in [-1000, 1000] m/s, got 10000")
    has(error_of(function() s:ball { x = 6, y = 12, vz = 0 / 0 } end), "vz: ")
    has(error_of(function() s:ball { x = 6, y = 12, z = "high" } end), "z: expected a number, got string")
  end)

  it("makes a player jump: its reach height rises, and falls back when it lands", function()
    local s = quantum.scenario(COURT)
    local standing = s:players()[1].reach_height
    assert.are.equal(2.4, math.floor(standing * 100 + 0.5) / 100)   -- rules/basketball/field.lua
    s:jump("Maya", 0.6, 0.5)
    assert.is_true(math.abs(s:players()[1].reach_height - standing - 0.6) < 1e-5)
    s:run(0.6)
    assert.are.equal(standing, s:players()[1].reach_height)
    has(error_of(function() s:jump("Maya", 4) end), "a jump's height must be in (0, 3] m")
    has(error_of(function() s:jump("Maya", 0.5, 0 / 0) end), "a jump must last (0, 2] s")
    has(error_of(function() s:jump("Mya") end), "did you mean 'Maya'?")
  end)
end)

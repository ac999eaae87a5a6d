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

  it("says which way to call a method or a function", function()
    local s = quantum.scenario(SPORT)
    has(error_of(function() s.run(1) end), "call it with a colon")
    has(error_of(function() quantum:scenario(SPORT) end), "call it with a dot")
    has(error_of(function() s:place("Green", 0, 0) end), "unknown player 'Green'")
  end)
end)

-- Rule specs of the futsal pitch (tests/sports/futsal): kicks leave the feet, along the ground
-- (rolling, slowed by the floor's friction 0.4/s) or lofted over a player in the way.
local SPORT = "tests/sports/futsal"
local first = require("spec_helpers").first

-- Ann holds the ball at (-3, 0); Cy stands between her and Bo at (3, 0); Kim far away.
local function line_up(seed)
  local s = quantum.scenario(SPORT, { seed = seed })
  s:place("Ann", -3, 0)
  s:place("Cy", 0, 0)
  s:place("Bo", 3, 0)
  s:place("Kim", 9, 5)
  s:give("Ann")
  return s
end

describe("Kicks", function()
  it("along the ground meet the player in the way", function()
    local s = line_up(1)
    s:kick("Ann", 8, 0)
    local caught = first(s:run(3.0, "intercept"), "intercept")
    assert.is_truthy(caught, "Cy, on the ground pass's line, took it")
    assert.are.equal("Cy", caught.actor)
  end)

  it("lofted go over the player in the way to the one behind", function()
    local s = line_up(2)
    -- 4 m/s along, 7 m/s up: 2.3 m high over Cy's 1.8 m reach, and coming down through Bo's
    -- 1.4 s later.
    s:kick("Ann", 4, 0, 7)
    local events = s:run(4.0, "pass")
    local pass = first(events, "pass")
    assert.is_nil(first(events, "intercept"), "Cy never touched it")
    assert.is_truthy(pass, "Bo got it")
    assert.are.equal("Bo", pass.actor)
  end)

  it("are told as kicks, and a ground kick rolls to a stop that is told loose", function()
    local s = quantum.scenario(SPORT, { seed = 3 })
    s:place("Ann", -3, -4)
    for _, p in ipairs { { "Bo", -9, 5 }, { "Cy", 9, 5 }, { "Kim", 9, -5 } } do s:place(p[1], p[2], p[3]) end
    s:give("Ann")
    -- 1.6 m/s stops after 1.6 / 0.4 = 4 m, in the open; it is loose below 0.5 m/s, after
    -- ln(1.6 / 0.5) / 0.4 = 2.9 s.
    s:kick("Ann", 1.6, 0)
    local events = s:run(6.0, "loose")
    local kick, loose = first(events, "kick"), first(events, "loose")
    assert.is_truthy(kick)
    assert.are.same({ "Ann kicks" }, kick.said)
    assert.is_truthy(loose, "the ball slowed to a stop")
    assert.is_true(math.abs(loose.t - math.log(1.6 / 0.5) / 0.4) < 0.2, "loose at " .. loose.t)
    assert.is_true(loose.x > -3 + 0.6 + 2.5 and loose.x < -3 + 0.6 + 4, "loose at x " .. loose.x)
  end)
end)

describe("game.kick", function()
  it("lofts a pass by name over the defender, and shoots along the ground at a goal", function()
    local s = quantum.scenario(SPORT, { seed = 5, params = { opening = "chip" } })
    s:place("Ann", -3, 0)
    s:place("Cy", 0, 0)
    s:place("Bo", 3, 0)
    s:place("Kim", 9, 5)
    s:give("Ann")
    local events = s:run(6.0, "goal")
    assert.is_nil(first(events, "intercept"), "the chip went over Cy")
    local pass, goal = first(events, "pass"), first(events, "goal")
    assert.is_truthy(pass)
    assert.are.equal("Bo", pass.actor)
    assert.is_truthy(goal, "Bo's shot along the ground went in")
    local kicks = {}
    for _, e in ipairs(events) do
      if e.type == "kick" then kicks[#kicks + 1] = e.actor end
    end
    assert.are.same({ "Ann", "Bo" }, kicks)
  end)

  it("is an error for a player without the ball", function()
    local s = quantum.scenario(SPORT, { seed = 6, params = { opening = "wrong" } })
    s:give("Ann")
    local errors = s:errors()
    assert.are.equal(1, #errors)
    assert.is_truthy(errors[1]:find("game.kick: Cy does not hold the ball (Ann does)", 1, true), errors[1])
  end)
end)

describe("Restarts", function()
  it("give a kick-in where the ball went out to the other team's nearest, once they stand there", function()
    local s = quantum.scenario(SPORT, { seed = 7 })
    s:place("Ann", -3, 4)
    s:place("Bo", -8, -5)
    s:place("Cy", 2, 3)
    s:place("Kim", 9, -5)
    s:give("Ann")
    s:kick("Ann", 0, 8)  -- straight over the side line at y = 6
    local events = s:run(3.0, "out")
    local out = first(events, "out")
    assert.is_truthy(out)
    assert.is_true(math.abs(out.x + 3) < 0.5, "out at x " .. out.x)
    local told = out.said[1] or ""
    assert.is_truthy(told:find("^Cy, to %-[23]%.%d, 6%.0$"), "Cy is told where: " .. told)
    assert.is_nil(first(s:run(3.0, "give"), "give"), "no kick-in before Cy is there")
    s:place("Cy", out.x, 5.5)
    local give = first(s:run(1.0, "give"), "give")
    assert.is_truthy(give, "Cy takes it at the line")
    assert.are.equal("Cy", give.actor)
  end)

  it("put everyone in formation after a goal, the team that conceded at the centre", function()
    local s = quantum.scenario(SPORT, { seed = 8 })
    s:place("Ann", 6, 0)
    s:place("Kim", 9, 5)
    s:place("Cy", -3, 0)
    s:place("Bo", -5, 3)
    s:give("Ann")
    s:kick("Ann", 12, 0)  -- along the ground into the Red goal: Red conceded
    local goal = first(s:run(3.0, "goal"), "goal")
    assert.is_truthy(goal)
    local said = table.concat(goal.said, " / ")
    for _, who in ipairs { "Ann, to %-1%.0, 0%.0", "Bo, to %-4%.0, 3%.0", "Kim, to 9%.0, 0%.0", "Cy, to centre" } do
      assert.is_truthy(said:find(who), who .. " in: " .. said)
    end
    local places = {}
    for _, p in ipairs(s:players()) do places[p.name] = { p.place_x, p.place_y } end
    assert.are.same({ -4, 3 }, places.Bo)
    assert.are.same({ 0, 0 }, places.Cy)
    s:place("Cy", 0.3, 0)
    local give = first(s:run(2.0, "give"), "give")
    assert.is_truthy(give)
    assert.are.equal("Cy", give.actor)
  end)

  it("refuse a place that is no spot, naming the spots", function()
    local s = quantum.scenario(SPORT, { seed = 9, params = { opening = "nowhere" } })
    s:give("Ann")
    local errors = s:errors()
    assert.are.equal(1, #errors)
    assert.is_truthy(errors[1]:find("centre", 1, true), errors[1])
  end)
end)

-- Rule specs for the power-ups in rules/powerups, played in Quantum air hockey: each one's effect
-- on the tweaked probabilities, and realized frequencies that follow them (chi-square, 400
-- seeded runs, rejected only below p = 0.001; see rules/spec_helpers.lua).
local SPORT = "airhockey"  -- by name: found here, in QUANTUM_PATH or among the engine's sports
local helpers = require "spec_helpers"

-- A shot at Red's goal with Red's mallet half in the way; `before` moves or grants first.
local function half_blocked(before)
  return function(s)
    s:place("Red's mallet", 0.88, 0.06)
    if before then before(s) end
    s:ball { x = 0.5, y = 0.0, vx = 2.5, vy = 0.0, turn = 0.1, count = 400, by = "Blue's mallet" }
  end
end

-- Blue shot last: Red's mallet meeting the ball is an intercept.
local function outcome_of(fate)
  if fate.kind == "body" then return fate.team == "red" and "intercept" or "shot" end
  return fate.kind
end

local function realized(setup)
  return helpers.outcomes_follow_the_tweaked_fates(SPORT, { particles = 400 }, setup, outcome_of)
end

-- The tweaked distribution alone, from one probe.
local function tweaked(setup)
  local s = quantum.scenario(SPORT, { particles = 400 })
  setup(s)
  local out = {}
  for _, f in ipairs(s:fates()) do
    local k = outcome_of(f)
    out[k] = (out[k] or 0) + f.tweaked
  end
  return out
end

describe("Power-ups", function()
  local plain = tweaked(half_blocked())

  it("penalty: the holder's intercept becomes rarer, as often as computed", function()
    local with = realized(half_blocked(function(s) s:grant("Red's mallet", "penalty", { strength = 0.2 }) end))
    assert.is_true(with.intercept < 0.7 * plain.intercept, string.format("intercept %.3f with, %.3f without", with.intercept, plain.intercept))
  end)

  it("penalty 0: the holder's mallet cannot meet the ball", function()
    local with = tweaked(half_blocked(function(s) s:grant("Red's mallet", "penalty", { strength = 0 }) end))
    assert.are.equal(0, with.intercept or 0)
    -- ...and in play it never does.
    for seed = 1, 20 do
      local s = quantum.scenario(SPORT, { particles = 400, seed = seed })
      half_blocked(function(q) q:grant("Red's mallet", "penalty", { strength = 0 }) end)(s)
      local e = helpers.outcome(s:run(2.0, "intercept"))
      assert.is_true(e == nil or e.type ~= "intercept", "seed " .. seed .. ": intercepted under a penalty of 0")
    end
  end)

  it("attract: the holder's intercept becomes likelier, as often as computed", function()
    local with = realized(half_blocked(function(s) s:grant("Red's mallet", "attract") end))
    assert.is_true(with.intercept > plain.intercept + 0.05, string.format("intercept %.3f with, %.3f without", with.intercept, plain.intercept))
  end)

  it("goal seeker: the holder's shot finds the goal more often, as often as computed", function()
    local with = realized(half_blocked(function(s) s:grant("Blue's mallet", "goal_seeker") end))
    assert.is_true(with.goal > plain.goal + 0.05, string.format("goal %.3f with, %.3f without", with.goal, plain.goal))
  end)

  it("stun: a penalty only while the holder moves", function()
    local still = tweaked(half_blocked(function(s) s:grant("Red's mallet", "stun") end))
    assert.is_true(math.abs(still.intercept - plain.intercept) < 1e-9, "standing still, no penalty")
    -- Sliding sideways at 0.3 m/s: penalized, and realized as computed.
    local moving = realized(half_blocked(function(s)
      s:move("Red's mallet", 0.88, 0.36, 1.0)
      s:grant("Red's mallet", "stun")
    end))
    local unpunished = tweaked(half_blocked(function(s) s:move("Red's mallet", 0.88, 0.36, 1.0) end))
    assert.is_true(moving.intercept < 0.7 * unpunished.intercept,
      string.format("intercept %.3f stunned, %.3f not", moving.intercept, unpunished.intercept))
  end)

  it("slow motion: a penalty only while the holder moves faster than its limit", function()
    -- Sliding sideways at 0.3 m/s, as in the stun spec.
    local function slowly(s) s:move("Red's mallet", 0.88, 0.36, 1.0) end
    local slow = tweaked(half_blocked(function(s)
      slowly(s)
      s:grant("Red's mallet", "slow_motion")
    end))
    local slow_free = tweaked(half_blocked(slowly))
    assert.is_true(slow.intercept > 0.05 and math.abs(slow.intercept - slow_free.intercept) < 1e-9, "under the limit, no penalty")
    -- Over a limit of 0.2 m/s the same motion is penalized, and realized as computed.
    local fast = realized(half_blocked(function(s)
      slowly(s)
      s:grant("Red's mallet", "slow_motion", { limit = 0.2 })
    end))
    assert.is_true(fast.intercept < 0.7 * slow_free.intercept,
      string.format("intercept %.3f slowed, %.3f not", fast.intercept, slow_free.intercept))
  end)

  it("black ice: a penalty once the holder leaves the motion it had", function()
    -- Across the shot's line at 0.5 m/s, reaching it as the ball does.
    local function sliding(s) s:place("Red's mallet", 0.88, 0.12); s:move("Red's mallet", 0.88, -0.38, 1.0) end
    -- The ice comes while the mallet slides; then it stops dead on the line.
    local stopped = realized(half_blocked(function(s)
      sliding(s)
      s:grant("Red's mallet", "black_ice")
      s:place("Red's mallet", 0.88, 0.06)
    end))
    assert.is_true(stopped.intercept < 0.7 * plain.intercept,
      string.format("intercept %.3f on ice, %.3f off", stopped.intercept, plain.intercept))
    local kept = tweaked(half_blocked(function(s)
      sliding(s)
      s:grant("Red's mallet", "black_ice")
    end))
    local free = tweaked(half_blocked(sliding))
    assert.is_true(kept.intercept > 0.05 and math.abs(kept.intercept - free.intercept) < 1e-9, "keeping its motion, no penalty")
  end)

  -- A shot along the left side of the table, Red's mallet out of the way.
  local function along_the_side(before)
    return function(s)
      s:place("Red's mallet", 0.6, -0.4)
      if before then before(s) end
      -- Fanned wide, so some of it misses the mouth, and what comes out is not all on target.
      s:ball { x = -0.6, y = 0.3, vx = 2.5, vy = 0.0, turn = 0.6, count = 400, by = "Blue's mallet" }
    end
  end
  local side_shot = tweaked(along_the_side())

  it("wormhole: a shot along the left side comes out in front of Red's goal, as often as computed", function()
    -- Blue's wormhole: a mouth at (-0.3, 0.3) on the shot's line, the other at (0.6, 0). Without
    -- it the shot meets Red's end wall first, and only its rebounds may find the goal.
    -- Goal into Red's goal, or anything else (the rest is too thin to count apart).
    local function goal_or_not(fate) return fate.kind == "goal" and "goal" or "other" end
    local function classify(events)
      local e = helpers.outcome(events)
      return e and e.type == "goal" and "goal" or "other"
    end
    local with = helpers.outcomes_follow_the_tweaked_fates(SPORT, { particles = 400 },
      along_the_side(function(s) s:grant("Blue's mallet", "wormhole") end), goal_or_not, classify)
    assert.is_true(with.goal > (side_shot.goal or 0) + 0.05,
      string.format("goal %.3f through the wormhole, %.3f without", with.goal, side_shot.goal or 0))
  end)

  it("wormhole: closes when it runs out", function()
    local s = quantum.scenario(SPORT, { seed = 1, particles = 400 })
    s:grant("Blue's mallet", "wormhole", { seconds = 0.5 })
    s:run(1.0)
    local said = table.concat(s:said(), " | ")
    assert.is_truthy(said:find("The wormhole closes", 1, true), said)
    along_the_side()(s)
    local goal = 0
    for _, f in ipairs(s:fates()) do
      if f.kind == "goal" then goal = goal + f.tweaked end
    end
    -- (Not exactly equal: a second in, the Brownian noise the prediction replays is another.)
    assert.is_true(math.abs(goal - (side_shot.goal or 0)) < 0.05,
      string.format("closed: the shot goes as it would without (goal %.3f, %.3f)", goal, side_shot.goal or 0))
  end)

  it("ends after its duration, with the script's phrases", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    s:grant("Red's mallet", "penalty", { seconds = 0.5 })
    local events = s:run(1.0)
    local started, ended
    for _, e in ipairs(events) do
      if e.type == "powerup" then started = e end
      if e.type == "powerup_end" then ended = e end
    end
    assert.are.equal("penalty", started.powerup)
    assert.are.equal("Red's mallet", ended.actor)
    assert.is_true(math.abs(ended.t - 0.5) < 0.02, "ended at " .. ended.t)
    local said = table.concat(s:said(), " | ")
    assert.is_truthy(said:find("Penalty for Red's mallet", 1, true), said)
    assert.is_truthy(said:find("Red's mallet's penalty is over", 1, true), said)
  end)

  it("refuses an unknown power-up by name", function()
    local s = quantum.scenario(SPORT, { seed = 1 })
    local ok, err = pcall(function() s:grant("Red's mallet", "teleport") end)
    assert.is_false(ok)
    assert.is_truthy(tostring(err):find("no power-up 'teleport'", 1, true), tostring(err))
  end)
end)

-- Helpers for rule specs (loaded by them, not a spec itself): `quantum test` puts the engine's
-- rules folder on the specs' require path, so any spec may
--   local helpers = require "spec_helpers"
local helpers = {}

-- The first event of type `kind` in a list of events, or nil.
function helpers.first(events, kind)
  for _, e in ipairs(events) do
    if e.type == kind then return e end
  end
end

-- How many events of type `kind` a list holds.
function helpers.count(events, kind)
  local n = 0
  for _, e in ipairs(events) do
    if e.type == kind then n = n + 1 end
  end
  return n
end

-- The first event that ends the ball's flight: anything but the ball given or thrown (a spec's
-- s:give and s:throw are told in the next run), a bounce off a wall on the way, or a power-up
-- starting or ending.
local passing = { give = true, throw = true, bounce = true, powerup = true, powerup_end = true }
function helpers.outcome(events)
  for _, e in ipairs(events) do
    if not passing[e.type] then return e end
  end
end

-- The first thing the scenario's announcer said that contains `text`, or nil.
function helpers.heard(s, text)
  for _, said in ipairs(s:said()) do
    if said:find(text, 1, true) then return said end
  end
end

-- Realized frequencies follow the probabilities the factors compute. A scene is set up n times
-- with different seeds; its fates, tweaked by the sport's factors, modifiers, power-ups and the
-- handicaps, give the expected distribution of the first outcome (bounces on the way are
-- decisions of their own, drawn with the same tweak); chi-square goodness of fit, rejected only
-- below p = 0.001. Short flights: each draw is then made on fates predicted that very frame.
-- category(fate) names a fate's outcome; classify(events) names a run's (default: the type of
-- its first outcome, "shot" for a mallet). Returns the expected and the Newtonian distribution.
function helpers.outcomes_follow_the_tweaked_fates(sport, opts, setup, category, classify)
  classify = classify or function(events)
    local e = helpers.outcome(events)
    return e and e.type or "none"
  end
  local probe = quantum.scenario(sport, opts)
  setup(probe)
  local expected, newtonian = {}, {}
  for _, f in ipairs(probe:fates()) do
    local k = category(f)
    expected[k] = (expected[k] or 0) + f.tweaked
    newtonian[k] = (newtonian[k] or 0) + f.mass
  end
  local n, seen = 400, {}
  for seed = 1, n do
    opts.seed = seed
    local s = quantum.scenario(sport, opts)
    setup(s)
    local k = classify(s:run(3.0, "shot"))
    seen[k] = (seen[k] or 0) + 1
  end
  local chi2, cells, report = 0, 0, ""
  for k, p in pairs(expected) do
    assert(p * n >= 5, k .. " is too rare for chi-square; change the scene")
    chi2 = chi2 + ((seen[k] or 0) - p * n) ^ 2 / (p * n)
    cells = cells + 1
    report = report .. string.format(" %s: Newtonian %.3f, tweaked %.3f, seen %d/%d;", k, newtonian[k], p, seen[k] or 0, n)
  end
  for k, count in pairs(seen) do assert(expected[k] ~= nil, "unpredicted outcome " .. k .. " x" .. count) end
  local p = quantum.chi_square_p(chi2, cells - 1)
  assert(p > 0.001, string.format("chi2 = %.2f, p = %.5f;%s", chi2, p, report))
  return expected, newtonian
end

-- A fate's outcome as a run names it: "shot" for a mallet, else its kind.
function helpers.shot_or_goal(fate) return fate.kind == "body" and "shot" or fate.kind end

return helpers

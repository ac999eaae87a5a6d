-- Rule specs of the tackle pitch (tests/sports/tackles): while an opponent's body touches the
-- holder's, it takes the ball at tackles.rate x factors.tackle per second (1.5 x 2 = 3 here).
local SPORT = "tests/sports/tackles"
local first = require("spec_helpers").first

-- Ann holds the ball at (0, 0); `who` stands `gap` m from her, the others far away.
local function press(seed, who, gap)
  local s = quantum.scenario(SPORT, { seed = seed })
  for _, p in ipairs { { "Bo", -8, 5 }, { "Cy", 8, -5 }, { "Kim", 9, 5 } } do s:place(p[1], p[2], p[3]) end
  s:place("Ann", 0, 0)
  s:place(who, gap, 0)
  s:give("Ann")
  return s
end

describe("Tackles", function()
  it("take the ball off the holder when the bodies touch, told with who lost it", function()
    local s = press(1, "Cy", 1.0)
    local tackle = first(s:run(5.0, "tackle"), "tackle")
    assert.is_truthy(tackle, "Cy took the ball within 5 s")
    assert.are.equal("Cy", tackle.actor)
    assert.are.equal("Ann", tackle.previous)
    assert.are.equal("Cy", s:holder())
    assert.are.same({ "Cy takes it off Ann" }, tackle.said)
  end)

  it("never happen out of reach, nor by a teammate, nor where a modifier rules them out", function()
    for _, case in ipairs { { "Cy", 1.3 }, { "Bo", 0.5 }, { "Kim", 0.5 } } do
      local s = press(2, case[1], case[2])
      assert.is_nil(first(s:run(4.0), "tackle"), case[1] .. " at " .. case[2] .. " m")
      assert.are.equal("Ann", s:holder())
    end
  end)

  -- The time to the first tackle is exponential with rate 3/s, frame by frame exactly: over 300
  -- seeds, the share tackled within 0.1, 0.25, 0.5 and 1 s (and later) against 1 - e^(-3t), by
  -- chi-square on 4 degrees of freedom, rejected only at p < 0.001.
  it("come at the rate times the factor", function()
    local edges, counts, n = { 0.1, 0.25, 0.5, 1.0 }, { 0, 0, 0, 0, 0 }, 300
    for seed = 1, n do
      local tackle = first(press(seed, "Cy", 1.0):run(1.0, "tackle"), "tackle")
      local bin = #edges + 1
      if tackle then
        for k, edge in ipairs(edges) do
          if tackle.t - 1e-9 <= edge then bin = k break end
        end
      end
      counts[bin] = counts[bin] + 1
    end
    local chi2, before = 0, 0
    for k = 1, #edges + 1 do
      local upto = edges[k] and (1 - math.exp(-3 * edges[k])) or 1
      local expected = (upto - before) * n
      chi2 = chi2 + (counts[k] - expected) ^ 2 / expected
      before = upto
    end
    assert.is_true(quantum.chi_square_p(chi2, #edges) > 0.001, "chi2 " .. chi2)
  end)
end)

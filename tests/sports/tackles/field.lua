-- A small pitch of players who catch, for tackles: Ann and Bo attack, Cy defends, Kim keeps the
-- other goal's box. x along the pitch, y to its left; metres.
return {
  name = "Tackle pitch",
  ball = { radius = 0.11, friction = 0.6 },
  bounds = { { -10, -6 }, { 10, 6 } },
  spots = { { name = "centre", at = { 0, 0 } } },
  bodies = {
    { name = "Ann", team = "blue", catches = true, radius = 0.6, at = { -3, 0 } },
    { name = "Bo", team = "blue", catches = true, radius = 0.6, at = { -3, 3 } },
    { name = "Cy", team = "red", catches = true, radius = 0.6, at = { 3, 0 } },
    { name = "Kim", team = "red", catches = true, radius = 0.6, at = { 8, 0 }, role = "keeper" },
  },
}

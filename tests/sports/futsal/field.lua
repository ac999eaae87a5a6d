-- A small futsal pitch with height, written from docs/field-files.md: the ball rolls on the floor
-- and slows by its friction, or flies in arcs when lofted. x along the pitch, y to its left, z up;
-- metres. Everyone "catches": a player who gets to the ball controls it, the outfield players at
-- their feet (`kicks`: their own throws leave as kicks), Kim, the keeper, in his hands. Ann is a
-- back: her zone, where the simulated players keep her, is Blue's half.
return {
  name = "Futsal pitch",
  gravity = 9.81,
  ball = { radius = 0.11, friction = 0.4, floor_restitution = 0.6 },
  bounds = { { -10, -6 }, { 10, 6 } },
  goals = {
    { name = "Blue goal", team = "blue", from = { -10, -1.5 }, to = { -10, 1.5 } },
    { name = "Red goal", team = "red", from = { 10, -1.5 }, to = { 10, 1.5 } },
  },
  spots = { { name = "centre", at = { 0, 0 } } },
  bodies = {
    { name = "Ann", kicks = true, team = "blue", catches = true, radius = 0.5, reach = 1.8, at = { -3, 0 },
      zone = { { -10, -6 }, { 0, 6 } } },
    { name = "Bo", kicks = true, team = "blue", catches = true, radius = 0.5, reach = 1.8, at = { 3, 2 } },
    { name = "Cy", kicks = true, team = "red", catches = true, radius = 0.5, reach = 1.8, at = { 0, 0 } },
    { name = "Kim", team = "red", catches = true, radius = 0.5, reach = 1.8, at = { 9, 0 } },
  },
}

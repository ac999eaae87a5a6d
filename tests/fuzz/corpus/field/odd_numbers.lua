return { name = "odd", ball = { radius = 0/0 }, brownian = -1, bounds = { { -1e308, -1 }, { 1e308, 1 } },
         walls = { { name = "w", points = { { 0, 0 }, { 0, 0 } } } },
         goals = { { team = "blue", from = { 1/0, 0 }, to = { 0, 1 } } },
         bodies = { { team = "red", radius = 1e-9, at = { 50, 50 }, catches = true } } }

return { gravity = 9.81, floor_restitution = 0.7,
         walls = { { name = "board", points = { { 1, -0.9 }, { 1, 0.9 } }, bottom = 2.9, top = 4.0 } },
         hoops = { { name = "hoop", team = "red", at = { 0.6, 0 }, height = 3.05, radius = 0.23 } },
         spots = { { team = "blue", at = { 0, 0 } } },
         bodies = { { name = "A", team = "blue", radius = 0.3, at = { -1, 0 }, catches = true, reach = 2.4 } } }

-- The announcer's numbers at their edges; sport_fuzz found 4.4e104 as a rate reaching an int.
return {
  name = "audio numbers",
  match = { seconds = 1, particles = 50 },
  audio = { voice = "en-us", rate = 450, volume = 0, keep = 100, duck = 1, repeat_gap = 60, wait_for = 5,
            priorities = { goal = 100, shot = 0, timer = 7 }, supersede = { shot = false } },
  on = { drop = function(game, e) game.cancel(2^31); game.aim("red", { 3e38, 0 }) end },
}

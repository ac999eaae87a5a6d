-- Wormhole: two mouths on the field; what enters one leaves the other, at the same offset and
-- with the same velocity. Field metres; the defaults suit the air hockey table (2 m x 1 m): a
-- mouth in the holder's half, near the left wall, and one in front of the opponents' goal.
return {
  name = "wormhole",
  duration = 10,
  defaults = { ax = -0.3, ay = 0.3, bx = 0.6, by = 0.0, radius = 0.1 },
  phrases = { start = "A wormhole opens for {player}", over = "The wormhole closes" },
  start = function(holder, game, p)
    -- Mirrored for a holder who attacks toward -x (the red end's player).
    local side = holder.x < 0 and 1 or -1
    game.wormhole(side * p.ax, p.ay, side * p.bx, p.by, p.radius)
  end,
  stop = function(holder, game)
    game.wormhole()
  end,
  factor = function() end,  -- it changes where the ball goes, not the odds
}

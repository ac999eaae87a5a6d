-- The doubles announcer's calls, a module of the sport's own: require "calls".
local calls = {}

-- What to say of a touch: a pass between teammates, an intercept, or a shot.
function calls.of_touch(e)
  if e.previous_team == e.team and e.previous ~= e.actor then return "pass" end
  if e.type == "intercept" then return "intercept" end
  return "shot"
end

return calls

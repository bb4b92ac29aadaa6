-- EXP_GTDZA: the tutorial's own environment example (its section 6.2), go
-- to the drop zone while avoiding obstacles (the GTDZ+Avoid skill). As the
-- tutorial writes it: the default obstacle grid (size 1 + up to 2, spacing
-- 18), the bot starting at (-0.5, 0), a zone of half side 5 turned 45
-- degrees, NextOnCollisionAndTimeout after 20,000 ticks, +100 per tick
-- inside the zone (SensorOverThreshold on the zone sensor) and
-- ClosingOnTarget on the zone (k 0.001). The zone moves to a random place
-- at every reset and, once reached, after the step's rewards (postStepOps).
-- evo adds a border the sensors see, as in EXP_GTOA, and reports how many
-- zones the bot reached in each episode (the metric zones_reached, on each
-- episode line of evo run and in a learning run's log.csv; docs/lua.md).
local arena = require "lib.arena"

local env = {}
local zone

local function place_zone(scene)
	local bx, by = env.bot:pose()
	local x, y = arena.random_point(scene, 40, { { bx, by } }, 10)
	zone:place(x, y)
end

function env.init(scene, task)
	arena.border(scene, 50, 2)
	scene:grid{ x0 = -45, y0 = -45, x1 = 45, y1 = 45, spacing = 18, jitter = 4,
		min_size = 1, size_variability = 2, clearance = 3 }
	env.bot = scene:bot{ x = -0.5, y = 0 }
	zone = scene:zone{ name = "target", x = -20, y = -20, size = 5, angle = 45 }
	-- the zone trackers, whatever the bot model calls them
	env.in_zone = env.bot:sensors("zone", "untargeted")
	for _, kind in ipairs{ "zone", "bearing", "distance", "presence" } do
		for _, s in ipairs(env.bot:sensors(kind, "untargeted")) do
			env.bot:target(s, zone)
		end
	end
	scene:control("NextOnCollisionAndTimeout", { bot = env.bot, ticks = 20000 })
	scene:reward("SensorOverThreshold", { bot = env.bot, sensors = env.in_zone,
		threshold = 0.5, k = 100 })
	scene:reward("ClosingOnTarget", { bot = env.bot, target = zone, k = 0.001 })
	env.reached = scene:metric("zones_reached")
end

function env.reset(scene, episode)
	place_zone(scene)
end

-- Reached: the bot was paid for this step; the zone moves and the
-- distances are forgotten, so the jump is not punished.
function env.post_step(scene)
	local s = env.in_zone[1]
	if s and env.bot:value(s) > 0.5 then
		env.reached:add()
		place_zone(scene)
		scene:reset_rewards()
	end
end

return env

-- GoToZone: the GTDZ+Avoid skill's own task, shaped to learn fast. The
-- drop zone of EXP_Collect's arena (a ±40 border, a zone of half side 5),
-- no obstacles but the border, as in EXP_Collect. Per step: k 1 for closing
-- on the zone, +20·(v − 0.5) while the bot is inside it, −1 while touching
-- anything. Once reached, the zone moves elsewhere. It reports the metric
-- zones_reached.
local arena = require "lib.arena"

local env = {}
local zone

local function place_zone(scene)
	local bx, by = env.bot:pose()
	local x, y = arena.random_point(scene, 30, { { bx, by } }, 12)
	zone:place(x, y)
end

function env.init(scene, task)
	arena.border(scene, 40, 2)
	env.bot = scene:bot{ x = 0, y = 0 }
	zone = scene:zone{ name = "dropzone", x = -20, y = -20, size = 5 }
	env.in_zone = env.bot:sensors("zone", "untargeted")
	for _, kind in ipairs{ "zone", "bearing", "distance", "presence" } do
		for _, s in ipairs(env.bot:sensors(kind, "untargeted")) do
			env.bot:target(s, zone)
		end
	end
	scene:reward("ClosingOnTarget", { bot = env.bot, target = zone, k = 1 })
	scene:reward("SensorOverThreshold", { bot = env.bot, sensors = env.in_zone,
		threshold = 0.5, k = 20 })
	scene:reward("PunishOnCollision", { bot = env.bot, k = -1 })
	scene:control("NextOnTimeout", { bot = env.bot, ticks = tonumber(task.TICKLIM) or 3000 })
	env.reached = scene:metric("zones_reached")
end

function env.reset(scene, episode)
	place_zone(scene)
end

function env.post_step(scene)
	local s = env.in_zone[1]
	if s and env.bot:value(s) > 0.5 then
		env.reached:add()
		place_zone(scene)
		scene:reset_rewards()
	end
end

return env

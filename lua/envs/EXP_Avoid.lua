-- EXP_Avoid: roam a 400 x 400 arena full of cylinders without touching
-- anything (EvoAgents' EXP_Avoid; docs/world.md lists the figures).
local arena = require "lib.arena"

local env = {}

function env.init(scene, task)
	arena.border(scene, 200, 4)
	-- About 300 cylinders of radius 2.2 to 6.2 on a grid of spacing 23,
	-- each moved by up to 12 on each axis; none near the start.
	scene:grid{ x0 = -189, y0 = -189, x1 = 189, y1 = 189, spacing = 23,
		jitter = 12, min_size = 2.2, size_variability = 4, clearance = 2 }
	local bot = scene:bot{ x = 0, y = 5 }
	-- every proximity sensor of the bot, whatever the bot model calls them
	local sensors = bot:sensors("proximity")
	scene:reward("ForwardMotion", { bot = bot, k = 0.002, k2 = -0.02 })
	scene:reward("Speed", { bot = bot, k = 0.0001 })
	scene:reward("PunishOnCollision", { bot = bot, k = -15 })
	scene:reward("SensorUnderThreshold", { bot = bot, sensors = sensors,
		threshold = 0.5, k = -10 })
	scene:reward("SensorOverThreshold", { bot = bot, sensors = sensors,
		threshold = 0.5, k = 0.2 })
	scene:control("NextOnTimeout", { bot = bot, ticks = tonumber(task.TICKLIM) or 15000 })
end

return env

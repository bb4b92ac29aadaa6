-- EXP_GTOA: go to an object while avoiding obstacles: EXP_GTO in a field
-- of cylinders, with a penalty for touching them (docs/world.md).
local arena = require "lib.arena"

local env = {}
local object

local function place_object(scene, bot)
	local bx, by = bot:pose()
	local x, y = arena.random_point(scene, 40, { { bx, by } }, 10)
	object:place(x, y)
end

function env.init(scene, task)
	arena.border(scene, 50, 2)
	object = scene:object{ name = "object", x = 20, y = 0, radius = 0.5 }
	env.bot = scene:bot{ x = 0, y = 0 }
	-- The tutorial's default grid: size 1 + up to 2, spacing 18.
	scene:grid{ x0 = -45, y0 = -45, x1 = 45, y1 = 45, spacing = 18, jitter = 4,
		min_size = 1, size_variability = 2, clearance = 3 }
	scene:reward("ClosingOnTarget", { bot = env.bot, target = "nearest_object", k = 1 })
	scene:reward("SensorOverThreshold", { bot = env.bot, sensors = { "SENSOBJ" },
		threshold = 0.5, k = 1 })
	scene:reward("PunishOnCollision", { bot = env.bot, k = -5 })
	scene:control("NextOnTimeout", { bot = env.bot, ticks = tonumber(task.TICKLIM) or 3000 })
end

function env.reset(scene, episode)
	place_object(scene, env.bot)
end

function env.post_step(scene)
	if env.bot:value("SENSOBJ") > 0.5 then
		place_object(scene, env.bot)
		scene:reset_rewards()
	end
end

return env

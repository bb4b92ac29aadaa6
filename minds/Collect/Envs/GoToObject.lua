-- GoToObject: the GTO+Avoid skill's own task, shaped to learn fast. One
-- object in EXP_Collect's arena (a ±40 border), no obstacles but the
-- border, as in EXP_Collect. Per step: k 1 for closing on the object,
-- +300·(v − 0.5) (90) once it is within reach of the claw (SENSOBJ: in
-- front, as the claw needs it, so that circling close to it pays little),
-- −1 while touching anything. Once reached, the object moves elsewhere.
-- It reports the metric objects_reached.
local arena = require "lib.arena"

local env = {}
local object

local function place_object(scene)
	local bx, by = env.bot:pose()
	local x, y = arena.random_point(scene, 30, { { bx, by } }, 12)
	object:place(x, y)
end

function env.init(scene, task)
	arena.border(scene, 40, 2)
	object = scene:object{ name = "object", x = 20, y = 0, radius = 0.5 }
	env.bot = scene:bot{ x = 0, y = 0 }
	env.detectors = env.bot:sensors("object_detector")
	scene:reward("ClosingOnTarget", { bot = env.bot, target = "nearest_object", k = 1 })
	scene:reward("SensorOverThreshold", { bot = env.bot, sensors = env.detectors,
		threshold = 0.5, k = 300 })
	scene:reward("PunishOnCollision", { bot = env.bot, k = -1 })
	scene:control("NextOnTimeout", { bot = env.bot, ticks = tonumber(task.TICKLIM) or 3000 })
	env.reached = scene:metric("objects_reached")
end

function env.reset(scene, episode)
	place_object(scene)
end

function env.post_step(scene)
	local d = env.detectors[1]
	if d and env.bot:value(d) > 0.5 then
		env.reached:add()
		place_object(scene)
		scene:reset_rewards()
	end
end

return env

-- The go-to-object environments (EXP_GTO, EXP_GTOA): an object to reach in
-- a bordered arena, optionally among obstacles. Once reached, the object
-- moves to a new random place, as EvoAgents' postStepOps did.
local arena = require "lib.arena"

-- opts.grid: a scene:grid table, or nil for none;
-- opts.collision: the reward per step spent touching anything.
return function(opts)
	local env = {}
	local object

	local function place_object(scene)
		local bx, by = env.bot:pose()
		local x, y = arena.random_point(scene, 40, { { bx, by } }, 10)
		object:place(x, y)
	end

	function env.init(scene, task)
		arena.border(scene, 50, 2)
		object = scene:object{ name = "object", x = 20, y = 0, radius = 0.5 }
		env.bot = scene:bot{ x = 0, y = 0 }
		if opts.grid then scene:grid(opts.grid) end
		scene:reward("ClosingOnTarget", { bot = env.bot, target = "nearest_object", k = 1 })
		-- every object detector of the bot, whatever the model calls it
		env.detectors = env.bot:sensors("object_detector")
		scene:reward("SensorOverThreshold", { bot = env.bot, sensors = env.detectors,
			threshold = 0.5, k = 1 })
		scene:reward("PunishOnCollision", { bot = env.bot, k = opts.collision })
		scene:control("NextOnTimeout", { bot = env.bot,
			ticks = tonumber(task.TICKLIM) or 3000 })
	end

	function env.reset(scene, episode)
		place_object(scene)
	end

	-- Reached: move the object and forget the distances, so the jump is
	-- not punished.
	function env.post_step(scene)
		local d = env.detectors[1]
		if d and env.bot:value(d) > 0.5 then
			place_object(scene)
			scene:reset_rewards()
		end
	end

	return env
end

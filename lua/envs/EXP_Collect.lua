-- EXP_Collect: pick up objects with the claw and carry them into the drop
-- zone. A delivered object leaves the world; when all are delivered, they
-- come back at new places (docs/world.md).
local arena = require "lib.arena"

local N_OBJECTS = 4
local env = {}
local zone
local objects = {}

local function scatter(scene)
	local zx, zy = zone:pos()
	local bx, by = env.bot:pose()
	local taken = { { zx, zy }, { bx, by } }
	for _, o in ipairs(objects) do
		local x, y = arena.random_point(scene, 30, taken, 8)
		o:place(x, y)
		o:set_active(true)
		taken[#taken + 1] = { x, y }
	end
end

function env.init(scene, task)
	arena.border(scene, 40, 2)
	zone = scene:zone{ name = "dropzone", x = -20, y = -20, size = 5 }
	for i = 1, N_OBJECTS do
		objects[i] = scene:object{ name = "object" .. i, x = 10 * i, y = 10, radius = 0.5 }
	end
	env.bot = scene:bot{ x = 0, y = 0 }
	-- the drop-zone trackers, whatever the bot model calls them: every
	-- presence, distance, bearing and zone sensor that looks at nothing yet
	for _, kind in ipairs{ "presence", "distance", "bearing", "zone" } do
		for _, s in ipairs(env.bot:sensors(kind, "untargeted")) do
			env.bot:target(s, zone)
		end
	end
	scene:reward("Collect", { bot = env.bot, target = zone, k = 100 })
	scene:reward("ClosingOnTarget", { bot = env.bot, target = "nearest_object", k = 0.2 })
	scene:reward("PunishOnCollision", { bot = env.bot, k = -1 })
	scene:control("NextOnTimeout", { bot = env.bot, ticks = tonumber(task.TICKLIM) or 6000 })
end

function env.reset(scene, episode)
	local x, y = arena.random_point(scene, 25, { { 0, 0 } }, 12)
	zone:place(x, y)
	scatter(scene)
end

function env.post_step(scene)
	for _, o in ipairs(objects) do
		if o:active() then return end
	end
	scatter(scene)
	scene:reset_rewards()
end

return env

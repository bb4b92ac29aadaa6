-- LightArena: a phototactic swarm of e-pucks (minds/Phototaxis/README.md).
-- A walled arena 1.6 m square with a light of intensity 0.05 at its centre
-- (a light sensor facing it reads 1 within 0.22 m, 0.2 at 0.5 m) over a
-- black patch of radius 0.2 m, and a post that hides the light from part
-- of the arena. The bots start scattered 0.45 to 0.7 m from the light,
-- facing anywhere. Each tick pays the team the mean over its bots of
-- 1 - d / 1.2, d the bot's distance to the light in metres: the sooner the
-- swarm gathers at the light, the more. The metric `at_light` is how many
-- bots stand on the black patch at the end of the episode.
local HALF = 0.8
local PATCH = 0.2

local env = {}
local bots = {}

function env.init(scene, task)
	scene:wall{ x1 = -HALF, y1 = -HALF, x2 = HALF, y2 = -HALF }
	scene:wall{ x1 = HALF, y1 = -HALF, x2 = HALF, y2 = HALF }
	scene:wall{ x1 = HALF, y1 = HALF, x2 = -HALF, y2 = HALF }
	scene:wall{ x1 = -HALF, y1 = HALF, x2 = -HALF, y2 = -HALF }
	scene:light{ x = 0, y = 0, intensity = 0.05, colour = "yellow" }
	scene:patch{ x = 0, y = 0, radius = PATCH, grey = 0 }
	scene:cylinder{ x = 0.32, y = 0, radius = 0.05 }
	local teams = scene:teams()
	bots = require("lib.teams").spawn(scene, { spacing = 0.1 })
	local function closeness()
		local sum = 0
		for _, b in ipairs(bots) do
			local x, y = b:pose()
			sum = sum + 1 - math.sqrt(x * x + y * y) / 1.2
		end
		return sum / #bots
	end
	if #teams == 0 then
		scene:reward(closeness, { bot = bots[1] })
	else
		scene:reward(closeness, { team = teams[1].name })
	end
	env.at_light = scene:metric("at_light")
	scene:control("NextOnTimeout", { ticks = tonumber(task.TICKLIM) or 600 })
end

function env.reset(scene, episode)
	local taken = {}
	for _, b in ipairs(bots) do
		local x, y, ok
		repeat
			local r, a = scene:random(0.45, 0.7), scene:random(0, 2 * math.pi)
			x, y = r * math.cos(a), r * math.sin(a)
			ok = true
			for _, p in ipairs(taken) do
				if (x - p[1]) ^ 2 + (y - p[2]) ^ 2 < 0.1 ^ 2 then ok = false end
			end
		until ok
		taken[#taken + 1] = { x, y }
		b:place(x, y, scene:random(-180, 180))
	end
end

function env.post_step(scene)
	local n = 0
	for _, b in ipairs(bots) do
		local x, y = b:pose()
		if x * x + y * y <= PATCH * PATCH then n = n + 1 end
	end
	env.at_light:set(n)
end

return env

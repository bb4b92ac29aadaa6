-- EXP_Pursuit: pursuit and evasion between two teams (docs/teams.md). The
-- task's first team pursues, its second evades, in a walled arena with a
-- few pillars. A pursuer that touches an evader catches it: the pursuers
-- win the episode (scene:winner), their team is paid 10 and the evaders'
-- team loses 10, and the episode ends. An evader that is not caught by
-- TICKLIM wins. Each pursuer is paid for closing on the nearest evader
-- (ClosingOnTarget, 0.1 a metre), each evader 0.01 a tick for staying
-- free. The metric `caught` is 1 for an episode the pursuers won.
local arena = require "lib.arena"

local HALF = 20 -- the arena is [-20, 20]^2 inside its wall
local CATCH = 2.2 -- centre to centre: two bots of radius 1 touching

local env = {}
local hunters, prey = {}, {}

function env.init(scene, task)
	local list = scene:teams()
	if #list ~= 2 then
		error("EXP_Pursuit needs two teams (TEAM lines), the pursuers first; the task has "
			.. #list, 0)
	end
	env.hunt, env.flee = list[1].name, list[2].name
	arena.border(scene, HALF + 1.5, 1.5)
	for _, p in ipairs{ { -8, -8 }, { 8, 8 }, { -8, 8 }, { 8, -8 } } do
		scene:cylinder{ x = p[1], y = p[2], radius = 1.5 }
	end
	for i = 1, list[1].size do hunters[i] = scene:bot{ team = env.hunt, x = -12, y = 3 * i } end
	for i = 1, list[2].size do prey[i] = scene:bot{ team = env.flee, x = 12, y = 3 * i } end
	env.caught = scene:metric("caught")
	-- the catch, worked out once a tick by the first reward function,
	-- which pays the pursuers; the second charges the evaders
	scene:reward(function(scene)
		for _, h in ipairs(hunters) do
			local hx, hy = h:pose()
			for _, p in ipairs(prey) do
				local px, py = p:pose()
				if (hx - px) ^ 2 + (hy - py) ^ 2 < CATCH * CATCH then
					env.done = true
					scene:winner(env.hunt)
					env.caught:set(1)
					return 10
				end
			end
		end
		return 0
	end, { team = env.hunt })
	scene:reward(function(scene) return env.done and -10 or 0 end, { team = env.flee })
	scene:reward("ClosingOnTarget", { team = env.hunt, target = "nearest_opponent", k = 0.1 })
	scene:reward("Step", { team = env.flee, k = 0.01 })
	scene:control(function(scene) return env.done end)
	scene:control("NextOnTimeout", { ticks = tonumber(task.TICKLIM) or 600 })
end

function env.reset(scene, episode)
	env.done = false
	-- the evaders win unless caught
	scene:winner(env.flee)
	local taken = {}
	for _, h in ipairs(hunters) do
		local x, y = arena.random_point(scene, HALF - 3, taken, 4)
		h:place(-math.abs(x), y, scene:random(0, 360))
		taken[#taken + 1] = { -math.abs(x), y }
	end
	for _, p in ipairs(prey) do
		local x, y = arena.random_point(scene, HALF - 3, taken, 4)
		p:place(math.abs(x), y, scene:random(0, 360))
		taken[#taken + 1] = { math.abs(x), y }
	end
end

return env

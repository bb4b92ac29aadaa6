-- EXP_Forage: cooperative foraging (docs/teams.md). Forty food objects lie
-- scattered in a walled arena; a bot gathers one by touching it (reward
-- Gather: 1 each, paid to that bot), and it leaves the world. In 1,500
-- ticks one bot cannot clear the arena: a team can. The episode ends when
-- every object is gathered, or at TICKLIM. The metric `collected` counts
-- the objects gathered in the episode, by every bot.
--
-- Teams: every bot of every team forages; a one-agent task runs one bot.
-- A bot sees its food with its object trackers (the nearest free object)
-- and its walls and the other bots with its proximity sensors.
local arena = require "lib.arena"
local teams = require "lib.teams"

local N_OBJECTS = 40
local HALF = 30 -- the arena is [-30, 30]^2 inside its wall

local env = {}
local objects = {}
local bots = {}

function env.init(scene, task)
	arena.border(scene, HALF + 1.5, 1.5)
	for i = 1, N_OBJECTS do
		objects[i] = scene:object{ name = "food" .. i, x = 0, y = 0, radius = 0.5 }
	end
	local by_team
	bots, by_team = teams.spawn(scene, { spacing = 4 })
	if #scene:teams() == 0 then
		scene:reward("Gather", { bot = bots[1], k = 1 })
	else
		for _, t in ipairs(scene:teams()) do
			scene:reward("Gather", { team = t.name, k = 1 })
		end
	end
	env.collected = scene:metric("collected")
	-- the episode ends once every object is gathered; the count is kept
	-- as it goes
	scene:control(function(scene)
		local n = 0
		for _, b in ipairs(bots) do n = n + b:counts().gathered end
		env.collected:set(n)
		return n == N_OBJECTS
	end)
	scene:control("NextOnTimeout", { ticks = tonumber(task.TICKLIM) or 1500 })
	env.by_team = by_team
end

function env.reset(scene, episode)
	local taken = teams.scatter(scene, bots, HALF - 4, {}, 5)
	for _, o in ipairs(objects) do
		local x, y = arena.random_point(scene, HALF - 2, taken, 2.5)
		taken[#taken + 1] = { x, y }
		o:place(x, y)
		o:set_active(true)
	end
end

return env

-- Roam: the Avoid example's environment. EXP_Avoid's arena (a 400 x 400
-- field of about 300 cylinders, lua/envs/EXP_Avoid.lua), but scored for
-- covering ground without touching anything:
--   +0.2 per unit/s of speed along the heading (about +1 a tick flat out,
--        negative when backing),
--   -10 every tick the bot touches something,
--   -1 * sum(0.25 - v) over the proximity sensors reading 0.25 or less
--        (something within 3 of the rim).
-- A bot standing still scores 0, so only a bot that moves can do well;
-- EXP_Avoid pays about 1 a tick for standing still in the open.
-- Each episode starts at (0, 5), clear of the grid, facing a random way
-- (bot:place takes degrees, as every angle in Lua does).
local arena = require "lib.arena"

local env = {}
local bot

function env.init(scene, task)
	arena.border(scene, 200, 4)
	scene:grid{ x0 = -189, y0 = -189, x1 = 189, y1 = 189, spacing = 23,
		jitter = 12, min_size = 2.2, size_variability = 4, clearance = 2 }
	bot = scene:bot{ x = 0, y = 5 }
	local sensors = {}
	for i = 1, 10 do sensors[i] = "S" .. i end
	scene:reward("ForwardSpeed", { bot = bot, k = 0.2 })
	scene:reward("PunishOnCollision", { bot = bot, k = -10 })
	scene:reward("SensorUnderThreshold", { bot = bot, sensors = sensors,
		threshold = 0.25, k = -1 })
	scene:control("NextOnTimeout", { bot = bot, ticks = tonumber(task.TICKLIM) or 15000 })
end

function env.reset(scene, episode)
	bot:place(0, 5, scene:random(0, 360))
end

return env

-- Kheperax's standard maze and task (docs/world.md, "The mazes"), for
-- KheperaxBot: 250 steps; fitness the sum over the steps of -(dl^2 + dr^2),
-- the squares of the commanded wheel moves (dl = (2c - 1) * 0.025), in
-- [-0.3125, 0]; behaviour the final (x, y) in the unit square. Solved when
-- the robot ends within 0.05 of the target (0.15, 0.9).
local maze = require "lib.maze"

return maze.env(maze.kheperax, {
	ticks = 250, reach = 0.05, stop_at_goal = false,
	rewards = function(scene, bot, goal)
		scene:reward("Effort", { bot = bot, k = -0.025 ^ 2 })
	end,
})

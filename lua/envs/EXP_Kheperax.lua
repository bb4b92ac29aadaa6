-- Kheperax's standard maze and task (docs/world.md, "The mazes"), for
-- KheperaxBot: 250 steps; fitness the sum over the steps of -(dl^2 + dr^2),
-- the squares of the commanded wheel moves (dl = (2c - 1) * 0.025), in
-- [-0.3125, 0]; behaviour the final (x, y) in the unit square. The task
-- has no goal to solve: it is a coverage task (quality-diversity fills the
-- maze's grid of final positions), and a learning run that stopped at the
-- first robot to end near the target (0.15, 0.9) would cut it short.
local maze = require "lib.maze"

return maze.env(maze.kheperax, {
	ticks = 250, reach = 0.05, stop_at_goal = false, no_solved = true,
	rewards = function(scene, bot, goal)
		scene:reward("Effort", { bot = bot, k = -0.025 ^ 2 })
	end,
})

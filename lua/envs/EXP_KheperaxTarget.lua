-- Kheperax's target task on its standard maze (docs/world.md, "The mazes"),
-- for KheperaxBot: each step pays -(the distance to the target (0.15, 0.9)),
-- in the unit square's units; the episode ends when the robot comes within
-- 0.05 of it (solved), or after 250 steps.
local maze = require "lib.maze"

return maze.env(maze.kheperax, {
	ticks = 250, reach = 0.05, stop_at_goal = true,
	rewards = function(scene, bot, goal)
		scene:reward("Distance", { bot = bot, target = goal,
			k = -1 / maze.kheperax.scale })
	end,
})

-- The hard maze of the novelty-search paper (Lehman & Stanley 2011;
-- docs/world.md, "The mazes"), for MazeBot: 400 steps, over when the robot
-- comes within 5 units of the goal; fitness 300 - its distance to the goal
-- at the end (the paper's units: 8 to a metre of evo's world).
local maze = require "lib.maze"

return maze.env(maze.hard, {
	ticks = 400, reach = 5, stop_at_goal = true,
	rewards = function(scene, bot, goal)
		scene:reward("FinalDistance", { bot = bot, target = goal,
			k = -1 / maze.hard.scale, k2 = 300 })
	end,
})

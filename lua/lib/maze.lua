-- The deceptive mazes (docs/world.md, "The mazes"): their walls as published,
-- in the papers' own units, and what every maze environment does with them.
-- A maze is scaled into evo's world so that its robot has a radius of 1 m,
-- as BotType8 has: the novelty-search mazes (Lehman & Stanley 2011; robot
-- radius 8) by 1/8, Kheperax's unit square (robot radius 0.015) by 1/0.015.
local maze = {}

-- The medium and hard maps of the novelty-search paper, from Lehman's
-- published maze files (medium_maze.txt, hard_maze.txt): start, heading
-- (degrees), goal, and the walls as {x1, y1, x2, y2}.
maze.medium = {
	scale = 1 / 8, start = { 30, 22 }, heading = 0, goal = { 270, 100 },
	walls = {
		{ 293, 7, 289, 130 }, { 289, 130, 6, 134 }, { 6, 134, 8, 5 },
		{ 8, 5, 292, 7 }, { 241, 130, 58, 65 }, { 114, 7, 73, 42 },
		{ 130, 91, 107, 46 }, { 196, 8, 139, 51 }, { 219, 122, 182, 63 },
		{ 267, 9, 214, 63 }, { 271, 129, 237, 88 },
	},
}

maze.hard = {
	scale = 1 / 8, start = { 36, 184 }, heading = 0, goal = { 31, 20 },
	walls = {
		{ 41, 5, 3, 8 }, { 3, 8, 4, 49 }, { 4, 49, 57, 53 }, { 4, 49, 7, 202 },
		{ 7, 202, 195, 198 }, { 195, 198, 186, 8 }, { 186, 8, 39, 5 },
		{ 56, 54, 56, 157 }, { 57, 106, 158, 162 }, { 77, 201, 108, 164 },
		{ 6, 80, 33, 121 }, { 192, 146, 87, 91 }, { 56, 55, 133, 30 },
	},
}

-- Kheperax's "standard" map (kheperax 0.2.0): the unit square, its nine
-- inside walls, then the four borders; start (0.15, 0.15) facing +y, the
-- target (0.15, 0.9) of radius 0.05.
maze.kheperax = {
	scale = 1 / 0.015, start = { 0.15, 0.15 }, heading = 90,
	goal = { 0.15, 0.9 }, bounds = { 0, 0, 1, 1 },
	walls = {
		{ 0.25, 0.25, 0.25, 0.75 }, { 0.14, 0.45, 0.0, 0.65 },
		{ 0.25, 0.75, 0.0, 0.8 }, { 0.25, 0.75, 0.66, 0.875 },
		{ 0.355, 0.0, 0.525, 0.185 }, { 0.25, 0.5, 0.75, 0.215 },
		{ 1.0, 0.25, 0.435, 0.55 }, { 0.0, 0.8, 0.0, 1.0 },
		{ 0.355, 0.0, 1.0, 0.0 },
		{ 0, 0, 1, 0 }, { 0, 0, 0, 1 }, { 0, 1, 1, 1 }, { 1, 1, 1, 0 },
	},
}

-- The box around a maze's walls, in its own units: x0, y0, x1, y1.
function maze.bounds(m)
	if m.bounds then return table.unpack(m.bounds) end
	local x0, y0, x1, y1 = math.huge, math.huge, -math.huge, -math.huge
	for _, w in ipairs(m.walls) do
		x0 = math.min(x0, w[1], w[3]); x1 = math.max(x1, w[1], w[3])
		y0 = math.min(y0, w[2], w[4]); y1 = math.max(y1, w[2], w[4])
	end
	return x0, y0, x1, y1
end

-- Build maze m in the scene: its walls, the goal (a zone of half side
-- goal_size, in the maze's units, that the viewer shows and the radars look
-- at) and the bot at the start. Returns the bot and the goal element.
function maze.build(scene, m, goal_size)
	local s = m.scale
	for _, w in ipairs(m.walls) do
		scene:wall{ x1 = w[1] * s, y1 = w[2] * s, x2 = w[3] * s, y2 = w[4] * s }
	end
	local goal = scene:zone{ name = "goal", x = m.goal[1] * s, y = m.goal[2] * s,
		size = goal_size * s }
	local bot = scene:bot{ x = m.start[1] * s, y = m.start[2] * s, angle = m.heading }
	for _, name in ipairs(bot:sensors("radar", "untargeted")) do
		bot:target(name, goal)
	end
	return bot, goal
end

-- The bot's distance to the goal, in the maze's units.
function maze.distance(m, bot)
	local x, y = bot:pose()
	local s = m.scale
	return math.sqrt((x / s - m.goal[1]) ^ 2 + (y / s - m.goal[2]) ^ 2)
end

-- The behaviour: where the bot ended, scaled into [0, 1]^2 over the maze's
-- bounds.
function maze.behaviour(m, bot)
	local x, y = bot:pose()
	local x0, y0, x1, y1 = maze.bounds(m)
	local function unit(v) return math.max(0, math.min(1, v)) end
	return { unit((x / m.scale - x0) / (x1 - x0)), unit((y / m.scale - y0) / (y1 - y0)) }
end

-- An environment for maze m: its walls, bot and goal; the episode of
-- `ticks` steps (TICKLIM overrides it), ended early when the bot's centre
-- comes within `reach` of the goal (maze units) when `stop_at_goal`;
-- `rewards(scene, bot, goal)` adds the fitness; solved when the bot ends
-- within `reach`, unless `no_solved` (a task whose aim is not the goal:
-- a learning run stops at its first solver).
function maze.env(m, opts)
	local env = {}
	local bot, goal
	function env.init(scene, task)
		bot, goal = maze.build(scene, m, opts.reach or 0.05)
		opts.rewards(scene, bot, goal)
		local ticks = tonumber(task.TICKLIM) or opts.ticks
		-- NextOnTimeout ends the episode once more than `ticks` steps
		-- were checked: ticks - 1 gives episodes of `ticks` steps
		scene:control("NextOnTimeout", { bot = bot, ticks = ticks - 1 })
		if opts.stop_at_goal then
			scene:control("NextOnTargetReached", { bot = bot, target = goal,
				threshold = opts.reach * m.scale })
		end
	end
	function env.behaviour(scene, b) return maze.behaviour(m, b) end
	if not opts.no_solved then
		function env.solved(scene, b) return maze.distance(m, b) < opts.reach end
	end
	return env
end

return maze

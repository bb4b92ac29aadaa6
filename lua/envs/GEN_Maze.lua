-- GEN_Maze: OPENENDED's generator of mazes for MazeBot (docs/openended.md).
-- A maze is a grid of w x h cells of CELL metres inside a border; the bot
-- starts in cell (1, 1) facing +x, the goal is cell (w, h). Its genes are
-- its walls: {x, y, dir, len, gap}, a wall of `len` cells from cell (x, y)
-- along +x (dir 0) or +y (dir 1), with a passage at its cell number `gap`
-- (0-based). A wall of len 0 spans the whole maze from the border: the
-- row y (dir 0) or the column x (dir 1), however wide or tall the maze
-- grows, its passage at cell `gap` counted from the border, or at the far
-- border when gap is -1. Mutations add a short wall, drop a wall, add a
-- spanning wall with its passage at one end, move a wall's passage
-- anywhere, one cell along or to the far end of its wall, or enlarge the
-- maze by a row or a column (their shares: ADD_WALL ... below); a mutant
-- whose goal cannot be reached is drawn again. Spanning walls whose
-- passages lie at alternate ends make the bot turn back: detours. A
-- maze's size is its solution path: the fewest cell steps from start to
-- goal (a breadth-first search over the free cells), and its episode
-- lasts TICKS_BASE + TICKS_PER_CELL ticks per step of it.
local openended = require "lib.openended"

local CELL = 4            -- metres: MazeBot's radius is 1
local TICKS_BASE = 100
local TICKS_PER_CELL = 60 -- 2 s a cell at 30 ticks a second
local MAX_SIDE = 24
local TRIES = 20          -- draws of a mutant before the parent is kept

local gen = {}

-- The first maze: 3 x 2 cells, no wall (path 3).
function gen.seed() return { w = 3, h = 2, walls = {} } end

local function copy(g)
	local walls = {}
	for i, w in ipairs(g.walls) do walls[i] = { w[1], w[2], w[3], w[4], w[5] } end
	return { w = g.w, h = g.h, walls = walls }
end

-- The blocked cells: blocked[(y - 1) * w + x] for the walls' cells but
-- their passages, the start and the goal.
local function blocked_cells(g)
	local b = {}
	for _, wall in ipairs(g.walls) do
		local x, y, dir, len, gap = wall[1], wall[2], wall[3], wall[4], wall[5]
		if len == 0 then -- spanning: from the border to the border
			len = dir == 0 and g.w or g.h
			if dir == 0 then x = 1 else y = 1 end
			if gap < 0 then gap = len - 1 end
		end
		for k = 0, len - 1 do
			local cx, cy = x + (dir == 0 and k or 0), y + (dir == 1 and k or 0)
			if k ~= gap and cx >= 1 and cx <= g.w and cy >= 1 and cy <= g.h then
				b[(cy - 1) * g.w + cx] = true
			end
		end
	end
	b[1] = nil
	b[g.w * g.h] = nil
	return b
end

-- The solution path's length in cell steps, nil when the goal cannot be
-- reached (breadth-first search, four neighbours).
function gen.path_length(g)
	local b, w, h = blocked_cells(g), g.w, g.h
	local dist, queue, head = { [1] = 0 }, { 1 }, 1
	while queue[head] do
		local c = queue[head]; head = head + 1
		if c == w * h then return dist[c] end
		local x, y = (c - 1) % w + 1, (c - 1) // w + 1
		for _, d in ipairs{ { 1, 0 }, { -1, 0 }, { 0, 1 }, { 0, -1 } } do
			local nx, ny = x + d[1], y + d[2]
			local n = (ny - 1) * w + nx
			if nx >= 1 and nx <= w and ny >= 1 and ny <= h and not b[n] and not dist[n] then
				dist[n] = dist[c] + 1
				queue[#queue + 1] = n
			end
		end
	end
	return nil
end

gen.size = gen.path_length

function gen.valid(g) return gen.path_length(g) ~= nil end

function gen.ticks(g) return TICKS_BASE + TICKS_PER_CELL * (gen.path_length(g) or 0) end

-- rng: learn.rng's generator (rng:unit() in [0, 1)).
local function draw(rng, lo, hi) return lo + math.floor(rng:unit() * (hi - lo + 1)) end

-- The far end of a wall from its passage: the passage at the end
-- farther from where it is (a spanning wall's at -1, the far border, or 0).
local function far_end(wall)
	if wall[4] == 0 then return wall[5] == 0 and -1 or 0 end
	return wall[5] < wall[4] / 2 and wall[4] - 1 or 0
end

-- Where a spanning wall along dir may go: the inner rows (dir 0) or
-- columns (dir 1), not the first nor the last, with no spanning wall of
-- that dir on them or beside them (a corridor is left between two).
local function span_rows(m, dir)
	local taken, list = {}, {}
	for _, w in ipairs(m.walls) do
		if w[4] == 0 and w[3] == dir then taken[dir == 0 and w[2] or w[1]] = true end
	end
	for at = 2, (dir == 0 and m.h or m.w) - 1 do
		if not (taken[at - 1] or taken[at] or taken[at + 1]) then list[#list + 1] = at end
	end
	return list
end

-- A wall's passage one cell along it, either way (a spanning wall's
-- "far border" becomes the cell it is at now, then moves).
local function shift_gap(m, wall, step)
	local len = wall[4] == 0 and (wall[3] == 0 and m.w or m.h) or wall[4]
	local gap = wall[5] < 0 and len - 1 or wall[5]
	wall[5] = math.max(0, math.min(len - 1, gap + step))
end

-- The kinds of mutation, by where a draw in [0, 1) falls: below ADD_WALL
-- a short wall, then a wall dropped, a spanning wall, a passage anywhere
-- on its wall, a passage one cell along, a passage to the far end, and
-- from FAR_GAP on a row or a column more.
local ADD_WALL, DROP_WALL, ADD_SPAN, MOVE_GAP, SHIFT_GAP, FAR_GAP =
	0.15, 0.25, 0.45, 0.55, 0.7, 0.8

local function mutant(g, rng)
	local m = copy(g)
	local r = rng:unit()
	local of_a_wall = (r >= ADD_WALL and r < DROP_WALL) or (r >= ADD_SPAN and r < FAR_GAP)
	if of_a_wall and #m.walls == 0 then r = 0 end -- no wall to change: one added
	if r < ADD_WALL then
		local dir = draw(rng, 0, 1)
		local len = draw(rng, 2, math.max(2, dir == 0 and m.w or m.h))
		m.walls[#m.walls + 1] = { draw(rng, 1, m.w), draw(rng, 1, m.h), dir, len, draw(rng, 0, len - 1) }
	elseif r < DROP_WALL then
		table.remove(m.walls, draw(rng, 1, #m.walls))
	elseif r < ADD_SPAN then
		local dir = draw(rng, 0, 1)
		local free = span_rows(m, dir)
		if #free == 0 then return nil end -- no room: drawn again
		local at = free[draw(rng, 1, #free)]
		m.walls[#m.walls + 1] = { dir == 1 and at or 1, dir == 0 and at or 1, dir, 0,
			draw(rng, 0, 1) == 0 and 0 or -1 }
	elseif r < MOVE_GAP then
		local wall = m.walls[draw(rng, 1, #m.walls)]
		local len = wall[4] == 0 and (wall[3] == 0 and m.w or m.h) or wall[4]
		wall[5] = draw(rng, 0, len - 1)
	elseif r < SHIFT_GAP then
		shift_gap(m, m.walls[draw(rng, 1, #m.walls)], draw(rng, 0, 1) == 0 and -1 or 1)
	elseif r < FAR_GAP then
		local wall = m.walls[draw(rng, 1, #m.walls)]
		wall[5] = far_end(wall)
	elseif rng:unit() < 0.5 then
		m.w = math.min(MAX_SIDE, m.w + 1)
	else
		m.h = math.min(MAX_SIDE, m.h + 1)
	end
	return m
end

-- A mutant of g whose goal can be reached; g's copy after TRIES draws.
function gen.mutate(g, rng)
	for _ = 1, TRIES do
		local m = mutant(g, rng)
		if m and gen.valid(m) then return m end
	end
	return copy(g)
end

local function centre(cx, cy) return (cx - 0.5) * CELL, (cy - 0.5) * CELL end

function gen.init(scene, task)
	gen.bot = scene:bot{ x = CELL / 2, y = CELL / 2 }
	gen.goal = scene:zone{ name = "goal", x = 0, y = 0, size = CELL / 4 }
	for _, name in ipairs(gen.bot:sensors("radar", "untargeted")) do
		gen.bot:target(name, gen.goal)
	end
	scene:reward("FinalDistance", { bot = gen.bot, target = gen.goal, k = -1, k2 = 100 })
	scene:control("NextOnTargetReached", { bot = gen.bot, target = gen.goal, threshold = CELL / 2 })
end

-- The episode's obstacles: a box for each blocked cell and each cell of
-- the border; the bot at the start, the goal in its cell.
function gen.build(scene, g)
	local list, b = {}, blocked_cells(g)
	local function box(cx, cy)
		local x, y = centre(cx, cy)
		list[#list + 1] = { x = x, y = y, size = CELL / 2, shape = "box" }
	end
	for cy = 0, g.h + 1 do
		for cx = 0, g.w + 1 do
			if cx == 0 or cy == 0 or cx == g.w + 1 or cy == g.h + 1 or b[(cy - 1) * g.w + cx] then
				box(cx, cy)
			end
		end
	end
	gen.bot:place(CELL / 2, CELL / 2, 0)
	gen.goal:place(centre(g.w, g.h))
	return list
end

function gen.solved(scene, bot, g)
	local x, y = bot:pose()
	local gx, gy = centre(g.w, g.h)
	return (x - gx) ^ 2 + (y - gy) ^ 2 < (CELL / 2) ^ 2
end

return openended.env(gen)

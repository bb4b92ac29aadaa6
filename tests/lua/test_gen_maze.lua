-- Unit tests of lua/envs/GEN_Maze.lua's genomes and lua/lib/openended.lua's
-- genome text (docs/openended.md), run by tests/sim/lua/test_lua_scripts.c.
-- Each entry of the returned table is one test; it fails by raising.
local openended = require "lib.openended"
local gen = require("envs.GEN_Maze").generator
local random = require "learn.rng"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local T = {}

-- Solution paths worked out by hand on the grid (start (1, 1), goal
-- (w, h), steps between neighbouring cells).
function T.solution_paths_are_the_fewest_steps()
	check(gen.path_length(gen.seed()) == 3, "the seed, 3 x 2 and empty: 2 + 1 steps")
	check(gen.path_length{ w = 3, h = 3, walls = {} } == 4, "3 x 3, empty: 2 + 2")
	-- a serpentine in 3 x 5: row 2 open only at x = 3, row 4 only at
	-- x = 1: (1,1) (2,1) (3,1) (3,2) (3,3) (2,3) (1,3) (1,4) (1,5) (2,5)
	-- (3,5), 10 steps where an empty grid takes 6
	local snake = { w = 3, h = 5, walls = { { 1, 2, 0, 3, 2 }, { 1, 4, 0, 3, 0 } } }
	check(gen.path_length(snake) == 10, "the serpentine: " .. tostring(gen.path_length(snake)))
	check(gen.size(snake) == 10 and gen.ticks(snake) == 100 + 60 * 10, "size and ticks follow the path")
	-- a wall across the whole maze whose passage lies outside it
	local shut = { w = 3, h = 2, walls = { { 2, 1, 1, 3, 2 } } }
	check(gen.path_length(shut) == nil and not gen.valid(shut), "no way through")
end

-- Walls of len 0 span the maze from border to border, however it grows;
-- passages at alternate ends make a detour, worked out by hand.
function T.spanning_walls_make_detours()
	-- 4 x 5, row 2 spanned with its passage at the far border (x = 4),
	-- row 4 with its passage at x = 1: along row 1 to x = 4 (3 steps), down
	-- to row 3 (2), back to x = 1 (3), down to row 5 (2), on to x = 4 (3):
	-- 13 steps where w + h - 2 = 7, a detour of 6 = 2 (w - 1), one
	-- crossing of the maze there and back
	local snake = { w = 4, h = 5, walls = { { 1, 2, 0, 0, -1 }, { 1, 4, 0, 0, 0 } } }
	check(gen.path_length(snake) == 13, "the spanned serpentine: " .. tostring(gen.path_length(snake)))
	-- one column wider, the walls still span it and the far passage
	-- follows the border: 4 + 2 + 4 + 2 + 4 = 16, a detour of 2 (5 - 1) = 8
	snake.w = 5
	check(gen.path_length(snake) == 16, "wider: " .. tostring(gen.path_length(snake)))
	-- a column spanned in 3 x 3 with its passage at y = 1 (gap 0): the
	-- bot goes along row 1 and down, 4 steps as in the empty grid
	check(gen.path_length{ w = 3, h = 3, walls = { { 2, 1, 1, 0, 0 } } } == 4, "column, near")
	-- 5 x 3, column 2 open at its far end (y = 3), column 4 at y = 1:
	-- down to (1,3) 2, across to (3,3) 2, up to (3,1) 2, across to (5,1) 2,
	-- down to (5,3) 2: 10 steps where w + h - 2 = 6, a detour of 2 (h - 1)
	local cols = { w = 5, h = 3, walls = { { 2, 1, 1, 0, -1 }, { 4, 1, 1, 0, 0 } } }
	check(gen.path_length(cols) == 10, "columns: " .. tostring(gen.path_length(cols)))
	-- a spanning wall's passage out of the maze shuts it
	check(not gen.valid{ w = 3, h = 3, walls = { { 1, 2, 0, 0, 5 } } }, "no way through")
end

-- Mutants are valid, leave their parent as it was, and in many draws add
-- walls, move passages and enlarge the maze, from one seed the same ones.
function T.mutations_are_valid_and_seeded()
	local function run(seed)
		local rng, g, texts = random.new(seed), gen.seed(), {}
		local grew, walls, moved, spans, detour = false, 0, false, 0, 0
		for i = 1, 120 do
			local before = openended.encode(g)
			local m = gen.mutate(g, rng)
			check(openended.encode(g) == before, "mutate changed its parent")
			check(gen.valid(m), "an invalid mutant: " .. openended.encode(m))
			grew = grew or m.w > g.w or m.h > g.h
			walls = math.max(walls, #m.walls)
			if #m.walls == #g.walls and #g.walls > 0 and m.w == g.w and m.h == g.h
				and openended.encode(m) ~= before then moved = true end
			texts[i] = openended.encode(m)
			local n = 0
			for _, w in ipairs(m.walls) do if w[4] == 0 then n = n + 1 end end
			spans = math.max(spans, n)
			detour = math.max(detour, gen.path_length(m) - (m.w + m.h - 2))
			g = m
		end
		check(grew and walls > 3 and moved and spans >= 2, "every kind of mutation happened")
		check(detour >= 4, "a mutant makes a detour of " .. detour .. " steps")
		return table.concat(texts, "\n")
	end
	check(run(5) == run(5), "one seed, one sequence")
	check(run(5) ~= run(6), "another seed, another sequence")
end

-- A genome's text: keys sorted, integers as integers, read back as it was.
function T.genome_text_round_trips()
	local g = { w = 4, h = 3, walls = { { 1, 2, 0, 3, 1 } }, name = "a \"b\"", f = 0.1 }
	local text = openended.encode(g)
	check(text == '{f=0.10000000000000001,h=3,name="a \\"b\\"",w=4,walls={{1,2,0,3,1,},},}', text)
	local back = openended.decode(text)
	check(openended.encode(back) == text and back.walls[1][4] == 3, "read back")
	check(not pcall(openended.encode, { print }), "a function is no genome")
end

return T

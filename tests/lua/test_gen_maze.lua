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

-- Mutants are valid, leave their parent as it was, and in many draws add
-- walls, move passages and enlarge the maze, from one seed the same ones.
function T.mutations_are_valid_and_seeded()
	local function run(seed)
		local rng, g, texts = random.new(seed), gen.seed(), {}
		local grew, walls, moved = false, 0, false
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
			g = m
		end
		check(grew and walls > 3 and moved, "every kind of mutation happened")
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

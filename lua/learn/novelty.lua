-- NOVELTY: novelty search (Lehman & Stanley, "Abandoning Objectives:
-- Evolution through the Search for Novelty Alone", Evolutionary
-- Computation 19(2), 2011) over NEAT's genomes.
--
--	local novelty = require "learn.novelty"
--	local random = require "learn.rng"
--	local pop = novelty.new{ inputs = 10, outputs = 2, options = { pop_size = 250 },
--		rng = random.new(42) }
--	for gen = 1, 100 do
--		local fit, desc = {}, {}
--		for i, g in ipairs(pop:genomes()) do fit[i], desc[i] = run(novelty.to_net(g)) end
--		pop:tell(fit, desc)
--	end
--	print(pop.best.fitness, #pop.archive // pop.dims)
--
-- A candidate is scored by what it did, not by how well: each generation
-- comes with a behaviour descriptor per genome (numbers in [0, 1], the
-- bot's final position by default: docs/learning.md), and a genome's
-- novelty is the mean Euclidean distance from its descriptor to its k
-- nearest neighbours among the rest of the generation and the archive.
-- NEAT (learn.neat: speciation, fitness sharing, crossover, mutation)
-- then breeds the next generation with novelty in place of fitness. The
-- archive takes every candidate whose novelty exceeds rho_min, and rho_min
-- adapts as in Lehman's reference code (noveltyset.h): after `stall`
-- generations in a row that added none it is multiplied by `lower` (never
-- below `rho_floor`), and after a generation that added more than `crowd`
-- it is multiplied by `raise`.
--
-- The objective still counts for the result: pop.best is the best genome
-- by fitness ever seen, the champion the loop saves, and the loop stops
-- at a solution as with NEAT.
--
-- Determinism: the novelty of a generation does not depend on the order
-- of the neighbours (the k smallest distances are summed in ascending
-- order), the archive takes candidates in genomes() order, and the only
-- random draws (NOVELTY_RANDOM_ADD's) go through the population's rng.
-- The kNN is evo.novelty's C where the state has it (the learning
-- loop's), else knn_lua, which it equals bit for bit.
local common = require "learn.common"
local neat = require "learn.neat"
local random = require "learn.rng"

local novelty = {}

local fast = package.loaded["evo.novelty"]

-- Novelty search's own options, with the paper's or the reference code's
-- value; every NEAT option (NEAT_* keys, POPSIZE) applies too.
novelty.defaults = {
	k = 15, -- nearest neighbours a novelty is the mean distance to (paper: 15)
	rho_min = 0.03, -- the archive's threshold at the start; the reference code's 6.0 in a maze
	-- about 200 units wide, where descriptors are in [0, 1]
	rho_floor = 0.00125, -- rho_min never goes below this (reference code: 0.25 of 200)
	stall = 10, -- generations in a row with no addition before rho_min is lowered (reference code: 10)
	lower = 0.95, -- rho_min is multiplied by this then (reference code: 0.95, "lowered by 5%")
	crowd = 4, -- more additions than this in one generation raise rho_min (reference code: 4)
	raise = 1.2, -- rho_min is multiplied by this then (reference code: 1.2, "raised by 20%")
	archive_limit = 0, -- the archive's size at most, the oldest dropped first; 0: no limit (paper)
	random_add = 0, -- chance that a candidate below rho_min enters the archive anyway (0: never,
	-- as in the reference code's threshold rule)
	fitness_weight = 0, -- 0: the score is novelty alone (paper); above: (1 - w) times novelty
	-- plus w times fitness, each scaled to [0, 1] over the generation
	min_fitness = "off", -- minimal criterion: a candidate whose fitness is below this number
	-- scores 0 and never enters the archive; off: none
	coverage_grid = 0, -- cells a dimension of a passive result grid every evaluated descriptor
	-- is marked in, its coverage logged (pyribs' measure); 0: none
}

-- .simbatch key -> option name.
novelty.task_keys = {
	NOVELTY_K = "k",
	NOVELTY_THRESHOLD = "rho_min",
	NOVELTY_THRESHOLD_FLOOR = "rho_floor",
	NOVELTY_STALL = "stall",
	NOVELTY_LOWER = "lower",
	NOVELTY_CROWD = "crowd",
	NOVELTY_RAISE = "raise",
	NOVELTY_ARCHIVE_LIMIT = "archive_limit",
	NOVELTY_RANDOM_ADD = "random_add",
	NOVELTY_FITNESS_WEIGHT = "fitness_weight",
	NOVELTY_MIN_FITNESS = "min_fitness",
	NOVELTY_COVERAGE_GRID = "coverage_grid",
}

-- The keys of another method's table this one reads too: every NEAT key.
novelty.other_keys = neat.task_keys

novelty.ranges = {
	k = { lo = 1, hi = 1000, int = true },
	rho_min = { lo = 0, above = true },
	rho_floor = common.POSITIVE,
	stall = common.COUNT,
	lower = { lo = 0, hi = 1, above = true },
	crowd = common.WHOLE,
	raise = { lo = 1 },
	archive_limit = common.WHOLE,
	random_add = common.PROB,
	fitness_weight = common.PROB,
	coverage_grid = { lo = 0, hi = 10000, int = true },
}

for name in pairs(novelty.defaults) do
	assert(neat.defaults[name] == nil, "novelty: option " .. name .. " is also NEAT's")
end

-- The minimal criterion's fitness, or nil when off.
local function min_fitness(o)
	return o.min_fitness ~= "off" and tonumber(o.min_fitness) or nil
end

-- Options from a task table: NEAT's (neat.options_from_task) and novelty
-- search's. Returns the options and the sorted NEAT_* and NOVELTY_* keys
-- neither knows; raises on a malformed value.
function novelty.options_from_task(task)
	local o, unknown = neat.options_from_task(task)
	local own, more = common.options_from(task, "NOVELTY_", novelty.task_keys, novelty.defaults,
		function(key, s, value)
			if key == "NOVELTY_MIN_FITNESS" and s ~= "off" then
				local v = tonumber(s)
				if not v or v ~= v or v == math.huge or v == -math.huge then
					error(key .. ": expected off or a number, found '" .. tostring(value) .. "'", 0)
				end
			end
		end, novelty.ranges)
	for k, v in pairs(own) do o[k] = v end
	for _, k in ipairs(more) do unknown[#unknown + 1] = k end
	table.sort(unknown)
	return o, unknown
end

---------------------------------------------------------------------------
-- Novelty

-- The novelty of each point of `points` (a flat list, d numbers a point)
-- against the other points and the archive (flat too): the mean of the k
-- smallest distances, summed in ascending order; the mean of all when
-- there are fewer than k, 0 when there are none.
function novelty.knn_lua(points, archive, d, k)
	local n, m = #points // d, #archive // d
	local out = {}
	for i = 1, n do
		local base = (i - 1) * d
		local dist = {}
		local function to(set, j)
			local s = 0.0
			for q = 1, d do
				local t = points[base + q] - set[j * d + q]
				s = s + t * t
			end
			dist[#dist + 1] = math.sqrt(s)
		end
		for j = 0, n - 1 do
			if j ~= i - 1 then to(points, j) end
		end
		for j = 0, m - 1 do to(archive, j) end
		table.sort(dist)
		local c = math.min(k, #dist)
		local sum = 0.0
		for q = 1, c do sum = sum + dist[q] end
		out[i] = c > 0 and sum / c or 0.0
	end
	return out
end
novelty.knn = fast and fast.knn or novelty.knn_lua

-- `values` scaled to [0, 1] over the entries `pass` marks: (x - min) /
-- (max - min), 0 where all are equal.
local function scaled(values, pass)
	local lo, hi = math.huge, -math.huge
	for i, x in ipairs(values) do
		if pass[i] then lo, hi = math.min(lo, x), math.max(hi, x) end
	end
	local out = {}
	for i, x in ipairs(values) do out[i] = hi > lo and (x - lo) / (hi - lo) or 0.0 end
	return out
end

-- The scores NEAT breeds by: novelty, or with fitness_weight w the mix
-- (1 - w) N + w F of both scaled over the generation; 0 for a candidate
-- that fails the minimal criterion.
function novelty.scores(nov, fitness, pass, o)
	local w = o.fitness_weight
	local out = {}
	if w == 0 then
		for i, x in ipairs(nov) do out[i] = pass[i] and x or 0.0 end
		return out
	end
	local n, f = scaled(nov, pass), scaled(fitness, pass)
	for i in ipairs(nov) do out[i] = pass[i] and (1 - w) * n[i] + w * f[i] or 0.0 end
	return out
end

---------------------------------------------------------------------------
-- The archive

-- Adds candidate i of the generation (its descriptor in `flat`, dims
-- numbers a candidate) with what a user wants to know of it: its
-- generation, fitness and novelty.
local function archive_add(self, flat, i, generation, fitness, nov)
	local a, meta, d = self.archive, self.archive_meta, self.dims
	for q = 1, d do a[#a + 1] = flat[(i - 1) * d + q] end
	meta[#meta + 1] = generation
	meta[#meta + 1] = fitness
	meta[#meta + 1] = nov
end

-- Drops the oldest entries past archive_limit.
local function archive_trim(self)
	local limit, d = self.options.archive_limit, self.dims
	local n = #self.archive // d
	if limit == 0 or n <= limit then return end
	local drop = n - limit
	table.move(self.archive, drop * d + 1, n * d, 1)
	for q = #self.archive, limit * d + 1, -1 do self.archive[q] = nil end
	table.move(self.archive_meta, drop * 3 + 1, n * 3, 1)
	for q = #self.archive_meta, limit * 3 + 1, -1 do self.archive_meta[q] = nil end
end

-- The archive's rule for one generation: every candidate that meets the
-- minimal criterion and whose novelty exceeds rho_min is added (in
-- genomes() order), and with random_add each other one that meets it
-- with that chance; then rho_min adapts to how many passed it (the
-- random additions do not count, as in the reference code). Returns
-- how many passed rho_min.
function novelty.update_archive(self, flat, fitness, nov, pass)
	local o = self.options
	local added = 0
	for i = 1, #nov do
		if pass[i] then
			if nov[i] > self.rho_min then
				archive_add(self, flat, i, self.generation, fitness[i], nov[i])
				added = added + 1
			elseif o.random_add > 0 and self.rng:unit() < o.random_add then
				archive_add(self, flat, i, self.generation, fitness[i], nov[i])
			end
		end
	end
	archive_trim(self)
	self.stalled = added == 0 and self.stalled + 1 or 0
	if self.stalled >= o.stall then
		self.rho_min = math.max(o.rho_floor, self.rho_min * o.lower)
		self.stalled = 0
	end
	if added > o.crowd then self.rho_min = self.rho_min * o.raise end
	return added
end

---------------------------------------------------------------------------
-- Population: NEAT's, bred by novelty

local Pop = setmetatable({}, { __index = neat.Pop })
Pop.__index = Pop

function novelty.new(args)
	local user, own = {}, {}
	for k, v in pairs(args.options or {}) do
		if novelty.defaults[k] ~= nil then own[k] = v else user[k] = v end
	end
	local pop = neat.new{ inputs = args.inputs, outputs = args.outputs, options = user, rng = args.rng }
	setmetatable(pop, Pop)
	local o = pop.options
	for k, v in pairs(novelty.defaults) do o[k] = v end
	for k, v in pairs(own) do o[k] = v end
	pop.rho_min = o.rho_min -- the threshold in force
	pop.stalled = 0 -- generations in a row that added nothing
	pop.archive = {} -- the archive's descriptors, flat, dims numbers each
	pop.archive_meta = {} -- generation, fitness and novelty of each entry, flat
	pop.last = { added = 0, best_novelty = 0.0 } -- the last generation's, for the log
	return pop
end

-- The descriptors of a generation, checked: one list of d numbers per
-- genome, the same d as before; returns them flat and d.
local function flatten(self, descriptors, n)
	if type(descriptors) ~= "table" or #descriptors ~= n then
		error("NOVELTY needs a behaviour descriptor of every candidate (the environment's "
			.. "behaviour hook, or the bot's final position); this task gives none", 0)
	end
	local d = self.dims or #descriptors[1]
	if d < 1 then error("NOVELTY: a behaviour descriptor of no numbers", 0) end
	local flat = {}
	for i = 1, n do
		local x = descriptors[i]
		if type(x) ~= "table" or #x ~= d then
			error(string.format("NOVELTY: candidate %d's behaviour descriptor has %s numbers, "
				.. "not %d as the others'", i - 1, type(x) == "table" and #x or "no", d), 0)
		end
		for q = 1, d do
			local v = x[q]
			if type(v) ~= "number" or v ~= v or v == math.huge or v == -math.huge then
				error(string.format("NOVELTY: candidate %d's behaviour descriptor holds %s",
					i - 1, tostring(v)), 0)
			end
			flat[#flat + 1] = v + 0.0
		end
	end
	self.dims = d
	return flat
end

-- Advance one generation given each genome's fitness and behaviour
-- descriptor (in genomes() order).
function Pop:tell(fitness, descriptors)
	local o, n = self.options, #self.population
	local flat = flatten(self, descriptors, n)
	self:note_best(fitness)
	local nov = novelty.knn(flat, self.archive, self.dims, o.k)
	local floor = min_fitness(o)
	local pass, best = {}, 0.0
	for i = 1, n do
		pass[i] = not floor or fitness[i] >= floor
		if nov[i] > best then best = nov[i] end
	end
	local added = novelty.update_archive(self, flat, fitness, nov, pass)
	self.last = { added = added, best_novelty = best }
	if o.coverage_grid > 0 then novelty.mark_grid(self, flat) end
	self:reproduce(novelty.scores(nov, fitness, pass, o))
end

---------------------------------------------------------------------------
-- The result grid: how much of the descriptor space the run has visited

-- The grid holds at most MAX_GRID cells (coverage_grid ^ d).
local MAX_GRID = 10000000

-- Marks the cell of every descriptor of the generation (flat, dims
-- numbers each) in the passive result grid of coverage_grid cells a
-- dimension (learn.mapelites' grid cells: the last part closed at 1).
-- The grid only counts: it never changes the search.
function novelty.mark_grid(self, flat)
	local cells, d = self.options.coverage_grid, self.dims
	if not self.grid then
		if cells ^ d > MAX_GRID then
			error(string.format("NOVELTY_COVERAGE_GRID: %d cells a dimension in %d dimensions "
				.. "is more than %d cells", cells, d, MAX_GRID), 0)
		end
		self.grid, self.grid_filled = {}, 0
	end
	local grid_cell = require("learn.mapelites").grid_cell
	local b = {}
	for i = 0, #flat // d - 1 do
		for q = 1, d do b[q] = flat[i * d + q] end
		local c = grid_cell(b, cells)
		if not self.grid[c] then
			self.grid[c] = true
			self.grid_filled = self.grid_filled + 1
		end
	end
end

-- The share of the result grid's cells some evaluated descriptor fell in.
function Pop:coverage()
	if not self.grid then return 0.0 end
	return self.grid_filled / self.options.coverage_grid ^ self.dims
end

-- The loop's own columns of log.csv, and this generation's values; with
-- NOVELTY_COVERAGE_GRID, the result grid's coverage too.
novelty.log_columns = { "archive", "threshold", "best_novelty" }
function Pop:log_names()
	if self.options.coverage_grid == 0 then return novelty.log_columns end
	return { "archive", "threshold", "best_novelty", "coverage" }
end
function Pop:log_values()
	local v = { #self.archive // (self.dims or 1), self.rho_min, self.last.best_novelty }
	if self.options.coverage_grid > 0 then v[4] = self:coverage() end
	return v
end

function Pop:stats()
	local s = neat.Pop.stats(self)
	s.archive, s.threshold = #self.archive // (self.dims or 1), self.rho_min
	return s
end

---------------------------------------------------------------------------
-- The archive as a file of the run folder

local function num(x) return string.format("%.17g", x) end

-- archive.csv: a header, then one row per archived behaviour, oldest
-- first: `generation` it joined in, its descriptor d1 .. dN, its
-- `fitness` and its `novelty` when it joined.
function Pop:archive_csv()
	local d = self.dims or 0
	local head = { "generation" }
	for q = 1, d do head[#head + 1] = "d" .. q end
	head[#head + 1] = "fitness"
	head[#head + 1] = "novelty"
	local out = { table.concat(head, ",") }
	local a, meta = self.archive, self.archive_meta
	for i = 0, (d > 0 and #a // d or 0) - 1 do
		local row = { tostring(math.tointeger(meta[3 * i + 1]) or meta[3 * i + 1]) }
		for q = 1, d do row[#row + 1] = num(a[i * d + q]) end
		row[#row + 1] = num(meta[3 * i + 2])
		row[#row + 1] = num(meta[3 * i + 3])
		out[#out + 1] = table.concat(row, ",")
	end
	return table.concat(out, "\n") .. "\n"
end

-- archive.csv into the run folder with each checkpoint (learnsim.lua),
-- just before it: the file always holds the archive of the checkpoint
-- written after it, or of a generation a resumed run redoes identically.
function novelty.checkpoint_files(pop, host)
	host.save("archive.csv", pop:archive_csv())
end

-- At the end of the run (learnsim.lua): says where the archive is.
function novelty.write_archive(pop, host, during)
	if during then return end
	host.save("archive.csv", pop:archive_csv())
	host.print(string.format("novelty archive: %d behaviours in %s/archive.csv",
		#pop.archive // (pop.dims or 1), host.run_dir))
end

---------------------------------------------------------------------------
-- Checkpoints, networks: NEAT's

function novelty.save(pop, shared)
	return common.save(pop, "evo-novelty-1", shared)
end

function novelty.load(t, rng)
	return common.load(t, "evo-novelty-1", Pop, rng, random.load)
end

novelty.to_net = neat.to_net
novelty.pack_net = neat.pack_net
novelty.to_net_text = neat.to_net_text
novelty.Pop = Pop
return novelty

-- MAPELITES: MAP-Elites (Mouret & Clune 2015, "Illuminating search spaces
-- by mapping elites") over the weights of a fixed layered network
-- (docs/learning.md), with the isotropic + line variation of Vassiliades &
-- Mouret 2018 ("Discovering the elite hypervolume by leveraging interspecies
-- correlation") and, for descriptors of more than two numbers, the CVT
-- archive of Vassiliades, Chatzilygeroudis & Mouret 2018, optionally
-- CMA-ME's improvement emitters (Fontaine et al. 2020) on learn.cmaes in
-- place of the variation, and draws the archive (archive.png: a grid's
-- cells or a CVT's regions).
--
--	local mapelites = require "learn.mapelites"
--	local random = require "learn.rng"
--	local pop = mapelites.new{ inputs = 5, outputs = 2, layers = 1, hidden = 8,
--		options = { batch_size = 64 }, rng = random.new(42) }
--	for gen = 1, 100 do
--		local fit, desc = {}, {}
--		for i, g in ipairs(pop:genomes()) do
--			fit[i], desc[i] = evaluate(mapelites.to_net(g)) -- desc[i]: d numbers in [0, 1]
--		end
--		pop:tell(fit, desc)
--	end
--
-- The archive. Every candidate has a behaviour descriptor b in [0, 1]^d
-- (the environment's `behaviour` hook, docs/lua.md), which names one cell
-- of the archive. A grid archive cuts each dimension into `cells` equal
-- parts: coordinate b_k falls in part floor(b_k * cells), the last part
-- closed at 1 (values outside [0, 1] count as the nearest bound), and the
-- cell is 1 + sum_k part_k * cells^(k-1) (the first dimension varies
-- fastest; in 2D, cell = 1 + x + cells * y). A CVT archive has cvt_cells
-- centroids, and a descriptor's cell is its nearest centroid (evo.linalg's
-- nearest; the first of equals). The centroids are k-means (Lloyd's
-- iterations until no point changes cell, at most CVT_ITERATIONS) over
-- cvt_samples points uniform in [0, 1]^d, started from the first
-- cvt_cells of them, all drawn from a stream seeded by the run's seed; the
-- checkpoint holds them, so a resumed run has the same cells.
--
-- A candidate enters the archive when its cell is empty or its fitness is
-- higher than the cell's elite's (higher is better; a NaN fitness or
-- descriptor never enters), the batch in order, so of two equal candidates
-- for one cell the first stays.
--
-- The search. The first batch is initial_batch random networks (`init`):
-- "lecun" draws each weight of a node uniform in +-sqrt(3 / fan_in), its
-- bias 0, as Kheperax's and QDax's networks start; "normal" draws every
-- weight and bias normal(0, init_power). Every later batch is batch_size
-- offspring, each x' = x_i + sigma_iso N(0, I) + sigma_line N(0, 1)
-- (x_j - x_i) with the parents x_i and x_j drawn uniformly, with
-- replacement, from the archive's elites (the order of the draws: i, j,
-- the line's normal, then one normal a weight). Vassiliades & Mouret's
-- defaults are sigma_iso 0.01 and sigma_line 0.2; Kheperax's reference
-- configuration uses 0.2 and 0.
--
-- The network is learn.cmaes's (to_net): layers hidden layers HIDDEN wide
-- (hidden_act: tanh, sigmoid or relu), sigmoid outputs, a bias a node
-- (bias), the genome's weights in net_build's order.
--
-- Measures: coverage, the share of the archive's cells that hold an elite;
-- QD-score, the sum over the elites of (fitness - qd_offset).
--
-- Determinism. Every draw goes through the given rng (learn.rng); the CVT
-- stream is another generator from (seed, cells, samples); mapelites.save
-- holds the whole state.
local cmaes = require "learn.cmaes"
local common = require "learn.common"
local netfile = require "learn.netfile"
local random = require "learn.rng"

local mapelites = {}

mapelites.defaults = {
	batch_size = 100, -- offspring a generation
	initial_batch = 0, -- random networks of generation 0; 0: batch_size
	cells = 100, -- grid archive: cells a dimension
	archive = "auto", -- "grid", "cvt", or "auto" (grid up to 2 dimensions)
	cvt_cells = 1000, -- CVT archive: centroids
	cvt_samples = 50000, -- CVT archive: the k-means' random points
	sigma_iso = 0.01, -- isotropic variation
	sigma_line = 0.2, -- line variation
	init = "lecun", -- first networks: "lecun" or "normal"
	init_power = 1.0, -- init normal: the weights' standard deviation
	hidden_act = "tanh", -- "tanh", "sigmoid" or "relu"
	bias = true, -- every node has a bias
	qd_offset = 0.0, -- QD-score sums fitness - qd_offset
	target_coverage = 0.0, -- stop once the coverage reaches this; 0: never
	emitter = "isoline", -- offspring: "isoline" (iso + line variation) or "cmame"
	emitters = 5, -- cmame: improvement emitters
	emitter_sigma = 0.5, -- cmame: each emitter's CMA-ES starting step size
	emitter_batch = 36, -- cmame: offspring of each emitter a generation
}

mapelites.task_keys = {
	POPSIZE = "batch_size",
	MAPELITES_BATCH = "batch_size",
	MAPELITES_INITIAL_BATCH = "initial_batch",
	MAPELITES_CELLS = "cells",
	MAPELITES_ARCHIVE = "archive",
	MAPELITES_CVT_CELLS = "cvt_cells",
	MAPELITES_CVT_SAMPLES = "cvt_samples",
	MAPELITES_SIGMA_ISO = "sigma_iso",
	MAPELITES_SIGMA_LINE = "sigma_line",
	MAPELITES_INIT = "init",
	MAPELITES_INIT_POWER = "init_power",
	MAPELITES_HIDDEN_ACT = "hidden_act",
	MAPELITES_BIAS = "bias",
	MAPELITES_QD_OFFSET = "qd_offset",
	MAPELITES_TARGET_COVERAGE = "target_coverage",
	MAPELITES_EMITTER = "emitter",
	MAPELITES_EMITTERS = "emitters",
	MAPELITES_EMITTER_SIGMA = "emitter_sigma",
	MAPELITES_EMITTER_BATCH = "emitter_batch",
}

local CHOICES = {
	archive = { auto = true, grid = true, cvt = true },
	init = { lecun = true, normal = true },
	hidden_act = { tanh = true, sigmoid = true, relu = true },
	emitter = { isoline = true, cmame = true },
}

-- A grid holds at most MAX_CELLS cells (cells ^ d).
local MAX_CELLS = 10000000
-- Lloyd's iterations of the CVT at most.
local CVT_ITERATIONS = 100

mapelites.ranges = {
	batch_size = common.POPULATION,
	initial_batch = { lo = 0, hi = 100000, int = true },
	cells = { lo = 1, hi = 10000, int = true },
	cvt_cells = { lo = 1, hi = 100000, int = true },
	cvt_samples = { lo = 1, hi = 10000000, int = true },
	sigma_iso = common.POSITIVE, sigma_line = common.POSITIVE,
	init_power = common.POSITIVE, qd_offset = { lo = -1e9, hi = 1e9 },
	target_coverage = common.PROB,
	emitters = { lo = 1, hi = 1000, int = true },
	emitter_sigma = { lo = 0, above = true },
	emitter_batch = { lo = 2, hi = 10000, int = true },
}

function mapelites.options_from_task(task)
	local o, unknown = common.options_from(task, "MAPELITES_", mapelites.task_keys,
		mapelites.defaults, common.choices(mapelites.task_keys, CHOICES), mapelites.ranges)
	local cells = o.cvt_cells or mapelites.defaults.cvt_cells
	local samples = o.cvt_samples or mapelites.defaults.cvt_samples
	if samples < cells then
		error(string.format("MAPELITES_CVT_SAMPLES: %d random points cannot place %d "
			.. "centroids (MAPELITES_CVT_CELLS)", samples, cells), 0)
	end
	return o, unknown
end

---------------------------------------------------------------------------
-- The archive's cells

-- The grid cell (1-based) of descriptor b with `cells` parts a dimension.
function mapelites.grid_cell(b, cells)
	local cell, scale = 1, 1
	for k = 1, #b do
		local x = b[k]
		local part = math.floor((x < 0 and 0 or (x > 1 and 1 or x)) * cells)
		if part >= cells then part = cells - 1 end
		cell = cell + part * scale
		scale = scale * cells
	end
	return cell
end

-- The centre of grid cell `cell` (its descriptor coordinates), d dimensions.
function mapelites.grid_centre(cell, cells, d)
	local c, r = {}, cell - 1
	for k = 1, d do
		c[k] = (r % cells + 0.5) / cells
		r = r // cells
	end
	return c
end

-- k centroids in [0, 1]^d: Lloyd's k-means over n points uniform in the
-- cube drawn from rng, started from the first k points. A flat list of
-- k * d numbers.
function mapelites.cvt(d, k, n, rng)
	local linalg = require "evo.linalg"
	local points = {}
	for i = 1, n * d do points[i] = rng:unit() end
	local c = {}
	for i = 1, k * d do c[i] = points[i] end
	local cell
	for _ = 1, CVT_ITERATIONS do
		local now = linalg.nearest(d, c, points)
		local same = cell ~= nil
		for i = 1, n do
			if same and now[i] ~= cell[i] then same = false end
		end
		cell = now
		if same then break end
		local sum, count = {}, {}
		for i = 1, k * d do sum[i] = 0.0 end
		for j = 1, k do count[j] = 0 end
		for i = 1, n do
			local j = cell[i]
			count[j] = count[j] + 1
			local base, p = (j - 1) * d, (i - 1) * d
			for m = 1, d do sum[base + m] = sum[base + m] + points[p + m] end
		end
		-- a centroid no point chose stays where it is
		for j = 1, k do
			if count[j] > 0 then
				local base = (j - 1) * d
				for m = 1, d do c[base + m] = sum[base + m] / count[j] end
			end
		end
	end
	return c
end

---------------------------------------------------------------------------
-- The population

local Pop = {}
Pop.__index = Pop

-- A genome (learn.cmaes's shape) of the population's network.
function Pop:genome(weights)
	return { inputs = self.inputs, outputs = self.outputs, layers = self.layers,
		width = self.width, bias = self.options.bias, recurrent = false,
		hidden_act = self.options.hidden_act, weights = weights }
end

-- The fan-in of each weight of the genome (its node's inputs, bias
-- included) and whether it is a bias, in net_build's order.
local function fan_ins(self)
	local width = require("learn.genetic").width(self.inputs, self.outputs, self.width)
	local fan, is_bias, prev = {}, {}, self.inputs
	local b = self.options.bias
	for l = 0, self.layers do
		local count = l < self.layers and width or self.outputs
		for _ = 1, count do
			if b then
				fan[#fan + 1], is_bias[#fan + 1] = prev, true
			end
			for _ = 1, prev do fan[#fan + 1], is_bias[#fan + 1] = prev, false end
		end
		prev = count
	end
	return fan, is_bias
end

-- A random weight vector (see `init` in the header).
function Pop:random_weights()
	local rng, w = self.rng, {}
	if self.options.init == "normal" then
		for i = 1, self.n do w[i] = self.options.init_power * rng:normal() end
		return w
	end
	local fan, is_bias = fan_ins(self)
	for i = 1, self.n do
		if is_bias[i] then
			w[i] = 0.0
		else
			local a = math.sqrt(3 / fan[i])
			w[i] = a * (2 * rng:unit() - 1)
		end
	end
	return w
end

-- args: inputs, outputs, layers (default 1), hidden (HIDDEN), options, rng.
function mapelites.new(args)
	local o = common.merged(mapelites.defaults, args.options, "mapelites.new")
	local rng = args.rng or error("mapelites.new: an rng is required (learn.rng: random.new(seed))")
	local layers = args.layers or 1
	local pop = setmetatable({
		options = o, inputs = args.inputs, outputs = args.outputs, layers = layers,
		width = args.hidden, rng = rng, generation = 0, evaluations = 0, species = {},
		n = cmaes.weight_count(args.inputs, args.outputs, layers, args.hidden, o.bias, false),
		best = nil,
		-- the archive: elites[cell] = { weights, fitness, descriptor,
		-- generation }; filled lists the cells in the order they were
		-- first filled (the parents are drawn from it)
		elites = {}, filled = {}, qd_sum = 0.0,
		dims = nil, n_cells = nil, kind = nil, centroids = nil,
		-- the seed of the CVT's stream (mapelites.new's rng state, before any draw)
		cvt_seed = rng:save()[1],
	}, Pop)
	local first = o.initial_batch > 0 and o.initial_batch or o.batch_size
	local popl = {}
	for i = 1, first do popl[i] = pop:genome(pop:random_weights()) end
	pop.population = popl
	return pop
end

function Pop:genomes() return self.population end

-- Sets up the archive for descriptors of d numbers (at the first tell).
function Pop:make_archive(d)
	local o = self.options
	local kind = o.archive
	if kind == "auto" then kind = d <= 2 and "grid" or "cvt" end
	self.dims, self.kind = d, kind
	if kind == "grid" then
		local total = o.cells ^ d
		if total > MAX_CELLS then
			error(string.format("MAPELITES_CELLS: a grid of %d cells a dimension in %d "
				.. "dimensions has %.0f cells, more than %d: use MAPELITES_ARCHIVE:cvt",
				o.cells, d, total, MAX_CELLS), 0)
		end
		self.n_cells = math.tointeger(total)
	else
		self.n_cells = o.cvt_cells
		local stream = random.new(self.cvt_seed ~ 0x43565400)
		self.centroids = mapelites.cvt(d, o.cvt_cells, o.cvt_samples, stream)
	end
end

-- The cells of a batch of descriptors (nil where a descriptor is not d
-- finite numbers).
function Pop:cells_of(descriptors)
	local d, cells = self.dims, {}
	local ok = {}
	for i, b in ipairs(descriptors) do
		local good = type(b) == "table" and #b == d
		for k = 1, good and d or 0 do
			local x = b[k]
			if type(x) ~= "number" or x ~= x then good = false end
		end
		ok[i] = good
	end
	if self.kind == "grid" then
		for i, b in ipairs(descriptors) do
			if ok[i] then cells[i] = mapelites.grid_cell(b, self.options.cells) end
		end
		return cells
	end
	local flat, which = {}, {}
	for i, b in ipairs(descriptors) do
		if ok[i] then
			which[#which + 1] = i
			for k = 1, d do
				local x = b[k]
				flat[#flat + 1] = x < 0 and 0.0 or (x > 1 and 1.0 or x + 0.0)
			end
		end
	end
	local near = require("evo.linalg").nearest(d, self.centroids, flat)
	for m, i in ipairs(which) do cells[i] = near[m] end
	return cells
end

-- Offers one candidate to the archive; true when it entered.
function Pop:offer(cell, weights, f, b)
	if not cell or f ~= f then return false end
	local e = self.elites[cell]
	if e and not (f > e.fitness) then return false end
	local offset = self.options.qd_offset
	if e then
		self.qd_sum = self.qd_sum - (e.fitness - offset)
	else
		self.filled[#self.filled + 1] = cell
	end
	self.qd_sum = self.qd_sum + (f - offset)
	local desc = {}
	for k = 1, #b do desc[k] = b[k] + 0.0 end
	self.elites[cell] = { weights = weights, fitness = f, descriptor = desc,
		generation = self.generation }
	return true
end

-- The isotropic + line variation of parents xi and xj: a new weight list
-- xi + iso N(0, I) + line N(0, 1) (xj - xi), the line's normal drawn first.
function mapelites.isoline_lua(xi, xj, iso, line, rng)
	local t = line * rng:normal()
	local w = {}
	for k = 1, #xi do
		w[k] = xi[k] + iso * rng:normal() + t * (xj[k] - xi[k])
	end
	return w
end
-- evo.neat's C (the learning loop's state has it) draws the same numbers
-- from learn.rng's words and adds them in the same order, bit for bit;
-- a generator of another kind (a test's) goes through isoline_lua.
local fast = package.loaded["evo.neat"]
function mapelites.isoline(xi, xj, iso, line, rng)
	if fast and getmetatable(rng) == random.Rng then return fast.isoline(xi, xj, iso, line, rng) end
	return mapelites.isoline_lua(xi, xj, iso, line, rng)
end

-- One offspring of the archive (see the header).
function Pop:offspring()
	local rng, filled, elites = self.rng, self.filled, self.elites
	local n_f = #filled
	local xi = elites[filled[1 + math.floor(rng:unit() * n_f)]].weights
	local xj = elites[filled[1 + math.floor(rng:unit() * n_f)]].weights
	return mapelites.isoline(xi, xj, self.options.sigma_iso, self.options.sigma_line, rng)
end

-- fitness[i] and descriptors[i] (d numbers in [0, 1]) are those of
-- genomes()[i]: the batch enters the archive and the next is drawn.
function Pop:tell(fitness, descriptors)
	local popl = self.population
	assert(#fitness == #popl, "tell: one fitness per genome")
	if type(descriptors) ~= "table" or #descriptors ~= #popl then
		error("MAPELITES needs a behaviour descriptor for every candidate (the environment's "
			.. "behaviour hook, docs/lua.md)", 0)
	end
	if not self.dims then
		local d = type(descriptors[1]) == "table" and #descriptors[1] or 0
		if d < 1 then error("MAPELITES: the behaviour descriptor has no numbers", 0) end
		self:make_archive(d)
	end
	self.evaluations = self.evaluations + #fitness
	local cells = self:cells_of(descriptors)
	self.added = 0
	local status, gain = {}, {}
	for i, g in ipairs(popl) do
		local f = fitness[i]
		local old = cells[i] and self.elites[cells[i]]
		if self:offer(cells[i], g.weights, f, descriptors[i]) then
			self.added = self.added + 1
			status[i], gain[i] = old and 1 or 2, old and f - old.fitness or f
		else
			status[i], gain[i] = 0, (old and f == f) and f - old.fitness or -math.huge
		end
		if f == f and (not self.best or f > self.best.fitness) then
			self.best = { genome = common.deep_copy(g), fitness = f }
		end
	end
	self.generation = self.generation + 1
	if self.options.emitter == "cmame" and #self.filled > 0 then
		self:tell_emitters(status, gain)
		return
	end
	local nextp = {}
	if #self.filled == 0 then
		-- nothing entered (every fitness NaN): start again at random
		for i = 1, self.options.batch_size do nextp[i] = self:genome(self:random_weights()) end
	else
		for i = 1, self.options.batch_size do nextp[i] = self:genome(self:offspring()) end
	end
	self.population = nextp
	if not self.best then self.best = { genome = common.deep_copy(popl[1]), fitness = fitness[1] } end
end

---------------------------------------------------------------------------
-- CMA-ME's improvement emitters (Fontaine, Togelius, Nikolaidis & Hoover
-- 2020, "Covariance Matrix Adaptation for the Rapid Illumination of
-- Behavior Space")
--
-- With emitter "cmame", every batch after the first is `emitters` times
-- `emitter_batch` offspring, emitter by emitter: each emitter is a CMA-ES
-- (learn.cmaes, no restarts of its own, lambda emitter_batch) whose mean
-- starts at an elite drawn uniformly from the archive and whose sigma
-- starts at emitter_sigma. After the batch has entered the archive (in
-- order, emitter 1's offspring first), each emitter ranks its own
-- offspring by improvement: those that filled an empty cell first, by
-- fitness; then those that beat a cell's elite, by how much; then the
-- rest, by fitness minus their cell's elite's (ties by order). CMA-ES
-- updates on that ranking (its mu best). An emitter none of whose
-- offspring entered the archive restarts: a fresh CMA-ES at another
-- elite. The emitters draw from the population's rng.

-- The order of a batch's offspring by improvement: status 2 (a new cell)
-- before 1 (a better elite) before 0 (not entered), and within a status
-- the higher gain first (the fitness for a new cell, the fitness minus the
-- elite's otherwise); ties keep the batch's order.
function mapelites.improvement_order(status, gain)
	local order = {}
	for i = 1, #status do order[i] = i end
	table.sort(order, function(a, b)
		if status[a] ~= status[b] then return status[a] > status[b] end
		if gain[a] ~= gain[b] then return gain[a] > gain[b] end
		return a < b
	end)
	return order
end

-- A fresh emitter: CMA-ES at an elite drawn from the archive. Emitters
-- hold no rng (the checkpoint holds the population's once): it is lent to
-- them for each call.
function Pop:new_emitter()
	local o, rng = self.options, self.rng
	local x0 = self.elites[self.filled[1 + math.floor(rng:unit() * #self.filled)]].weights
	local e = cmaes.new{ inputs = self.inputs, outputs = self.outputs, layers = self.layers,
		hidden = self.width, rng = rng, options = { pop_size = o.emitter_batch,
		sigma = o.emitter_sigma, restarts = 0, ipop = false, bias = o.bias,
		hidden_act = o.hidden_act } }
	for k = 1, self.n do e.mean[k] = x0[k] end
	e:sample()
	e.rng = nil
	return e
end

-- The next batch: every emitter's offspring, in emitter order.
function Pop:emitter_batch()
	local popl = {}
	for _, e in ipairs(self.emitters) do
		for _, g in ipairs(e.population) do popl[#popl + 1] = g end
	end
	self.population = popl
end

-- After a batch (its status and gain, see improvement_order): each
-- emitter updates on its offspring's ranking, or restarts when none of
-- them entered the archive; then the next batch.
function Pop:tell_emitters(status, gain)
	local o = self.options
	if not self.emitters then
		-- the first batch was random: the emitters start now
		self.emitters, self.emitter_restarts = {}, 0
		for k = 1, o.emitters do self.emitters[k] = self:new_emitter() end
		self:emitter_batch()
		return
	end
	local lambda = o.emitter_batch
	for k, e in ipairs(self.emitters) do
		local st, ga, entered = {}, {}, 0
		for j = 1, lambda do
			local i = (k - 1) * lambda + j
			st[j], ga[j] = status[i], gain[i]
			if st[j] > 0 then entered = entered + 1 end
		end
		if entered == 0 then
			self.emitters[k] = self:new_emitter()
			self.emitter_restarts = self.emitter_restarts + 1
		else
			-- CMA-ES ranks by "fitness": lambda for the first, down to 1
			local rank = {}
			for r, j in ipairs(mapelites.improvement_order(st, ga)) do rank[j] = lambda - r + 1 end
			-- (a checkpoint's copy has lost its class)
			setmetatable(e, cmaes.Pop)
			e.rng = self.rng
			e:tell(rank)
			e.rng = nil
		end
	end
	self:emitter_batch()
end

-- The share of cells that hold an elite, and the QD-score.
function Pop:coverage()
	if not self.n_cells then return 0.0 end
	return #self.filled / self.n_cells
end

function Pop:qd_score() return self.qd_sum end

-- A run of MAP-Elites fills its archive for its whole budget: a network
-- that solves the task (env.solved) neither stops it nor becomes the
-- champion by that (learnsim.lua).
mapelites.whole_budget = true

-- Why the run stops after generation gen, or nil: target_coverage reached.
function Pop:stop_reason(gen)
	local t = self.options.target_coverage
	if t > 0 and self:coverage() >= t then
		return string.format("target coverage %.4g%% reached in generation %d (%d evaluations)",
			100 * t, gen, self.evaluations)
	end
	return nil
end

-- Two more columns of log.csv (learnsim.lua), and their values.
mapelites.log_columns = { "coverage", "qd_score" }
function Pop:log_values() return { self:coverage(), self:qd_score() } end

---------------------------------------------------------------------------
-- The archive as files of the run folder

local function num(x) return string.format("%.17g", x) end

-- archive.csv: a header, then one row per elite in cell order: cell,
-- d descriptor values, fitness, the generation it entered, its n weights.
function Pop:archive_csv()
	local out = {}
	local head = { "cell" }
	for k = 1, self.dims or 0 do head[#head + 1] = "d" .. k end
	head[#head + 1] = "fitness"
	head[#head + 1] = "generation"
	for k = 1, self.n do head[#head + 1] = "w" .. k end
	out[1] = table.concat(head, ",")
	local cells = {}
	for i, c in ipairs(self.filled) do cells[i] = c end
	table.sort(cells)
	for _, c in ipairs(cells) do
		local e = self.elites[c]
		local row = { tostring(c) }
		for k = 1, #e.descriptor do row[#row + 1] = num(e.descriptor[k]) end
		row[#row + 1] = num(e.fitness)
		row[#row + 1] = tostring(e.generation)
		for k = 1, self.n do row[#row + 1] = num(e.weights[k]) end
		out[#out + 1] = table.concat(row, ",")
	end
	return table.concat(out, "\n") .. "\n", cells
end

-- The .net text of the elite of `cell`, or nil when the cell is empty.
function Pop:elite_net_text(cell)
	local e = self.elites[cell]
	if not e then return nil end
	local d = {}
	for k = 1, #e.descriptor do d[k] = string.format("%.6g", e.descriptor[k]) end
	return mapelites.to_net_text(cmaes.to_net(self:genome(e.weights)), string.format(
		"MAP-Elites elite of cell %d, descriptor (%s), fitness %.17g, generation %d",
		cell, table.concat(d, ", "), e.fitness, e.generation))
end

-- For the heatmap: the grid's width and height and each cell's fitness
-- (NaN where empty), row by row from y = 0; nil unless a 1- or 2-D grid.
function Pop:grid_fitness()
	if self.kind ~= "grid" or self.dims > 2 then return nil end
	local nx = self.options.cells
	local ny = self.dims == 2 and nx or 1
	local v = {}
	for c = 1, nx * ny do
		local e = self.elites[c]
		v[c] = e and e.fitness or 0 / 0
	end
	return nx, ny, v
end

-- A CVT archive's picture is CVT_PIXELS x CVT_PIXELS points of the
-- descriptor square (one point of its first dimension for d = 1).
local CVT_PIXELS = 250

-- Each point's centroid, by point: worked out once a run (the centroids
-- never move) and kept beside the population, not in it (the checkpoint
-- holds the population).
local cvt_owner = setmetatable({}, { __mode = "k" })

-- The centroid (1-based) each point of the picture lies nearest to, in
-- the first two descriptor dimensions (the first alone for d = 1): the
-- points are the centres of a CVT_PIXELS grid over [0, 1]^2.
local function cvt_owners(self)
	if cvt_owner[self] then return cvt_owner[self] end
	local d, c = self.dims, self.centroids
	local dd = d >= 2 and 2 or 1
	local proj = {}
	for j = 0, #c // d - 1 do
		for m = 1, dd do proj[#proj + 1] = c[j * d + m] end
	end
	local nx, ny = CVT_PIXELS, dd == 2 and CVT_PIXELS or 1
	local points = {}
	for y = 0, ny - 1 do
		for x = 0, nx - 1 do
			points[#points + 1] = (x + 0.5) / nx
			if dd == 2 then points[#points + 1] = (y + 0.5) / ny end
		end
	end
	local owner = require("evo.linalg").nearest(dd, proj, points)
	cvt_owner[self] = owner
	return owner
end

-- For the heatmap of a CVT archive: the picture's points across and up,
-- each point's value the fitness of its centroid's elite (NaN where
-- empty), and what the picture shows.
function Pop:cvt_fitness()
	if self.kind ~= "cvt" then return nil end
	local owner = cvt_owners(self)
	local fit = {}
	for c = 1, self.n_cells do
		local e = self.elites[c]
		fit[c] = e and e.fitness or 0 / 0
	end
	local v = {}
	for i = 1, #owner do v[i] = fit[owner[i]] end
	local note
	if self.dims > 2 then
		note = string.format("(CVT; numbers 1, 2 of %d)", self.dims)
	else
		note = string.format("(CVT, %d cells)", self.n_cells)
	end
	return CVT_PIXELS, self.dims >= 2 and CVT_PIXELS or 1, v, note
end

-- centroids.csv: a CVT archive's cells, one row each: `cell`, and its
-- centroid c1 .. cN.
function Pop:centroids_csv()
	local d, c = self.dims, self.centroids
	local head = { "cell" }
	for k = 1, d do head[#head + 1] = "c" .. k end
	local out = { table.concat(head, ",") }
	for j = 0, #c // d - 1 do
		local row = { tostring(j + 1) }
		for k = 1, d do row[#row + 1] = num(c[j * d + k]) end
		out[#out + 1] = table.concat(row, ",")
	end
	return table.concat(out, "\n") .. "\n"
end

-- The archive into the run folder (learnsim.lua, through its host): the
-- heatmap (archive.png: a 1- or 2-D grid's cells, a CVT's regions) as the
-- run goes (`during`), and at the end archive.csv, each elite's network,
-- elites/elite-CELL.net (CELL zero-padded to the width of the largest cell
-- number), and a CVT's centroids.csv.
function mapelites.write_archive(pop, host, during)
	local nx, ny, v = pop:grid_fitness()
	if nx then host.heatmap(nx, ny, v, during) end
	local note
	nx, ny, v, note = pop:cvt_fitness()
	if nx then host.heatmap(nx, ny, v, during, note) end
	if during then return end
	local text, cells = pop:archive_csv()
	host.save("archive.csv", text)
	if pop.kind == "cvt" then host.save("centroids.csv", pop:centroids_csv()) end
	local names, texts = {}, {}
	-- zero-padded to the width of the largest cell, so that they sort
	-- in cell order: elite-007.net before elite-042.net
	local width = #tostring(pop.n_cells or 1)
	for i, c in ipairs(cells) do
		names[i] = string.format("elites/elite-%0" .. width .. "d.net", c)
		texts[i] = pop:elite_net_text(c)
	end
	host.save_many(names, texts)
	host.print(string.format("archive: %d elites in %d cells (coverage %.2f%%, QD-score %.6g) "
		.. "in %s/archive.csv, their networks in %s/elites/", #cells, pop.n_cells or 0,
		100 * pop:coverage(), pop:qd_score(), host.run_dir, host.run_dir))
end

mapelites.to_net = cmaes.to_net
-- .net text with each weight the Q16 value it was scored with (netfile):
-- an elite replayed from its file ends in its own cell.
mapelites.to_net_text = netfile.text

---------------------------------------------------------------------------
-- Checkpoints

function mapelites.save(pop, shared)
	return common.save(pop, "evo-mapelites-1", shared)
end

function mapelites.load(t, rng)
	return common.load(t, "evo-mapelites-1", Pop, rng, random.load)
end

return mapelites

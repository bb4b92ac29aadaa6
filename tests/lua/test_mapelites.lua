-- Unit tests of lua/learn/mapelites.lua, run by tests/sim/lua/test_lua_scripts.c
-- (which registers evo.linalg, as the learning loop does). Each entry of
-- the returned table is one test; it fails by raising.
local mapelites = require "learn.mapelites"
local random = require "learn.rng"
local serialize = require "learn.serialize"
local linalg = require "evo.linalg"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local function near(a, b, tol, what)
	check(math.abs(a - b) <= tol, string.format("%s: %.17g, expected %.17g", what, a, b))
end

local T = {}

-- A 100 x 100 grid: x in [0.01 k, 0.01 (k+1)) is part k, 1 is in part 99,
-- and the cell is 1 + x part + 100 * y part.
function T.grid_cells_by_hand()
	local g = mapelites.grid_cell
	check(g({ 0, 0 }, 100) == 1, "(0, 0)")
	check(g({ 0.999, 0 }, 100) == 100, "(0.999, 0): the last of the first row")
	check(g({ 1, 1 }, 100) == 10000, "(1, 1): the last cell")
	check(g({ 0.015, 0.027 }, 100) == 1 + 1 + 2 * 100, "(0.015, 0.027)")
	check(g({ -0.5, 2 }, 100) == 1 + 99 * 100, "outside the cube: the nearest bound")
	check(g({ 0.5 }, 10) == 6, "1-D")
	check(g({ 0.25, 0.5, 0.75 }, 4) == 1 + 1 + 4 * 2 + 16 * 3, "3-D, the first dimension fastest")
	local c = mapelites.grid_centre(202, 100, 2)
	near(c[1], 0.015, 1e-12, "centre x")
	near(c[2], 0.025, 1e-12, "centre y")
end

-- Squared distances from (0.5, 0.5) to (0.1, 0.1), (0.9, 0.9), (0.1, 0.9)
-- are all 0.32: the first centroid takes the tie.
function T.nearest_centroid_by_hand()
	local c = { 0.1, 0.1, 0.9, 0.9, 0.1, 0.9 }
	local cell = linalg.nearest(2, c, { 0.2, 0.3, 0.6, 0.7, 0.2, 0.6, 0.5, 0.5 })
	check(cell[1] == 1 and cell[2] == 2 and cell[3] == 3, "the nearest of three")
	check(cell[4] == 1, "a tie goes to the first centroid")
	check(not pcall(linalg.nearest, 2, c, { 0.1, 0.2, 0.3 }), "points not in pairs")
end

-- k-means of 2 centroids over points uniform in [0, 1] settles at the
-- halves' centres, 0.25 and 0.75; 4 centroids in the unit square at the
-- quarters' centres (0.25 or 0.75 in each coordinate).
function T.cvt_centroids_are_the_halves_and_quarters()
	local c = mapelites.cvt(1, 2, 20000, random.new(3))
	local lo, hi = math.min(c[1], c[2]), math.max(c[1], c[2])
	near(lo, 0.25, 0.01, "low centroid")
	near(hi, 0.75, 0.01, "high centroid")
	c = mapelites.cvt(2, 4, 20000, random.new(4))
	for i = 1, 8 do
		check(math.abs(c[i] - 0.25) < 0.02 or math.abs(c[i] - 0.75) < 0.02,
			string.format("coordinate %d: %.4f", i, c[i]))
	end
end

-- The variation xi + iso N(0, I) + line N(0, 1) (xj - xi) with xi = 0 and
-- xj = 1: each weight has mean 0 and variance iso^2 + line^2, and two
-- weights share the line's term, so their covariance is line^2.
function T.isoline_statistics_are_the_formulas()
	local rng = random.new(5)
	local xi, xj = { 0, 0 }, { 1, 1 }
	local function stats(iso, line)
		local n, s1, s2, s11, s22, s12 = 20000, 0, 0, 0, 0, 0
		for _ = 1, n do
			local w = mapelites.isoline(xi, xj, iso, line, rng)
			s1, s2 = s1 + w[1], s2 + w[2]
			s11, s22, s12 = s11 + w[1] * w[1], s22 + w[2] * w[2], s12 + w[1] * w[2]
		end
		local m1, m2 = s1 / n, s2 / n
		return m1, s11 / n - m1 * m1, s12 / n - m1 * m2
	end
	local m, var, cov = stats(0.01, 0.2)
	near(m, 0, 0.01, "mean")
	near(var, 0.01 ^ 2 + 0.2 ^ 2, 0.0401 * 0.05, "variance iso^2 + line^2")
	near(cov, 0.2 ^ 2, 0.04 * 0.05, "covariance line^2")
	m, var, cov = stats(0.2, 0)
	near(m, 0, 0.01, "mean, iso only")
	near(var, 0.04, 0.04 * 0.05, "variance iso^2")
	near(cov, 0, 0.002, "no covariance without the line")
end

local function small(options)
	return mapelites.new{ inputs = 2, outputs = 1, layers = 1, hidden = 2,
		options = options, rng = random.new(7) }
end

-- A batch of four on a 10 x 10 grid, QD offset -1: cell 1 twice (the
-- better one stays), a NaN fitness and a NaN descriptor never enter.
function T.elites_coverage_and_qd_score_by_hand()
	local pop = small{ cells = 10, batch_size = 5, initial_batch = 6, qd_offset = -1 }
	check(#pop:genomes() == 6, "the initial batch")
	check(pop.n == 2 * 3 + 3, "2-2-1 with biases: 9 weights")
	pop:tell({ 0.5, 0.7, 2.0, 0 / 0, 3.0, 0.7 },
		{ { 0.01, 0.02 }, { 0.05, 0.05 }, { 0.95, 0.95 }, { 0.5, 0.5 }, { 0.5, 0 / 0 }, { 0, 0 } })
	check(pop.elites[1].fitness == 0.7, "the better of cell 1 stays")
	check(pop.elites[100].fitness == 2.0, "cell 100")
	check(pop.elites[56] == nil, "a NaN fitness never enters")
	check(#pop.filled == 2, "two cells filled")
	near(pop:coverage(), 2 / 100, 0, "coverage")
	near(pop:qd_score(), (0.7 + 1) + (2.0 + 1), 1e-12, "QD-score")
	check(pop.best.fitness == 3.0, "the best is the best evaluated, in a cell or not")
	check(#pop:genomes() == 5, "a batch of offspring")
	-- an equal fitness does not replace (cell 1's 0.7 came second in the batch
	-- and replaced 0.5; a third 0.7 does not)
	local before = pop.elites[1].weights
	pop:tell({ 0.7, 0, 0, 0, 0 }, { { 0, 0 }, { 0, 0 }, { 0, 0 }, { 0, 0 }, { 0, 0 } })
	check(pop.elites[1].weights == before, "an equal fitness keeps the elite")
	local text, cells = pop:archive_csv()
	check(#cells == 2 and cells[1] == 1 and cells[2] == 100, "archive rows in cell order")
	check(text:match("^cell,d1,d2,fitness,generation,w1,"), "archive header")
	check(pop:elite_net_text(100):match("cell 100, descriptor %(0.95, 0.95%), fitness 2,"),
		"the elite's .net says where it came from")
	local nx, ny, v = pop:grid_fitness()
	check(nx == 10 and ny == 10 and v[100] == 2.0 and v[2] ~= v[2], "the heatmap's values")
end

-- Offspring come from the archive: with one elite and sigma_iso 0 they are
-- its copy.
function T.offspring_of_one_elite_without_noise_are_copies()
	local pop = small{ cells = 4, batch_size = 3, initial_batch = 1, sigma_iso = 0 }
	local w = pop:genomes()[1].weights
	pop:tell({ 1 }, { { 0.3, 0.3 } })
	for _, g in ipairs(pop:genomes()) do
		for k = 1, #w do check(g.weights[k] == w[k], "a copy") end
	end
end

-- lecun: biases 0, weights within sqrt(3 / fan_in).
function T.lecun_initial_weights()
	local pop = small{}
	local w = pop:genomes()[1].weights
	-- hidden node: bias, 2 inputs; output: bias, 2 hidden
	check(w[1] == 0 and w[4] == 0 and w[7] == 0, "biases 0")
	for _, k in ipairs({ 2, 3, 5, 6, 8, 9 }) do
		check(math.abs(w[k]) <= math.sqrt(1.5) and w[k] ~= 0, "weight " .. k)
	end
end

-- A CVT archive for 3-D descriptors: the cell of a descriptor is its
-- nearest centroid; a checkpoint taken after a generation goes on with the
-- same draws and the same centroids.
function T.cvt_archive_and_checkpoint_go_on_identically()
	local pop = small{ cvt_cells = 20, cvt_samples = 400, batch_size = 4, initial_batch = 4 }
	local function desc(i, g) return { (i * 0.17 + g * 0.05) % 1, (i * 0.31) % 1, 0.5 } end
	local function fit(p, g)
		local f, d = {}, {}
		for i, x in ipairs(p:genomes()) do
			f[i] = x.weights[1] + x.weights[2]
			d[i] = desc(i, g)
		end
		return f, d
	end
	local f, d = fit(pop, 0)
	pop:tell(f, d)
	check(pop.kind == "cvt" and pop.n_cells == 20 and #pop.centroids == 60, "a CVT of 20 in 3-D")
	local c = linalg.nearest(3, pop.centroids, d[1])[1]
	check(pop.elites[c] ~= nil, "the first candidate's cell is its nearest centroid")
	local saved = serialize.dump(mapelites.save(pop))
	local again = mapelites.load(serialize.load(saved, "checkpoint"))
	for g = 1, 3 do
		f, d = fit(pop, g)
		pop:tell(f, d)
		local f2, d2 = fit(again, g)
		again:tell(f2, d2)
	end
	check(serialize.dump(mapelites.save(pop)) == serialize.dump(mapelites.save(again)),
		"the resumed population is the same")
end

-- The variation in C (evo.neat's isoline and rng_normal, what the loop
-- runs) draws and adds exactly as the Lua: the same weights to the bit
-- from two generators of one seed, which end in the same state.
function T.isoline_and_normal_in_c_are_the_lua_ones()
	local fast = package.loaded["evo.neat"]
	check(fast and fast.isoline and fast.rng_normal, "the loop's state has the kernels")
	local a, b = random.new(99), random.new(99)
	for _ = 1, 1000 do
		local x, y = a:normal(), a.normal_lua(b)
		check(x == y, string.format("normal: %.17g, Lua %.17g", x, y))
	end
	local xi, xj = {}, {}
	for k = 1, 66 do xi[k], xj[k] = a:normal(), a:normal() end
	b = random.load(a:save())
	for _ = 1, 50 do
		local w1 = mapelites.isoline(xi, xj, 0.02, 0.3, a)
		local w2 = mapelites.isoline_lua(xi, xj, 0.02, 0.3, b)
		check(#w1 == 66 and #w2 == 66, "66 weights")
		for k = 1, 66 do check(w1[k] == w2[k], "weight " .. k) end
		xi = w1
	end
	local sa, sb = a:save(), b:save()
	for k = 1, 4 do check(sa[k] == sb[k], "the same state after") end
end

-- CMA-ME's ranking by hand: two new cells (fitness 3 and 5), two better
-- elites (gains 0.5 and 2), two not entered (gains -1 and -0.25): the new
-- cells first, the higher fitness first (5: offspring 4, then 3:
-- offspring 1), then the gains 2 (offspring 6) and 0.5 (offspring 2),
-- then -0.25 (offspring 5) and -1 (offspring 3). Equal keys keep order.
function T.cmame_ranks_by_improvement_by_hand()
	local order = mapelites.improvement_order({ 2, 1, 0, 2, 0, 1 }, { 3, 0.5, -1, 5, -0.25, 2 })
	check(table.concat(order, " ") == "4 1 6 2 5 3", table.concat(order, " "))
	check(table.concat(mapelites.improvement_order({ 1, 1, 1 }, { 0, 0, 0 }), " ") == "1 2 3",
		"ties in order")
end

-- CMA-ME on a made-up task: the descriptor is the first two weights
-- squashed into (0, 1), the fitness minus the squared norm. Every batch
-- is emitters x emitter_batch; the coverage grows from the random first
-- batch; a checkpoint taken mid-run goes on identically (the emitters'
-- CMA-ES states, without an rng of their own, and the population's rng).
function T.cmame_fills_the_archive_and_resumes_identically()
	local pop = small{ cells = 20, batch_size = 10, emitter = "cmame", emitters = 3,
		emitter_batch = 8, emitter_sigma = 0.5 }
	local function step(p)
		local f, d = {}, {}
		for i, x in ipairs(p:genomes()) do
			local w = x.weights
			local s = 0.0
			for k = 1, #w do s = s + w[k] * w[k] end
			f[i] = -s
			d[i] = { 1 / (1 + math.exp(-2 * w[1])), 1 / (1 + math.exp(-2 * w[2])) }
		end
		p:tell(f, d)
	end
	check(#pop:genomes() == 10, "a random first batch of batch_size")
	step(pop)
	local first = pop:coverage()
	check(#pop.emitters == 3 and #pop:genomes() == 24, "then 3 emitters of 8")
	for _ = 1, 5 do step(pop) end
	local saved = serialize.dump(mapelites.save(pop))
	local again = mapelites.load(serialize.load(saved, "checkpoint"))
	for _ = 1, 30 do
		step(pop)
		step(again)
	end
	check(pop:coverage() > 2 * first, string.format("coverage grows: %g after the first batch, "
		.. "%g after 36", first, pop:coverage()))
	check(pop.evaluations == 10 + 35 * 24, "evaluations: " .. pop.evaluations)
	check(serialize.dump(mapelites.save(pop)) == serialize.dump(mapelites.save(again)),
		"the resumed population is the same")
	check(pop.emitter_restarts >= 0 and pop.emitters[1].rng == nil, "emitters hold no rng")
end

-- An elite's .net holds each weight as the Q16.16 value it was scored
-- with, exactly: x * 65536 rounded to nearest, ties away from zero.
function T.elite_weights_are_written_as_their_q16_values()
	local net = { inputs = 1, outputs = 1, outputs_ids = { 1 },
		nodes = { { id = 1, act = "sigmoid", bias = 0.5 } },
		links = { { from = 0, to = 1, weight = 1.5 / 65536 },
			{ from = 0, to = 1, weight = -1.5 / 65536 },
			{ from = 0, to = 1, weight = 1.4999 / 65536 } } }
	local text = mapelites.to_net_text(net)
	check(text:find("node:1:sigmoid:0.5\n", 1, true), "0.5")
	check(text:find("link:0:1:0.000030517578125\n", 1, true), "a tie rounds up: 2 / 65536")
	check(text:find("link:0:1:-0.000030517578125\n", 1, true), "and away from zero below 0")
	check(text:find("link:0:1:0.0000152587890625\n", 1, true), "1 / 65536")
	check(small{}:elite_net_text(1) == nil, "no elite in an empty cell")
end

function T.options_are_checked()
	local ok, err = pcall(mapelites.options_from_task, { MAPELITES_ARCHIVE = "hex" })
	check(not ok and err:match("^MAPELITES_ARCHIVE: expected auto, cvt, grid, found 'hex'"), err)
	ok, err = pcall(mapelites.options_from_task, { MAPELITES_CELLS = "0" })
	check(not ok and err:match("^MAPELITES_CELLS: expected a whole number from 1 to 10000"), err)
	ok, err = pcall(mapelites.options_from_task, { MAPELITES_CVT_CELLS = "50", MAPELITES_CVT_SAMPLES = "10" })
	check(not ok and err:match("^MAPELITES_CVT_SAMPLES: 10 random points cannot place 50"), err)
	local o, unknown = mapelites.options_from_task{ MAPELITES_SIGMA_ISO = "0.2",
		MAPELITES_SIGMA_LINE = "0", POPSIZE = "2048", MAPELITES_BOGUS = "1" }
	check(o.sigma_iso == 0.2 and o.sigma_line == 0 and o.batch_size == 2048, "values")
	check(#unknown == 1 and unknown[1] == "MAPELITES_BOGUS", "unknown keys")
	local pop = small{ archive = "grid", cells = 1000, batch_size = 1, initial_batch = 1 }
	ok, err = pcall(pop.tell, pop, { 1 }, { { 0.1, 0.2, 0.3 } })
	check(not ok and tostring(err):match("^MAPELITES_CELLS: .* use MAPELITES_ARCHIVE:cvt"), tostring(err))
	ok, err = pcall(pop.tell, small{ batch_size = 1, initial_batch = 1 }, { 1 }, nil)
	check(not ok and tostring(err):match("behaviour descriptor"), tostring(err))
end

return T

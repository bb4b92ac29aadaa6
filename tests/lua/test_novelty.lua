-- Unit tests of lua/learn/novelty.lua and its kNN kernel evo.novelty
-- (sim/learn/lua_novelty.c), run by tests/sim/lua/test_lua_scripts.c
-- (whose states have evo.novelty, as the learning loop's does): novelty
-- and the archive's rule against values worked out by hand, the C kNN
-- against the Lua one on random data, and a run on synthetic descriptors.
local novelty = require "learn.novelty"
local neat = require "learn.neat"
local random = require "learn.rng"
local serialize = require "learn.serialize"
local kernel = package.loaded["evo.novelty"]

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local function near(a, b, what)
	check(math.abs(a - b) <= 1e-12, string.format("%s: %.17g, expected %.17g", what, a, b))
end

local T = {}

function T.the_loop_state_has_the_kernel_and_novelty_uses_it()
	check(kernel, "evo.novelty is loaded")
	check(novelty.knn == kernel.knn, "novelty.knn is C")
end

-- Three candidates A (0, 0), B (3, 4), C (6, 8) and one archive entry
-- R (0, 4): |AB| = 5, |AC| = 10, |BC| = 5, |AR| = 4, |BR| = 3,
-- |CR| = sqrt(36 + 16) = sqrt(52). With k = 2: A's two nearest are R and
-- B, (4 + 5) / 2 = 4.5; B's are R and A (or C), (3 + 5) / 2 = 4; C's are
-- B and R, (5 + sqrt 52) / 2. With k = 15, more than there are: the mean
-- of all three, A (5 + 10 + 4) / 3.
function T.novelty_of_hand_made_points()
	local points, archive = { 0, 0, 3, 4, 6, 8 }, { 0, 4 }
	for _, knn in ipairs{ novelty.knn_lua, kernel.knn } do
		local n = knn(points, archive, 2, 2)
		check(#n == 3, "one novelty per point")
		check(n[1] == 4.5, "A: " .. n[1])
		check(n[2] == 4.0, "B: " .. n[2])
		near(n[3], (5 + math.sqrt(52)) / 2, "C")
		local all = knn(points, archive, 2, 15)
		near(all[1], 19 / 3, "A, every neighbour")
		-- without the archive, A's neighbours are B and C
		check(knn(points, {}, 2, 2)[1] == 7.5, "A without the archive")
		-- k = 1: the nearest alone
		check(knn(points, archive, 2, 1)[2] == 3.0, "B's nearest is R")
	end
end

-- A point is not its own neighbour, but a twin is one at distance 0; a
-- lone point with an empty archive has novelty 0.
function T.twins_and_a_lone_point()
	for _, knn in ipairs{ novelty.knn_lua, kernel.knn } do
		local n = knn({ 0.5, 0.5, 0.5, 0.5, 1.0, 0.5 }, {}, 2, 1)
		check(n[1] == 0 and n[2] == 0, "twins are at 0 from each other")
		check(n[3] == 0.5, "the third's nearest is 0.5 away: " .. n[3])
		check(knn({ 0.25 }, {}, 1, 15)[1] == 0, "a lone point")
		check(knn({ 0.25 }, { 0.75 }, 1, 15)[1] == 0.5, "a point and the archive")
	end
end

-- The C kernel is the Lua reference to the last bit, on random points in
-- 2 and 5 dimensions, archives of 0 to 3,000, k of 1, 15 and more than
-- there are.
function T.c_and_lua_agree_on_random_data()
	local rng = random.new(7)
	for _, case in ipairs{ { 250, 0, 2, 15 }, { 250, 3000, 2, 15 }, { 40, 500, 5, 1 },
		{ 10, 3, 5, 100 }, { 1, 20, 3, 15 } } do
		local n, m, d, k = table.unpack(case)
		local points, archive = {}, {}
		for i = 1, n * d do points[i] = rng:unit() end
		for i = 1, m * d do archive[i] = rng:unit() end
		-- a few exact duplicates, where ties are
		if n > 2 then for q = 1, d do points[d + q] = points[q] end end
		local a, b = novelty.knn_lua(points, archive, d, k), kernel.knn(points, archive, d, k)
		for i = 1, n do
			check(a[i] == b[i], string.format("n %d, m %d, d %d, k %d: point %d: Lua %.17g, C %.17g",
				n, m, d, k, i, a[i], b[i]))
		end
	end
end

function T.the_kernel_refuses_what_is_not_points()
	check(not pcall(kernel.knn, { 1, 2, 3 }, {}, 2, 15), "3 numbers are not points of 2")
	check(not pcall(kernel.knn, { 1, 0 / 0 }, {}, 2, 15), "a NaN")
	check(not pcall(kernel.knn, { 1, 2 }, {}, 2, 0), "k = 0")
	check(not pcall(kernel.knn, { 1, 2 }, { "x", 1 }, 2, 1), "an archive of words")
end

-- A population of 5 on 2-number descriptors, with rho_min 1, lowered after
-- 2 stalled generations, raised after more than 1 addition.
local function small_pop(options)
	local o = { pop_size = 5, rho_min = 1.0, stall = 2, crowd = 1 }
	for k, v in pairs(options or {}) do o[k] = v end
	local pop = novelty.new{ inputs = 2, outputs = 1, options = o, rng = random.new(3) }
	pop.dims = 2
	return pop
end

local FLAT = { 0.1, 0.1, 0.2, 0.2, 0.3, 0.3, 0.4, 0.4, 0.5, 0.5 }
local FIT = { 1, 2, 3, 4, 5 }
local ALL = { true, true, true, true, true }

-- Candidates 2 and 4 exceed rho_min 1 (strictly: 3's 1.0 does not), so
-- they join the archive in that order, and two additions, more than
-- crowd = 1, raise rho_min by 20% to 1.2. Then two generations with no
-- addition lower it by 5%, to 1.14; with rho_floor 1.2, it stays 1.2.
function T.the_archive_rule_by_hand()
	local pop = small_pop()
	local added = novelty.update_archive(pop, FLAT, FIT, { 0.5, 1.5, 1.0, 2.0, 0.1 }, ALL)
	check(added == 2, "two added: " .. added)
	check(serialize.dump(pop.archive) == serialize.dump{ 0.2, 0.2, 0.4, 0.4 }, "2 and 4, in order")
	-- generation, fitness, novelty of each entry
	check(serialize.dump(pop.archive_meta) == serialize.dump{ 0, 2, 1.5, 0, 4, 2.0 }, "what each is")
	near(pop.rho_min, 1.2, "raised by 20%")
	local low = { 0.1, 0.1, 0.1, 0.1, 0.1 }
	novelty.update_archive(pop, FLAT, FIT, low, ALL)
	near(pop.rho_min, 1.2, "one stalled generation changes nothing")
	check(pop.stalled == 1, "stalled once")
	novelty.update_archive(pop, FLAT, FIT, low, ALL)
	near(pop.rho_min, 1.2 * 0.95, "two lower it by 5%")
	check(pop.stalled == 0, "and the count starts again")
	-- exactly one addition: no raise, and the stall count is reset
	novelty.update_archive(pop, FLAT, FIT, low, ALL)
	novelty.update_archive(pop, FLAT, FIT, { 5, 0, 0, 0, 0 }, ALL)
	check(pop.stalled == 0, "an addition resets the count")
	near(pop.rho_min, 1.2 * 0.95, "one addition is not more than crowd = 1")
	check(#pop.archive == 6, "three entries")

	local floored = small_pop{ rho_floor = 1.2 }
	floored.rho_min = 1.2
	novelty.update_archive(floored, FLAT, FIT, low, ALL)
	novelty.update_archive(floored, FLAT, FIT, low, ALL)
	check(floored.rho_min == 1.2, "never below rho_floor")
end

-- A candidate that fails the minimal criterion never enters the archive,
-- however novel; archive_limit drops the oldest entries; random_add = 1
-- adds every other candidate without counting it towards the raise.
function T.minimal_criterion_limit_and_random_additions()
	local pop = small_pop()
	local added = novelty.update_archive(pop, FLAT, FIT, { 3, 3, 3, 3, 3 },
		{ true, false, true, false, false })
	check(added == 2 and #pop.archive == 4, "only the two that pass")
	check(pop.archive[1] == 0.1 and pop.archive[3] == 0.3, "candidates 1 and 3")

	local limited = small_pop{ archive_limit = 3 }
	novelty.update_archive(limited, FLAT, FIT, { 3, 3, 0, 0, 0 }, ALL)
	novelty.update_archive(limited, FLAT, FIT, { 0, 0, 9, 9, 0 }, ALL)
	check(serialize.dump(limited.archive) == serialize.dump{ 0.2, 0.2, 0.3, 0.3, 0.4, 0.4 },
		"the newest 3: " .. serialize.dump(limited.archive))
	check(#limited.archive_meta == 9 and limited.archive_meta[2] == 2, "their records with them")

	local chance = small_pop{ random_add = 1 }
	added = novelty.update_archive(chance, FLAT, FIT, { 0, 0, 0, 0, 0 }, ALL)
	check(added == 0 and #chance.archive == 10, "all 5 at random, none counted")
	check(chance.stalled == 1, "a generation of random additions is a stalled one")
end

-- Scores: novelty itself (w = 0), 0 for a candidate that fails; with
-- w = 0.25, 0.75 N + 0.25 F, each scaled over the candidates that pass:
-- novelty 1, 3, 2 -> 0, 1, 0.5 and fitness 10, 0, 5 -> 1, 0, 0.5 give
-- 0.25, 0.75, 0.5; with the second failing, novelty 1, 2 -> 0, 1 and
-- fitness 10, 5 -> 1, 0 give 0.25, 0, 0.75.
function T.scores_by_hand()
	local o = { fitness_weight = 0 }
	local s = novelty.scores({ 1, 3, 2 }, { 10, 0, 5 }, { true, false, true }, o)
	check(s[1] == 1 and s[2] == 0 and s[3] == 2, "novelty, 0 for the failing one")
	o.fitness_weight = 0.25
	s = novelty.scores({ 1, 3, 2 }, { 10, 0, 5 }, { true, true, true }, o)
	check(s[1] == 0.25 and s[2] == 0.75 and s[3] == 0.5, "the mix: " .. serialize.dump(s))
	s = novelty.scores({ 1, 3, 2 }, { 10, 0, 5 }, { true, false, true }, o)
	check(s[1] == 0.25 and s[2] == 0 and s[3] == 0.75, "over those that pass: " .. serialize.dump(s))
	s = novelty.scores({ 2, 2 }, { 1, 1 }, { true, true }, o)
	check(s[1] == 0 and s[2] == 0, "no spread: 0")
end

-- The descriptors a synthetic task gives: a network's two outputs for the
-- input (0.5, 0.5); fitness rewards the first output alone (a deceptive
-- objective would trap NEAT; here it only has to be tracked).
local function run(pop, generations)
	local log = {}
	for _ = 1, generations do
		local fit, desc = {}, {}
		for i, g in ipairs(pop:genomes()) do
			local out = neat.eval_float(neat.to_net(g), { 0.5, 0.5 })
			desc[i] = { out[1], out[2] }
			fit[i] = out[1]
		end
		pop:tell(fit, desc)
		log[#log + 1] = string.format("%d %.17g %.17g %.17g", #pop.archive // 2, pop.rho_min,
			pop.last.best_novelty, pop.best.fitness)
	end
	return table.concat(log, "\n")
end

local function new_run(seed)
	return novelty.new{ inputs = 2, outputs = 2, rng = random.new(seed),
		options = { pop_size = 30, rho_min = 0.05 } }
end

-- NEAT breeds by the score: after tell, each genome of the generation
-- carries its novelty as the fitness NEAT ranked it by, while pop.best is
-- the best by the objective. The archive grows from the first generation.
function T.neat_breeds_by_novelty_and_keeps_the_best_by_fitness()
	local pop = new_run(5)
	local genomes = pop:genomes()
	local fit, desc = {}, {}
	for i = 1, #genomes do
		fit[i] = i == 1 and 100 or 0
		desc[i] = { (i - 1) / #genomes, 0.5 }
	end
	local flat = {}
	for i = 1, #genomes do flat[#flat + 1], flat[#flat + 2] = desc[i][1], desc[i][2] end
	local expect = novelty.knn_lua(flat, {}, 2, 15)
	pop:tell(fit, desc)
	for i, g in ipairs(genomes) do
		check(g.fitness == expect[i], "genome " .. i .. " ranked by its novelty")
	end
	check(pop.best.fitness == 100, "the best by fitness: " .. pop.best.fitness)
	-- the ends of the line are the most novel: (1 + ... + 15) / 15 / 30 = 8 / 30
	near(pop.last.best_novelty, 8 / 30, "best novelty")
	check(#pop.archive // 2 == 30, "every candidate beats rho_min 0.05 in generation 0")
	near(pop.rho_min, 0.06, "30 additions raise it")
	check(pop.generation == 1 and #pop:genomes() == 30, "a new generation of 30")
end

-- A checkpoint holds the archive, the threshold and the random stream: a
-- run saved after 4 generations and loaded goes on as the one never saved.
function T.a_run_resumed_from_its_checkpoint_goes_on_identically()
	local whole = new_run(11)
	local first = run(whole, 4)
	local rest = run(whole, 4)
	local saved = new_run(11)
	check(run(saved, 4) == first, "the same seed, the same run")
	local text = serialize.dump(novelty.save(saved, true))
	local back = novelty.load(serialize.load(text, "checkpoint"))
	check(getmetatable(back) == novelty.Pop, "a novelty population")
	check(run(back, 4) == rest, "resumed:\n" .. rest)
	check(#back.archive > 0, "with its archive")
	check(not pcall(neat.load, novelty.save(back)), "NEAT refuses a novelty checkpoint")
end

function T.descriptors_are_checked()
	local pop = new_run(1)
	local fit = {}
	for i = 1, 30 do fit[i] = 0 end
	local ok, msg = pcall(pop.tell, pop, fit)
	check(not ok and msg:find("NOVELTY needs a behaviour descriptor of every candidate", 1, true), msg)
	local desc = {}
	for i = 1, 30 do desc[i] = { 0.5, 0.5 } end
	desc[7] = { 0.5 }
	ok, msg = pcall(pop.tell, pop, fit, desc)
	check(not ok and msg:find("candidate 6's behaviour descriptor has 1 numbers, not 2", 1, true), msg)
	desc[7] = { 0.5, 0 / 0 }
	ok, msg = pcall(pop.tell, pop, fit, desc)
	check(not ok and msg:find("candidate 6's behaviour descriptor holds", 1, true), msg)
end

function T.options_from_a_task()
	local o, unknown = novelty.options_from_task{ NOVELTY_K = "5", POPSIZE = "250",
		NEAT_ADD_NODE_PROB = "0.1", NOVELTY_MIN_FITNESS = "-2.5", NOVELTY_BOGUS = "1", NEAT_BOGUS = "1" }
	check(o.k == 5 and o.pop_size == 250 and o.add_node_prob == 0.1, "NOVELTY_ and NEAT keys")
	check(o.min_fitness == "-2.5", "a minimal criterion")
	check(#unknown == 2 and unknown[1] == "NEAT_BOGUS" and unknown[2] == "NOVELTY_BOGUS",
		"unknown keys of both prefixes")
	local ok, msg = pcall(novelty.options_from_task, { NOVELTY_K = "0" })
	check(not ok and msg == "NOVELTY_K: expected a whole number from 1 to 1000, found '0'", msg)
	ok, msg = pcall(novelty.options_from_task, { NOVELTY_MIN_FITNESS = "low" })
	check(not ok and msg == "NOVELTY_MIN_FITNESS: expected off or a number, found 'low'", msg)
	ok, msg = pcall(novelty.options_from_task, { NOVELTY_LOWER = "1.5" })
	check(not ok and msg:find("NOVELTY_LOWER: expected", 1, true), msg)
	local pop = novelty.new{ inputs = 1, outputs = 1, rng = random.new(1),
		options = novelty.options_from_task{ NOVELTY_MIN_FITNESS = "3", POPSIZE = "4" } }
	check(pop.options.pop_size == 4 and #pop:genomes() == 4, "NEAT's options reach NEAT")
	check(pop.options.k == 15 and pop.rho_min == 0.03, "defaults")
	-- fitness below 3 fails: every candidate scores 0 and none is archived
	local fit, desc = { 1, 2, 3, 4 }, { { 0 }, { 0.25 }, { 0.5 }, { 1 } }
	local genomes = pop:genomes()
	pop:tell(fit, desc)
	check(genomes[1].fitness == 0 and genomes[2].fitness == 0, "below 3: 0")
	check(genomes[3].fitness > 0 and genomes[4].fitness > 0, "3 and above: their novelty")
	check(#pop.archive == 2 and pop.archive[1] == 0.5 and pop.archive[2] == 1.0, "only those archived")
end

-- The result grid (NOVELTY_COVERAGE_GRID): every evaluated descriptor
-- marks its cell, whether or not it enters the archive. A 4 x 4 grid and
-- four candidates at (0, 0), (0.1, 0.2), (0.3, 0.3) and (1, 1): cells of
-- 0.25, the first two in cell (0, 0), the third in (1, 1), the last in
-- (3, 3) (1 is in the last part): 3 of 16 cells, 0.1875. A second batch
-- at the same places marks nothing new; one at (0.5, 0.99) marks (2, 3).
function T.the_result_grid_counts_every_evaluated_descriptor()
	local pop = novelty.new{ inputs = 1, outputs = 1, rng = random.new(1),
		options = novelty.options_from_task{ NOVELTY_COVERAGE_GRID = "4", POPSIZE = "4",
			NOVELTY_THRESHOLD = "100" } }
	check(pop:coverage() == 0, "nothing evaluated yet")
	check(pop:log_names()[4] == "coverage", "a coverage column")
	local desc = { { 0, 0 }, { 0.1, 0.2 }, { 0.3, 0.3 }, { 1, 1 } }
	pop:tell({ 0, 0, 0, 0 }, desc)
	check(#pop.archive == 0, "none passes a threshold of 100")
	check(pop:coverage() == 3 / 16, "3 of 16 cells: " .. pop:coverage())
	check(pop:log_values()[4] == 3 / 16, "logged")
	pop:tell({ 0, 0, 0, 0 }, desc)
	check(pop:coverage() == 3 / 16, "the same cells again")
	pop:tell({ 0, 0, 0, 0 }, { { 0.5, 0.99 }, { 0, 0 }, { 0, 0 }, { 0, 0 } })
	check(pop:coverage() == 4 / 16, "one more cell: " .. pop:coverage())
	local back = novelty.load(serialize.load(serialize.dump(novelty.save(pop, true)), "c"))
	check(back:coverage() == 4 / 16, "the checkpoint holds the grid")
	local plain = novelty.new{ inputs = 1, outputs = 1, rng = random.new(1),
		options = { pop_size = 4 } }
	check(#plain:log_names() == 3, "no grid, no column")
	local ok, msg = pcall(novelty.options_from_task, { NOVELTY_COVERAGE_GRID = "-1" })
	check(not ok and msg:find("NOVELTY_COVERAGE_GRID: expected", 1, true), msg)
end

return T

-- Unit tests of lua/learn/genetic.lua, run by tests/sim/lua/test_lua_scripts.c.
-- Each entry of the returned table is one test; it fails by raising.
local genetic = require "learn.genetic"
local random = require "learn.rng"
local serialize = require "learn.serialize"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local T = {}

-- GENETIC draws from learn.rng and writes with learn.netfile; it does not
-- load NEAT. Every learn.* module is unloaded first, so learn.genetic and
-- what it requires load afresh, whatever this file loaded.
function T.genetic_does_not_load_neat()
	for name in pairs(package.loaded) do
		if name:match("^learn%.") then package.loaded[name] = nil end
	end
	local m = require "learn.genetic"
	check(type(m.to_net_text) == "function" and type(m.load) == "function", "learn.genetic loads")
	check(package.loaded["learn.rng"] and package.loaded["learn.netfile"], "with the shared rng and writer")
	check(package.loaded["learn.neat"] == nil, "learn.genetic loaded learn.neat")
end

-- A genome whose genes are base+1, base+2, ... so each gene says which
-- parent and position it came from.
local function tagged(n, base)
	local w = {}
	for i = 1, n do w[i] = base + i end
	return { inputs = 1, outputs = 1, layers = 0, weights = w }
end

function T.uniform_crossover_takes_each_gene_from_a_parent_at_its_position()
	local n = 200
	local a, b = tagged(n, 1000), tagged(n, 2000)
	local rng = random.new(1)
	local from_a = 0
	for _ = 1, 20 do
		local c = genetic.crossover_uniform(a, b, rng)
		check(#c.weights == n, "child has n genes")
		for i, x in ipairs(c.weights) do
			check(x == 1000 + i or x == 2000 + i, "gene " .. i .. " from a parent at the same position")
			if x == 1000 + i then from_a = from_a + 1 end
		end
	end
	-- 4000 fair coin flips: mean 2000, sigma about 32.
	check(math.abs(from_a - 2000) < 160, "about half the genes from each parent: " .. from_a)
	check(a.weights[1] == 1001 and b.weights[1] == 2001, "parents unchanged")
end

function T.one_point_crossover_is_a_prefix_of_one_parent_and_a_suffix_of_the_other()
	local n = 50
	local a, b = tagged(n, 1000), tagged(n, 2000)
	local rng = random.new(2)
	for _ = 1, 100 do
		local c = genetic.crossover_one_point(a, b, rng)
		local cut = 0
		while cut < n and c.weights[cut + 1] == 1000 + cut + 1 do cut = cut + 1 end
		check(cut >= 1 and cut <= n - 1, "each parent gives at least one gene")
		for i = cut + 1, n do check(c.weights[i] == 2000 + i, "suffix from b at the same position") end
	end
end

function T.mutation_changes_about_rate_times_n_genes()
	local n, rate, total, trials = 1000, 0.1, 0, 20
	local rng = random.new(3)
	for _ = 1, trials do
		local g = tagged(n, 0)
		local before = genetic.copy(g)
		local count = genetic.mutate(g, rate, 0.5, 1e9, rng)
		local changed = 0
		for i = 1, n do
			if g.weights[i] ~= before.weights[i] then changed = changed + 1 end
		end
		check(changed == count, "mutate reports the genes it changed")
		total = total + changed
	end
	-- Binomial(20000, 0.1): mean 2000, sigma about 42.
	check(math.abs(total - 2000) < 4 * 42, "about rate*n genes mutate: " .. total)
end

function T.mutation_clamps_to_weight_max()
	local g = tagged(100, 0)
	genetic.mutate(g, 1, 100, 8, random.new(4))
	for _, x in ipairs(g.weights) do check(x >= -8 and x <= 8, "clamped") end
end

function T.tournament_prefers_fitter()
	local fitness = { 1, 2, 3, 4, 5, 6, 7, 8, 9, 10 }
	local rng = random.new(5)
	local wins = {}
	for i = 1, 10 do wins[i] = 0 end
	local trials = 20000
	for _ = 1, trials do
		local i = genetic.tournament(fitness, 3, rng)
		wins[i] = wins[i] + 1
	end
	for i = 2, 10 do check(wins[i] > wins[i - 1], "fitter wins more often") end
	-- P(best of 3 draws from 10 is the top) = 1 - 0.9^3 = 0.271.
	local p = 1 - 0.9 ^ 3
	local sigma = math.sqrt(trials * p * (1 - p))
	check(math.abs(wins[10] - trials * p) < 4 * sigma, "top wins with 1-(9/10)^3: " .. wins[10])
	check(genetic.tournament(fitness, 1, rng) >= 1, "size 1 is a uniform pick")
	-- NaN never beats a number.
	local nan = { 0 / 0, 0 / 0, 1 }
	for _ = 1, 200 do
		local i = genetic.tournament(nan, 60, rng)
		check(i == 3, "NaN loses")
	end
end

function T.elitism_keeps_the_best_unchanged()
	local pop = genetic.new { inputs = 2, outputs = 1, layers = 1, rng = random.new(6),
		options = { pop_size = 10, elitism = 2, mutation_rate = 1, crossover_rate = 1 } }
	local g = pop:genomes()
	local fitness = { 1, 2, 9, 4, 5, 8, 7, 0, 3, 6 }
	local best, second = genetic.copy(g[3]), genetic.copy(g[6])
	pop:tell(fitness)
	local n = pop:genomes()
	check(#n == 10, "population size kept")
	for i, x in ipairs(best.weights) do check(n[1].weights[i] == x, "the best unchanged, first") end
	for i, x in ipairs(second.weights) do check(n[2].weights[i] == x, "the second unchanged") end
	for k = 3, 10 do
		local same = true
		for i, x in ipairs(best.weights) do same = same and n[k].weights[i] == x end
		check(not same, "with mutation rate 1 the others differ")
	end
	check(pop.best.fitness == 9, "best fitness")
	for i, x in ipairs(best.weights) do check(pop.best.genome.weights[i] == x, "best genome") end
	check(#pop.species == 0, "no species")
	check(pop.evaluations == 10 and pop.generation == 1, "counters")
end

function T.weight_count_matches_net_build()
	-- net_build: layers of width max(n_in, n_out), each node bias + fan-in.
	check(genetic.weight_count(2, 1, 1) == 2 * 3 + 1 * 3, "2-2-1")
	check(genetic.weight_count(2, 1, 0) == 3, "2-1")
	check(genetic.weight_count(11, 2, 1) == 11 * 12 + 2 * 12, "Avoid with layers:1")
	check(genetic.weight_count(1, 3, 2) == 3 * 2 + 3 * 4 + 3 * 4, "1-3-3-3")
	local pop = genetic.new { inputs = 11, outputs = 2, layers = 1, rng = random.new(7) }
	check(#pop:genomes()[1].weights == 156, "genomes have weight_count genes")
	check(#pop:genomes() == genetic.defaults.pop_size, "default population")
end

function T.hidden_sets_the_width_of_the_hidden_layers()
	-- HIDDEN:4 on Avoid: 4 hidden nodes of 11 + 1 weights, 2 outputs of 4 + 1
	check(genetic.weight_count(11, 2, 1, 4) == 4 * 12 + 2 * 5, "Avoid with HIDDEN:4")
	check(genetic.weight_count(2, 1, 2, 3) == 3 * 3 + 3 * 4 + 1 * 4, "2-3-3-1")
	local pop = genetic.new { inputs = 11, outputs = 2, layers = 1, hidden = 4, rng = random.new(7) }
	local g = pop:genomes()[1]
	check(#g.weights == 58 and g.width == 4, "genomes carry HIDDEN's width")
	local net = genetic.to_net(g)
	-- 4 hidden nodes and 2 outputs; hidden ids from 13 on
	check(#net.nodes == 6, "nodes: 4 hidden + 2 outputs")
	check(net.nodes[4].id == 16 and net.nodes[5].id == 11, "ids: hidden 13..16, then outputs")
	check(#net.links == 4 * 11 + 2 * 4, "links")
	-- the width survives a copy, a generation and a checkpoint
	local fit = {}
	for i = 1, #pop:genomes() do fit[i] = i end
	pop:tell(fit)
	check(pop:genomes()[1].width == 4 and #pop:genomes()[1].weights == 58, "after tell")
	local back = genetic.load(genetic.save(pop))
	check(back.width == 4 and back:genomes()[2].width == 4, "after a checkpoint")
end

-- The network sim/mind/net_build.c builds for 2 inputs, 1 hidden layer, 1 output,
-- written by hand: hidden ids 3, 4 (after inputs 0, 1 and output 2), listed
-- hidden first, each node its bias then its links from the previous layer.
local HAND_NET = [[
inputs:2
outputs:1
node:3:sigmoid:1
node:4:sigmoid:4
node:2:sigmoid:7
output:2
link:0:3:2
link:1:3:3
link:0:4:5
link:1:4:6
link:3:2:8
link:4:2:9
]]

function T.to_net_matches_net_build_layout()
	local g = { inputs = 2, outputs = 1, layers = 1, weights = { 1, 2, 3, 4, 5, 6, 7, 8, 9 } }
	local net = genetic.to_net(g)
	check(genetic.to_net_text(net) == HAND_NET, "layout:\n" .. genetic.to_net_text(net))
	check(net.outputs_ids[1] == 2 and net.inputs == 2 and net.outputs == 1, "shape")
	-- And the float evaluation of it: sigmoid everywhere. (NEAT's float
	-- evaluator, which any network table takes; learn.genetic itself does
	-- not load learn.neat.)
	local neat = require "learn.neat"
	local s = neat.activations.sigmoid
	local x1, x2 = 0.3, 0.7
	local h3, h4 = s(1 + 2 * x1 + 3 * x2), s(4 + 5 * x1 + 6 * x2)
	local y = neat.eval_float(net, { x1, x2 })[1]
	check(math.abs(y - s(7 + 8 * h3 + 9 * h4)) < 1e-12, "evaluates as a layered net")
	-- layers = 0: inputs straight to the outputs.
	local direct = genetic.to_net { inputs = 2, outputs = 1, layers = 0, weights = { 1, 2, 3 } }
	check(genetic.to_net_text(direct) == "inputs:2\noutputs:1\nnode:2:sigmoid:1\noutput:2\nlink:0:2:2\nlink:1:2:3\n",
		"layers:0")
end

function T.options_from_task()
	local o, unknown = genetic.options_from_task { GA_POPSIZE = "20", GA_ELITISM = "3",
		GA_MUTATION_RATE = "0.2", GA_CROSSOVER = "one_point", GA_BOGUS = "1", NEAT_C1 = "2", TICKLIM = "5" }
	check(o.pop_size == 20 and o.elitism == 3 and o.mutation_rate == 0.2 and o.crossover == "one_point", "values")
	check(#unknown == 1 and unknown[1] == "GA_BOGUS", "only unknown GA_ keys")
	check(genetic.options_from_task { POPSIZE = "7" }.pop_size == 7, "POPSIZE")
	check(not pcall(genetic.options_from_task, { GA_ELITISM = "x" }), "a malformed number raises")
	check(not pcall(genetic.options_from_task, { GA_CROSSOVER = "two_point" }), "an unknown crossover raises")
	for k, name in pairs(genetic.task_keys) do
		check(genetic.defaults[name] ~= nil, k .. " sets a known option")
	end
end

-- A smooth task: fitness = -sum (w_i - 0.5)^2, best 0.
local function generation(pop)
	local fit = {}
	for i, g in ipairs(pop:genomes()) do
		local s = 0
		for _, x in ipairs(g.weights) do s = s - (x - 0.5) ^ 2 end
		fit[i] = s
	end
	pop:tell(fit)
end

function T.save_load_continues_identically()
	local a = genetic.new { inputs = 2, outputs = 1, layers = 1, rng = random.new(8), options = { pop_size = 20 } }
	for _ = 1, 5 do generation(a) end
	local text = serialize.dump(genetic.save(a))
	local b = genetic.load(serialize.load(text, "checkpoint"))
	check(serialize.dump(genetic.save(b)) == text, "save(load(save)) is save")
	for _ = 1, 5 do
		generation(a)
		generation(b)
	end
	check(serialize.dump(genetic.save(a)) == serialize.dump(genetic.save(b)), "resumed = uninterrupted")
	check(b.generation == 10 and b.evaluations == 200, "counters")
end

function T.same_seed_same_run_and_it_learns()
	local function run(seed)
		local pop = genetic.new { inputs = 2, outputs = 1, layers = 1, rng = random.new(seed), options = { pop_size = 30 } }
		generation(pop)
		local first = pop.best.fitness
		for _ = 1, 40 do generation(pop) end
		return serialize.dump(genetic.save(pop)), first, pop.best.fitness
	end
	local a, f0, f1 = run(9)
	check(a == run(9), "same seed, same run")
	check(a ~= run(10), "other seed, other run")
	check(f1 > f0 and f1 > -0.5, "fitness rises: " .. f0 .. " -> " .. f1)
end

return T

-- GENETIC: a generational genetic algorithm over evo's fixed layered
-- networks, in pure Lua 5.4 (docs/learning.md).
--
--	local genetic = require "learn.genetic"
--	local random = require "learn.rng"
--	local pop = genetic.new{ inputs = 2, outputs = 1, layers = 1,
--		options = { pop_size = 50 }, rng = random.new(42) }
--	for gen = 1, 100 do
--		local fit = {}
--		for i, g in ipairs(pop:genomes()) do fit[i] = evaluate(genetic.to_net(g)) end
--		pop:tell(fit)
--	end
--
-- Topology. The network is the one evo builds for a neural skill with
-- `layers:N` (sim/mind/net_build.h): N hidden layers of width max(n_in, n_out),
-- or the task's HIDDEN, every node fed by every node of the previous layer plus a bias, sigmoid
-- everywhere. Ids: inputs 0..n_in-1, outputs n_in..n_in+n_out-1, hidden
-- nodes from n_in+n_out on, layer by layer. A genome is the flat weight
-- vector in net_build's order: nodes listed hidden layer 1, ..., hidden
-- layer N, then the outputs; for each node its bias, then the weights from
-- the previous layer's nodes in id order. Keeping net_build's order means a
-- genome and the C builder can never disagree about which weight is which.
--
-- A genome is { inputs, outputs, layers, width, weights = {...} } (width nil:
-- the default): the shape travels with the weights so to_net needs nothing
-- else.
--
-- Determinism. Every draw goes through the rng given to genetic.new (the
-- xoshiro generator of learn.rng); loops run over arrays only, so the same
-- seed gives the same run, and genetic.save / genetic.load hold it all.
--
-- Fitness is "higher is better"; NaN counts as the worst.
local common = require "learn.common"
local netfile = require "learn.netfile"
local random = require "learn.rng"

local genetic = {}

genetic.defaults = {
	pop_size = 50, -- genomes per generation
	elitism = 2, -- the best this many pass to the next generation unchanged
	tournament = 3, -- tournament size for selecting a parent (drawn with replacement)
	crossover_rate = 0.7, -- chance a child comes from two parents; else a copy of one
	crossover = "uniform", -- "uniform" (each gene from either parent) or "one_point"
	mutation_rate = 0.1, -- chance each gene of a child is mutated
	mutation_power = 0.5, -- a mutation adds normal(0, power)
	init_power = 1.0, -- first weights are normal(0, power)
	weight_max = 8.0, -- weights are clamped to [-w, w] (.net needs |w| < 128)
}

-- .simbatch key -> option name. POPSIZE is the tutorial's own key;
-- GA_MUT_RATE and GA_MUT_POWER are short names kept for tasks written with
-- them.
genetic.task_keys = {
	GA_MUT_RATE = "mutation_rate",
	GA_MUT_POWER = "mutation_power",
	POPSIZE = "pop_size",
	GA_POPSIZE = "pop_size",
	GA_ELITISM = "elitism",
	GA_TOURNAMENT = "tournament",
	GA_CROSSOVER_RATE = "crossover_rate",
	GA_CROSSOVER = "crossover",
	GA_MUTATION_RATE = "mutation_rate",
	GA_MUTATION_POWER = "mutation_power",
	GA_INIT_POWER = "init_power",
	GA_WEIGHT_MAX = "weight_max",
}

local CHOICES = { crossover = { uniform = true, one_point = true } }

-- The numbers each option takes (common.options_from): the elite and a
-- tournament are at most a population.
genetic.ranges = {
	pop_size = common.POPULATION, elitism = { lo = 0, hi = 10000, int = true },
	tournament = common.POPULATION,
	crossover_rate = common.PROB, mutation_rate = common.PROB, mutation_power = common.POSITIVE,
	init_power = common.POSITIVE, weight_max = common.WEIGHT_MAX,
}

function genetic.options_from_task(task)
	local o, unknown = common.options_from(task, "GA_", genetic.task_keys, genetic.defaults,
		function(key, s, value)
			local name = genetic.task_keys[key]
			if CHOICES[name] and not CHOICES[name][s] then
				error(key .. ": unknown value '" .. tostring(value) .. "'", 0)
			end
		end, genetic.ranges)
	local elitism = o.elitism or genetic.defaults.elitism
	local size = o.pop_size or genetic.defaults.pop_size
	if elitism > size then
		error(string.format("GA_ELITISM: %d is more than the population (%d)", elitism, size), 0)
	end
	return o, unknown
end


---------------------------------------------------------------------------
-- The layered shape (sim/mind/net_build.h)

-- The hidden layers' width: the task's HIDDEN when given, else net_build's
-- default max(n_in, n_out).
function genetic.width(n_in, n_out, hidden) return hidden or math.max(n_in, n_out, 1) end

-- Number of weights of the layered network: net_build's weight count.
function genetic.weight_count(n_in, n_out, layers, hidden)
	local w, prev, count = genetic.width(n_in, n_out, hidden), n_in, 0
	for _ = 1, layers do
		count = count + w * (prev + 1)
		prev = w
	end
	return count + n_out * (prev + 1)
end

-- Genome -> network table, the shape neat.to_net gives (the host's evaluate
-- and learn.netfile take it), with net_build's ids and listing order.
function genetic.to_net(g)
	local n_in, n_out, layers = g.inputs, g.outputs, g.layers
	local width = genetic.width(n_in, n_out, g.width)
	local w = g.weights
	assert(#w == genetic.weight_count(n_in, n_out, layers, g.width), "to_net: wrong number of weights")
	local nodes, links, outputs_ids = {}, {}, {}
	local k = 0
	local prev_first, prev_count = 0, n_in
	for l = 0, layers do
		local count = l < layers and width or n_out
		local first = l < layers and n_in + n_out + l * width or n_in
		for j = 0, count - 1 do
			local id = first + j
			k = k + 1
			nodes[#nodes + 1] = { id = id, act = "sigmoid", bias = w[k] }
			for s = 0, prev_count - 1 do
				k = k + 1
				links[#links + 1] = { from = prev_first + s, to = id, weight = w[k] }
			end
		end
		prev_first, prev_count = first, count
	end
	for j = 0, n_out - 1 do outputs_ids[j + 1] = n_in + j end
	return { inputs = n_in, outputs = n_out, nodes = nodes, outputs_ids = outputs_ids, links = links }
end

genetic.to_net_text = netfile.text

local function clamp(x, m) return x > m and m or (x < -m and -m or x) end

function genetic.copy(g)
	local w = {}
	for i, x in ipairs(g.weights) do w[i] = x end
	return { inputs = g.inputs, outputs = g.outputs, layers = g.layers, width = g.width, weights = w }
end

-- A genome of normal(0, power) weights; hidden: the hidden layers' width
-- (nil: the default).
function genetic.random_genome(n_in, n_out, layers, power, weight_max, rng, hidden)
	local w = {}
	for i = 1, genetic.weight_count(n_in, n_out, layers, hidden) do
		w[i] = clamp(rng:normal() * power, weight_max)
	end
	return { inputs = n_in, outputs = n_out, layers = layers, width = hidden, weights = w }
end

---------------------------------------------------------------------------
-- Operators (exposed for tests)

-- Each gene from a or b with equal chance, position by position.
function genetic.crossover_uniform(a, b, rng)
	local c = genetic.copy(a)
	for i, x in ipairs(b.weights) do
		if rng:unit() < 0.5 then c.weights[i] = x end
	end
	return c
end

-- Genes 1..cut from a, cut+1..n from b, cut uniform in 1..n-1 (so each
-- parent gives at least one gene when n >= 2).
function genetic.crossover_one_point(a, b, rng)
	local c = genetic.copy(a)
	local n = #a.weights
	if n < 2 then return c end
	local cut = 1 + math.floor(rng:unit() * (n - 1))
	for i = cut + 1, n do c.weights[i] = b.weights[i] end
	return c
end

-- Each gene mutates with chance `rate` by adding normal(0, power), then is
-- clamped. Changes g in place; returns how many genes it mutated.
function genetic.mutate(g, rate, power, weight_max, rng)
	local count = 0
	local w = g.weights
	for i = 1, #w do
		if rng:unit() < rate then
			w[i] = clamp(w[i] + rng:normal() * power, weight_max)
			count = count + 1
		end
	end
	return count
end

local function better(a, b)
	-- NaN is the worst fitness, so a NaN never wins a comparison.
	if a ~= a then return false end
	if b ~= b then return true end
	return a > b
end
genetic.better = better

-- The indices 1..#fitness, best first (better's order, ties by index).
function genetic.rank(fitness)
	local order = {}
	for i = 1, #fitness do order[i] = i end
	table.sort(order, function(a, b)
		if better(fitness[a], fitness[b]) then return true end
		if better(fitness[b], fitness[a]) then return false end
		return a < b
	end)
	return order
end

-- Index of the fittest of k draws (with replacement) from 1..#fitness;
-- ties go to the earlier draw.
function genetic.tournament(fitness, k, rng)
	local n = #fitness
	local best = 1 + math.floor(rng:unit() * n)
	for _ = 2, k do
		local i = 1 + math.floor(rng:unit() * n)
		if better(fitness[i], fitness[best]) then best = i end
	end
	return best
end

---------------------------------------------------------------------------
-- The population

local Pop = {}
Pop.__index = Pop

-- args: inputs, outputs, layers (hidden layers, default 1), hidden (their
-- width, default max(inputs, outputs): the task's HIDDEN), options, rng.
function genetic.new(args)
	local o = common.merged(genetic.defaults, args.options, "genetic.new")
	local rng = args.rng or error("genetic.new: an rng is required (learn.rng: random.new(seed))")
	local layers = args.layers or 1
	assert(o.pop_size >= 1 and o.pop_size == math.floor(o.pop_size), "GA_POPSIZE must be a whole number >= 1")
	assert(o.elitism >= 0 and o.elitism <= o.pop_size, "GA_ELITISM must be between 0 and the population size")
	assert(o.tournament >= 1, "GA_TOURNAMENT must be at least 1")
	local pop = setmetatable({
		options = o, inputs = args.inputs, outputs = args.outputs, layers = layers,
		width = args.hidden, rng = rng, generation = 0, evaluations = 0, species = {},
		population = {}, best = nil,
	}, Pop)
	for i = 1, o.pop_size do
		pop.population[i] = genetic.random_genome(args.inputs, args.outputs, layers,
			o.init_power, o.weight_max, rng, args.hidden)
	end
	return pop
end

function Pop:genomes() return self.population end

-- fitness[i] is the fitness of genomes()[i]. Builds the next generation:
-- the `elitism` best unchanged (in fitness order, ties by index), then
-- children of tournament-selected parents, crossed over with chance
-- crossover_rate, then mutated.
function Pop:tell(fitness)
	local o, rng, popl = self.options, self.rng, self.population
	assert(#fitness == #popl, "tell: one fitness per genome")
	self.evaluations = self.evaluations + #fitness
	local order = genetic.rank(fitness)
	local top = order[1]
	if not self.best or better(fitness[top], self.best.fitness) then
		self.best = { genome = genetic.copy(popl[top]), fitness = fitness[top] }
	end
	local next_pop = {}
	for e = 1, math.min(o.elitism, #popl) do next_pop[e] = genetic.copy(popl[order[e]]) end
	local cross = o.crossover == "one_point" and genetic.crossover_one_point or genetic.crossover_uniform
	while #next_pop < o.pop_size do
		local a = popl[genetic.tournament(fitness, o.tournament, rng)]
		local child
		if rng:unit() < o.crossover_rate then
			local b = popl[genetic.tournament(fitness, o.tournament, rng)]
			child = cross(a, b, rng)
		else
			child = genetic.copy(a)
		end
		genetic.mutate(child, o.mutation_rate, o.mutation_power, o.weight_max, rng)
		next_pop[#next_pop + 1] = child
	end
	self.population = next_pop
	self.generation = self.generation + 1
end

---------------------------------------------------------------------------
-- Checkpoints: plain tables, the rng's state included.

-- `shared`: see common.save.
function genetic.save(pop, shared)
	return common.save(pop, "evo-genetic-1", shared)
end

function genetic.load(t, rng)
	return common.load(t, "evo-genetic-1", Pop, rng, random.load)
end

return genetic

-- ANNEALING: simulated annealing over evo's fixed layered networks (the
-- shape and genome of learn.genetic), in pure Lua 5.4 (docs/learning.md).
--
-- One point is current. A move proposes a neighbour (every weight plus
-- normal(0, SA_STEP_POWER), clamped) and accepts it by Metropolis for
-- maximisation: always when it is no worse, else with probability
-- exp((f_new - f_cur) / T). After every move T <- alpha * T.
--
-- A "generation" is a batch of K = SA_STEPS_PER_GENERATION moves (default
-- 1); with K > 1 the evaluator runs the K neighbours on its threads:
--   * the K neighbours are all drawn around the current point as it is at
--     the start of the generation (they are independent of each other);
--   * after evaluation they are decided in order 1..K: neighbour i is
--     compared with the current fitness as it stands after neighbours
--     1..i-1 were decided, and replaces the current point if accepted;
--   * T is multiplied by alpha after each of the K decisions.
-- With K = 1 this is the tutorial's strictly sequential, single-threaded
-- annealing. The first generation also evaluates the starting point: its
-- batch is the start followed by K-1 neighbours of it, and only those K-1
-- are moves (T cools K-1 times).
--
-- Determinism as in learn.genetic: every draw goes through the given rng,
-- and annealing.save / annealing.load hold the whole state.
local common = require "learn.common"
local genetic = require "learn.genetic"
local random = require "learn.rng"

local annealing = {}

annealing.defaults = {
	t0 = 100.0, -- starting temperature, in fitness units
	alpha = 0.995, -- cooling factor per move
	step_power = 0.3, -- a neighbour adds normal(0, power) to every weight
	steps_per_generation = 1, -- K: moves (candidates) per generation; 1 is
	-- the tutorial's sequential, single-threaded annealing
	init_power = 1.0, -- the starting point's weights are normal(0, power)
	weight_max = 8.0, -- weights are clamped to [-w, w] (.net needs |w| < 128)
}

-- .simbatch key -> option name; SA_COOLING and SA_STEP are short names
-- kept for tasks written with them.
annealing.task_keys = {
	SA_COOLING = "alpha",
	SA_STEP = "step_power",
	SA_T0 = "t0",
	SA_ALPHA = "alpha",
	SA_STEP_POWER = "step_power",
	SA_STEPS_PER_GENERATION = "steps_per_generation",
	SA_INIT_POWER = "init_power",
	SA_WEIGHT_MAX = "weight_max",
}

-- The numbers each option takes (common.options_from); alpha = 1 is no
-- cooling at all. A generation's moves are a batch, at most a population.
annealing.ranges = {
	t0 = common.POSITIVE, alpha = { lo = 0, hi = 1, above = true }, step_power = common.POSITIVE,
	steps_per_generation = common.POPULATION, init_power = common.POSITIVE,
	weight_max = common.WEIGHT_MAX,
}

function annealing.options_from_task(task)
	return common.options_from(task, "SA_", annealing.task_keys, annealing.defaults, nil,
		annealing.ranges)
end

annealing.to_net = genetic.to_net
annealing.to_net_text = genetic.to_net_text

-- Metropolis acceptance for maximisation: delta = f_new - f_cur. An
-- improvement (or a tie) is always accepted without drawing, so the
-- rng's sequence depends only on the worse moves; a worse move is
-- accepted with probability exp(delta / T). NaN is never accepted.
function annealing.accept(delta, T, rng)
	if delta ~= delta then return false end
	if delta >= 0 then return true end
	if T <= 0 then return false end
	return rng:unit() < math.exp(delta / T)
end

function annealing.neighbour(g, power, weight_max, rng)
	local c = genetic.copy(g)
	local w = c.weights
	for i = 1, #w do
		local x = w[i] + rng:normal() * power
		w[i] = x > weight_max and weight_max or (x < -weight_max and -weight_max or x)
	end
	return c
end

local Pop = {}
Pop.__index = Pop

-- args: inputs, outputs, layers (hidden layers, default 1), hidden (their
-- width, default max(inputs, outputs): the task's HIDDEN), options, rng.
function annealing.new(args)
	local o = common.merged(annealing.defaults, args.options, "annealing.new")
	local rng = args.rng or error("annealing.new: an rng is required (learn.rng: random.new(seed))")
	local k = o.steps_per_generation
	assert(k >= 1 and k == math.floor(k), "SA_STEPS_PER_GENERATION must be a whole number >= 1")
	assert(o.t0 >= 0 and o.alpha > 0 and o.alpha <= 1, "SA_T0 must be >= 0 and SA_ALPHA in (0, 1]")
	local layers = args.layers or 1
	local pop = setmetatable({
		options = o, inputs = args.inputs, outputs = args.outputs, layers = layers,
		width = args.hidden, rng = rng, generation = 0, evaluations = 0, moves = 0,
		accepted = 0, species = {}, temperature = o.t0,
		current = genetic.random_genome(args.inputs, args.outputs, layers, o.init_power,
			o.weight_max, rng, args.hidden),
		current_fitness = nil, batch = nil, best = nil,
	}, Pop)
	return pop
end

-- The batch is drawn once and kept (it is part of a checkpoint), so
-- calling genomes() twice gives the same candidates.
function Pop:genomes()
	if not self.batch then
		local o, b = self.options, {}
		if self.current_fitness == nil then b[1] = genetic.copy(self.current) end
		while #b < o.steps_per_generation do
			b[#b + 1] = annealing.neighbour(self.current, o.step_power, o.weight_max, self.rng)
		end
		self.batch = b
	end
	return self.batch
end

function Pop:tell(fitness)
	local b = self:genomes()
	assert(#fitness == #b, "tell: one fitness per genome")
	self.evaluations = self.evaluations + #fitness
	local first = 1
	if self.current_fitness == nil then
		self.current_fitness = fitness[1]
		first = 2
	end
	for i = 1, #b do
		if not self.best or genetic.better(fitness[i], self.best.fitness) then
			self.best = { genome = genetic.copy(b[i]), fitness = fitness[i] }
		end
	end
	for i = first, #b do
		local f = fitness[i]
		-- A NaN current point (e.g. the start) gives way to any number.
		local delta = self.current_fitness ~= self.current_fitness and math.huge or f - self.current_fitness
		if annealing.accept(delta, self.temperature, self.rng) then
			self.current, self.current_fitness = b[i], f
			self.accepted = self.accepted + 1
		end
		self.moves = self.moves + 1
		self.temperature = self.temperature * self.options.alpha
	end
	self.batch = nil
	self.generation = self.generation + 1
end

-- `shared`: see common.save.
function annealing.save(pop, shared)
	return common.save(pop, "evo-annealing-1", shared)
end

function annealing.load(t, rng)
	return common.load(t, "evo-annealing-1", Pop, rng, random.load)
end

return annealing

-- Unit tests of lua/learn/annealing.lua, run by tests/sim/lua/test_lua_scripts.c.
-- Each entry of the returned table is one test; it fails by raising.
local annealing = require "learn.annealing"
local genetic = require "learn.genetic"
local random = require "learn.rng"
local serialize = require "learn.serialize"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local T = {}

-- ANNEALING draws from learn.rng and writes with learn.netfile (through
-- learn.genetic); it does not load NEAT. Every learn.* module is unloaded
-- first, so learn.annealing and what it requires load afresh, whatever
-- this file loaded.
function T.annealing_does_not_load_neat()
	for name in pairs(package.loaded) do
		if name:match("^learn%.") then package.loaded[name] = nil end
	end
	local m = require "learn.annealing"
	check(type(m.to_net_text) == "function" and type(m.load) == "function", "learn.annealing loads")
	check(package.loaded["learn.rng"] and package.loaded["learn.netfile"], "with the shared rng and writer")
	check(package.loaded["learn.neat"] == nil, "learn.annealing loaded learn.neat")
end

function T.worse_moves_are_accepted_with_the_metropolis_probability()
	local rng = random.new(1)
	local n = 40000
	for _, c in ipairs { { -1, 1 }, { -5, 10 }, { -3, 1 }, { -0.1, 2 } } do
		local delta, temp = c[1], c[2]
		local p = math.exp(delta / temp)
		local hits = 0
		for _ = 1, n do
			if annealing.accept(delta, temp, rng) then hits = hits + 1 end
		end
		local sigma = math.sqrt(n * p * (1 - p))
		check(math.abs(hits - n * p) < 4 * sigma,
			string.format("delta %g, T %g: %d of %d, expected %.0f", delta, temp, hits, n, n * p))
	end
end

function T.improvements_are_always_accepted_without_a_draw()
	local rng = random.new(2)
	local before = serialize.dump(rng:save())
	for _, d in ipairs { 0, 1e-12, 1, 1e9 } do
		check(annealing.accept(d, 1, rng), "improvement accepted")
		check(annealing.accept(d, 0, rng), "even at T = 0")
	end
	check(serialize.dump(rng:save()) == before, "no random draw for an improvement")
	check(not annealing.accept(-1e-9, 0, rng), "at T = 0 a worse move is rejected")
	check(not annealing.accept(0 / 0, 1, rng), "NaN rejected")
end

-- A smooth task: fitness = -sum (w_i - 0.5)^2, best 0.
local function fitness_of(g)
	local s = 0
	for _, x in ipairs(g.weights) do s = s - (x - 0.5) ^ 2 end
	return s
end

local function generation(pop)
	local fit = {}
	for i, g in ipairs(pop:genomes()) do fit[i] = fitness_of(g) end
	pop:tell(fit)
	return fit
end

function T.cooling_schedule_is_exact()
	local o = { t0 = 50, alpha = 0.9, steps_per_generation = 4 }
	local pop = annealing.new { inputs = 2, outputs = 1, layers = 1, rng = random.new(3), options = o }
	check(pop.temperature == 50, "starts at T0")
	generation(pop)
	-- The first batch holds the start and 3 moves.
	check(pop.moves == 3 and pop.temperature == 50 * 0.9 * 0.9 * 0.9, "3 moves: T0 alpha^3")
	local t = pop.temperature
	for _ = 1, 5 do
		generation(pop)
		for _ = 1, 4 do t = t * 0.9 end
		check(pop.temperature == t, "alpha once per move")
	end
	check(pop.moves == 23 and pop.evaluations == 24, "counters")
	check(math.abs(pop.temperature - 50 * 0.9 ^ 23) < 1e-12, "T0 alpha^moves")
end

function T.batch_is_start_then_neighbours_decided_in_order()
	local pop = annealing.new { inputs = 2, outputs = 1, layers = 1, rng = random.new(4),
		options = { steps_per_generation = 3, t0 = 0 } }
	local start = genetic.copy(pop.current)
	local b = pop:genomes()
	check(pop:genomes() == b, "genomes() twice gives the same batch")
	check(#b == 3, "K candidates")
	for i, x in ipairs(start.weights) do check(b[1].weights[i] == x, "the first batch starts with the start") end
	-- T = 0: greedy. Candidate 2 better than the start, 3 better than the
	-- start but worse than 2: 2 is kept.
	pop:tell { 1, 5, 3 }
	check(pop.current_fitness == 5 and pop.accepted == 1, "greedy, in order")
	for i, x in ipairs(b[2].weights) do check(pop.current.weights[i] == x, "current is candidate 2") end
	check(pop.best.fitness == 5, "best")
	-- The next batch: all neighbours of candidate 2.
	local n = pop:genomes()
	check(#n == 3, "K neighbours")
	for _, g in ipairs(n) do
		local d = 0
		for i, x in ipairs(g.weights) do d = d + math.abs(x - b[2].weights[i]) end
		check(d > 0 and d < 9 * 0.3 * 10, "a neighbour of the current point")
	end
	pop:tell { 4, 6, 7 }
	check(pop.current_fitness == 7 and pop.accepted == 3, "6 then 7 accepted")
	check(#pop.species == 0, "no species")
end

function T.it_climbs_and_keeps_the_best()
	local pop = annealing.new { inputs = 2, outputs = 1, layers = 1, rng = random.new(5),
		options = { t0 = 0.1, alpha = 0.99, step_power = 0.1 } }
	generation(pop)
	local first = pop.best.fitness
	local seen = -math.huge
	for _ = 1, 60 do
		for _, f in ipairs(generation(pop)) do seen = math.max(seen, f) end
	end
	check(pop.best.fitness >= seen and pop.best.fitness == fitness_of(pop.best.genome), "best ever kept")
	check(pop.best.fitness > first + 1, "fitness rises: " .. first .. " -> " .. pop.best.fitness)
end

function T.save_load_continues_identically()
	local a = annealing.new { inputs = 2, outputs = 1, layers = 1, rng = random.new(6) }
	for _ = 1, 5 do generation(a) end
	a:genomes() -- a batch drawn but not yet told is part of the state too
	local text = serialize.dump(annealing.save(a))
	local b = annealing.load(serialize.load(text, "checkpoint"))
	check(serialize.dump(annealing.save(b)) == text, "save(load(save)) is save")
	for _ = 1, 5 do
		generation(a)
		generation(b)
	end
	check(serialize.dump(annealing.save(a)) == serialize.dump(annealing.save(b)), "resumed = uninterrupted")
end

function T.same_seed_same_run()
	local function run(seed)
		local pop = annealing.new { inputs = 3, outputs = 2, layers = 1, rng = random.new(seed) }
		for _ = 1, 10 do generation(pop) end
		return serialize.dump(annealing.save(pop))
	end
	check(run(7) == run(7), "same seed, same run")
	check(run(7) ~= run(8), "other seed, other run")
end

function T.options_from_task()
	local o, unknown = annealing.options_from_task { SA_T0 = "5", SA_ALPHA = "0.9", SA_STEP_POWER = "0.2",
		SA_STEPS_PER_GENERATION = "1", SA_NOPE = "1", GA_ELITISM = "1" }
	check(o.t0 == 5 and o.alpha == 0.9 and o.step_power == 0.2 and o.steps_per_generation == 1, "values")
	check(#unknown == 1 and unknown[1] == "SA_NOPE", "only unknown SA_ keys")
	check(not pcall(annealing.options_from_task, { SA_T0 = "hot" }), "a malformed number raises")
	check(not pcall(annealing.new, { inputs = 1, outputs = 1, rng = random.new(1),
		options = { steps_per_generation = 0 } }), "K >= 1")
end

function T.to_net_is_the_layered_net()
	local g = { inputs = 2, outputs = 1, layers = 1, weights = { 1, 2, 3, 4, 5, 6, 7, 8, 9 } }
	check(annealing.to_net_text(annealing.to_net(g)) == genetic.to_net_text(genetic.to_net(g)), "same as genetic")
end

return T

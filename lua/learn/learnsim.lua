-- LEARNSIM: train the task's LEARNINGSKILL inside its hierarchy
-- (docs/learning.md). The algorithm proposes networks; host.evaluate runs
-- them in C on the worker threads; every generation is logged, its best
-- network saved and a checkpoint written, so --resume goes on exactly where
-- a killed run stopped.
--
-- `host` is the loop's C side, the module evo.learn: the task, the run
-- folder, the evaluator. It is not the scene scripts' evo module.
local host = require "evo.learn"
local common = require "learn.common"
local random = require "learn.rng"
local serialize = require "learn.serialize"

local task = host.task
local method = (task.LEARNINGMETHOD or "NEAT"):upper()
local MODULES = common.MODULES
if not MODULES[method] then
	error("LEARNINGMETHOD " .. method .. " is not available: evo trains with NEAT, GENETIC or ANNEALING", 0)
end
local algo = require(MODULES[method])

-- NUMGEN, or `evo run --generations N` for a quick try of a task as it is
local generations = host.generations or tonumber(task.NUMGEN or "50")
local planned = generations
if not generations or generations < 1 or generations ~= math.floor(generations) then
	error("NUMGEN must be a whole number of generations, found '" .. tostring(task.NUMGEN) .. "'", 0)
end

-- Stop early once the best fitness reaches TARGETFITNESS, or, on the
-- literature tasks (ENV XOR, DPV, DPNV), once a candidate solves the task.
local target = tonumber(task.TARGETFITNESS or "")
local literature = ({ XOR = true, DPV = true, DPNV = true })[(task.ENV or ""):upper()]

-- How many of a fresh population's networks the final replay compares the
-- champion with.
local REPLAY_RANDOM = 20
-- The curve is redrawn after the first generation and then once at least
-- CURVE_SECONDS of evaluation have passed since the last drawing: every
-- generation of a task whose generations take seconds, and no drawing per
-- generation where a drawing would cost as much as the generation.
local CURVE_SECONDS = 1.0

-- A malformed option stops the run at its line in the task file.
local options = common.task_options(algo, task, host.task_path, host.task_lines)

-- HIDDEN: the width of GENETIC's and ANNEALING's hidden layers (the
-- parser checked it is a whole number >= 1). NEAT grows its own.
local hidden = tonumber(task.HIDDEN or "")
if hidden and method == "NEAT" then
	common.warning(host.task_path, host.task_lines, "HIDDEN", "HIDDEN is the width of "
		.. "GENETIC's and ANNEALING's hidden layers; NEAT grows its own and ignores it")
	hidden = nil
end

-- The checkpoint `text` read back: the population and the checkpoint's
-- table. It is refused, with its path and what is wrong, unless it is a
-- learning run's checkpoint for this skill; where the task now sets an
-- option otherwise, a warning says the run goes on with the checkpoint's.
local function resume(text, path)
	local c = serialize.load(text, path)
	if type(c) ~= "table" or math.type(c.generation) ~= "integer" or c.generation < 0
		or type(c.pop) ~= "table" or type(c.history) ~= "table"
		or type(c.history.best) ~= "table" or type(c.history.mean) ~= "table" then
		error(path .. ": not a learning run's checkpoint (it needs generation, pop and history)", 0)
	end
	if c.seed ~= nil and c.seed ~= host.seed then
		error(string.format("%s: the checkpoint is of a run with seed %s, not %s: resume it with "
			.. "--seed %s", path, tostring(c.seed), tostring(host.seed), tostring(c.seed)), 0)
	end
	local ok, p = pcall(algo.load, c.pop)
	if not ok then error(path .. ": " .. tostring(p), 0) end
	if p.inputs ~= host.inputs or p.outputs ~= host.outputs then
		error(string.format("%s: the checkpoint's networks have %s inputs and %s outputs; the skill "
			.. "now has %d and %d", path, tostring(p.inputs), tostring(p.outputs),
			host.inputs, host.outputs), 0)
	end
	if hidden ~= p.width and method ~= "NEAT" then
		common.warning(host.task_path, host.task_lines, "HIDDEN", string.format("HIDDEN is %s "
			.. "in the task but the checkpoint's hidden layers are %s wide; the run goes on "
			.. "with %s", tostring(hidden or "not set"), tostring(p.width or "the default"),
			tostring(p.width or "the default")))
	end
	local keys = {}
	for k in pairs(task) do keys[#keys + 1] = k end
	table.sort(keys)
	for _, k in ipairs(keys) do
		local name = algo.task_keys[k]
		local was = name and p.options and p.options[name]
		if was ~= nil and options[name] ~= nil and was ~= options[name] then
			common.warning(host.task_path, host.task_lines, k, string.format("%s is %s in the task "
				.. "but %s in the checkpoint; the run goes on with %s", k, tostring(options[name]),
				tostring(was), tostring(was)))
		end
	end
	return p, c
end

local pop, first, history, solver
local saved = host.resume and host.read("checkpoint.lua")
if host.resume and not saved then
	host.print("no checkpoint in " .. host.run_dir .. ": starting from generation 0")
end
if saved then
	local c
	pop, c = resume(saved, host.run_dir .. "/checkpoint.lua")
	first = c.generation + 1
	history = c.history
	solver = c.solver
	host.print(string.format("resuming after generation %d", c.generation))
	if c.stopped then generations = c.generation + 1 end
else
	-- layers: the skill's `layers:`, and hidden: the task's HIDDEN, the
	-- fixed shape of GENETIC and ANNEALING (NEAT grows its own and
	-- ignores both).
	pop = algo.new{ inputs = host.inputs, outputs = host.outputs, layers = host.layers,
		hidden = hidden, options = options, rng = random.new(host.seed) }
	first = 0
	history = { best = {}, mean = {} }
end
host.open_log(first)
local since_curve = 0

for gen = first, generations - 1 do
	local genomes = pop:genomes()
	local nets = {}
	for i, g in ipairs(genomes) do nets[i] = algo.to_net(g) end
	local fitness, seconds, solved, _, metrics = host.evaluate(nets, gen)
	local best_i, sum = 1, 0
	for i, f in ipairs(fitness) do
		sum = sum + f
		if f > fitness[best_i] then best_i = i end
	end
	-- DPNV decides success after the generation, on one network: the one
	-- the method picks (NEAT: as NEAT's original code picks it), else the
	-- best (the first of equals).
	if host.success_test then
		local pick = pop.test_candidate and pop:test_candidate(fitness) or best_i
		solved[pick] = host.success_test(nets[pick])
	end
	local n_solved = 0
	for i, f in ipairs(fitness) do
		if solved[i] then
			n_solved = n_solved + 1
			if not solver or f > solver.fitness then
				solver = { net = nets[i], fitness = f, generation = gen }
			end
		end
	end
	local best_net = nets[best_i]
	pop:tell(fitness)
	history.best[#history.best + 1] = fitness[best_i]
	history.mean[#history.mean + 1] = sum / #fitness
	host.save(string.format("best/gen-%04d.net", gen), algo.to_net_text(best_net,
		string.format("generation %d, fitness %.17g", gen, fitness[best_i])))
	-- the environment's metrics (docs/lua.md) of the generation's best, the
	-- network of the `best` column
	host.log{ generation = gen, generations = generations, best = fitness[best_i],
		mean = sum / #fitness, best_ever = pop.best.fitness, species = #pop.species,
		evaluations = #fitness, solved = n_solved, seconds = seconds,
		metrics = metrics[best_i] }
	-- the curve so far, so a long run can be watched as it goes (the last
	-- one comes after the loop)
	since_curve = since_curve + seconds
	if gen == first or since_curve >= CURVE_SECONDS then
		host.curve(history.best, history.mean, true)
		since_curve = 0
	end
	local stop
	if solver then
		stop = string.format("solved in generation %d", gen)
	elseif target and pop.best.fitness >= target then
		stop = string.format("target fitness %.17g reached in generation %d", target, gen)
	end
	-- The checkpoint last: a run killed before it is written resumes from
	-- the previous generation and redoes this one identically.
	host.save("checkpoint.lua", serialize.dump{ generation = gen, seed = host.seed, pop = algo.save(pop, true),
		history = history, solver = solver, stopped = stop ~= nil })
	if stop then
		host.print(stop)
		generations = gen + 1
		break
	end
end

-- The champion: the best solver when the task has a success criterion and
-- a candidate met it, else the best network the method has seen.
local champion, champion_fitness
if solver then
	champion, champion_fitness = solver.net, solver.fitness
else
	champion, champion_fitness = algo.to_net(pop.best.genome), pop.best.fitness
end
host.save_champion(algo.to_net_text(champion, string.format(
	"trained by evo: %s, seed %d, %d generations, fitness %.17g",
	method, host.seed, generations, champion_fitness)))
host.curve(history.best, history.mean)

-- In a world, replay the champion beside networks as the method first
-- drew them, on episodes training never saw (those of generation NUMGEN,
-- or of --generations),
-- and print what each scores and how long each spent touching things.
if not literature then
	local fresh = algo.new{ inputs = host.inputs, outputs = host.outputs, layers = host.layers,
		hidden = hidden,
		options = options, rng = random.new(host.seed + 1) }
	local nets = { champion }
	for i, g in ipairs(fresh:genomes()) do
		if i > REPLAY_RANDOM then break end
		nets[#nets + 1] = algo.to_net(g)
	end
	local fitness, _, _, collisions, metrics = host.evaluate(nets, planned)
	local f_sum, c_sum, m_sum = 0, 0, {}
	for k = 1, #host.metrics do m_sum[k] = 0 end
	for i = 2, #nets do
		f_sum, c_sum = f_sum + fitness[i], c_sum + collisions[i]
		for k = 1, #host.metrics do m_sum[k] = m_sum[k] + metrics[i][k] end
	end
	local n = #nets - 1
	-- the environment's metrics, each a mean over the repetitions, after
	-- the collisions: ", in_zone 12.5"
	local function with_metrics(line, values, divisor)
		for k, name in ipairs(host.metrics) do
			line = line .. string.format(", %s %.1f", name, values[k] / divisor)
		end
		return line
	end
	host.print(string.format("replay on unseen episodes (%d x %d ticks each):", host.reps, host.ticks))
	host.print(with_metrics(string.format("  champion:                 fitness %12.1f, %7d collision ticks",
		fitness[1], collisions[1]), metrics[1], 1))
	host.print(with_metrics(string.format("  untrained networks (%2d): fitness %12.1f, %7.0f collision ticks (mean)",
		n, f_sum / n, c_sum / n), m_sum, n))
end
return champion_fitness

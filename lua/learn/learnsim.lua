-- LEARNSIM: train the task's LEARNINGSKILL inside its hierarchy
-- (docs/learning.md). The algorithm proposes networks; evo.evaluate runs
-- them in C on the worker threads; every generation is logged, its best
-- network saved and a checkpoint written, so --resume goes on exactly where
-- a killed run stopped.
local evo = require "evo"
local serialize = require "learn.serialize"

local task = evo.task
local method = (task.LEARNINGMETHOD or "NEAT"):upper()
-- Every method's module has the same interface: options_from_task, new,
-- genomes/tell, best, species, save/load, to_net, to_net_text.
local MODULES = { NEAT = "learn.neat", GENETIC = "learn.genetic", ANNEALING = "learn.annealing" }
if not MODULES[method] then
	error("LEARNINGMETHOD " .. method .. " is not available: evo trains with NEAT, GENETIC or ANNEALING", 0)
end
local neat = require "learn.neat"
local algo = require(MODULES[method])

local generations = tonumber(task.NUMGEN or "50")
if not generations or generations < 1 or generations ~= math.floor(generations) then
	error("NUMGEN must be a whole number of generations, found '" .. tostring(task.NUMGEN) .. "'", 0)
end

-- Stop early once the best fitness reaches a target: TARGETFITNESS, or for
-- the literature tasks (ENV XOR, DPV, DPNV) their solved mark, 1e6, which
-- sim/literature.h adds to a candidate that solves the task.
local target = tonumber(task.TARGETFITNESS or "")
if not target and ({ XOR = true, DPV = true, DPNV = true })[(task.ENV or ""):upper()] then
	target = 1e6
end

local options, unknown = algo.options_from_task(task)
for _, k in ipairs(unknown) do evo.warn("unknown key " .. k .. " (ignored)") end

local pop, first, history
local saved = evo.resume and evo.read("checkpoint.lua")
if saved then
	local c = serialize.load(saved, "checkpoint.lua")
	pop = algo.load(c.pop)
	first = c.generation + 1
	history = c.history
	evo.print(string.format("resuming after generation %d", c.generation))
else
	-- layers: the skill's `layers:`, the fixed shape of GENETIC and
	-- ANNEALING (NEAT grows its own and ignores it).
	pop = algo.new{ inputs = evo.inputs, outputs = evo.outputs, layers = evo.layers,
		options = options, rng = neat.rng(evo.seed) }
	first = 0
	history = { best = {}, mean = {} }
end
evo.open_log(first)

for gen = first, generations - 1 do
	local genomes = pop:genomes()
	local nets = {}
	for i, g in ipairs(genomes) do nets[i] = algo.to_net(g) end
	local fitness, seconds = evo.evaluate(nets, gen)
	local best_i, sum = 1, 0
	for i, f in ipairs(fitness) do
		sum = sum + f
		if f > fitness[best_i] then best_i = i end
	end
	local best_net = nets[best_i]
	pop:tell(fitness)
	history.best[#history.best + 1] = fitness[best_i]
	history.mean[#history.mean + 1] = sum / #fitness
	evo.save(string.format("best/gen-%04d.net", gen), algo.to_net_text(best_net,
		string.format("generation %d, fitness %.17g", gen, fitness[best_i])))
	evo.log{ generation = gen, generations = generations, best = fitness[best_i],
		mean = sum / #fitness, best_ever = pop.best.fitness, species = #pop.species,
		evaluations = #fitness, seconds = seconds }
	-- The checkpoint last: a run killed before it is written resumes from
	-- the previous generation and redoes this one identically.
	evo.save("checkpoint.lua", serialize.dump{ generation = gen, pop = algo.save(pop),
		history = history })
	if target and pop.best.fitness >= target then
		evo.print(string.format("target fitness %.17g reached in generation %d", target, gen))
		generations = gen + 1
		break
	end
end

local champion = algo.to_net(pop.best.genome)
evo.save_champion(algo.to_net_text(champion, string.format(
	"trained by evo: %s, seed %d, %d generations, fitness %.17g",
	method, evo.seed, generations, pop.best.fitness)))
evo.curve(history.best, history.mean)
return pop.best.fitness

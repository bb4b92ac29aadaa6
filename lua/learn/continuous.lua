-- LEARNSIMCONTINUOUS: every neural skill of the hierarchy is trained in
-- turn in the task's environment, round after round (docs/learning.md).
--
-- A turn trains one skill for NUMGEN generations, the other skills running
-- their current networks; its champion then replaces the skill's network
-- only if it scores better on fixed validation episodes. The skills take
-- their turns in host.order (SKILLORDER, else bottom-up: each skill after
-- its sub-skills). A checkpoint after every generation holds the whole
-- state (round, turn, population, the current networks, the summary), so
-- --resume goes on mid-round to the result of an uninterrupted run.
--
-- `host` is the loop's C side, the module evo.learn (sim/learn/learn.c).
local host = require "evo.learn"
local common = require "learn.common"
local random = require "learn.rng"
local serialize = require "learn.serialize"
local netfile = require "learn.netfile"

local task = host.task
local method = (task.LEARNINGMETHOD or "NEAT"):upper()
if not common.MODULES[method] then
	error("LEARNINGMETHOD " .. method .. " is not available: evo trains with NEAT, GENETIC, ANNEALING, CMAES, NOVELTY or MAPELITES", 0)
end
if method == "MAPELITES" then
	error("LEARNINGMETHOD MAPELITES keeps an archive of one skill's behaviours: it trains a "
		.. "LEARNSIM task, not LEARNSIMCONTINUOUS's turns", 0)
end
local algo = require(common.MODULES[method])
local options = common.task_options(algo, task, host.task_path, host.task_lines)

-- The parser checked NUMGEN, ROUNDS and VALIDATION are within their ranges
-- (core/src/parse_simbatch.c: whole numbers from 1).
local per_turn = host.generations or tonumber(task.NUMGEN)
-- ROUNDS: how many rounds; absent, the run goes on until it is stopped.
local rounds = tonumber(task.ROUNDS or "")
-- VALIDATION: the validation evaluations of a network, each of EVALREP
-- episodes.
local validation = tonumber(task.VALIDATION or "4")
-- The validation episodes are those of this generation, which training
-- never reaches: the same episodes for every skill in every round.
local VALIDATION_GEN = 2147483647
local CURVE_SECONDS = 1.0

local hidden = tonumber(task.HIDDEN or "")
if hidden and (method == "NEAT" or method == "NOVELTY") then
	hidden = nil -- common.task_options warned
end

if task.LEARNINGSKILL then
	common.warning(host.task_path, host.task_lines, "LEARNINGSKILL", "LEARNINGSKILL is ignored: "
		.. "LEARNSIMCONTINUOUS trains every skill of SKILLORDER, or every neural skill bottom-up")
end

local order = host.order
local names = {}
for i, sk in ipairs(order) do names[i] = sk.name end
local order_text = table.concat(names, ",")

local SUMMARY_HEADER = "round,skill,first_generation,last_generation,current,champion,replaced\n"

-- The run's state; the checkpoint is this table.
local state
local cp_path = host.run_dir .. "/checkpoint.lua"
local saved = host.resume and host.read("checkpoint.lua")
if host.resume and not saved then
	host.print("no checkpoint in " .. host.run_dir .. ": starting from round 1")
end
if saved then
	state = serialize.load(saved, cp_path)
	if type(state) ~= "table" or state.continuous ~= true or math.type(state.round) ~= "integer"
		or math.type(state.turn) ~= "integer" or math.type(state.step) ~= "integer"
		or math.type(state.generation) ~= "integer" or type(state.nets) ~= "table"
		or type(state.history) ~= "table" or type(state.summary) ~= "string" then
		error(cp_path .. ": not a LEARNSIMCONTINUOUS run's checkpoint", 0)
	end
	if state.seed ~= host.seed then
		error(string.format("%s: the checkpoint is of a run with seed %s, not %s: resume it with "
			.. "--seed %s", cp_path, tostring(state.seed), tostring(host.seed), tostring(state.seed)), 0)
	end
	if state.order ~= order_text then
		error(string.format("%s: the checkpoint's skills take their turns in the order %s; the "
			.. "task's order is %s", cp_path, tostring(state.order), order_text), 0)
	end
	host.print(string.format("resuming in round %d, skill %s, after %d of its generations",
		state.round, names[state.turn] or "?", state.step))
else
	state = { continuous = true, seed = host.seed, order = order_text, round = 1, turn = 1,
		step = 0, generation = -1, nets = {}, replaced = {}, summary = SUMMARY_HEADER,
		history = { best = {}, mean = {} } }
	for _, sk in ipairs(order) do
		state.nets[sk.name] = host.read_skill_net(sk.name)
			or error(string.format("skill %s has no network in Skills/%s/%s.net to start from",
				sk.name, sk.name, sk.name), 0)
	end
end

local function file_of(name) return "current-" .. name .. ".net" end

local function checkpoint(pop)
	state.pop = pop and algo.save(pop, true) or nil
	host.save("checkpoint.lua", serialize.dump(state))
end

-- The mean fitness of net over the validation evaluations (each the sum of
-- EVALREP episodes), on the episodes of VALIDATION_GEN.
local function validate(net)
	local nets = {}
	for i = 1, validation do nets[i] = net end
	local fitness = host.evaluate(nets, VALIDATION_GEN)
	local sum = 0
	for _, f in ipairs(fitness) do sum = sum + f end
	return sum / validation
end

-- The run folder's current networks (what the other skills run) and the
-- shipped networks of the skills this run replaced are written from the
-- state, so that a run killed between two of these files resumes whole.
host.open_log(state.generation + 1, { "round", "turn" })
for _, sk in ipairs(order) do host.save(file_of(sk.name), state.nets[sk.name]) end
for name in pairs(state.replaced) do host.save_skill_net(name, state.nets[name]) end
local since_curve = 0

while not rounds or state.round <= rounds do
	local t = state.turn
	local sk = order[t]
	local others = {}
	for _, o in ipairs(order) do
		if o.name ~= sk.name then others[o.name] = file_of(o.name) end
	end
	local inputs, outputs = host.begin_turn(sk.name, others)
	local pop
	if state.pop then
		local ok, p = pcall(algo.load, state.pop)
		if not ok then error(cp_path .. ": " .. tostring(p), 0) end
		pop = p
	else
		-- each turn's population from its own stream of the run seed
		local turn_no = (state.round - 1) * #order + t
		pop = algo.new{ inputs = inputs, outputs = outputs, layers = sk.layers, hidden = hidden,
			options = options, rng = random.new(host.seed * 1000003 + 7919 * turn_no) }
		state.first = state.generation + 1
		host.print(string.format("round %d, skill %s (%d of %d): %d generation%s", state.round,
			sk.name, t, #order, per_turn, per_turn == 1 and "" or "s"))
	end
	while state.step < per_turn do
		local gen = state.generation + 1
		local nets = {}
		for i, g in ipairs(pop:genomes()) do nets[i] = algo.to_net(g) end
		local fitness, seconds, _, _, metrics = host.evaluate(nets, gen)
		local best_i, sum = 1, 0
		for i, f in ipairs(fitness) do
			sum = sum + f
			if f > fitness[best_i] then best_i = i end
		end
		local species = #pop.species -- the evaluated generation's (tell() speciates the next)
		pop:tell(fitness)
		local h = state.history
		h.best[#h.best + 1] = fitness[best_i]
		h.mean[#h.mean + 1] = sum / #fitness
		host.save(string.format("best/gen-%04d.net", gen), algo.to_net_text(nets[best_i],
			string.format("round %d, skill %s, generation %d, fitness %.17g", state.round,
				sk.name, gen, fitness[best_i])))
		local row = { table.unpack(metrics[best_i]) }
		row[#row + 1] = state.round
		row[#row + 1] = t
		host.log{ generation = gen, generations = rounds and rounds * #order * per_turn or 0,
			best = fitness[best_i], mean = sum / #fitness, best_ever = pop.best.fitness,
			species = species, evaluations = #fitness, solved = 0, seconds = seconds,
			metrics = row }
		since_curve = since_curve + seconds
		if state.step == 0 or since_curve >= CURVE_SECONDS then
			host.curve(h.best, h.mean, true)
			since_curve = 0
		end
		state.generation, state.step = gen, state.step + 1
		checkpoint(pop)
	end
	-- The turn's end: the champion, as the .net text it would be saved
	-- as, against the current network, on the validation episodes.
	local text = algo.to_net_text(algo.to_net(pop.best.genome), string.format(
		"trained by evo: LEARNSIMCONTINUOUS %s, seed %d, round %d, generations %d-%d, fitness %.17g",
		method, host.seed, state.round, state.first or 0, state.generation, pop.best.fitness))
	local current = validate(netfile.parse(state.nets[sk.name], file_of(sk.name)))
	local champion = validate(netfile.parse(text, "champion"))
	local replaced = champion > current
	state.summary = state.summary .. string.format("%d,%s,%d,%d,%.17g,%.17g,%s\n", state.round,
		sk.name, state.first or 0, state.generation, current, champion, replaced and "yes" or "no")
	if replaced then
		state.nets[sk.name] = text
		state.replaced[sk.name] = true
		host.save(file_of(sk.name), text)
	end
	host.save("summary.csv", state.summary)
	local shown_champion, shown_current = common.two_scores(champion, current)
	host.print(string.format("round %d, skill %s: champion %s, current %s on %d validation "
		.. "evaluations: %s", state.round, sk.name, shown_champion, shown_current, validation,
		replaced and "replaced" or "kept"))
	state.step, state.first = 0, nil
	state.turn = t + 1
	if state.turn > #order then state.turn, state.round = 1, state.round + 1 end
	checkpoint(nil)
	if replaced then host.save_skill_net(sk.name, text) end
end
host.curve(state.history.best, state.history.mean)
host.print(string.format("%d rounds done; which skill improved in which round: %s/summary.csv",
	rounds, host.run_dir))

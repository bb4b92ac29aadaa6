-- LEARNSIM: train the task's LEARNINGSKILL inside its hierarchy
-- (docs/learning.md). The algorithm proposes networks; host.evaluate runs
-- them in C on the worker threads; every generation is logged, its best
-- network saved and a checkpoint written, so --resume goes on exactly where
-- a killed run stopped.
--
-- `host` is the loop's C side, the module evo.learn: the task, the run
-- folder, the evaluator. It is not the scene scripts' evo module.
--
-- A team task (LEARN2DSIMMULTI, docs/teams.md) trains its learning
-- team's skill the same way, with host.teams set: each network is a team
-- of clones, or (HETEROGENEOUS) one member of a team the loop makes up
-- each generation; several learning teams take turns, each with a
-- population of its own.
local host = require "evo.learn"
-- The collector starts a cycle when the heap has grown to 4 times what the
-- last one kept (Lua's default: 2): a generation makes as many tables as
-- the population holds, and at the default a good part of the loop's time
-- went to marking the live genomes again and again.
collectgarbage("incremental", 400)
local common = require "learn.common"
local random = require "learn.rng"
local serialize = require "learn.serialize"

local task = host.task
local method = (task.LEARNINGMETHOD or "NEAT"):upper()
local MODULES = common.MODULES
if not MODULES[method] then
	error("LEARNINGMETHOD " .. method .. " is not available: evo trains with NEAT, GENETIC, ANNEALING, CMAES, NOVELTY or MAPELITES", 0)
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
-- The curve is drawn as the run goes once at least CURVE_SECONDS of
-- evaluation have passed since the process started or since the last
-- drawing, and once at the end: every generation of a task whose
-- generations take seconds, no drawing per generation where a drawing
-- would cost as much as the generation, and one drawing in all for a run
-- shorter than that (XOR's, a tenth of a second).
local CURVE_SECONDS = 1.0
-- The checkpoint is written after the first generation of a process,
-- after the last one, and after any generation that ends CHECKPOINT_SECONDS
-- (of wall time, host.clock: os.clock would count every evaluating
-- thread's CPU, two seconds a second on two threads) or more after the
-- last checkpoint: every
-- generation of a task whose generations take a second, and not 25 times
-- in a run of XOR that lasts a tenth of a second. A run killed between two
-- checkpoints goes on from the last one and does the generations after it
-- again, identically (their rows of log.csv are dropped and written anew).
-- A checkpoint that took more than CHECKPOINT_SECONDS / CHECKPOINT_SHARE to
-- write (a MAP-Elites archive of ten thousand networks takes a second) is
-- written again only after CHECKPOINT_SHARE times that, so writing
-- checkpoints never costs more than a tenth of the run.
local CHECKPOINT_SECONDS = 1.0
local CHECKPOINT_SHARE = 10

-- A malformed option stops the run at its line in the task file.
local options = common.task_options(algo, task, host.task_path, host.task_lines)

-- HIDDEN: the width of the hidden layers of GENETIC, ANNEALING and CMAES (the
-- parser checked its range, evo run that the networks fit). NEAT grows its own.
local hidden = tonumber(task.HIDDEN or "")
if hidden and (method == "NEAT" or method == "NOVELTY") then
	hidden = nil -- common.task_options warned
end

-- The learners: the learning teams of a team task, else the one skill.
local teams = host.teams
local learners = teams and teams.learning
	or { { inputs = host.inputs, outputs = host.outputs, layers = host.layers, size = 1 } }

-- The learner whose turn generation `gen` is (co-evolution: ALTERNATE
-- generations each, in LEARNINGTEAM's order).
local function learner_of(gen)
	if #learners == 1 then return 1 end
	return (gen // teams.alternate) % #learners + 1
end

-- Learner k's first population: the run seed's generator for the first,
-- another stream for each other one.
local function new_pop(k, seed)
	local L = learners[k]
	return algo.new{ inputs = L.inputs, outputs = L.outputs, layers = L.layers,
		hidden = hidden, options = options, rng = random.new(seed + 7919 * (k - 1)) }
end

-- The teams of n networks for learner L in generation gen, as the flat
-- list of the networks each member runs, team after team: a team of
-- clones of each network, or (heterogeneous) the networks shuffled from
-- (seed, generation) and cut into teams, the last one filled from the
-- start of the shuffled order.
local function make_groups(n, L, gen)
	local groups, size = {}, L.size
	if not teams.heterogeneous then
		for i = 1, n do
			for _ = 1, size do groups[#groups + 1] = i end
		end
		return groups
	end
	local order = {}
	for i = 1, n do order[i] = i end
	local r = random.new((host.seed * 1000003 + gen) ~ 0x5EED7EA3)
	for i = n, 2, -1 do
		local j = 1 + math.floor(r:unit() * i)
		order[i], order[j] = order[j], order[i]
	end
	for k = 1, ((n + size - 1) // size) * size do
		groups[k] = order[(k - 1) % n + 1]
	end
	return groups
end

-- Evaluate the networks of learner k in generation gen: what
-- host.evaluate gives, and the teams' share of episodes won.
local function evaluate(nets, gen, k)
	if not teams then return host.evaluate(nets, gen) end
	local L = learners[k]
	local groups = make_groups(#nets, L, gen)
	local fitness, seconds, solved, collisions, metrics, wins, team_fit, group =
		host.evaluate(nets, gen, groups, L.index)
	local seen, won, n_teams = {}, 0, #groups // L.size
	for i = 1, #nets do
		if not seen[group[i]] then
			seen[group[i]] = true
			won = won + wins[i]
		end
	end
	return fitness, seconds, solved, collisions, metrics, {
		groups = groups, wins = wins, team_fitness = team_fit, group = group,
		win_rate = won / (n_teams * host.reps) }
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
		local name = algo.task_keys[k] or (algo.other_keys and algo.other_keys[k])
		local was = name and p.options and p.options[name]
		if was ~= nil and options[name] ~= nil and was ~= options[name] then
			common.warning(host.task_path, host.task_lines, k, string.format("%s is %s in the task "
				.. "but %s in the checkpoint; the run goes on with %s", k, tostring(options[name]),
				tostring(was), tostring(was)))
		end
	end
	return p, c
end

local pops, first, history, solver, best_team
local saved = host.resume and host.read("checkpoint.lua")
if host.resume and not saved then
	host.print("no checkpoint in " .. host.run_dir .. ": starting from generation 0")
end
if saved then
	local c, p
	p, c = resume(saved, host.run_dir .. "/checkpoint.lua")
	pops = { p }
	for k = 2, #learners do
		local ok, q = pcall(algo.load, c.more_pops and c.more_pops[k - 1])
		if not ok or q.inputs ~= learners[k].inputs or q.outputs ~= learners[k].outputs then
			error(host.run_dir .. "/checkpoint.lua: no population of team " .. learners[k].name
				.. " that fits its skill", 0)
		end
		pops[k] = q
	end
	first = c.generation + 1
	history = c.history
	solver = c.solver
	best_team = c.best_team or {}
	-- a finished run (its champion saved: a run killed between its last
	-- checkpoint and the champion does the last steps again): nothing to
	-- replay, the skill's network stays
	local saved_champion = host.read("champion.net")
		or (teams and host.read("champion-" .. learners[1].name .. ".net"))
	if (c.stopped or first >= generations) and saved_champion then
		host.print(string.format("the run in %s is complete: its last generation, %d, was %s; "
			.. "nothing to do%s", host.run_dir, c.generation,
			c.stopped and "where it stopped (its criterion was met)"
				or string.format("the last of its %d (%s)", generations, host.generations
					and host.run_dir .. "/options.txt" or "the task's NUMGEN"),
			c.stopped and "" or string.format(" (--generations N, N > %d, goes on)", generations)))
		return
	end
	host.print(string.format("resuming after generation %d", c.generation))
else
	-- layers: the skill's `layers:`, and hidden: the task's HIDDEN, the
	-- fixed shape of GENETIC and ANNEALING (NEAT grows its own and
	-- ignores both).
	pops = {}
	for k = 1, #learners do pops[k] = new_pop(k, host.seed) end
	first = 0
	history = { best = {}, mean = {} }
	best_team = {}
end
-- a method's own columns of log.csv (NOVELTY: archive, threshold,
-- best_novelty; MAPELITES: coverage, qd_score)
-- the method's columns of log.csv (a population may add its own: NOVELTY's
-- result grid)
local log_columns = pops[1].log_names and pops[1]:log_names() or algo.log_columns
host.open_log(first, log_columns)
local since_curve = 0
local last_checkpoint = host.clock()
local checkpoint_cost = 0.0 -- seconds the last checkpoint took to write

for gen = first, generations - 1 do
	local k = learner_of(gen)
	local pop = pops[k]
	-- co-evolution: the other learning teams run the best of their own
	-- turns so far (at first, the networks in their folders)
	for j = 1, #learners do
		if j ~= k and pops[j].best and pops[j].best.genome then
			host.set_team_net(learners[j].index, algo.to_net(pops[j].best.genome))
		end
	end
	local genomes = pop:genomes()
	-- evaluate takes the networks packed where the method packs them
	-- (NEAT, in C: no Lua table per network); the few kept after the
	-- generation are made as tables (net_of)
	local pack = not teams and algo.pack_net
	local nets = {}
	for i, g in ipairs(genomes) do nets[i] = pack and pack(g) or algo.to_net(g) end
	local function net_of(i) return pack and algo.to_net(genomes[i]) or nets[i] end
	local fitness, seconds, solved, _, metrics, t = evaluate(nets, gen, k)
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
				solver = { net = net_of(i), fitness = f, generation = gen }
			end
		end
	end
	-- a heterogeneous team's champion is the best team ever seen, its
	-- members' networks in member order
	if t and teams.heterogeneous then
		local size, top = learners[k].size, nil
		for i = 1, #nets do
			if not top or t.team_fitness[i] > t.team_fitness[top] then top = i end
		end
		if not best_team[k] or t.team_fitness[top] > best_team[k].fitness then
			local j = t.group[top]
			local members = {}
			for m = 1, size do members[m] = nets[t.groups[(j - 1) * size + m]] end
			best_team[k] = { nets = members, fitness = t.team_fitness[top], generation = gen }
		end
	end
	local best_net = net_of(best_i)
	-- the species of the generation just evaluated (tell() speciates the next)
	local species = #pop.species
	-- what each network's episodes did (evo.descriptors: nil for
	-- literature and team tasks), for the methods that search behaviours
	pop:tell(fitness, host.descriptors())
	history.best[#history.best + 1] = fitness[best_i]
	history.mean[#history.mean + 1] = sum / #fitness
	host.save(string.format("best/gen-%04d.net", gen), algo.to_net_text(best_net,
		string.format("generation %d, fitness %.17g", gen, fitness[best_i])))
	-- the environment's metrics (docs/lua.md) of the generation's best, the
	-- network of the `best` column; a team task's learning team (its
	-- number in the task) and the generation's share of episodes won
	local row = metrics[best_i]
	-- the method's own figures (MAP-Elites's coverage, novelty's archive)
	-- go to log.csv and on the progress line
	local note
	if pop.log_values then
		row = { table.unpack(row) }
		local parts = {}
		for i, v in ipairs(pop:log_values()) do
			row[#row + 1] = v
			parts[i] = string.format("%s %.4g", log_columns[i], v)
		end
		note = table.concat(parts, "  ")
	end
	if t then
		row = { table.unpack(row) }
		row[#row + 1] = learners[k].index
		row[#row + 1] = t.win_rate
	end
	host.log{ generation = gen, generations = generations, best = fitness[best_i],
		mean = sum / #fitness, best_ever = pop.best.fitness, species = species,
		evaluations = #fitness, solved = n_solved, seconds = seconds,
		metrics = row, note = note }
	-- the curve so far, so a long run can be watched as it goes (the last
	-- one comes after the loop)
	since_curve = since_curve + seconds
	if since_curve >= CURVE_SECONDS then
		host.curve(history.best, history.mean, true)
		if algo.write_archive then algo.write_archive(pop, host, true) end
		since_curve = 0
	end
	local stop
	if solver and not algo.whole_budget then
		stop = string.format("solved in generation %d", gen)
	elseif target and pop.best.fitness >= target then
		stop = string.format("target fitness %.17g reached in generation %d", target, gen)
	elseif pop.stop_reason then
		-- the method's own criterion (MAPELITES: its target coverage)
		stop = pop:stop_reason(gen)
	end
	-- The checkpoint last: a run killed before it is written resumes from
	-- the previous checkpoint and redoes the generations since identically.
	if gen == first or stop or gen == generations - 1
		or host.clock() - last_checkpoint
			>= math.max(CHECKPOINT_SECONDS, CHECKPOINT_SHARE * checkpoint_cost) then
		local t0 = host.clock()
		-- the method's files that go with the checkpoint (NOVELTY's archive.csv)
		if algo.checkpoint_files then algo.checkpoint_files(pops[1], host) end
		local more
		if #learners > 1 then
			more = {}
			for j = 2, #learners do more[j - 1] = algo.save(pops[j], true) end
		end
		host.save("checkpoint.lua", serialize.dump{ generation = gen, seed = host.seed,
			pop = algo.save(pops[1], true), more_pops = more, history = history, solver = solver,
			stopped = stop ~= nil, best_team = teams and best_team or nil })
		last_checkpoint = host.clock()
		checkpoint_cost = last_checkpoint - t0
	end
	if stop then
		host.print(stop)
		generations = gen + 1
		break
	end
end
local pop = pops[1]

-- The champion: the best solver when the task has a success criterion and
-- a candidate met it, else the best network the method has seen.
-- A method that searches its whole budget (MAPELITES: an archive, not a
-- solver) neither stops at the first solver nor makes it the champion.
local champion, champion_fitness
if solver and not algo.whole_budget then
	champion, champion_fitness = solver.net, solver.fitness
else
	champion, champion_fitness = algo.to_net(pop.best.genome), pop.best.fitness
end

-- A learner's champion team: its members' networks, and its fitness.
local function champion_team(k)
	local L = learners[k]
	if teams.heterogeneous and best_team[k] then
		return best_team[k].nets, best_team[k].fitness
	end
	local net = algo.to_net(pops[k].best.genome)
	local members = {}
	for m = 1, L.size do members[m] = net end
	return members, pops[k].best.fitness
end

if not teams and algo.whole_budget then
	-- MAPELITES: the result is the archive, a network for each kind of
	-- behaviour; its best fitness may be the least of them (Kheperax's
	-- is the least effort: a bot that stands still). The best elite is
	-- champion.net in the run folder; the skill keeps its network.
	host.save("champion.net", algo.to_net_text(champion, string.format(
		"trained by evo: %s, seed %d, %d generations, fitness %.17g (the archive's best "
		.. "fitness)", method, host.seed, generations, champion_fitness)))
	host.print(string.format("MAP-Elites keeps an archive, not one network: Skills/%s/%s.net is left "
		.. "as it was; the elite of best fitness is %s/champion.net, every elite in %s/elites/ "
		.. "(run one with --net %s=FILE, or copy it to Skills/%s/%s.net)", host.skill, host.skill,
		host.run_dir, host.run_dir, host.skill, host.skill, host.skill))
elseif not teams then
	host.save_champion(algo.to_net_text(champion, string.format(
		"trained by evo: %s, seed %d, %d generations, fitness %.17g",
		method, host.seed, generations, champion_fitness)))
else
	for k, L in ipairs(learners) do
		if not pops[k].best then
			-- co-evolution stopped before this team's first turn
			host.print(string.format("team %s had no turn in %d generations "
				.. "(ALTERNATE %d): nothing trained, its network left as it was",
				L.name, generations, teams.alternate))
			goto next_team
		end
		local members, f = champion_team(k)
		for m = 1, (teams.heterogeneous and L.size or 1) do
			host.save_champion(algo.to_net_text(members[m], string.format(
				"trained by evo: %s, seed %d, %d generations, team %s%s, team fitness %.17g",
				method, host.seed, generations, L.name,
				teams.heterogeneous and string.format(" member %d", m) or "", f)),
				L.index, m, teams.heterogeneous)
		end
		::next_team::
	end
end
host.curve(history.best, history.mean)
-- MAPELITES: the archive (archive.csv, each elite's .net, the heatmap);
-- NOVELTY: its archive.csv
if algo.write_archive then algo.write_archive(pop, host, false) end

-- the environment's metrics, each a mean over the repetitions, after
-- the collisions: ", in_zone 12.5"
local function with_metrics(line, values, divisor)
	for k, name in ipairs(host.metrics) do
		line = line .. string.format(", %s %.1f", name, values[k] / divisor)
	end
	return line
end

-- In a world, replay the champion beside networks as the method first
-- drew them, on episodes training never saw (those of generation NUMGEN,
-- or of --generations),
-- and print what each scores and how long each spent touching things.
if not literature and not teams then
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
	host.print(string.format("replay on unseen episodes (%d x %d ticks each):", host.reps, host.ticks))
	host.print(with_metrics(string.format("  champion:                 fitness %12.1f, %7d collision ticks",
		fitness[1], collisions[1]), metrics[1], 1))
	host.print(with_metrics(string.format("  untrained networks (%2d): fitness %12.1f, %7.0f collision ticks (mean)",
		n, f_sum / n, c_sum / n), m_sum, n))
elseif teams then
	-- Each learning team: its champion team beside untrained teams (the
	-- first networks of a fresh population, a team of clones each, or
	-- SIZE different ones), the other learning teams running their
	-- champions. Team reward, collisions, metrics and share of episodes
	-- won, each a mean over the repetitions.
	-- (a team that had no turn keeps the network it started with)
	for j = 1, #learners do
		if pops[j].best then
			host.set_team_net(learners[j].index, champion_team(j)[1])
		end
	end
	host.print(string.format("replay on unseen episodes (%d x %d ticks each):", host.reps, host.ticks))
	for k, L in ipairs(learners) do
		if not pops[k].best then goto next_replay end
		local size = teams.heterogeneous and L.size or 1
		local members = champion_team(k)
		local fresh = new_pop(k, host.seed + 1)
		local nets, groups = {}, {}
		for m = 1, size do nets[m] = members[m] end
		local n_fresh = 0
		for i, g in ipairs(fresh:genomes()) do
			if n_fresh == REPLAY_RANDOM * size then break end
			nets[#nets + 1] = algo.to_net(g)
			n_fresh = n_fresh + 1
		end
		-- whole teams only
		while n_fresh % size ~= 0 do
			nets[#nets] = nil
			n_fresh = n_fresh - 1
		end
		local n_teams = 1 + n_fresh // size
		for t = 1, n_teams do
			for m = 1, L.size do
				groups[#groups + 1] = teams.heterogeneous and ((t - 1) * size + m) or t
			end
		end
		local _, _, _, collisions, metrics, wins, team_fit, group =
			host.evaluate(nets, planned, groups, L.index)
		-- each team's figures from the first network of it
		local row = {}
		for i = 1, #nets do
			if not row[group[i]] then
				row[group[i]] = { f = team_fit[i], c = collisions[i], m = metrics[i], w = wins[i] }
			end
		end
		local f_sum, c_sum, w_sum, m_sum = 0, 0, 0, {}
		for m = 1, #host.metrics do m_sum[m] = 0 end
		for t = 2, n_teams do
			f_sum, c_sum, w_sum = f_sum + row[t].f, c_sum + row[t].c, w_sum + row[t].w
			for m = 1, #host.metrics do m_sum[m] = m_sum[m] + row[t].m[m] end
		end
		local reps, n = host.reps, n_teams - 1
		host.print(with_metrics(string.format("  team %s, champion:              reward %10.1f, %7.0f collision ticks",
			L.name, row[1].f / reps, row[1].c / reps), row[1].m, 1)
			.. string.format(", won %.1f%%", 100 * row[1].w / reps))
		host.print(with_metrics(string.format("  team %s, untrained teams (%2d): reward %10.1f, %7.0f collision ticks",
			L.name, n, f_sum / n / reps, c_sum / n / reps), m_sum, n)
			.. string.format(", won %.1f%%", 100 * w_sum / n / reps))
		::next_replay::
	end
end
return champion_fitness

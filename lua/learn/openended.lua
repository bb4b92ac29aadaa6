-- OPENENDED: minimal-criterion coevolution of environments and agents
-- (Brant & Stanley 2017; with resource limitation, 2020; docs/openended.md).
-- The environments come from the generator the task's ENV names (a file
-- that returns lib.openended's env(gen)); the agents are NEAT genomes of
-- the task's LEARNINGSKILL. Each batch:
--   - OPEN_ENV_BATCH environments, each a mutant of the next one in the
--     environments' queue, are tried on every admitted agent: a new one
--     (its genome never admitted before) is admitted when some agent
--     solves it, and counts in ANNECS;
--   - OPEN_AGENT_BATCH agents, each a NEAT mutant of the next one in the
--     agents' queue, are tried on the admitted environments, oldest first:
--     one is admitted by the first it solves whose uses are below
--     OPEN_RESOURCE (resource limitation), which then counts one use more;
--   - each queue keeps its OPEN_ENVS (OPEN_AGENTS) newest members.
-- The first agents and environment come from a bootstrap: POPSIZE fresh
-- NEAT genomes, mutated for at most OPEN_BOOTSTRAP rounds until some solve
-- the generator's seed environment.
-- With OPEN_SKILL, the hierarchy develops: after OPEN_DEVELOP batches that
-- admitted no environment, a skill from the template is added under the
-- learning skill, trained in focus on the frontier and frozen (develop,
-- below); the run folder's Mind/ is the grown hierarchy's mind folder.
--
-- The machinery is learning's (host, the module evo.learn): the same
-- evaluator and threads (host.set_genome picks the environment of the
-- next host.evaluate), log.csv and progress line, checkpoint and --resume.
local host = require "evo.learn"
local common = require "learn.common"
local random = require "learn.rng"
local serialize = require "learn.serialize"
local neat = require "learn.neat"
local openended = require "lib.openended"

local task = host.task
local function where(key) return common.where(host.task_path, host.task_lines, key) end

local O = require("learn.openended_options").check(task, host.task_path, host.task_lines)
local ENVS, AGENTS, ENV_BATCH = O.envs, O.agents, O.env_batch
local AGENT_BATCH, RESOURCE, BOOTSTRAP = O.agent_batch, O.resource, O.bootstrap
local RETENTION = O.retention
local DEVELOP, FOCUS, MAXSKILLS, TEMPLATE = O.develop, O.focus, O.max_skills, O.template
local PROGRESS = O.progress
if DEVELOP == 0 or MAXSKILLS == 0 then TEMPLATE = nil end
local batches = host.generations or tonumber(task.NUMGEN or "50")
local options = common.task_options(neat, task, host.task_path, host.task_lines)

-- The generator, loaded as the workers load it (its errors name its
-- file:line); it must return lib.openended's env(gen). A generator may
-- come from a mind folder someone sent, and this state has Lua's whole
-- library: it runs in a sandbox of the scene scripts' kind (docs/lua.md,
-- "What a script may use"), with the base library's safe part, string,
-- table, math without its generator, utf8, os.clock, load of text, and
-- the scene scripts' require (host.guard.require: modules from the mind
-- folder, then lua/, none that links out of them), in the same sandbox.
-- Every call into it has a scene script's limits (host.guard.call,
-- docs/lua.md "Limits"): loading it those of loading a script, each
-- call of its functions those of env.reset; one reached ends the run.
local guard = host.guard or error("OPENENDED: no guard for the generator", 0)
local GEN_LOADED = {} -- the modules the generator required in the loop
local function sandbox()
	local env, loaded = {}, GEN_LOADED
	for _, k in ipairs{ "assert", "error", "ipairs", "next", "pairs", "pcall", "print", "rawequal",
		"rawget", "rawlen", "rawset", "select", "tonumber", "tostring", "type", "xpcall",
		"getmetatable", "setmetatable" } do
		env[k] = _G[k]
	end
	for _, lib in ipairs{ "string", "table", "math", "utf8", "coroutine" } do
		local t = {}
		for k, v in pairs(_G[lib]) do t[k] = v end
		env[lib] = t
	end
	env.math.random, env.math.randomseed = nil, nil -- the loop's draws are learn.rng's
	env.string.dump = nil
	guard.patterns(env.string)
	env.os = { clock = os.clock }
	env._G = env
	env.package = { loaded = loaded }
	function env.load(chunk, name, _, e)
		if type(chunk) ~= "string" then error("load takes source text only", 2) end
		return load(chunk, name, "t", e or env)
	end
	env.require = guard.require(loaded, env)
	return env
end
local env_path = host.env_path or error(host.task_path .. ": OPENENDED needs ENV, "
	.. "an environment generator (docs/openended.md)", 0)
local chunk, load_err = loadfile(env_path, "t", sandbox())
if not chunk then error(load_err, 0) end
local ok, env = pcall(guard.call, "loading the environment", "load", chunk)
if not ok then error(tostring(env), 0) end
local gen = type(env) == "table" and env.generator
local FUNCTIONS = { "seed", "mutate", "size", "valid", "ticks", "init", "build", "solved" }
if not gen then
	error(string.format("%s: not an environment generator: it must return "
		.. "require('lib.openended').env(gen), gen having %s (docs/openended.md)",
		env_path, table.concat(FUNCTIONS, ", ")), 0)
end
for _, f in ipairs(FUNCTIONS) do
	if type(gen[f]) ~= "function" then
		error(string.format("%s: the generator has no function %s (it needs %s: docs/openended.md)",
			env_path, f, table.concat(FUNCTIONS, ", ")), 0)
	end
end
-- gen[f](...) under the limits, an error raised at the generator's
-- file:line as it is
local function call(f, ...)
	local r = table.pack(pcall(guard.call, f, "call", gen[f], ...))
	if not r[1] then error(tostring(r[2]), 0) end
	return table.unpack(r, 2, r.n)
end

-- The run's state: the checkpoint holds all of it.
local S
local saved = host.resume and host.read("checkpoint.lua")
if host.resume and not saved then
	host.print("no checkpoint in " .. host.run_dir .. ": starting from batch 0")
end
local pop, rng
if saved then
	local path = host.run_dir .. "/checkpoint.lua"
	S = serialize.load(saved, path)
	if type(S) ~= "table" or S.format ~= "evo-openended-1" then
		error(path .. ": not an OPENENDED run's checkpoint", 0)
	end
	if S.seed ~= host.seed then
		error(string.format("%s: the checkpoint is of a run with seed %s, not %s: resume it "
			.. "with --seed %s", path, tostring(S.seed), tostring(host.seed), tostring(S.seed)), 0)
	end
	pop = neat.load(S.pop)
	rng = pop.rng
	for _, a in ipairs(S.agents) do neat.own_genes(a.genome) end
	for _, a in ipairs(S.archive) do neat.own_genes(a.genome) end
	if S.best then neat.own_genes(S.best.solver) end
	host.print(string.format("resuming after batch %d", S.batch))
else
	rng = random.new(host.seed)
	pop = neat.new{ inputs = host.inputs, outputs = host.outputs, options = options, rng = rng }
	S = { format = "evo-openended-1", seed = host.seed, batch = -1, envs = {}, agents = {},
		annecs = 0, largest = 0, env_next = 0, agent_next = 0, next_id = 0, seen = {},
		admitted = {}, idle = 0, frontier = {}, skills = {}, archive = {} }
end
local net_of = neat.pack_net or neat.to_net

-- Which of `genomes` solve environment `text` in batch b; and the
-- evaluation's seconds.
local function solvers(text, genomes, b)
	if #genomes == 0 then return {}, 0 end
	host.set_genome(text)
	local nets = {}
	for i, g in ipairs(genomes) do nets[i] = net_of(g) end
	local _, seconds, solved = host.evaluate(nets, b)
	return solved, seconds
end

local function admit_env(genome, text, b, solver_genome)
	S.next_id = S.next_id + 1
	local size = call("size", genome)
	if type(size) ~= "number" or size ~= size then
		error(string.format("%s: the generator's size returned %s, not a number",
			env_path, size == size and type(size) or "nan"), 0)
	end
	S.envs[#S.envs + 1] = { id = S.next_id, genome = genome, text = text, size = size,
		batch = b, uses = 0 }
	S.seen[text] = true
	S.annecs = S.annecs + 1
	if size > S.largest then S.largest = size end
	-- every admitted environment; the agent that solved it then is
	-- solvers/env-NNNN.net, and the checkpoint keeps only the champion's
	-- genome (the one that solved the largest, the first of equals): a
	-- genome for each of ten thousand environments would make every
	-- checkpoint tens of megabytes
	S.admitted[#S.admitted + 1] = { id = S.next_id, batch = b, size = size, text = text,
		skills = S.skills and #S.skills or 0 }
	if not S.best or size > S.best.size then
		S.best = { id = S.next_id, size = size, solver = neat.copy_genome(solver_genome) }
	end
	host.save(string.format("solvers/env-%04d.net", S.next_id), neat.to_net_text(
		neat.to_net(solver_genome), string.format("solved environment %d (size %.17g) when "
			.. "batch %d admitted it", S.next_id, size, b)))
	while #S.envs > ENVS do table.remove(S.envs, 1) end
end

-- Retention's bookkeeping (retention() below): each admitted
-- environment's `known`, the numbers of the kept agents known to solve
-- it, and `tried`, the highest agent number that was tried on it.
local function note_solver(env_id, agent_id)
	local a = S.admitted[env_id]
	a.known = a.known or {}
	a.known[#a.known + 1] = agent_id
end

local function forget_agent(agent_id)
	for _, a in ipairs(S.admitted) do
		for i = #(a.known or {}), 1, -1 do
			if a.known[i] == agent_id then table.remove(a.known, i) end
		end
	end
end

-- Whether agent `id` is the only known solver of some admitted
-- environment.
local function sole_solver(id)
	for _, a in ipairs(S.admitted) do
		if a.known and #a.known == 1 and a.known[1] == id then return true end
	end
	return false
end

-- An agent leaving the queue that is the only known solver of some
-- admitted environment goes to the archive: it breeds no more and tries
-- no new environment, but it is kept in the run, so what the run solved
-- stays solved (retention). Any other leaves the run.
local function admit_agent(genome, b)
	S.agent_id = (S.agent_id or 0) + 1
	S.agents[#S.agents + 1] = { genome = genome, batch = b, id = S.agent_id }
	while #S.agents > AGENTS do
		local old = table.remove(S.agents, 1)
		if sole_solver(old.id) then
			S.archive[#S.archive + 1] = old
		else
			forget_agent(old.id)
		end
	end
	return S.agent_id
end

-- The bootstrap: fresh genomes, mutated until some solve the seed.
local function bootstrap(b)
	local seed = call("seed")
	local text = openended.encode(seed)
	local genomes, seconds, evaluations = {}, 0, 0
	for i, g in ipairs(pop.population) do genomes[i] = neat.copy_genome(g) end
	for round = 1, BOOTSTRAP do
		local solved, s = solvers(text, genomes, b)
		seconds, evaluations = seconds + s, evaluations + #genomes
		local first
		for i, g in ipairs(genomes) do
			if solved[i] then
				first = first or g
				admit_agent(g, b)
			end
		end
		if first then
			admit_env(seed, text, b, first)
			for _, a in ipairs(S.agents) do note_solver(S.next_id, a.id) end
			S.admitted[S.next_id].tried = S.agent_id
			host.print(string.format("bootstrap: %d of %d agents solve the seed environment "
				.. "after %d round(s)", #S.agents, #genomes, round))
			return seconds, evaluations
		end
		for _, g in ipairs(genomes) do neat.mutate(pop, g, rng) end
	end
	error(string.format("%s: no agent solved the generator's seed environment in "
		.. "OPEN_BOOTSTRAP %d rounds of %d genomes", where("OPEN_BOOTSTRAP"), BOOTSTRAP,
		#genomes), 0)
end

local function agent_genomes()
	local list = {}
	for i, a in ipairs(S.agents) do list[i] = a.genome end
	return list
end

local keep_frontier -- development's, below

-- One batch: new environments, then new agents.
local function batch(b)
	local seconds, evaluations, new_envs, new_agents = 0, 0, 0, 0
	for _ = 1, ENV_BATCH do
		S.env_next = S.env_next % #S.envs + 1
		local parent = S.envs[S.env_next]
		local child = call("mutate", parent.genome, rng)
		if openended.encode(parent.genome) ~= parent.text then
			-- the admitted environment would no longer be what was solved
			error(string.format("%s: the generator's mutate changed the genome it was "
				.. "given (environment %d); it must return a changed copy "
				.. "(docs/openended.md)", env_path, parent.id), 0)
		end
		local text = openended.encode(child)
		if call("valid", child) and not S.seen[text] then
			local genomes = agent_genomes()
			local solved, s = solvers(text, genomes, b)
			seconds, evaluations = seconds + s, evaluations + #genomes
			local admitted = false
			for i, g in ipairs(genomes) do
				if solved[i] then
					admit_env(child, text, b, g)
					new_envs = new_envs + 1
					admitted = true
					for k = i, #genomes do
						if solved[k] then note_solver(S.next_id, S.agents[k].id) end
					end
					S.admitted[S.next_id].tried = S.agents[#S.agents].id
					break
				end
			end
			if not admitted then keep_frontier(child, text) end
		end
	end
	local children = {}
	for k = 1, AGENT_BATCH do
		S.agent_next = S.agent_next % #S.agents + 1
		local child = neat.copy_genome(S.agents[S.agent_next].genome)
		neat.mutate(pop, child, rng)
		children[k] = child
	end
	local pending = children
	for _, e in ipairs(S.envs) do
		if #pending == 0 then break end
		if e.uses < RESOURCE then
			local solved, s = solvers(e.text, pending, b)
			seconds, evaluations = seconds + s, evaluations + #pending
			local left = {}
			for i, g in ipairs(pending) do
				if solved[i] and e.uses < RESOURCE then
					e.uses = e.uses + 1
					note_solver(e.id, admit_agent(g, b))
					new_agents = new_agents + 1
				else
					left[#left + 1] = g
				end
			end
			pending = left
		end
	end
	return seconds, evaluations, new_envs, new_agents
end

---------------------------------------------------------------------------
-- Development (docs/openended.md, "Development"): when OPEN_DEVELOP
-- batches in a row admitted no environment, a skill made from the
-- template OPEN_SKILL names is added under the learning skill (the master
-- in minds/OpenMaze): the learning skill gets one more output, SK:<new>,
-- in every agent kept; the new skill is trained by NEAT in focus for
-- OPEN_FOCUS generations on the frontier, every other skill frozen, the
-- learning skill running the run's champion; its champion is frozen, and
-- the run goes on with the grown hierarchy. The grown hierarchy is an
-- ordinary mind folder in the run folder, Mind/, rewritten at each
-- checkpoint; the workers evaluate with it (host.grow).
local FRONTIER = 8     -- unsolved mutants kept for the frontier, newest
local RECENT = 3       -- newest admitted environments added to a focus
local BONUS = 100      -- a focus's fitness per frontier environment solved
-- the new output's link from the bias node: neat_sigmoid(4.9 w) = 0.25,
-- an influence of 0.25 (docs/openended.md says why)
local INFLUENCE = 0.25
local BIAS_WEIGHT = -math.log(1 / INFLUENCE - 1) / 4.9
local LS = task.LEARNINGSKILL
local TASK_FILE = host.task_path:match("([^/]+)$")
local GROWN_TASK = "Mind/Tasks/" .. TASK_FILE

-- A valid mutant no agent solved, kept for the frontier (newest last).
function keep_frontier(genome, text)
	if not TEMPLATE then return end
	S.frontier[#S.frontier + 1] = { genome = genome, text = text }
	while #S.frontier > FRONTIER do table.remove(S.frontier, 1) end
end

-- A file of the task's mind folder, or nil.
local function mind_file(rel)
	local f = io.open(host.mind_dir .. "/" .. rel, "r")
	if not f then return nil end
	local text = f:read("a")
	f:close()
	return text
end

-- The task's mind folder as the grown one starts from, read once (the
-- checkpoint keeps it): the bot's files, the skills under MASTERSKILL
-- (their SK: outputs followed), the generator when it is the folder's and
-- the folder's modules it required,
-- the template, the task and a DEMOSIM task of the generator.
local function base_mind()
	if S.mind then return S.mind end
	local m = { files = {}, skills = {} }
	local function file(name, text) if text then m.files[#m.files + 1] = { name = name, text = text } end end
	local bot = task.BOTNAME or ""
	file(bot .. ".botdesc", mind_file(bot .. ".botdesc"))
	file(bot .. ".vardesc", mind_file(bot .. ".vardesc"))
	local seen, queue = {}, { task.MASTERSKILL or LS }
	while #queue > 0 do
		local name = table.remove(queue, 1)
		if not seen[name] then
			seen[name] = true
			local ades = mind_file("Skills/" .. name .. "/" .. name .. ".ades")
			if ades then
				m.skills[#m.skills + 1] = { name = name, ades = ades,
					net = mind_file("Skills/" .. name .. "/" .. name .. ".net") }
				for child in ades:gsub("#[^\n]*", ""):gmatch("SK:(%S+)") do
					queue[#queue + 1] = child
				end
			end
		end
	end
	local envs = host.mind_dir .. "/Envs/"
	if host.env_path and host.env_path:sub(1, #envs) == envs then
		local rel = host.env_path:sub(#host.mind_dir + 2)
		file(rel, mind_file(rel))
	end
	-- the modules of the mind folder the generator required, as the
	-- sandbox finds them (the mind folder first, then lua/)
	local names = {}
	for name in pairs(GEN_LOADED) do names[#names + 1] = name end
	table.sort(names)
	for _, name in ipairs(names) do
		local rel = name:gsub("%.", "/") .. ".lua"
		file(rel, mind_file(rel))
	end
	file(task.OPEN_SKILL, TEMPLATE.text)
	local f = io.open(host.task_path, "r")
	file("Tasks/" .. TASK_FILE, f and f:read("a"))
	if f then f:close() end
	local demo = { "# The grown hierarchy of an OPENENDED run, on its generator's seed",
		"# environment (written by evo run; docs/openended.md)", "TYPE:DEMOSIM" }
	for _, k in ipairs{ "BOTMODEL", "BOTNAME", "MASTERSKILL", "ENV", "TICKLIM" } do
		if task[k] then demo[#demo + 1] = k .. ":" .. task[k] end
	end
	file("Tasks/Demo.simbatch", table.concat(demo, "\n") .. "\n")
	S.mind = m
	return m
end

-- .ades text with one output more, `SK:name`, after its last output.
local function add_output(text, name)
	local out, need, done = {}, nil, false
	for line in (text:sub(-1) == "\n" and text or text .. "\n"):gmatch("([^\n]*)\n") do
		local n = not done and not need and tonumber(line:match("^%s*output:(%d+)%s*$"))
		if n then
			out[#out + 1] = "output:" .. (n + 1)
			need = n
		else
			out[#out + 1] = line
			if need then
				for _ in line:gsub("#.*", ""):gmatch("%S+") do need = need - 1 end
			end
		end
		if need and need <= 0 then
			out[#out + 1] = "SK:" .. name
			need, done = nil, true
		end
	end
	if not done then
		error(string.format("%s: Skills/%s/%s.ades has no output:N with its N outputs",
			host.mind_dir, LS, LS), 0)
	end
	return table.concat(out, "\n") .. "\n"
end

-- The champion: the agent that solved the largest admitted environment
-- (the first of equals).
local function champion() return S.best end

-- Mind/ in the run folder: the grown hierarchy as a mind folder, the
-- learning skill's network the champion.
local function write_mind(folder)
	if not TEMPLATE then return end
	local m = base_mind()
	local function put(name, text) host.save((folder or "Mind") .. "/" .. name, text) end
	for _, f in ipairs(m.files) do put(f.name, f.text) end
	local best = champion()
	for _, sk in ipairs(m.skills) do
		local ades, net = sk.ades, sk.net
		if sk.name == LS then
			for _, k in ipairs(S.skills) do ades = add_output(ades, k.name) end
			net = best and neat.to_net_text(neat.to_net(best.solver), string.format(
				"the champion of an OPENENDED run: it solved environment %d (size %.17g)",
				best.id, best.size)) or net
		end
		put("Skills/" .. sk.name .. "/" .. sk.name .. ".ades", ades)
		if net then put("Skills/" .. sk.name .. "/" .. sk.name .. ".net", net) end
	end
	for _, k in ipairs(S.skills) do
		put("Skills/" .. k.name .. "/" .. k.name .. ".ades", k.ades)
		if k.net then put("Skills/" .. k.name .. "/" .. k.name .. ".net", k.net) end
	end
end

-- Genome g with one output more: node `id`, linked from the bias node by
-- gene `innov` (so its output is INFLUENCE before any other link).
local function add_output_gene(g, id, innov)
	local bias, act
	for _, nd in ipairs(g.nodes) do
		if nd.kind == "bias" then bias = nd.id end
		if nd.kind == "output" then act = act or nd.act end
	end
	g.nodes[#g.nodes + 1] = { id = id, kind = "output", act = act }
	local links = {}
	for i, l in ipairs(g.links) do
		links[i] = { innov = l.innov, from = l.from, to = l.to, weight = l.weight,
			enabled = l.enabled }
	end
	links[#links + 1] = { innov = innov, from = bias, to = id, weight = BIAS_WEIGHT,
		enabled = true }
	g.links = links
	neat.own_genes(g)
end

-- How many of the environments `envs` ({text}) genome solves.
local function count_solved(genome, envs, b)
	local n = 0
	for _, e in ipairs(envs) do
		if solvers(e.text, { genome }, b)[1] then n = n + 1 end
	end
	return n
end

-- skills.csv: every skill added.
local function skills_csv()
	local out = { "skill,batch,reason,focus,frontier,solved_before,solved_after\n" }
	for _, k in ipairs(S.skills) do
		out[#out + 1] = string.format("%s,%d,\"%s\",%d,%d,%d,%d\n", k.name, k.batch, k.reason,
			k.focus, k.frontier, k.before, k.after)
	end
	return table.concat(out)
end

-- Focused training of skill `name` (the evaluator's candidates are its
-- networks) on `envs`, OPEN_FOCUS generations of NEAT: fitness the
-- episodes' summed, plus BONUS per frontier environment solved. Returns
-- the best genome's network, the evaluations and their seconds.
local function focus(name, envs, n_frontier, n_in, n_out, b)
	local fpop = neat.new{ inputs = n_in, outputs = n_out, options = options, rng = rng }
	local evaluations, seconds = 0, 0
	for _ = 1, FOCUS do
		local genomes = fpop:genomes()
		local nets, fit = {}, {}
		for i, g in ipairs(genomes) do nets[i], fit[i] = net_of(g), 0 end
		for k, e in ipairs(envs) do
			host.set_genome(e.text)
			local f, s, solved = host.evaluate(nets, b)
			evaluations, seconds = evaluations + #nets, seconds + s
			for i = 1, #nets do
				fit[i] = fit[i] + f[i] + ((k <= n_frontier and solved[i]) and BONUS or 0)
			end
		end
		fpop:tell(fit)
	end
	return neat.to_net_text(neat.to_net(fpop.best.genome), string.format(
		"trained by evo in focus: OPENENDED, seed %d, skill %s added after batch %d, "
		.. "fitness %.17g", host.seed, name, b, fpop.best.fitness)), evaluations, seconds
end

-- The workers evaluate the agents with the grown hierarchy.
local function grow_agents()
	local n_in, n_out = host.grow(GROWN_TASK, LS, {})
	if n_in ~= pop.inputs or n_out ~= pop.outputs then
		error(string.format("%s: the grown skill %s has %d inputs and %d outputs, "
			.. "its agents %d and %d", GROWN_TASK, LS, n_in, n_out, pop.inputs, pop.outputs), 0)
	end
end

-- Add skill <Template><k> after batch b. Returns the focus's evaluations
-- and their seconds.
local function develop(b)
	local k = #S.skills + 1
	local name = TEMPLATE.name .. k
	local reason = PROGRESS == "largest" and string.format("no environment larger than %g "
		.. "admitted in batches %d-%d", S.largest, b - S.idle + 1, b)
		or string.format("no environment admitted in batches %d-%d", b - S.idle + 1, b)
	local best = champion()
	local envs = {}
	for _, e in ipairs(S.frontier) do envs[#envs + 1] = e end
	local n_frontier = #envs
	for i = math.max(1, #S.envs - RECENT + 1), #S.envs do envs[#envs + 1] = S.envs[i] end
	local before = count_solved(best.solver, S.frontier, b)
	-- the learning skill's new output, in every genome of the run
	pop.next_node, pop.next_innov = pop.next_node + 1, pop.next_innov + 1
	pop.outputs = pop.outputs + 1
	for _, a in ipairs(S.agents) do add_output_gene(a.genome, pop.next_node, pop.next_innov) end
	for _, a in ipairs(S.archive) do add_output_gene(a.genome, pop.next_node, pop.next_innov) end
	add_output_gene(best.solver, pop.next_node, pop.next_innov)
	-- the template's text, its first word (the skill's name) the new name
	local t = TEMPLATE.text:gsub("^(%s*)([^\n]*)", function(space, line)
		return space .. name .. (line:match("^[^%s#]+(.*)$") or "")
	end, 1)
	-- its network until the focus ends: no link, every output 0.5 (the
	-- mind folder's loader wants one; the focus's candidates replace it)
	local blank = { inputs = TEMPLATE.inputs, outputs = TEMPLATE.outputs, nodes = {},
		outputs_ids = {}, links = {} }
	for i = 1, TEMPLATE.outputs do
		blank.nodes[i] = { id = TEMPLATE.inputs + i - 1, act = "neat_sigmoid", bias = 0 }
		blank.outputs_ids[i] = TEMPLATE.inputs + i - 1
	end
	S.skills[k] = { name = name, batch = b, reason = reason, focus = FOCUS,
		frontier = n_frontier, before = before, ades = t,
		net = neat.to_net_text(blank, "in focused training") }
	write_mind()
	-- focus: the learning skill runs the champion (Mind/'s network)
	local n_in, n_out = host.grow(GROWN_TASK, name,
		{ [LS] = "Mind/Skills/" .. LS .. "/" .. LS .. ".net" })
	local net, evaluations, seconds = focus(name, envs, n_frontier, n_in, n_out, b)
	S.skills[k].net = net
	write_mind()
	-- the hierarchy as it is now, kept: the agents admitted from now on
	-- until the next skill have its outputs (evo run --env N runs their
	-- solvers in it; envs.csv's skills column says which)
	write_mind("Mind-" .. k)
	grow_agents()
	S.skills[k].after = count_solved(best.solver, S.frontier, b)
	host.save("skills.csv", skills_csv())
	host.print(string.format("skill %s added after batch %d (%s): focused training of %d "
		.. "generations on %d frontier and %d admitted environments; the champion solves %d "
		.. "of the frontier before, %d after", name, b, reason, FOCUS, n_frontier,
		#envs - n_frontier, before, S.skills[k].after))
	S.idle, S.frontier = 0, {}
	return evaluations, seconds
end

-- envs.csv: every admitted environment, in order: its number, the batch
-- that admitted it, its size and its genome.
local function envs_csv()
	local out = { "env,batch,size,skills,genome\n" }
	for _, a in ipairs(S.admitted) do
		out[#out + 1] = string.format("%d,%d,%.17g,%d,\"%s\"\n", a.id, a.batch, a.size,
			a.skills or 0,
			(a.text:gsub('"', '""')))
	end
	return table.concat(out)
end

-- Try admitted environment a, which has no known solver, on the kept
-- agents numbered above its `tried`, the newest first, RETENTION_CHUNK at
-- a time, until some solve it: they are its known solvers. The agents
-- left untried are older than them and leave the queue before them, so
-- when the last known solver leaves, every kept agent not tried on a is
-- again numbered above `tried`. Returns the evaluations.
local RETENTION_CHUNK = 2
local function try_kept(a, b)
	local untried = {}
	for i = #S.agents, 1, -1 do
		if S.agents[i].id > (a.tried or 0) then untried[#untried + 1] = S.agents[i] end
	end
	for i = #S.archive, 1, -1 do
		if S.archive[i].id > (a.tried or 0) then untried[#untried + 1] = S.archive[i] end
	end
	a.known, a.tried = {}, S.agent_id
	local evaluations = 0
	for first = 1, #untried, RETENTION_CHUNK do
		local chunk, genomes = {}, {}
		for i = first, math.min(#untried, first + RETENTION_CHUNK - 1) do
			chunk[#chunk + 1] = untried[i]
			genomes[#genomes + 1] = untried[i].genome
		end
		local solved = solvers(a.text, genomes, b)
		evaluations = evaluations + #genomes
		for i, k in ipairs(chunk) do
			if solved[i] then a.known[#a.known + 1] = k.id end
		end
		if #a.known > 0 then break end
	end
	return evaluations
end

-- Retention, after every batch: is every environment admitted so far
-- still solved by some agent kept? An episode of GEN_Maze is the same in
-- every batch (no noise, a fixed start), so an agent that solved an
-- environment once solves it whenever tried, and one that failed fails
-- again. `known` (note_solver) holds the kept agents that solved it, from
-- the batches' own evaluations; an agent leaving the queue leaves it
-- (forget_agent). Only an environment with no known solver is tried, on
-- the kept agents not tried on it before (try_kept); one none of them
-- solves is lost, and said so, never hidden (retention.csv, and a line
-- of the run's output when the lost ones change), and tried again on
-- each agent admitted later. Every OPEN_RETENTION batches (0: never) a
-- full check tries every admitted environment on every agent kept,
-- afresh (for a generator whose episodes depend on their seed).
local function retention(b)
	local full = RETENTION > 0 and (b + 1) % RETENTION == 0
	local lost, evaluations = {}, 0
	for _, a in ipairs(S.admitted) do
		if full then a.known, a.tried = {}, nil end
		if a.known == nil or #a.known == 0 then evaluations = evaluations + try_kept(a, b) end
		if #a.known == 0 then lost[#lost + 1] = a.id end
	end
	S.retention = S.retention or {}
	local last = S.retention[#S.retention]
	S.retention[#S.retention + 1] = { batch = b, admitted = #S.admitted, lost = lost,
		evaluations = evaluations, full = full }
	if table.concat(lost, " ") == table.concat(last and last.lost or {}, " ") then return end
	if #lost > 0 then
		host.print(string.format("retention after batch %d: %d of the %d environments admitted "
			.. "%s no longer solved by any agent kept (%s; retention.csv)", b, #lost,
			#S.admitted, #lost == 1 and "is" or "are", table.concat(lost, ", ")))
	else
		host.print(string.format("retention after batch %d: all %d environments admitted are "
			.. "solved by agents kept again (retention.csv)", b, #S.admitted))
	end
end

-- retention.csv: a row per batch.
local function retention_csv()
	local out = { "batch,admitted,retained,lost,evaluations,full\n" }
	for _, r in ipairs(S.retention or {}) do
		out[#out + 1] = string.format("%d,%d,%d,%s,%d,%d\n", r.batch, r.admitted,
			r.admitted - #r.lost, table.concat(r.lost, " "), r.evaluations, r.full and 1 or 0)
	end
	return table.concat(out)
end

-- The checkpoint and the files that go with it (envs.csv, retention.csv,
-- Mind/) are written after the first batch of a process, after the last,
-- and after any batch that ends CHECKPOINT_SECONDS of wall time or more
-- after the last checkpoint, as learning's are (lua/learn/learnsim.lua):
-- a run of thousands of batches a few tenths of a second each does not
-- write its whole state thousands of times. A checkpoint that took long
-- to write waits CHECKPOINT_SHARE times as long. A run killed between two
-- checkpoints goes on from the last one and does the batches after it
-- again, identically. A batch after which a skill was added (a focused
-- training costs many batches) is always followed by a checkpoint.
local CHECKPOINT_SECONDS, CHECKPOINT_SHARE = 1.0, 10
local last_checkpoint, checkpoint_cost = host.clock(), 0
local first_batch = S.batch + 1
local function checkpoint(b, developed)
	if not (developed or b == first_batch or b == batches - 1 or host.clock() - last_checkpoint
		>= math.max(CHECKPOINT_SECONDS, CHECKPOINT_SHARE * checkpoint_cost)) then
		return
	end
	local t0 = host.clock()
	S.pop = neat.save(pop, true)
	host.save("envs.csv", envs_csv())
	host.save("retention.csv", retention_csv())
	write_mind()
	host.save("checkpoint.lua", serialize.dump(S))
	S.pop = nil
	last_checkpoint = host.clock()
	checkpoint_cost = last_checkpoint - t0
end

-- gallery.png: up to GALLERY admitted environments, at evenly spaced
-- ranks of envs.csv and the largest, each drawn at its episode's start
-- with its number, batch and size under it (sim/learn/gallery.c); after
-- the last batch, and after a batch when GALLERY_SECONDS have passed
-- since the last one was drawn.
local GALLERY, GALLERY_SECONDS = 24, 60
local gallery_at = host.clock()
local function gallery(b)
	local n, picked, best = #S.admitted, {}, 1
	for i, a in ipairs(S.admitted) do
		if a.size > S.admitted[best].size then best = i end
	end
	local function spread(slots)
		picked = {}
		for k = 1, slots do picked[1 + (k - 1) * (n - 1) // math.max(1, slots - 1)] = true end
	end
	spread(math.min(n, GALLERY))
	if not picked[best] then
		spread(GALLERY - 1)
		picked[best] = true
	end
	local items = {}
	for i, a in ipairs(S.admitted) do
		if picked[i] then
			items[#items + 1] = { a.text, string.format("env %d  batch %d  size %g", a.id,
				a.batch, a.size) }
		end
	end
	host.gallery(string.format("%s, seed %d: %d of the %d environments admitted by batch %d",
		host.task_path:match("([^/]+)%.simbatch$") or host.task_path, host.seed, #items, n, b),
		items)
	gallery_at = host.clock()
end

host.open_log(S.batch + 1, { "annecs", "largest", "envs", "agents", "skills" })
S.idle, S.frontier, S.skills = S.idle or 0, S.frontier or {}, S.skills or {}
if #S.skills > 0 then
	write_mind()
	grow_agents()
end
for b = S.batch + 1, batches - 1 do
	local seconds, evaluations, new_envs
	if b == 0 then
		seconds, evaluations = bootstrap(b)
		new_envs = 1
	else
		seconds, evaluations, new_envs = batch(b)
	end
	-- progress, for development: an environment admitted (OPEN_PROGRESS
	-- admitted), or one larger than any before (largest)
	local progressed
	if PROGRESS == "largest" then
		progressed = S.largest > (S.progress_size or 0)
		S.progress_size = S.largest
	else
		progressed = new_envs > 0
	end
	S.idle = progressed and 0 or S.idle + 1
	local developed = TEMPLATE and S.idle >= DEVELOP and #S.skills < MAXSKILLS
		and b < batches - 1
	if developed then
		local e, s = develop(b)
		evaluations, seconds = evaluations + e, seconds + s
	end
	local sum = 0
	for _, e in ipairs(S.envs) do sum = sum + e.size end
	S.batch = b
	host.log{ generation = b, generations = batches, best = S.largest, mean = sum / #S.envs,
		best_ever = S.annecs, species = 0, evaluations = evaluations, solved = new_envs,
		seconds = seconds, metrics = { S.annecs, S.largest, #S.envs, #S.agents, #S.skills },
		note = string.format("ANNECS %d  largest %g  envs %d  agents %d  skills %d", S.annecs,
			S.largest, #S.envs, #S.agents, #S.skills) }
	retention(b)
	if host.gallery and (b == batches - 1 or host.clock() - gallery_at >= GALLERY_SECONDS) then
		gallery(b)
	end
	checkpoint(b, developed)
end

-- The champion: the agent that solved the largest admitted environment
-- (the first of equals).
-- With skills added, its network has their outputs, which the task's
-- mind folder has not: it goes to the run folder only (and Mind/).
local best = S.best
if best then
	local text = neat.to_net_text(neat.to_net(best.solver), string.format(
		"trained by evo: OPENENDED, seed %d, %d batches, solved environment %d of size %.17g",
		host.seed, batches, best.id, best.size))
	if #S.skills > 0 then
		host.save("champion.net", text)
		host.print(string.format("champion in %s/champion.net, with the %d skill(s) added: the "
			.. "grown hierarchy is %s/Mind (Skills/%s/%s.net left as it was)", host.run_dir,
			#S.skills, host.run_dir, LS, LS))
	else
		host.save_champion(text)
	end
end

-- NEAT (NeuroEvolution of Augmenting Topologies), as Stanley & Miikkulainen
-- define it in "Evolving Neural Networks through Augmenting Topologies"
-- (Evolutionary Computation 10(2), 2002), in pure Lua 5.4.
--
--	local neat = require "learn.neat"
--	local random = require "learn.rng"
--	local pop = neat.new{ inputs = 2, outputs = 1, options = { pop_size = 150 },
--		rng = random.new(42) }
--	for gen = 1, 100 do
--		local fit = {}
--		for i, g in ipairs(pop:genomes()) do fit[i] = evaluate(neat.to_net(g)) end
--		pop:tell(fit)
--	end
--	print(pop.best.fitness, neat.to_net_text(neat.to_net(pop.best.genome)))
--
-- Genomes. Node ids 0..n-1 are the inputs, n is the bias node (its value is
-- always 1, as in the paper), n+1..n+m the outputs, then hidden nodes in the
-- order the innovation registry created them. A link gene is
-- { innov, from, to, weight, enabled }; links are kept sorted by innovation.
-- A node table never changes once made (mutations add nodes to a genome's
-- own list), so copies and children may share it; genes do change.
--
-- Bias. The paper feeds a constant-1 bias input; evo's .net has no such
-- input but a bias per node. neat.to_net therefore drops the bias node and
-- turns every enabled link bias->X into X's bias (the same value, since the
-- bias node is 1). Genomes stay exactly the paper's; the mapping is exact.
--
-- Determinism. Every random draw goes through the rng object given to
-- neat.new (a learn.rng generator: methods :unit() in [0,1) and
-- :normal()); math.random is never used, and every loop runs over arrays,
-- never over pairs(), so the same seed gives the same run. neat.save /
-- neat.load hold the whole state.
--
-- Fitness is "higher is better". Fitness sharing needs fitness >= 0: when a
-- generation has negative values they are shifted by the minimum for the
-- offspring allotment only (the shift does not change the ranking).
local common = require "learn.common"
local netfile = require "learn.netfile"
local random = require "learn.rng"

local neat = {}

-- evo.neat: the same kernels in C (sim/learn/lua_neat.c), in the states
-- evo gives it to (the learning loop's); elsewhere the Lua below runs.
local fast = package.loaded["evo.neat"]

-- Every parameter, with the paper's value where the paper gives one.
-- neat.task_keys says which .simbatch key sets each.
neat.defaults = {
	pop_size = 150, -- genomes per generation (paper: 150)
	c1 = 1.0, -- distance weight of excess genes (paper: 1.0)
	c2 = 1.0, -- distance weight of disjoint genes (paper: 1.0)
	c3 = 0.4, -- distance weight of the mean weight difference (paper: 0.4)
	threshold = 3.0, -- compatibility threshold delta_t (paper: 3.0); with target_species, where
	-- the threshold starts
	normalize_below = 20, -- N = 1 when both genomes have fewer genes than this (paper: 20); 0:
	-- always the larger genome's gene count. The rule has a cliff: E and D count 20 times less
	-- against a genome of 20 genes than against one of 19
	weight_mut_prob = 0.9, -- chance a genome's weights are mutated (NEAT's original code: 0.9; paper: 0.8)
	weight_mutation = "code", -- "code": NEAT's original code's scheme (see mutate_weights);
	-- "paper": each weight perturbed with perturb_prob, else replaced
	severe_prob = 0.5, -- "code": chance that a weight mutation is a severe one (NEAT's original code: 0.5)
	perturb_prob = 0.9, -- "paper": per weight, perturbed, else replaced (paper: 90%)
	perturb_power = 3.0, -- a perturbation adds uniform(-p, p) (NEAT's original code: 2.5; evo's
	-- fixed-point outputs saturate sooner, and larger steps leave the plateaus faster)
	replace_power = 3.0, -- a replaced weight draws uniform(-p, p) (NEAT's original code: 2.5)
	new_link_power = 1.0, -- an added link's weight draws uniform(-p, p) (NEAT's original code: 1.0)
	bias_input = 1.0, -- the bias node's constant input: a bias link of weight w gives its node a
	-- bias of w times this (NEAT's original code: 1.0 for XOR, 0.5 for the pole tasks)
	init_power = 1.0, -- the first generation's weights: uniform(-p, p) (NEAT's original code: 1.0)
	weight_max = 8.0, -- weights are clamped to [-w, w] (.net needs |w| < 128)
	add_node_prob = 0.03, -- chance of an add-node mutation (paper: 3%)
	add_link_prob = 0.05, -- chance of an add-link mutation (paper: 5%; 30% for large populations)
	add_link_tries = 20, -- random (from, to) pairs tried to find a new link
	split_bias = false, -- add-node may split a link from the bias node (NEAT's original code never
	-- does: the new node would be a constant, and evo folds the bias links into node biases)
	split_older = true, -- in a genome of fewer than 15 links, add-node prefers older links
	-- (NEAT's original code); else it picks an enabled link uniformly
	recurrent = false, -- add-link may create cycles (tasks that allow memory)
	recur_only_prob = 0, -- with recurrent: 0, add-link links any two nodes; above 0, the chance
	-- that it closes a cycle, and otherwise it does not (NEAT's original code; its p2nv: 0.2)
	activation = "neat_sigmoid", -- hidden and output nodes: an evo activation (paper: 1/(1+e^-4.9x))
	mutate_only_prob = 0.25, -- offspring from mutation without crossover (paper: 25%)
	mate_only_prob = 0.2, -- crossover offspring left unmutated (NEAT's original code: 0.2)
	mate_avg_prob = 0.4, -- crossover averages matching weights, else picks one (original code: 0.4)
	interspecies_prob = 0.001, -- crossover partner from another species (paper: 0.001)
	disable_prob = 0.75, -- a gene disabled in either parent is disabled in the child (paper: 75%)
	tie_smaller = true, -- crossover of equal fitness: the parent with fewer links counts as the
	-- fitter (NEAT's original code); false: disjoint genes of both at random (the paper)
	survival = 0.2, -- top fraction of each species that may reproduce (original code: 0.2)
	stagnation = 15, -- generations without improvement before a species gets no offspring (paper: 15)
	stagnation_penalty = 0.01, -- a stagnant species' share of offspring is multiplied by this
	-- (NEAT's original code: 0.01; 0: it gets none)
	elitism_offspring = 5, -- a species given more offspring than this keeps its champion unchanged
	-- (NEAT's original code; the paper says "species with more than five networks")
	rep_champion = true, -- the next generation is speciated against each species' champion
	-- (NEAT's original code); false: against a random member
	pop_champion = true, -- the generation's best genome is always copied unchanged into the next,
	-- whatever the size of its species (its species gets at least one offspring)
	target_species = 10, -- the threshold moves by threshold_step each generation towards this many
	-- species (NEAT 1.2's compat_adjust; SharpNEAT's default count: 10); 0: it stays delta_t, as
	-- in the paper (XOR's task sets 0). Genomes of 20 genes or more are compared divided by N,
	-- and a fixed 3.0 hardly ever splits them: Avoid's 24-gene genomes stayed one species
	threshold_step = 0.3, -- the threshold's step when target_species is set (NEAT 1.2: 0.3)
	threshold_min = 0.3, -- the threshold never goes below this (NEAT 1.2: 0.3)
	pop_stagnation = 0, -- generations without a new best before only the top two species reproduce;
	-- 0: off (paper: 20; evo's fixed-point XOR sits at exactly 9.0 for generations, which fires
	-- it while the search is still making progress)
	toggle_prob = 0, -- chance that a non-structural mutation also toggles a link on or off
	-- (NEAT's original code: mutate_toggle_enable_prob, 0.1 in its parameter files)
	reenable_prob = 0, -- chance that it also switches the first disabled link back on
	-- (NEAT's original code: mutate_gene_reenable_prob, 0.05)
	delta_coding = false, -- when pop_stagnation fires, the two species' offspring are all copies of
	-- their champion, weights mutated (0.8) or a link added (0.2), the last one unchanged
	-- (NEAT's original code); false: the two species reproduce as usual (the paper)
}

-- .simbatch key -> option name. POPSIZE is the tutorial's own key.
neat.task_keys = {
	POPSIZE = "pop_size",
	NEAT_POPSIZE = "pop_size",
	NEAT_C1 = "c1",
	NEAT_C2 = "c2",
	NEAT_C3 = "c3",
	NEAT_THRESHOLD = "threshold",
	NEAT_NORMALIZE_BELOW = "normalize_below",
	NEAT_WEIGHT_MUT_PROB = "weight_mut_prob",
	NEAT_WEIGHT_MUTATION = "weight_mutation",
	NEAT_SEVERE_PROB = "severe_prob",
	NEAT_PERTURB_PROB = "perturb_prob",
	NEAT_PERTURB_POWER = "perturb_power",
	NEAT_REPLACE_POWER = "replace_power",
	NEAT_NEW_LINK_POWER = "new_link_power",
	NEAT_INIT_POWER = "init_power",
	NEAT_BIAS_INPUT = "bias_input",
	NEAT_WEIGHT_MAX = "weight_max",
	NEAT_ADD_NODE_PROB = "add_node_prob",
	NEAT_ADD_LINK_PROB = "add_link_prob",
	NEAT_ADD_LINK_TRIES = "add_link_tries",
	NEAT_SPLIT_BIAS = "split_bias",
	NEAT_SPLIT_OLDER = "split_older",
	NEAT_RECURRENT = "recurrent",
	NEAT_RECUR_ONLY_PROB = "recur_only_prob",
	NEAT_ACTIVATION = "activation",
	NEAT_MUTATE_ONLY_PROB = "mutate_only_prob",
	NEAT_MATE_ONLY_PROB = "mate_only_prob",
	NEAT_MATE_AVG_PROB = "mate_avg_prob",
	NEAT_INTERSPECIES_PROB = "interspecies_prob",
	NEAT_DISABLE_PROB = "disable_prob",
	NEAT_TIE_SMALLER = "tie_smaller",
	NEAT_SURVIVAL = "survival",
	NEAT_STAGNATION = "stagnation",
	NEAT_STAGNATION_PENALTY = "stagnation_penalty",
	NEAT_ELITISM_OFFSPRING = "elitism_offspring",
	NEAT_REP_CHAMPION = "rep_champion",
	NEAT_POP_STAGNATION = "pop_stagnation",
	NEAT_DELTA_CODING = "delta_coding",
	NEAT_TOGGLE_PROB = "toggle_prob",
	NEAT_REENABLE_PROB = "reenable_prob",
	NEAT_POP_CHAMPION = "pop_champion",
	NEAT_TARGET_SPECIES = "target_species",
	NEAT_THRESHOLD_STEP = "threshold_step",
	NEAT_THRESHOLD_MIN = "threshold_min",
}

local ACTIVATIONS = {
	identity = function(x) return x end,
	sigmoid = function(x) return 1 / (1 + math.exp(-x)) end,
	neat_sigmoid = function(x) return 1 / (1 + math.exp(-4.9 * x)) end,
	tanh = function(x)
		local e = math.exp(-2 * math.abs(x))
		local t = (1 - e) / (1 + e)
		return x < 0 and -t or t
	end,
	relu = function(x) return x > 0 and x or 0 end,
	step = function(x) return x > 0 and 1 or 0 end,
	clamped = function(x) return math.min(1, math.max(0, x)) end,
	gauss = function(x) return math.exp(-x * x) end,
}

-- The numbers each option takes (common.options_from); bias_input takes
-- any finite number. add_link_tries is bounded: every add-link mutation
-- may make that many tries.
local P, W, C, WHOLE = common.PROB, common.POSITIVE, common.COUNT, common.WHOLE
neat.ranges = {
	pop_size = common.POPULATION, c1 = W, c2 = W, c3 = W, threshold = W, normalize_below = WHOLE,
	weight_mut_prob = P, severe_prob = P, perturb_prob = P, perturb_power = W,
	replace_power = W, new_link_power = W, init_power = W, weight_max = common.WEIGHT_MAX,
	add_node_prob = P, add_link_prob = P, add_link_tries = { lo = 0, hi = 1000, int = true },
	recur_only_prob = P, mutate_only_prob = P, mate_only_prob = P, mate_avg_prob = P,
	interspecies_prob = P, disable_prob = P, survival = { lo = 0, hi = 1, above = true },
	stagnation = C, stagnation_penalty = P, elitism_offspring = WHOLE, target_species = WHOLE,
	threshold_step = W, threshold_min = W, pop_stagnation = WHOLE, toggle_prob = P,
	reenable_prob = P,
}

-- Options from a task table (.simbatch key -> value, values as strings or
-- numbers). Returns the options and the sorted list of NEAT_* keys it does
-- not know (the caller warns); raises on a malformed value.
function neat.options_from_task(task)
	return common.options_from(task, "NEAT_", neat.task_keys, neat.defaults, function(key, s, value)
		if key == "NEAT_ACTIVATION" and not ACTIVATIONS[s] then
			error(key .. ": unknown activation '" .. tostring(value) .. "'", 0)
		end
		if key == "NEAT_WEIGHT_MUTATION" and s ~= "code" and s ~= "paper" then
			error(key .. ": '" .. tostring(value) .. "' is not a weight mutation scheme (code or paper)", 0)
		end
	end, neat.ranges)
end

---------------------------------------------------------------------------
-- Genomes

local function copy_node(n) return { id = n.id, kind = n.kind, act = n.act, value = n.value } end

local function copy_genome(g)
	local nodes, links = {}, {}
	for i, n in ipairs(g.nodes) do nodes[i] = copy_node(n) end
	for i, l in ipairs(g.links) do
		links[i] = { innov = l.innov, from = l.from, to = l.to, weight = l.weight, enabled = l.enabled }
	end
	return { nodes = nodes, links = links }
end
neat.copy_genome_lua = copy_genome
-- evo.neat's C where the state has it: the same copy.
if fast then copy_genome = fast.copy_genome end
neat.copy_genome = copy_genome

-- With evo.neat, a genome's links are one userdata of flat arrays (its
-- genes: #links, links[i].weight and the other fields read and write the
-- gene in place, ipairs walks them); a genome made in Lua (the tests')
-- may hold a list of gene tables, which the kernels take as well.
local function sort_genome(g)
	if type(g.links) == "table" then
		table.sort(g.links, function(a, b) return a.innov < b.innov end)
	else
		fast.sort_genes(g)
	end
	table.sort(g.nodes, function(a, b) return a.id < b.id end)
end

-- Appends gene table `l` to g's links.
local function add_gene(g, l)
	if type(g.links) == "table" then
		g.links[#g.links + 1] = l
	else
		fast.add_gene(g, l)
	end
end

-- A genome's links as genes where evo.neat is (a list of gene tables
-- becomes genes), as they are elsewhere.
local function own_genes(g)
	if fast and type(g.links) == "table" then g.links = fast.genes(g.links) end
	return g
end
neat.own_genes = own_genes

local function clamp(w, m) return w > m and m or (w < -m and -m or w) end

-- Compatibility distance delta = c1*E/N + c2*D/N + c3*W. neat.distance is
-- evo.neat's C when the state has it (the same arithmetic in the same
-- order: the same number to the last bit), else this.
function neat.distance_lua(a, b, o)
	local la, lb = a.links, b.links
	local i, j, na, nb = 1, 1, #la, #lb
	local matching, wdiff, disjoint = 0, 0.0, 0
	while i <= na and j <= nb do
		local x, y = la[i], lb[j]
		if x.innov == y.innov then
			matching = matching + 1
			wdiff = wdiff + math.abs(x.weight - y.weight)
			i, j = i + 1, j + 1
		elseif x.innov < y.innov then
			disjoint, i = disjoint + 1, i + 1
		else
			disjoint, j = disjoint + 1, j + 1
		end
	end
	local excess = (na - i + 1) + (nb - j + 1)
	local n = math.max(na, nb)
	if n < o.normalize_below then n = 1 end
	local w = matching > 0 and wdiff / matching or 0
	return o.c1 * excess / n + o.c2 * disjoint / n + o.c3 * w
end
neat.distance = fast and fast.distance or neat.distance_lua

-- Innovation registry: within one generation the same structural mutation
-- gets the same numbers. Links by (from, to); node splits by the innovation
-- of the link they split. Counters live in the population, the per-
-- generation maps are cleared by tell().
local function link_innovation(pop, from, to)
	local key = from .. ">" .. to
	local inn = pop.gen_links[key]
	if not inn then
		pop.next_innov = pop.next_innov + 1
		inn = pop.next_innov
		pop.gen_links[key] = inn
	end
	return inn
end

local function split_innovation(pop, link)
	local key = tostring(link.innov)
	local s = pop.gen_splits[key]
	if not s then
		pop.next_node = pop.next_node + 1
		s = { node = pop.next_node, inn_in = pop.next_innov + 1, inn_out = pop.next_innov + 2 }
		pop.next_innov = pop.next_innov + 2
		pop.gen_splits[key] = s
	end
	return s
end

-- Weight mutation. "paper": each weight is perturbed with perturb_prob,
-- else replaced. "code", as NEAT's original code does it
-- (Genome::mutate_link_weights): with severe_prob the mutation is severe
-- and each weight is perturbed with chance 0.7, replaced with 0.2 and
-- kept with 0.1; otherwise every weight is perturbed, except that in a
-- genome of 10 links or more the newest fifth (the links past 80% in
-- innovation order) is perturbed with 0.5, replaced with 0.2, kept with 0.3.
local function mutate_weights_lua(g, o, rng)
	local perturb, replace = o.perturb_prob, 1.0
	-- "code", not severe: the links past this index are the newest fifth
	local newest_after = math.huge
	if o.weight_mutation == "code" then
		local severe = rng:unit() < o.severe_prob
		perturb, replace = severe and 0.7 or 1.0, severe and 0.9 or 1.0
		if not severe and #g.links >= 10 then newest_after = #g.links * 0.8 end
	end
	for k, l in ipairs(g.links) do
		local p, r = perturb, replace
		if k - 1 > newest_after then p, r = 0.5, 0.7 end
		local u = rng:unit()
		if u < p then
			l.weight = clamp(l.weight + (rng:unit() * 2 - 1) * o.perturb_power, o.weight_max)
		elseif u < r then
			l.weight = clamp((rng:unit() * 2 - 1) * o.replace_power, o.weight_max)
		end
	end
end
-- evo.neat's C where the state has it: the same draws, the same weights.
local mutate_weights = fast and fast.mutate_weights or mutate_weights_lua
neat.mutate_weights, neat.mutate_weights_lua = mutate_weights, mutate_weights_lua

-- Does a path from `from` reach `to` over the genome's links (enabled or
-- not: a disabled link may come back through crossover)?
local function reaches(g, from, to)
	if type(g.links) ~= "table" then return fast.reaches(g, from, to) end
	if from == to then return true end
	local seen, stack = { [from] = true }, { from }
	while #stack > 0 do
		local n = table.remove(stack)
		for _, l in ipairs(g.links) do
			if l.from == n and not seen[l.to] then
				if l.to == to then return true end
				seen[l.to] = true
				stack[#stack + 1] = l.to
			end
		end
	end
	return false
end

-- Add a link between two unlinked nodes; without `recurrent`, only one that
-- keeps the genome acyclic. With `recurrent` and recur_only_prob above 0,
-- as in NEAT's original code, the mutation makes a link that closes a
-- cycle with that chance (a self-loop half the time) and one that does
-- not otherwise. Returns the new gene or nil.
function neat.mutate_add_link(pop, g, rng)
	local o = pop.options
	local nodes = g.nodes
	local graded = o.recurrent and o.recur_only_prob > 0
	local recur = graded and rng:unit() < o.recur_only_prob
	local targets = {} -- the nodes a self-loop may go round, needed only then
	if recur then
		for _, n in ipairs(nodes) do
			if n.kind ~= "input" and n.kind ~= "bias" then targets[#targets + 1] = n end
		end
	end
	for _ = 1, o.add_link_tries do
		local a, b
		if recur and rng:unit() < 0.5 then
			a = targets[1 + math.floor(rng:unit() * #targets)]
			b = a
		else
			a = nodes[1 + math.floor(rng:unit() * #nodes)]
			b = nodes[1 + math.floor(rng:unit() * #nodes)]
		end
		if b.kind ~= "input" and b.kind ~= "bias" then
			local exists = false
			for _, l in ipairs(g.links) do
				if l.from == a.id and l.to == b.id then exists = true break end
			end
			local ok
			if not o.recurrent then ok = not reaches(g, b.id, a.id)
			elseif graded then ok = reaches(g, b.id, a.id) == recur
			else ok = true end
			if not exists and ok then
				local l = { innov = link_innovation(pop, a.id, b.id), from = a.id, to = b.id,
					weight = clamp((rng:unit() * 2 - 1) * o.new_link_power, o.weight_max), enabled = true }
				add_gene(g, l)
				sort_genome(g)
				return l
			end
		end
	end
	return nil
end

-- Split an enabled link from->to: it is disabled, from->new gets weight 1
-- and new->to the old weight, so the network computes nearly the same.
-- Links from the bias node are not split unless split_bias is set: the new
-- node would only turn a constant into another constant. With
-- split_older, a genome of fewer than 15 links is walked oldest link
-- first, each candidate taken with chance 0.7 (none, at the end of the
-- walk: no mutation), as NEAT's original code does so that small genomes
-- do not keep splitting their newest links into chains.
function neat.mutate_add_node(pop, g, rng, link)
	if not link then
		local bias_id
		if not pop.options.split_bias then
			for _, n in ipairs(g.nodes) do
				if n.kind == "bias" then bias_id = n.id break end
			end
		end
		local enabled = {}
		for _, l in ipairs(g.links) do
			if l.enabled and l.from ~= bias_id then enabled[#enabled + 1] = l end
		end
		if #enabled == 0 then return nil end
		if pop.options.split_older and #g.links < 15 then
			for _, l in ipairs(enabled) do
				if rng:unit() < 0.7 then link = l break end
			end
			if not link then return nil end
		else
			link = enabled[1 + math.floor(rng:unit() * #enabled)]
		end
	end
	local s = split_innovation(pop, link)
	for _, n in ipairs(g.nodes) do
		if n.id == s.node then return nil end -- already split this generation
	end
	link.enabled = false
	g.nodes[#g.nodes + 1] = { id = s.node, kind = "hidden", act = pop.options.activation }
	add_gene(g, { innov = s.inn_in, from = link.from, to = s.node, weight = 1.0, enabled = true })
	add_gene(g, { innov = s.inn_out, from = s.node, to = link.to, weight = link.weight, enabled = true })
	sort_genome(g)
	return s.node
end

-- evo.neat's C where the state has it: the same draws, the same genes
-- and nodes, the same innovations (add-node with a link given stays Lua's).
neat.mutate_add_link_lua, neat.mutate_add_node_lua = neat.mutate_add_link, neat.mutate_add_node
if fast then
	neat.mutate_add_link = fast.add_link
	function neat.mutate_add_node(pop, g, rng, link)
		if link then return neat.mutate_add_node_lua(pop, g, rng, link) end
		return fast.add_node(pop, g, rng)
	end
end

-- NEAT's original code's toggle: a random link is switched on if it is
-- off, and off if it is on and its source feeds another enabled link (so
-- no node is cut off from the outputs by it).
function neat.mutate_toggle(g, rng)
	local n = #g.links
	if n == 0 then return end
	local l = g.links[1 + math.floor(rng:unit() * n)]
	if not l.enabled then
		l.enabled = true
		return
	end
	for _, other in ipairs(g.links) do
		if other ~= l and other.enabled and other.from == l.from then
			l.enabled = false
			return
		end
	end
end

-- NEAT's original code's re-enable: the first disabled link, in
-- innovation order, is switched back on.
function neat.mutate_reenable(g)
	for _, l in ipairs(g.links) do
		if not l.enabled then
			l.enabled = true
			return
		end
	end
end

-- One mutation step as NEAT's original code does it: a structural mutation,
-- else (maybe) the weights.
function neat.mutate_lua(pop, g, rng)
	local o = pop.options
	if rng:unit() < o.add_node_prob then
		neat.mutate_add_node(pop, g, rng)
	elseif rng:unit() < o.add_link_prob then
		neat.mutate_add_link(pop, g, rng)
	else
		if rng:unit() < o.weight_mut_prob then mutate_weights(g, o, rng) end
		if o.toggle_prob > 0 and rng:unit() < o.toggle_prob then neat.mutate_toggle(g, rng) end
		if o.reenable_prob > 0 and rng:unit() < o.reenable_prob then neat.mutate_reenable(g) end
	end
end
-- What a mutation does after its first draws, `what` as fast.mutate and
-- fast.breed say it: 1 an add-node mutation, 2 an add-link one, 0 (the
-- weights done) the toggle and re-enable draws.
local function mutate_rest(pop, g, rng, what)
	local o = pop.options
	if what == 1 then
		neat.mutate_add_node(pop, g, rng)
	elseif what == 2 then
		neat.mutate_add_link(pop, g, rng)
	else
		if o.toggle_prob > 0 and rng:unit() < o.toggle_prob then neat.mutate_toggle(g, rng) end
		if o.reenable_prob > 0 and rng:unit() < o.reenable_prob then neat.mutate_reenable(g) end
	end
end

-- evo.neat's C makes the first draws and the weight mutation (the same
-- draws, the same weights); the structural mutations stay Lua's.
if fast then
	function neat.mutate(pop, g, rng)
		mutate_rest(pop, g, rng, fast.mutate(g, pop.options, rng))
	end
else
	neat.mutate = neat.mutate_lua
end

-- Crossover: genes aligned by innovation; matching genes from either parent
-- at random, disabled with probability disable_prob when disabled in
-- either; disjoint and excess genes from the fitter parent, as they are
-- there. On equal fitness, with tie_smaller (NEAT's original code) the
-- parent with fewer links counts as the fitter; without it (the paper)
-- the disjoint and excess genes of both are inherited at random.
function neat.crossover_lua(a, fa, b, fb, o, rng)
	if fb > fa then a, fa, b, fb = b, fb, a, fa end
	local equal = fa == fb
	if equal and o.tie_smaller then
		if #b.links < #a.links then a, b = b, a end
		equal = false
	end
	-- NEAT's original code averages the matching weights in 40% of its
	-- crossovers (mate_multipoint_avg) and picks one parent's in the rest.
	local average = rng:unit() < (o.mate_avg_prob or 0)
	local child = { nodes = {}, links = {} }
	local bl = {}
	for _, l in ipairs(b.links) do bl[l.innov] = l end
	local al = {}
	for _, l in ipairs(a.links) do al[l.innov] = l end
	local function add(l, disabled_somewhere)
		local c = { innov = l.innov, from = l.from, to = l.to, weight = l.weight, enabled = l.enabled }
		if disabled_somewhere then c.enabled = rng:unit() >= o.disable_prob end
		child.links[#child.links + 1] = c
	end
	for _, l in ipairs(a.links) do
		local m = bl[l.innov]
		if m then
			local pick = rng:unit() < 0.5 and l or m
			add(pick, not l.enabled or not m.enabled)
			if average then child.links[#child.links].weight = (l.weight + m.weight) / 2 end
		elseif not equal or rng:unit() < 0.5 then
			add(l, false)
		end
	end
	if equal then
		for _, l in ipairs(b.links) do
			if not al[l.innov] and rng:unit() < 0.5 then
				-- Genes of two acyclic parents may close a cycle together.
				if o.recurrent or not reaches(child, l.to, l.from) then add(l, false) end
			end
		end
	end
	-- Nodes: all of the fitter parent's, then any the child's links need.
	local have = {}
	for _, n in ipairs(a.nodes) do
		child.nodes[#child.nodes + 1] = copy_node(n)
		have[n.id] = true
	end
	for _, n in ipairs(b.nodes) do
		if not have[n.id] then
			for _, l in ipairs(child.links) do
				if l.from == n.id or l.to == n.id then
					child.nodes[#child.nodes + 1] = copy_node(n)
					have[n.id] = true
					break
				end
			end
		end
	end
	sort_genome(child)
	return child
end

-- neat.crossover is evo.neat's C where the state has it (the same draws,
-- the same child), except for parents of equal fitness without
-- tie_smaller, which stay with the Lua above.
if fast then
	function neat.crossover(a, fa, b, fb, o, rng)
		return fast.crossover(a, fa, b, fb, o, rng) or own_genes(neat.crossover_lua(a, fa, b, fb, o, rng))
	end
else
	neat.crossover = neat.crossover_lua
end

---------------------------------------------------------------------------
-- Population

-- n children of one species appended to `children`: each of a parent
-- drawn among the `parents` first of `sorted` (the species' members,
-- fittest first), a mutated copy or a crossover with a mate, the mate
-- from another species of `alive` (genomes of `popl`) once in a while.
function neat.breed_lua(pop, children, sorted, n, parents, alive, popl)
	local o, rng = pop.options, pop.rng
	for _ = 1, n do
		local p1 = sorted[1 + math.floor(rng:unit() * parents)]
		local child
		-- A lone parent can only mate with itself: mutate it instead.
		if parents == 1 or rng:unit() < o.mutate_only_prob then
			child = copy_genome(p1)
			neat.mutate(pop, child, rng)
		else
			local p2
			if rng:unit() < o.interspecies_prob and #alive > 1 then
				local other = alive[1 + math.floor(rng:unit() * #alive)]
				p2 = popl[other.members[1 + math.floor(rng:unit() * #other.members)]]
			else
				p2 = sorted[1 + math.floor(rng:unit() * parents)]
			end
			child = neat.crossover(p1, p1.fitness, p2, p2.fitness, o, rng)
			-- A child of one genome with itself (or a twin) is a copy:
			-- it is always mutated, as in NEAT's original code.
			if rng:unit() >= o.mate_only_prob or p1 == p2 or neat.distance(p1, p2, o) == 0 then
				neat.mutate(pop, child, rng)
			end
		end
		children[#children + 1] = child
	end
end
-- evo.neat's C where the state has it: the same draws in the same order,
-- the same children (the structural mutations still Lua's); the paper's
-- crossover of equals (tie_smaller off) stays with breed_lua.
if fast then
	function neat.breed(pop, children, sorted, n, parents, alive, popl)
		if pop.options.tie_smaller then
			fast.breed(pop, children, sorted, n, parents, alive, popl, mutate_rest)
		else
			neat.breed_lua(pop, children, sorted, n, parents, alive, popl)
		end
	end
else
	neat.breed = neat.breed_lua
end

local Pop = {}
Pop.__index = Pop

local function merged_options(user)
	local o = {}
	for k, v in pairs(neat.defaults) do o[k] = v end
	for k, v in pairs(user or {}) do
		if neat.defaults[k] == nil then error("neat: unknown option '" .. tostring(k) .. "'", 2) end
		o[k] = v
	end
	return o
end

-- Assign genomes to species: the first species (in id order) whose
-- representative from the previous generation is within the threshold;
-- otherwise a new species with this genome as representative. Empty
-- species disappear.
local function speciate(pop)
	local o = pop.options
	local threshold = pop.threshold or o.threshold
	for _, s in ipairs(pop.species) do s.members = {} end
	-- evo.neat's C where the state has it: each genome's species number
	-- (a new one past the last for a genome that opens a species), found
	-- with the same distances in the same order, the new species made in
	-- the order they were opened, then the members and each genome's
	-- species as the loop below gives them
	if fast and neat.distance == fast.distance then
		local reps = {}
		for k, s in ipairs(pop.species) do reps[k] = s.rep end
		local homes, opened = fast.speciate(pop.population, reps, o, threshold)
		for _, gi in ipairs(opened) do
			pop.next_species = pop.next_species + 1
			pop.species[#pop.species + 1] = { id = pop.next_species, rep = copy_genome(pop.population[gi]),
				members = {}, best_fitness = -math.huge, last_improved = pop.generation,
				created = pop.generation }
		end
		fast.assign(pop.species, homes, pop.population)
	else
		for gi, g in ipairs(pop.population) do
			local home
			for _, s in ipairs(pop.species) do
				if neat.distance(g, s.rep, o) < threshold then home = s break end
			end
			if not home then
				pop.next_species = pop.next_species + 1
				home = { id = pop.next_species, rep = copy_genome(g), members = {},
					best_fitness = -math.huge, last_improved = pop.generation, created = pop.generation }
				pop.species[#pop.species + 1] = home
			end
			home.members[#home.members + 1] = gi
			g.species = home.id
		end
	end
	local kept = {}
	for _, s in ipairs(pop.species) do
		if #s.members > 0 then kept[#kept + 1] = s end
	end
	pop.species = kept
	-- Without rep_champion, the next generation is compared to a random
	-- member of this one (with it, tell() sets each species' champion).
	if not o.rep_champion then
		for _, s in ipairs(pop.species) do
			s.rep = copy_genome(pop.population[s.members[1 + math.floor(pop.rng:unit() * #s.members)]])
		end
	end
end
neat.speciate = speciate

function neat.new(args)
	local o = merged_options(args.options)
	local n, m = args.inputs, args.outputs
	assert(math.tointeger(n) and n >= 0 and math.tointeger(m) and m >= 1, "neat.new: inputs >= 0, outputs >= 1")
	local rng = args.rng or error("neat.new: an rng is required (learn.rng: random.new(seed))")
	local pop = setmetatable({
		options = o, inputs = n, outputs = m, rng = rng, generation = 0,
		next_innov = 0, next_node = n + m, next_species = 0,
		gen_links = {}, gen_splits = {}, species = {}, population = {},
		best = nil, evaluations = 0,
	}, Pop)
	-- The paper's start: every input and the bias linked to every output,
	-- no hidden node, random weights; the same innovation numbers in all.
	for i = 1, o.pop_size do
		local g = { nodes = {}, links = {} }
		for id = 0, n - 1 do g.nodes[#g.nodes + 1] = { id = id, kind = "input" } end
		g.nodes[#g.nodes + 1] = { id = n, kind = "bias", value = o.bias_input }
		for k = 1, m do g.nodes[#g.nodes + 1] = { id = n + k, kind = "output", act = o.activation } end
		local inn = 0
		for k = 1, m do
			for from = 0, n do
				inn = inn + 1
				g.links[#g.links + 1] = { innov = inn, from = from, to = n + k,
					weight = clamp((rng:unit() * 2 - 1) * o.init_power, o.weight_max), enabled = true }
			end
		end
		pop.population[i] = own_genes(g)
	end
	pop.next_innov = (n + 1) * m
	speciate(pop)
	return pop
end

-- The genomes of the current generation, to evaluate in this order.
function Pop:genomes() return self.population end

-- The genome of this generation to put through a costly success test
-- (DPNV's 100,000 steps and generalisation), picked as NEAT's original code
-- picks it: the champion of the best species whose best fitness rose above
-- its previous best since its champion was last tested; when every species
-- has been tested, the best species' champion. A species whose champion
-- failed is not tested again until it improves, so a plateau does not test
-- the same genome every generation. `fitness` is this generation's, in
-- genomes() order.
function Pop:test_candidate(fitness)
	local entries = {}
	for _, s in ipairs(self.species) do
		local champ
		for _, gi in ipairs(s.members) do
			if not champ or fitness[gi] > fitness[champ] then champ = gi end
		end
		if fitness[champ] > s.best_fitness then s.tested = false end
		entries[#entries + 1] = { s = s, champ = champ, f = fitness[champ] }
	end
	table.sort(entries, function(a, b)
		if a.f ~= b.f then return a.f > b.f end
		return a.s.id < b.s.id
	end)
	local pick = entries[1]
	for _, e in ipairs(entries) do
		if not e.s.tested then pick = e break end
	end
	pick.s.tested = true
	return pick.champ
end

-- Offspring per species in proportion to its summed adjusted fitness
-- (fitness / species size), rounded by largest remainder so the counts sum
-- to exactly `total`. `shares` are non-negative numbers.
function neat.allot(shares, total)
	local sum = 0
	for _, s in ipairs(shares) do sum = sum + s end
	local counts, rems, given = {}, {}, 0
	for i, s in ipairs(shares) do
		local exact = sum > 0 and s / sum * total or total / #shares
		counts[i] = math.floor(exact)
		rems[i] = exact - counts[i]
		given = given + counts[i]
	end
	local order = {}
	for i = 1, #shares do order[i] = i end
	table.sort(order, function(x, y)
		if rems[x] ~= rems[y] then return rems[x] > rems[y] end
		return x < y
	end)
	for k = 1, total - given do
		local i = order[(k - 1) % #order + 1]
		counts[i] = counts[i] + 1
	end
	return counts
end

-- Advance one generation given the fitness of each genome of genomes().
function Pop:tell(fitness)
	self:note_best(fitness)
	self:reproduce(fitness)
end

-- Keep self.best, the best genome ever seen by `fitness` (one number per
-- genome of genomes()).
function Pop:note_best(fitness)
	local popl = self.population
	assert(#fitness == #popl, "tell: one fitness per genome")
	if fast then
		-- the genome the loop below would copy last, copied once
		local i = fast.best_of(fitness, self.best and self.best.fitness)
		if i then
			self.best = { genome = copy_genome(popl[i]), fitness = fitness[i], generation = self.generation }
		end
		return
	end
	for i, g in ipairs(popl) do
		local f = fitness[i]
		assert(type(f) == "number" and f == f, "tell: fitness must be a number")
		if not self.best or f > self.best.fitness then
			self.best = { genome = copy_genome(g), fitness = f, generation = self.generation }
		end
	end
end

-- The next generation, bred by `score` (one number per genome of
-- genomes(), higher is better): NEAT's selection, speciation and
-- reproduction. tell breeds by fitness; learn.novelty by novelty.
function Pop:reproduce(score)
	local o, rng, popl = self.options, self.rng, self.population
	assert(#score == #popl, "tell: one fitness per genome")
	self.evaluations = self.evaluations + #popl
	-- each genome's fitness, the least, and each species' most
	local minf, most
	if fast then
		minf, most = fast.tally(popl, score, self.species)
	else
		minf, most = math.huge, {}
		for i, g in ipairs(popl) do
			local f = score[i]
			assert(type(f) == "number" and f == f, "tell: fitness must be a number")
			g.fitness = f
			if f < minf then minf = f end
		end
		for k, s in ipairs(self.species) do
			local smax = -math.huge
			for _, gi in ipairs(s.members) do smax = math.max(smax, popl[gi].fitness) end
			most[k] = smax
		end
	end
	local shift = minf < 0 and -minf or 0
	local nspecies = #self.species

	-- Stagnation, and the species that holds the best genome of this
	-- generation (it is never dropped).
	local best_species, best_f = nil, -math.huge
	local smaxes = {}
	for k, s in ipairs(self.species) do
		local smax = most[k]
		if smax > s.best_fitness then s.best_fitness, s.last_improved = smax, self.generation end
		if smax > best_f then best_species, best_f = s, smax end
		smaxes[s] = smax
	end
	local alive, stagnant = {}, {}
	for _, s in ipairs(self.species) do
		local stale = s ~= best_species and self.generation - s.last_improved >= o.stagnation
		if not stale or o.stagnation_penalty > 0 then
			alive[#alive + 1] = s
			stagnant[#alive] = stale
		end
	end

	-- Explicit fitness sharing: adjusted fitness = fitness / species size.
	local shares = fast and fast.share(popl, alive, shift) or {}
	for i, s in ipairs(alive) do
		local sum = shares[i]
		if not fast then
			sum = 0
			for _, gi in ipairs(s.members) do
				local g = popl[gi]
				g.adjusted = (g.fitness + shift) / #s.members
				sum = sum + g.adjusted
			end
		end
		shares[i] = stagnant[i] and sum * o.stagnation_penalty or sum
	end
	local counts = neat.allot(shares, o.pop_size)
	-- The species of the generation's best genome gets at least one
	-- offspring, so the champion copy below has a place.
	local best_alive
	for i, s in ipairs(alive) do
		if s == best_species then best_alive = i end
	end
	if o.pop_champion and best_alive and counts[best_alive] == 0 then
		local big = 1
		for i = 2, #counts do
			if counts[i] > counts[big] then big = i end
		end
		counts[big], counts[best_alive] = counts[big] - 1, 1
	end
	-- The paper's population-wide stagnation: when the best fitness has not
	-- improved for pop_stagnation generations, only the two species with
	-- the best genomes reproduce, half the population each; then the count
	-- starts again (NEAT's original code resets it the same way).
	local clones = {}
	local since = math.max(self.best.generation, self.dropoff_generation or -1)
	if o.pop_stagnation > 0 and self.generation - since >= o.pop_stagnation and #alive > 1 then
		self.dropoff_generation = self.generation
		local order = {}
		for i = 1, #alive do order[i] = i end
		table.sort(order, function(x, y)
			if smaxes[alive[x]] ~= smaxes[alive[y]] then return smaxes[alive[x]] > smaxes[alive[y]] end
			return x < y
		end)
		for i = 1, #alive do counts[i] = 0 end
		counts[order[1]] = o.pop_size - o.pop_size // 2
		counts[order[2]] = o.pop_size // 2
		if o.delta_coding then
			clones = { [order[1]] = true, [order[2]] = true }
			alive[order[1]].last_improved = self.generation
			alive[order[2]].last_improved = self.generation
		end
	end
	-- What the last generation decided, for logs and tests.
	self.last_counts, self.last_alive = counts, {}
	for i, s in ipairs(alive) do self.last_alive[i] = s.id end

	-- Reproduce.
	self.gen_links, self.gen_splits = {}, {}
	local children = {}
	for si, s in ipairs(alive) do
		-- Fittest first; equal fitness in random order. Fixed-point
		-- outputs saturate to exact values, so ties are common (XOR's
		-- networks that get three cases right score exactly 9), and a
		-- fixed order would make the same few genomes parents every time.
		local sorted
		if fast then
			-- the same draws and the same order, in C
			sorted = fast.ranked(popl, s.members, rng)
		else
			local members, idx, key = {}, {}, {}
			for k, gi in ipairs(s.members) do members[k] = popl[gi] end
			for k = 1, #members do idx[k], key[k] = k, rng:unit() end
			table.sort(idx, function(x, y)
				if members[x].fitness ~= members[y].fitness then return members[x].fitness > members[y].fitness end
				if key[x] ~= key[y] then return key[x] < key[y] end
				return x < y
			end)
			sorted = {}
			for k, x in ipairs(idx) do sorted[k] = members[x] end
		end
		if o.rep_champion then s.rep = copy_genome(sorted[1]) end
		local n = counts[si]
		if clones[si] then
			-- Delta coding: the champion's neighbourhood, the champion last.
			for k = 1, n do
				local child = copy_genome(sorted[1])
				if k < n then
					if rng:unit() < 0.8 then
						mutate_weights(child, o, rng)
					else
						neat.mutate_add_link(self, child, rng)
					end
				end
				children[#children + 1] = child
			end
			n = 0
		elseif n > 0 and (n > o.elitism_offspring or (o.pop_champion and s == best_species)) then
			children[#children + 1] = copy_genome(sorted[1])
			n = n - 1
		end
		-- The parents: the top survival fraction, floor(survival * n) + 1 as
		-- NEAT's original code counts them (so a species of 5 has 2).
		local parents = math.min(#sorted, math.floor(#sorted * o.survival) + 1)
		if n > 0 then neat.breed(self, children, sorted, n, parents, alive, popl) end
	end
	self.species = alive
	self.population = children
	self.generation = self.generation + 1
	-- NEAT 1.2's compat_adjust: move the threshold towards target_species,
	-- judged on the species of the generation just evaluated.
	if o.target_species > 0 then
		local t = self.threshold or o.threshold
		if nspecies < o.target_species then
			t = math.max(o.threshold_min, t - o.threshold_step)
		elseif nspecies > o.target_species then
			t = t + o.threshold_step
		end
		self.threshold = t
	end
	speciate(self)
end

-- Summary numbers for a log line.
function Pop:stats()
	return { generation = self.generation, species = #self.species, evaluations = self.evaluations,
		best = self.best and self.best.fitness }
end

---------------------------------------------------------------------------
-- Checkpoints: a plain table (numbers, strings, booleans, tables) with the
-- whole state, the rng's included. Format 2 came with NEAT's original
-- code's options (elitism_offspring and the rest): a checkpoint of format 1
-- would resume a different algorithm, so it is refused.

-- `shared`: see common.save.
function neat.save(pop, shared)
	return common.save(pop, "evo-neat-2", shared)
end

-- The reverse of neat.save. Give `rng` to use another rng object (its
-- state is then the caller's business); by default learn.rng's
-- load(t.rng).
function neat.load(t, rng)
	local pop = common.load(t, "evo-neat-2", Pop, rng, random.load)
	for _, g in ipairs(pop.population) do own_genes(g) end
	for _, s in ipairs(pop.species) do
		if s.rep then own_genes(s.rep) end
	end
	if pop.best then own_genes(pop.best.genome) end
	return pop
end

---------------------------------------------------------------------------
-- Networks in evo's .net shape

-- Genome -> network. Ids: 0..n-1 the inputs, n..n+m-1 the outputs in order,
-- then the hidden nodes in id order (renumbered so ids stay small whatever
-- the node counter reached). Disabled links are left out; links from the
-- bias node become node biases (weight times the bias node's input value).
function neat.to_net(g)
	local n, m = 0, 0
	local bias_id, bias_value
	for _, nd in ipairs(g.nodes) do
		if nd.kind == "input" then n = n + 1
		elseif nd.kind == "output" then m = m + 1
		elseif nd.kind == "bias" then bias_id, bias_value = nd.id, nd.value or 1.0 end
	end
	local map, nodes, outputs_ids = {}, {}, {}
	for _, nd in ipairs(g.nodes) do
		if nd.kind == "input" then map[nd.id] = nd.id end
	end
	local next_id = n
	for _, nd in ipairs(g.nodes) do
		if nd.kind == "output" then
			map[nd.id] = next_id
			nodes[#nodes + 1] = { id = next_id, act = nd.act, bias = 0.0 }
			outputs_ids[#outputs_ids + 1] = next_id
			next_id = next_id + 1
		end
	end
	for _, nd in ipairs(g.nodes) do
		if nd.kind == "hidden" then
			map[nd.id] = next_id
			nodes[#nodes + 1] = { id = next_id, act = nd.act, bias = 0.0 }
			next_id = next_id + 1
		end
	end
	local by_id = {}
	for _, nd in ipairs(nodes) do by_id[nd.id] = nd end
	local links = {}
	for _, l in ipairs(g.links) do
		if l.enabled then
			if l.from == bias_id then
				local nd = by_id[map[l.to]]
				nd.bias = nd.bias + l.weight * bias_value
			else
				links[#links + 1] = { from = map[l.from], to = map[l.to], weight = l.weight }
			end
		end
	end
	return { inputs = n, outputs = m, nodes = nodes, outputs_ids = outputs_ids, links = links }
end

-- evo.neat's C where the state has it: the same table.
neat.to_net_lua = neat.to_net
if fast then neat.to_net = fast.to_net end

-- neat.pack_net(g): the network neat.to_net(g) gives, packed for
-- evo.evaluate (a userdata; only evaluate, success_test and set_team_net
-- read it). Present only where evo.neat is.
neat.pack_net = fast and fast.pack_net

-- The network as .net text (learn.netfile), as every method writes it.
neat.to_net_text = netfile.text

-- Evaluation order as evo_net_compile computes it (docs/fixed-point.md):
-- depth-first from each output, sources in the listing order of their
-- links, post-order; a source on the search path closes a cycle; nodes no
-- output needs come last in listing order.
local function compile(net)
	local incoming = {}
	for _, nd in ipairs(net.nodes) do incoming[nd.id] = {} end
	for _, l in ipairs(net.links) do table.insert(incoming[l.to], l) end
	local placed, on_path, order = {}, {}, {}
	local function visit(id)
		if id < net.inputs or placed[id] or on_path[id] then return end
		on_path[id] = true
		for _, l in ipairs(incoming[id]) do visit(l.from) end
		on_path[id] = nil
		placed[id] = true
		order[#order + 1] = id
	end
	for _, id in ipairs(net.outputs_ids) do visit(id) end
	for _, nd in ipairs(net.nodes) do
		if not placed[nd.id] then placed[nd.id] = true; order[#order + 1] = nd.id end
	end
	local by_id = {}
	for _, nd in ipairs(net.nodes) do by_id[nd.id] = nd end
	local steps = {}
	for k, id in ipairs(order) do
		local nd = by_id[id]
		steps[k] = { id = id, bias = nd.bias, f = ACTIVATIONS[nd.act] or error("unknown activation " .. nd.act),
			links = incoming[id] }
	end
	return steps
end

local compiled = setmetatable({}, { __mode = "k" })

-- Evaluate a network in floating point, the way evo's C core does in Q16
-- (for tests; no rounding). `act` is the network's memory: pass the same
-- table on every step of an episode for recurrent networks (absent: a
-- fresh zeroed one). Returns the outputs and `act`.
function neat.eval_float(net, inputs, act)
	local steps = compiled[net]
	if not steps then steps = compile(net); compiled[net] = steps end
	act = act or {}
	for i = 1, net.inputs do act[i - 1] = inputs[i] end
	for _, st in ipairs(steps) do
		local sum = st.bias
		for _, l in ipairs(st.links) do sum = sum + l.weight * (act[l.from] or 0) end
		act[st.id] = st.f(sum)
	end
	local out = {}
	for k, id in ipairs(net.outputs_ids) do out[k] = act[id] end
	return out, act
end

neat.activations = ACTIVATIONS
-- The population's methods, for a method built on NEAT's (learn.novelty).
neat.Pop = Pop
return neat

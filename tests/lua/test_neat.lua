-- Unit tests of lua/learn/neat.lua, run by tests/sim/lua/test_lua_scripts.c.
-- Each entry of the returned table is one test; it fails by raising.
local neat = require "learn.neat"
local random = require "learn.rng"

-- Raise with the caller's file:line so the runner can show where.
local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local function near(a, b, eps) return math.abs(a - b) <= (eps or 1e-9) end

-- A genome by hand: n inputs (ids 0..n-1), bias n, outputs, hidden ids and
-- links { innov, from, to, weight, enabled? }.
local function genome(n, outputs, hidden, links)
	local g = { nodes = {}, links = {} }
	for id = 0, n - 1 do g.nodes[#g.nodes + 1] = { id = id, kind = "input" } end
	g.nodes[#g.nodes + 1] = { id = n, kind = "bias" }
	for _, id in ipairs(outputs) do g.nodes[#g.nodes + 1] = { id = id, kind = "output", act = "neat_sigmoid" } end
	for _, id in ipairs(hidden or {}) do g.nodes[#g.nodes + 1] = { id = id, kind = "hidden", act = "neat_sigmoid" } end
	for _, l in ipairs(links) do
		g.links[#g.links + 1] = { innov = l[1], from = l[2], to = l[3], weight = l[4], enabled = l[5] ~= false }
	end
	return g
end

-- NEAT's defaults with some changed.
local function options(t)
	local o = {}
	for k, v in pairs(neat.defaults) do o[k] = v end
	for k, v in pairs(t) do o[k] = v end
	return o
end

local function innovs(g)
	local t = {}
	for i, l in ipairs(g.links) do t[i] = l.innov end
	return table.concat(t, ",")
end

-- Genes as plain data: evo.neat keeps a genome's genes in a userdata,
-- compared and written out as the list of gene tables it stands for.
local function plain(v)
	local mt = type(v) == "userdata" and getmetatable(v)
	if mt and mt.__plain then return mt.__plain(v) end
	return v
end

local function deep_equal(a, b)
	a, b = plain(a), plain(b)
	if type(a) ~= type(b) then return false end
	if type(a) ~= "table" then return a == b or (a ~= a and b ~= b) end
	for k, v in pairs(a) do
		if not deep_equal(v, b[k]) then return false end
	end
	for k in pairs(b) do
		if a[k] == nil then return false end
	end
	return true
end

-- Two parents with matching genes 1, 2, disjoint 3, 4, 5 and excess 6, 7.
-- Inputs 0, 1, bias 2, output 3, hidden 4, 5.
local function parents()
	local a = genome(2, { 3 }, { 4 }, {
		{ 1, 0, 3, 1.1 }, { 2, 1, 3, 1.2 }, { 3, 2, 3, 1.3 }, { 5, 0, 4, 1.5 } })
	local b = genome(2, { 3 }, { 5 }, {
		{ 1, 0, 3, 2.1 }, { 2, 1, 3, 2.2 }, { 4, 1, 5, 2.4 }, { 6, 5, 3, 2.6 }, { 7, 2, 5, 2.7 } })
	return a, b
end

-- XOR with the float evaluator; fitness (4 - sum |err|)^2.
local XOR = { { 0, 0, 0 }, { 0, 1, 1 }, { 1, 0, 1 }, { 1, 1, 0 } }
local function xor_fitness(g)
	local net = neat.to_net(g)
	local err, solved = 0, true
	for _, c in ipairs(XOR) do
		local out = neat.eval_float(net, { c[1], c[2] })[1]
		err = err + math.abs(out - c[3])
		if (out > 0.5) ~= (c[3] == 1) then solved = false end
	end
	return (4 - err) ^ 2, solved
end

local function run_xor(seed, generations)
	local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(seed) }
	for gen = 1, generations do
		local fit, done = {}, false
		for i, g in ipairs(pop:genomes()) do
			local f, ok = xor_fitness(g)
			fit[i] = f
			if ok then done = true end
		end
		if done then
			-- Evaluations up to and including this generation.
			return gen, pop.evaluations + #fit, pop
		end
		pop:tell(fit)
	end
	return nil, pop.evaluations, pop
end

local T = {}

function T.crossover_aligns_matching_genes()
	local a, b = parents()
	local o = {}
	for k, v in pairs(neat.defaults) do o[k] = v end
	o.mate_avg_prob = 0
	local from_a, from_b = 0, 0
	local rng = random.new(1)
	for _ = 1, 200 do
		local c = neat.crossover(a, 10, b, 5, o, rng)
		check(innovs(c) == "1,2,3,5", "child genes by innovation: " .. innovs(c))
		for k = 1, 2 do
			local l = c.links[k]
			check(l.from == a.links[k].from and l.to == a.links[k].to, "matching gene keeps its ends")
			if l.weight == a.links[k].weight then from_a = from_a + 1
			elseif l.weight == b.links[k].weight then from_b = from_b + 1
			else check(false, "matching gene weight from neither parent") end
		end
	end
	check(from_a > 150 and from_b > 150, "matching genes from either parent at random")
	-- mate_avg_prob: the matching weights averaged instead.
	o.mate_avg_prob = 1
	local c = neat.crossover(a, 10, b, 5, o, rng)
	check(near(c.links[1].weight, 1.6) and near(c.links[2].weight, 1.7), "matching weights averaged")
end

function T.disjoint_and_excess_come_from_the_fitter_parent()
	local a, b = parents()
	local rng = random.new(2)
	for _ = 1, 50 do
		local c = neat.crossover(a, 1, b, 9, neat.defaults, rng)
		check(innovs(c) == "1,2,4,6,7", "b fitter: b's structure, got " .. innovs(c))
		local ids = {}
		for _, n in ipairs(c.nodes) do ids[#ids + 1] = n.id end
		check(table.concat(ids, ",") == "0,1,2,3,5", "b's nodes")
		c = neat.crossover(a, 9, b, 1, neat.defaults, rng)
		check(innovs(c) == "1,2,3,5", "a fitter: a's structure")
	end
end

function T.gene_disabled_in_a_parent_is_disabled_75_percent()
	local a, b = parents()
	a.links[1].enabled = false
	local rng, off = random.new(3), 0
	for _ = 1, 4000 do
		if not neat.crossover(a, 10, b, 5, neat.defaults, rng).links[1].enabled then off = off + 1 end
	end
	check(math.abs(off / 4000 - 0.75) < 0.03, "disabled in " .. off .. " of 4000")
end

function T.same_mutation_same_generation_same_innovation()
	local pop = neat.new { inputs = 1, outputs = 1, rng = random.new(4), options = { pop_size = 4, add_link_tries = 1000 } }
	-- Input 0, bias 1, output 2, hidden 3: the only new acyclic link is 1->3.
	local base = genome(1, { 2 }, { 3 }, { { 1, 0, 2, 0.5 }, { 2, 1, 2, 0.5 }, { 3, 0, 3, 0.5 }, { 4, 3, 2, 0.5 } })
	pop.next_innov, pop.next_node = 4, 3
	local g1, g2 = neat.copy_genome(base), neat.copy_genome(base)
	local l1 = neat.mutate_add_link(pop, g1, pop.rng)
	local l2 = neat.mutate_add_link(pop, g2, pop.rng)
	check(l1 and l2 and l1.from == 1 and l1.to == 3, "the only possible link")
	check(l1.innov == 5 and l2.innov == 5, "one innovation number for both")
	local n1 = neat.mutate_add_node(pop, g1, pop.rng, g1.links[1])
	local n2 = neat.mutate_add_node(pop, g2, pop.rng, g2.links[1])
	check(n1 == 4 and n2 == 4, "one node id for the same split")
	check(innovs(g1) == innovs(g2) and innovs(g1) == "1,2,3,4,5,6,7", "same split innovations: " .. innovs(g1))
	-- A new generation: the same mutation is a new innovation.
	pop.gen_links, pop.gen_splits = {}, {}
	local g3 = neat.copy_genome(base)
	check(neat.mutate_add_link(pop, g3, pop.rng).innov == 8, "next generation, next number")
	check(neat.mutate_add_node(pop, g3, pop.rng, g3.links[1]) == 5, "next generation, next node")
end

function T.add_node_splits_a_link()
	local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(5), options = { pop_size = 2 } }
	local g = neat.copy_genome(pop:genomes()[1])
	local old = g.links[2] -- 1 -> 3
	local w = old.weight
	local id = neat.mutate_add_node(pop, g, pop.rng, old)
	check(id == 4, "first hidden id after inputs, bias and output")
	check(not old.enabled, "the split link is disabled")
	local a, b
	for _, l in ipairs(g.links) do
		if l.to == id then a = l end
		if l.from == id then b = l end
	end
	check(a.from == 1 and a.weight == 1.0 and a.enabled, "in -> new with weight 1")
	check(b.to == 3 and b.weight == w and b.enabled, "new -> out with the old weight")
	check(a.innov == 4 and b.innov == 5, "two new innovations")
end

function T.add_node_leaves_the_bias_links_alone()
	-- A new node on a bias link would only be a constant: by default
	-- add-node splits the input links and never the bias one.
	local function splits_of_bias(split_bias)
		local pop = neat.new { inputs = 1, outputs = 1, rng = random.new(17),
			options = { pop_size = 2, split_bias = split_bias, split_older = false } }
		local bias = 0
		for _ = 1, 200 do
			local g = neat.copy_genome(pop:genomes()[1]) -- links 0->2 and bias 1->2
			pop.gen_splits = {}
			neat.mutate_add_node(pop, g, pop.rng)
			for _, l in ipairs(g.links) do
				if l.from == 1 and not l.enabled then bias = bias + 1 end
			end
		end
		return bias
	end
	check(splits_of_bias(false) == 0, "the bias link is never split")
	local n = splits_of_bias(true)
	check(n > 60 and n < 140, "with NEAT_SPLIT_BIAS, half the splits: " .. n)
end

function T.new_link_power_sets_the_range_of_added_links()
	local function widest(power)
		local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(18),
			options = { pop_size = 2, new_link_power = power, recurrent = true, add_link_tries = 1000 } }
		local w = 0
		for _ = 1, 100 do
			local g = neat.copy_genome(pop:genomes()[1])
			local l = neat.mutate_add_link(pop, g, pop.rng) -- the only free link: 3 -> 3
			w = math.max(w, math.abs(l.weight))
		end
		return w
	end
	check(widest(0.5) <= 0.5, "within +-0.5")
	check(widest(4) > 3, "up to +-4")
end

function T.weight_mutation_as_neat_code_does_it()
	-- 20 links: the newest fifth is the links past 80%, places 18 to 20
	-- (NEAT's code counts from 0 and takes those above 0.8 * 20).
	local function kept_fractions(severe_prob)
		local rng = random.new(21)
		local o = { weight_mutation = "code", severe_prob = severe_prob, perturb_power = 1,
			replace_power = 1, weight_max = 8 }
		local head, tail, trials = 0, 0, 2000
		for _ = 1, trials do
			local g = { links = {} }
			for k = 1, 20 do g.links[k] = { innov = k, from = 0, to = 1, weight = 0.5, enabled = true } end
			neat.mutate_weights(g, o, rng)
			for k, l in ipairs(g.links) do
				if l.weight == 0.5 then
					if k <= 17 then head = head + 1 else tail = tail + 1 end
				end
			end
		end
		return head / (17 * trials), tail / (3 * trials)
	end
	local head, tail = kept_fractions(0)
	check(head == 0, "a mild mutation changes every older weight: " .. head)
	check(math.abs(tail - 0.3) < 0.02, "and keeps 30% of the newest fifth: " .. tail)
	head, tail = kept_fractions(1)
	check(math.abs(head - 0.1) < 0.01 and math.abs(tail - 0.1) < 0.02,
		"a severe one keeps 10% everywhere: " .. head .. ", " .. tail)
	-- "paper": perturbed or replaced, never kept.
	local g = { links = {} }
	for k = 1, 20 do g.links[k] = { innov = k, from = 0, to = 1, weight = 0.5, enabled = true } end
	neat.mutate_weights(g, { weight_mutation = "paper", perturb_prob = 0.9, perturb_power = 1,
		replace_power = 1, weight_max = 8 }, random.new(22))
	for _, l in ipairs(g.links) do check(l.weight ~= 0.5, "paper: every weight changes") end
end

function T.add_node_prefers_older_links_in_small_genomes()
	-- Three input links and a bias link: walked oldest first, each taken
	-- with chance 0.7, so 70%, 21%, 6.3%, and 2.7% no split.
	local function picks(older)
		local pop = neat.new { inputs = 3, outputs = 1, rng = random.new(23),
			options = { pop_size = 2, split_older = older } }
		local n = { 0, 0, 0, 0 }
		for _ = 1, 4000 do
			local g = neat.copy_genome(pop:genomes()[1])
			pop.gen_splits = {}
			local k = 4
			if neat.mutate_add_node(pop, g, pop.rng) then
				for i = 1, 3 do
					if not g.links[i].enabled then k = i end
				end
			end
			n[k] = n[k] + 1
		end
		return n
	end
	local n = picks(true)
	check(math.abs(n[1] / 4000 - 0.7) < 0.03 and math.abs(n[2] / 4000 - 0.21) < 0.03
		and math.abs(n[3] / 4000 - 0.063) < 0.015 and math.abs(n[4] / 4000 - 0.027) < 0.01,
		"older links first: " .. table.concat(n, ","))
	n = picks(false)
	for i = 1, 3 do check(math.abs(n[i] / 4000 - 1 / 3) < 0.03, "uniform: " .. table.concat(n, ",")) end
	check(n[4] == 0, "uniform: always a split")
end

function T.equal_fitness_crossover_takes_the_smaller_parent()
	local a, b = parents() -- a: 4 links, b: 5
	local rng = random.new(24)
	for _ = 1, 50 do
		check(innovs(neat.crossover(a, 3, b, 3, neat.defaults, rng)) == "1,2,3,5", "a is smaller")
		check(innovs(neat.crossover(b, 3, a, 3, neat.defaults, rng)) == "1,2,3,5", "in either order")
	end
	local o = {}
	for k, v in pairs(neat.defaults) do o[k] = v end
	o.tie_smaller = false
	local seen = {}
	for _ = 1, 200 do seen[innovs(neat.crossover(a, 3, b, 3, o, rng))] = true end
	local kinds = 0
	for _ in pairs(seen) do kinds = kinds + 1 end
	check(kinds > 5, "without tie_smaller, the disjoint genes of both at random")
end

function T.disjoint_genes_keep_their_state()
	local a, b = parents()
	a.links[3].enabled = false -- innovation 3, disjoint
	local rng = random.new(25)
	for _ = 1, 200 do
		local c = neat.crossover(a, 10, b, 5, neat.defaults, rng)
		check(c.links[3].innov == 3 and not c.links[3].enabled, "a disabled disjoint gene stays disabled")
		check(c.links[4].enabled, "an enabled one stays enabled")
	end
end

function T.species_are_compared_to_their_champion()
	local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(26),
		options = { pop_size = 12, threshold = 100 } }
	local fit = {}
	for i = 1, 12 do fit[i] = i == 5 and 2 or 1 end
	local champ = neat.copy_genome(pop:genomes()[5])
	pop:tell(fit)
	check(#pop.species == 1 and deep_equal(pop.species[1].rep.links, champ.links),
		"the representative is the last generation's champion")
end

function T.equal_fitness_ranks_at_random()
	-- Ten genomes of equal fitness in one species: the champion kept
	-- unchanged is a different one from seed to seed.
	local copied = {}
	for seed = 1, 12 do
		local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(seed),
			options = { pop_size = 10, threshold = 100 } }
		local old = {}
		for i, g in ipairs(pop:genomes()) do old[i] = neat.copy_genome(g) end
		pop:tell({ 1, 1, 1, 1, 1, 1, 1, 1, 1, 1 })
		for i, g in ipairs(old) do
			for _, c in ipairs(pop:genomes()) do
				if deep_equal(c.links, g.links) then copied[i] = true end
			end
		end
	end
	local n = 0
	for _ in pairs(copied) do n = n + 1 end
	check(n >= 4, "champions drawn from " .. n .. " of 10 places")
end

function T.recur_only_prob_decides_cycles()
	-- Does the genome, with `l` added, have a path from l.to back to l.from?
	local function closes(g, l)
		if l.from == l.to then return true end
		local seen, stack = { [l.to] = true }, { l.to }
		while #stack > 0 do
			local n = table.remove(stack)
			for _, k in ipairs(g.links) do
				if k ~= l and k.from == n and not seen[k.to] then
					if k.to == l.from then return true end
					seen[k.to] = true
					stack[#stack + 1] = k.to
				end
			end
		end
		return false
	end
	local function count(p)
		local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(27),
			options = { pop_size = 2, recurrent = true, recur_only_prob = p } }
		local base = genome(2, { 3 }, { 4 }, { { 1, 0, 3, 1 }, { 2, 1, 4, 1 }, { 3, 4, 3, 1 } })
		local cyc, loops, n = 0, 0, 0
		for _ = 1, 400 do
			local g = neat.copy_genome(base)
			pop.gen_links = {}
			local l = neat.mutate_add_link(pop, g, pop.rng)
			if l then
				n = n + 1
				if closes(g, l) then cyc = cyc + 1 end
				if l.from == l.to then loops = loops + 1 end
			end
		end
		return cyc, loops, n
	end
	local cyc, loops, n = count(1)
	check(n > 350 and cyc == n, "every link closes a cycle: " .. cyc .. " of " .. n)
	check(loops > 0 and loops < n, "self-loops and longer cycles: " .. loops .. " self-loops")
	cyc, _, n = count(1e-9)
	check(n > 350 and cyc == 0, "none closes a cycle: " .. cyc .. " of " .. n)
end

function T.distance_and_speciation_by_threshold()
	-- The paper's settings: a fixed threshold, N = 1 below 20 genes.
	local paper = { pop_size = 2, normalize_below = 20, target_species = 0 }
	local o = options(paper)
	local rep = genome(2, { 3 }, {}, { { 1, 0, 3, 0 }, { 2, 1, 3, 0 }, { 3, 2, 3, 0 } })
	-- Only weights differ: delta = c3 * mean |dw| = 0.4 * 7.45 = 2.98.
	local below = genome(2, { 3 }, {}, { { 1, 0, 3, 7.45 }, { 2, 1, 3, 7.45 }, { 3, 2, 3, 7.45 } })
	local above = genome(2, { 3 }, {}, { { 1, 0, 3, 7.55 }, { 2, 1, 3, 7.55 }, { 3, 2, 3, 7.55 } })
	check(near(neat.distance(rep, below, o), 2.98), "delta below")
	check(near(neat.distance(rep, above, o), 3.02), "delta above")
	-- Structure: 1 disjoint + 2 excess, N = 1 under 20 genes.
	local s = genome(2, { 3 }, { 4 }, { { 1, 0, 3, 0 }, { 3, 2, 3, 0 }, { 4, 0, 4, 0 }, { 5, 4, 3, 0 } })
	check(near(neat.distance(rep, s, o), 1 * 2 + 1 * 1), "c1 E + c2 D")
	local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(6), options = paper }
	pop.species = { { id = 1, rep = rep, members = {}, best_fitness = 0, last_improved = 0 } }
	pop.next_species = 1
	pop.population = { below, above, neat.copy_genome(rep) }
	neat.speciate(pop)
	check(below.species == 1 and pop.population[3].species == 1, "within the threshold: the species")
	check(above.species == 2, "beyond the threshold: a new species")
	check(#pop.species == 2, "two species")
end

-- A genome of links with the given innovation numbers and one weight.
local function genes(innov_list, w)
	local links = {}
	for i, inn in ipairs(innov_list) do links[i] = { inn, 0, 99, w } end
	return genome(1, { 99 }, {}, links)
end
local function range(a, b, extra)
	local t = {}
	for i = a, b do t[#t + 1] = i end
	for _, i in ipairs(extra or {}) do t[#t + 1] = i end
	return t
end

function T.distance_normalises_from_twenty_genes()
	-- g: genes 1..8 of weight 0.5 and gene 30. Against a representative
	-- with genes 1..K of weight 0: 8 matching (mean |dw| 0.5), K - 8
	-- disjoint (9..K, below g's 30), 1 excess (30), N = K.
	local g = genes(range(1, 8, { 30 }), 0.5)
	local r19, r20 = genes(range(1, 19), 0), genes(range(1, 20), 0)
	-- The paper's rule (the default): N = 1 below 20 genes.
	-- K = 19: 1 + 11 + 0.4 * 0.5 = 12.2; K = 20: (1 + 12) / 20 + 0.2 = 0.85.
	-- A species whose representative reaches 20 genes thus takes in genomes
	-- that were 12 apart: XOR, seed 30, generation 54 put 148 of 150 in one
	-- (17 species, then 2, then 12); every fall of 40% or more in XOR's
	-- seeds 1-40 (12 of them) came with a representative of 20 or 21 genes.
	local o = options {}
	check(near(neat.distance(r19, g, o), 12.2), "19 genes: 12 + 0.2")
	check(near(neat.distance(r20, g, o), 0.85), "20 genes: 13/20 + 0.2")
	-- NEAT_NORMALIZE_BELOW:0 always divides: 12/19 + 0.2 = 0.8316 at 19 genes.
	local always = options { normalize_below = 0 }
	check(near(neat.distance(r19, g, always), 12 / 19 + 0.2), "always divided: 12/19 + 0.2")
	check(near(neat.distance(r20, g, always), 0.85), "always divided: 0.85")
	-- Divided by N, structure adds at most c1 + c2 = 2 (E + D <= 2N):
	-- genomes of 24 genes with none in common are 2.0 apart, under 3.0.
	check(near(neat.distance(genes(range(1, 24), 1), genes(range(25, 48), -1), o), 2.0), "disjoint: 2")
end

function T.avoid_sized_genomes_split_only_when_the_threshold_moves()
	-- Avoid's start: 11 inputs and the bias linked to 2 outputs, 24 genes
	-- in every genome. Two groups whose every weight differs by 2: delta =
	-- c3 * 2 = 0.8, whatever N is.
	local pop = neat.new { inputs = 11, outputs = 2, rng = random.new(21), options = { pop_size = 4 } }
	for i, g in ipairs(pop.population) do
		check(#g.links == 24, "24 genes")
		for _, l in ipairs(g.links) do l.weight = i <= 2 and 1 or -1 end
	end
	check(near(neat.distance(pop.population[1], pop.population[3], pop.options), 0.8), "delta 0.4 * 2")
	pop.species, pop.threshold = {}, 3.0
	neat.speciate(pop)
	check(#pop.species == 1, "the paper's fixed 3.0: one species")
	-- The default target (10 species) moves the threshold 0.3 a generation
	-- while there are fewer: 3.0 - 8 * 0.3 = 0.6 < 0.8 after 8 generations.
	check(neat.defaults.target_species == 10 and neat.defaults.threshold_step == 0.3, "default target 10, step 0.3")
	pop.species, pop.threshold = {}, 3.0 - 8 * 0.3
	neat.speciate(pop)
	check(#pop.species == 2, "at 0.6: two species, " .. #pop.species)
	-- One tell with one species: the threshold steps down by itself.
	local one = neat.new { inputs = 11, outputs = 2, rng = random.new(22), options = { pop_size = 10 } }
	check(#one.species == 1, "one species at the start")
	one:tell { 1, 2, 3, 4, 5, 6, 7, 8, 9, 10 }
	check(near(one.threshold, 2.7), "the default threshold moved to 2.7")
end

function T.fitness_sharing_divides_by_species_size()
	local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(7), options = { pop_size = 6 } }
	local g = pop:genomes()
	pop.species = {
		{ id = 1, rep = g[1], members = { 1, 2 }, best_fitness = -math.huge, last_improved = 0 },
		{ id = 2, rep = g[3], members = { 3, 4, 5, 6 }, best_fitness = -math.huge, last_improved = 0 },
	}
	pop.next_species = 2
	local fit = { 4, 2, 1, 1, 1, 1 }
	pop:tell(fit)
	for i = 1, 2 do check(near(g[i].adjusted, fit[i] / 2), "species of 2") end
	for i = 3, 6 do check(near(g[i].adjusted, fit[i] / 4), "species of 4") end
	-- Shares 3 and 1: offspring 4.5 and 1.5 of 6, largest remainder, tie to the first.
	check(pop.last_counts[1] == 5 and pop.last_counts[2] == 1, "offspring in proportion: " ..
		pop.last_counts[1] .. "," .. pop.last_counts[2])
end

function T.allot_sums_to_total()
	local rng = random.new(8)
	for _ = 1, 200 do
		local shares, n = {}, 1 + math.floor(rng:unit() * 10)
		for i = 1, n do shares[i] = rng:unit() < 0.2 and 0 or rng:unit() * 10 end
		local total = math.floor(rng:unit() * 300)
		local c, sum = neat.allot(shares, total), 0
		for i = 1, n do
			check(c[i] >= 0, "non-negative")
			sum = sum + c[i]
		end
		check(sum == total, "counts sum to the total")
	end
	local c = neat.allot({ 0, 0 }, 5)
	check(c[1] + c[2] == 5, "all-zero shares still fill the population")
end

function T.offspring_fill_the_population()
	local pop = neat.new { inputs = 3, outputs = 2, rng = random.new(9), options = { pop_size = 50, threshold = 1.0 } }
	local rng = random.new(99)
	for _ = 1, 15 do
		local fit = {}
		for i = 1, #pop:genomes() do fit[i] = rng:unit() * 10 - 3 end
		pop:tell(fit)
		check(#pop:genomes() == 50, "population size kept")
		local sum = 0
		for _, c in ipairs(pop.last_counts) do sum = sum + c end
		check(sum == 50, "offspring counts sum to the population size")
		local members = 0
		for _, s in ipairs(pop.species) do members = members + #s.members end
		check(members == 50, "every genome in one species")
	end
end

local function two_species_pop(seed)
	local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(seed),
		options = { pop_size = 10, stagnation = 15, stagnation_penalty = 0 } }
	pop.generation = 30
	pop.species = {
		{ id = 1, rep = pop.population[1], members = { 1, 2, 3, 4, 5 }, best_fitness = 100, last_improved = 5 },
		{ id = 2, rep = pop.population[6], members = { 6, 7, 8, 9, 10 }, best_fitness = 100, last_improved = 29 },
	}
	pop.next_species = 2
	return pop
end

function T.stagnant_species_get_no_offspring_but_the_best_survives()
	-- Species 1 has not improved for 25 generations and is not the best.
	local pop = two_species_pop(10)
	pop:tell({ 1, 1, 1, 1, 1, 5, 5, 5, 5, 5 })
	check(#pop.last_alive == 1 and pop.last_alive[1] == 2, "stagnant species dropped")
	check(pop.last_counts[1] == 10, "the rest get every offspring")
	-- Both stagnant: the one with the best genome survives.
	pop = two_species_pop(11)
	pop.species[2].last_improved = 1
	pop:tell({ 1, 1, 9, 1, 1, 5, 5, 5, 5, 5 })
	check(#pop.last_alive == 1 and pop.last_alive[1] == 1, "the best species survives its stagnation")
	check(#pop:genomes() == 10, "population refilled")
end

function T.stagnation_penalty_keeps_stagnant_species_small()
	-- With a penalty, species 1 (stagnant for 25 generations) is not
	-- dropped: its share is multiplied by the penalty.
	local pop = two_species_pop(10)
	pop.options.stagnation_penalty = 0.5
	pop:tell({ 1, 1, 1, 1, 1, 2, 2, 2, 2, 2 })
	check(#pop.last_alive == 2, "both species reproduce")
	-- Shares 1 and 2 before the penalty, 0.5 and 2 after: 2 and 8 of 10.
	check(pop.last_counts[1] == 2 and pop.last_counts[2] == 8, "the stagnant species gets a fifth: " ..
		pop.last_counts[1] .. "," .. pop.last_counts[2])
end

function T.elitism_copies_champions_unchanged()
	local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(12),
		options = { pop_size = 30, threshold = 100, weight_mut_prob = 1, weight_mutation = "paper", perturb_prob = 0 } }
	local fit = {}
	for i = 1, 30 do fit[i] = i % 7 + i / 100 end -- best: genome 27 (6.27)
	local champ = neat.copy_genome(pop:genomes()[27])
	pop:tell(fit)
	local copies = 0
	for _, g in ipairs(pop:genomes()) do
		if deep_equal(g.links, champ.links) and deep_equal(g.nodes, champ.nodes) then copies = copies + 1 end
	end
	check(copies >= 1, "the champion is in the next generation unchanged")
	-- A species given 5 offspring or fewer keeps no elite (without pop_champion).
	pop = neat.new { inputs = 2, outputs = 1, rng = random.new(12),
		options = { pop_size = 4, threshold = 100, weight_mut_prob = 1, weight_mutation = "paper", perturb_prob = 0,
			mutate_only_prob = 1, add_node_prob = 0, add_link_prob = 0, pop_champion = false } }
	champ = neat.copy_genome(pop:genomes()[1])
	pop:tell({ 9, 1, 1, 1 })
	for _, g in ipairs(pop:genomes()) do check(not deep_equal(g.links, champ.links), "no elite for 5 offspring or fewer") end
end

function T.pop_champion_survives_in_a_small_species()
	-- Threshold 0: every genome is a species of one, and none gets more
	-- than elitism_offspring offspring; the generation's best is still
	-- copied unchanged, even when its share alone would give its species
	-- no offspring.
	local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(13),
		options = { pop_size = 20, threshold = 0, weight_mut_prob = 1, weight_mutation = "paper", perturb_prob = 0,
			add_node_prob = 0, add_link_prob = 0 } }
	check(#pop.species == 20, "one species per genome")
	local fit = {}
	for i = 1, 20 do fit[i] = 1 end
	fit[7] = 1.01
	local champ = neat.copy_genome(pop:genomes()[7])
	pop:tell(fit)
	local copies = 0
	for _, g in ipairs(pop:genomes()) do
		if deep_equal(g.links, champ.links) then copies = copies + 1 end
	end
	check(copies == 1, "the champion is copied once: " .. copies)
	check(#pop:genomes() == 20, "population size kept")
end

function T.target_species_moves_the_threshold()
	local function run(target)
		local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(14),
			options = { pop_size = 30, threshold = 3.0, target_species = target, threshold_step = 0.5,
				threshold_min = 0.5 } }
		local fit = {}
		for i = 1, 30 do fit[i] = 1 end
		pop:tell(fit)
		return pop
	end
	-- One species at the start: under a target of 10 the threshold drops one
	-- step; with target_species 0 it stays the option's.
	check(run(0).threshold == nil, "off with a target of 0")
	check(run(10).threshold == 2.5, "below the target: one step down")
	local pop = run(10)
	for _ = 1, 20 do
		local fit = {}
		for i = 1, 30 do fit[i] = 1 end
		pop:tell(fit)
		check(pop.threshold >= 0.5, "never below threshold_min")
	end
	-- Many species: the threshold rises.
	pop = neat.new { inputs = 2, outputs = 1, rng = random.new(15),
		options = { pop_size = 30, threshold = 0, target_species = 5, threshold_step = 0.5 } }
	local fit = {}
	for i = 1, 30 do fit[i] = 1 end
	pop:tell(fit)
	check(pop.threshold == 0.5, "above the target: one step up")
	-- The threshold is state: a checkpoint keeps it.
	check(neat.load(neat.save(pop)).threshold == 0.5, "saved and loaded")
end

-- The checkpoint must be plain data: write it as Lua source and read it back.
local function serialise(v)
	v = plain(v)
	local t = type(v)
	if t == "number" then
		if math.type(v) == "integer" then return string.format("%d", v) end
		if v == math.huge then return "math.huge" elseif v == -math.huge then return "-math.huge" end
		return string.format("%.17g", v)
	elseif t == "string" then return string.format("%q", v)
	elseif t == "boolean" then return tostring(v)
	elseif t == "table" then
		local keys = {}
		for k in pairs(v) do keys[#keys + 1] = k end
		table.sort(keys, function(a, b)
			if type(a) == type(b) then return a < b end
			return type(a) == "number"
		end)
		local parts = {}
		for _, k in ipairs(keys) do parts[#parts + 1] = "[" .. serialise(k) .. "]=" .. serialise(v[k]) end
		return "{" .. table.concat(parts, ",") .. "}"
	end
	error("not plain data: " .. t)
end

local function xor_generation(pop)
	local fit = {}
	for i, g in ipairs(pop:genomes()) do fit[i] = xor_fitness(g) end
	pop:tell(fit)
end

function T.save_load_continues_the_same_run()
	local a = neat.new { inputs = 2, outputs = 1, rng = random.new(13), options = { pop_size = 60 } }
	for _ = 1, 5 do xor_generation(a) end
	local text = serialise(neat.save(a))
	check(serialise(neat.save(a, true)) == text, "the shared save writes what the copy writes")
	local shared, copied = neat.save(a, true), neat.save(a)
	check(shared.population == a.population and copied.population ~= a.population,
		"shared holds the population's tables, the copy does not")
	local b = neat.load(load("return " .. text)())
	check(serialise(neat.save(b)) == text, "save(load(save)) is save")
	for _ = 1, 5 do
		xor_generation(a)
		xor_generation(b)
	end
	check(serialise(neat.save(a)) == serialise(neat.save(b)), "the resumed run matches the uninterrupted one")
	check(b.generation == 10 and b.next_innov == a.next_innov and b.next_species == a.next_species, "counters")
end

function T.same_seed_same_populations()
	local function run(seed)
		local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(seed), options = { pop_size = 50 } }
		for _ = 1, 8 do xor_generation(pop) end
		return serialise(neat.save(pop))
	end
	check(run(14) == run(14), "same seed, same run")
	check(run(14) ~= run(15), "other seed, other run")
end

function T.to_net_maps_bias_and_renumbers()
	-- Inputs 0, 1, bias 2, outputs 3, 4, hidden 9 (ids need not be dense).
	local g = genome(2, { 3, 4 }, { 9 }, {
		{ 1, 0, 9, 1.5 }, { 2, 2, 9, -0.5 }, { 3, 9, 3, 2.0 }, { 4, 1, 3, 0.25, false },
		{ 5, 2, 4, 0.75 }, { 6, 1, 4, -1.0 } })
	local net = neat.to_net(g)
	check(net.inputs == 2 and net.outputs == 2, "sizes")
	check(net.outputs_ids[1] == 2 and net.outputs_ids[2] == 3, "outputs renumbered after the inputs")
	check(net.nodes[3].id == 4 and near(net.nodes[3].bias, -0.5), "hidden node with the bias link's weight")
	check(near(net.nodes[2].bias, 0.75), "output bias")
	check(#net.links == 3, "disabled and bias links left out")
	local text = neat.to_net_text(net)
	check(text == "inputs:2\noutputs:2\nnode:2:neat_sigmoid:0\nnode:3:neat_sigmoid:0.75\n" ..
		"node:4:neat_sigmoid:-0.5\noutput:2\noutput:3\nlink:0:4:1.5\nlink:4:2:2\nlink:1:3:-1\n", text)
	local s = neat.activations.neat_sigmoid
	local out = neat.eval_float(net, { 1, 1 })
	local h = s(1.5 - 0.5)
	check(near(out[1], s(2 * h)) and near(out[2], s(0.75 - 1)), "float evaluation")
end

function T.eval_float_recurrence_reads_the_previous_step()
	-- Node 1 = in + 0.5 * node 1 (a self-loop). Nodes 2 and 3 form a cycle:
	-- the search from output 2 reaches 3, whose source 2 is on the path, so
	-- 3 comes first and reads 2's previous value; 2 = 1 + 3.
	local net = { inputs = 1, outputs = 2, outputs_ids = { 1, 2 },
		nodes = { { id = 1, act = "identity", bias = 0 }, { id = 2, act = "identity", bias = 1 },
			{ id = 3, act = "identity", bias = 0 } },
		links = { { from = 0, to = 1, weight = 1 }, { from = 1, to = 1, weight = 0.5 },
			{ from = 3, to = 2, weight = 1 }, { from = 2, to = 3, weight = 1 } } }
	local out, act = neat.eval_float(net, { 1 })
	check(out[1] == 1 and out[2] == 1, "first step: memory is zero")
	out = neat.eval_float(net, { 1 }, act)
	check(out[1] == 1.5 and out[2] == 2, "second step reads the first")
	out = neat.eval_float(net, { 0 }, act)
	check(out[1] == 0.75 and out[2] == 3, "third step reads the second")
	out = neat.eval_float(net, { 0 })
	check(out[1] == 0 and out[2] == 1, "a fresh memory starts over")
end

function T.options_from_task()
	local o, unknown = neat.options_from_task { POPSIZE = "60", NEAT_C3 = "0.5", NEAT_RECURRENT = "1",
		NEAT_ACTIVATION = "tanh", NEAT_BOGUS = "3", NEAT_ALSO = "x", EVALREP = "2" }
	check(o.pop_size == 60 and o.c3 == 0.5 and o.recurrent == true and o.activation == "tanh", "mapped")
	check(#unknown == 2 and unknown[1] == "NEAT_ALSO" and unknown[2] == "NEAT_BOGUS", "unknown NEAT_ keys listed")
	check(o.EVALREP == nil, "other keys ignored")
	check(not pcall(neat.options_from_task, { NEAT_C1 = "one" }), "a malformed value raises")
	check(neat.options_from_task { NEAT_WEIGHT_MUTATION = "Paper" }.weight_mutation == "paper", "a scheme")
	local ok, msg = pcall(neat.options_from_task, { NEAT_WEIGHT_MUTATION = "gauss" })
	check(not ok and msg:find("NEAT_WEIGHT_MUTATION: 'gauss' is not a weight mutation scheme", 1, true),
		"an unknown scheme raises: " .. tostring(msg))
	for key, name in pairs(neat.task_keys) do check(neat.defaults[name] ~= nil, key .. " names an option") end
	-- Ranges and refused values: tests/lua/test_common.lua.
	check(neat.options_from_task({ NEAT_BIAS_INPUT = "-3" }).bias_input == -3, "any finite bias input")
	local pop = neat.new { inputs = 1, outputs = 1, rng = random.new(1), options = o }
	check(#pop:genomes() == 60, "options reach the population")
end

function T.recurrent_option_controls_cycles()
	local function count_cycles(recurrent)
		local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(16),
			options = { pop_size = 40, recurrent = recurrent, add_link_prob = 0.5, add_node_prob = 0.2 } }
		for _ = 1, 10 do xor_generation(pop) end
		-- Kahn's algorithm over the enabled links: what is left is on a cycle.
		local cyclic = 0
		for _, g in ipairs(pop:genomes()) do
			local indeg, left = {}, 0
			for _, n in ipairs(g.nodes) do indeg[n.id] = 0 end
			for _, l in ipairs(g.links) do
				if l.enabled then indeg[l.to] = indeg[l.to] + 1 end
			end
			local ready = {}
			for _, n in ipairs(g.nodes) do
				if indeg[n.id] == 0 then ready[#ready + 1] = n.id end
			end
			local done = 0
			while #ready > 0 do
				local id = table.remove(ready)
				done = done + 1
				for _, l in ipairs(g.links) do
					if l.enabled and l.from == id then
						indeg[l.to] = indeg[l.to] - 1
						if indeg[l.to] == 0 then ready[#ready + 1] = l.to end
					end
				end
			end
			left = #g.nodes - done
			if left > 0 then cyclic = cyclic + 1 end
		end
		return cyclic
	end
	check(count_cycles(false) == 0, "feed-forward: no self-loop, nothing leaves the output")
	check(count_cycles(true) > 0, "recurrent: loops appear")
end

function T.test_candidate_moves_on_from_a_tested_species()
	-- Species 1 holds the best genome (fitness 9), species 2 the next (7).
	local pop = two_species_pop(16)
	local fit = { 1, 9, 1, 1, 1, 1, 1, 7, 1, 1 }
	pop.species[1].best_fitness, pop.species[2].best_fitness = -math.huge, -math.huge
	check(pop:test_candidate(fit) == 2, "first the best species' champion")
	-- Its species now counts as tested until its best rises above its
	-- record; tell() sets the records.
	pop.species[1].best_fitness, pop.species[2].best_fitness = 9, 7
	check(pop:test_candidate(fit) == 8, "then the next species' champion, not the same genome again")
	check(pop:test_candidate(fit) == 2, "every species tested: the best species' champion")
	-- Species 2 improves: its new champion is tested before species 1's.
	fit[9] = 8
	check(pop:test_candidate(fit) == 9, "an improved species is tested again")
	-- Equal fitness: the first member, then species order by id.
	pop = two_species_pop(17)
	fit = { 3, 5, 5, 1, 1, 5, 1, 1, 1, 1 }
	check(pop:test_candidate(fit) == 2, "first of equals, lower species id first")
	check(pop:test_candidate(fit) == 6, "then the other species")
	-- The tested marks are state: a checkpoint keeps them.
	local loaded = neat.load(neat.save(pop))
	check(loaded:test_candidate(fit) == pop:test_candidate(fit), "saved and loaded")
end

function T.toggle_and_reenable()
	-- Input 0 feeds the output (innovation 1) and hidden node 4 (2); input 1
	-- feeds only the output (3).
	local function g3()
		return genome(2, { 3 }, { 4 }, { { 1, 0, 3, 1 }, { 2, 0, 4, 1 }, { 3, 1, 3, 1 }, { 4, 4, 3, 1 } })
	end
	local rng = random.new(18)
	local off = {}
	for _ = 1, 400 do
		local g = g3()
		neat.mutate_toggle(g, rng)
		for _, l in ipairs(g.links) do
			if not l.enabled then off[l.innov] = (off[l.innov] or 0) + 1 end
		end
	end
	check((off[1] or 0) > 60 and (off[2] or 0) > 60, "a link whose source feeds another can be switched off")
	check(off[3] == nil and off[4] == nil, "a node's only enabled outgoing link stays on")
	local g = g3()
	g.links[1].enabled, g.links[3].enabled = false, false
	neat.mutate_toggle(g, { unit = function() return 0.0 end })
	check(g.links[1].enabled, "a disabled link is switched on")
	g = g3()
	g.links[2].enabled, g.links[3].enabled = false, false
	neat.mutate_reenable(g)
	check(g.links[2].enabled and not g.links[3].enabled, "re-enable: the first disabled link only")
	-- Off by default: a non-structural mutation changes no enabled state.
	local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(19), options = { pop_size = 5 } }
	g = g3()
	g.links[3].enabled = false
	for _ = 1, 200 do neat.mutate(pop, g, pop.rng) end
	check(not g.links[3].enabled, "toggle_prob and reenable_prob are 0 unless set")
	-- Set, they act.
	pop = neat.new { inputs = 2, outputs = 1, rng = random.new(20),
		options = { pop_size = 5, add_node_prob = 0, add_link_prob = 0, reenable_prob = 1 } }
	g = g3()
	g.links[3].enabled = false
	neat.mutate(pop, g, pop.rng)
	check(g.links[3].enabled, "reenable_prob 1 re-enables")
end

function T.delta_coding_breeds_two_champions()
	local function run(delta)
		local pop = two_species_pop(21)
		pop.options.pop_stagnation, pop.options.delta_coding = 20, delta
		pop.options.stagnation = 100
		-- The best has not improved since generation 5 (now 30).
		pop.best = { genome = neat.copy_genome(pop.population[3]), fitness = 50, generation = 5 }
		local champs = { neat.copy_genome(pop.population[3]), neat.copy_genome(pop.population[7]) }
		pop:tell({ 1, 1, 9, 1, 1, 1, 8, 1, 1, 1 })
		return pop, champs
	end
	local pop, champs = run(true)
	check(pop.last_counts[1] == 5 and pop.last_counts[2] == 5, "half the population each")
	-- Every child is one of the champions, its weights mutated or a link
	-- added; the last of each species is its champion unchanged.
	local same = { 0, 0 }
	for _, g in ipairs(pop:genomes()) do
		local innov = {}
		for _, l in ipairs(g.links) do innov[l.innov] = true end
		for _, l in ipairs(champs[1].links) do check(innov[l.innov], "a champion's links are all kept") end
		check(#g.links <= #champs[1].links + 1, "at most one link added")
		for k = 1, 2 do
			if deep_equal(g.links, champs[k].links) then same[k] = same[k] + 1 end
		end
	end
	-- (A link cannot be added to these full genomes, so an add-link child
	-- may be unchanged as well.)
	check(same[1] >= 1 and same[2] >= 1, "each champion kept unchanged: " .. same[1] .. "," .. same[2])
	check(same[1] + same[2] < 10, "the others are mutated")
	for _, s in ipairs(pop.species) do check(s.last_improved == 30 or s.created == 31, "stagnation count restarted") end
	-- Without delta coding (the paper's rule) the two species still get
	-- half the population each.
	pop, champs = run(false)
	check(pop.last_counts[1] == 5 and pop.last_counts[2] == 5, "half the population each, without delta coding too")
end

function T.bias_input_scales_bias_links()
	-- A genome without a bias value (as written before the option): the
	-- bias link's weight is the node's bias.
	local g = genome(2, { 3 }, {}, { { 1, 0, 3, 1 }, { 2, 2, 3, 2.5 } })
	check(neat.to_net(g).nodes[1].bias == 2.5, "bias input 1 by default")
	-- NEAT's pole tasks feed 0.5: the same link gives half the bias, and
	-- copies and children keep the value.
	local pop = neat.new { inputs = 2, outputs = 1, rng = random.new(22), options = { pop_size = 6, bias_input = 0.5 } }
	local a = pop:genomes()[1]
	local w
	for _, l in ipairs(a.links) do
		if l.from == 2 then w = l.weight end
	end
	check(near(neat.to_net(a).nodes[1].bias, 0.5 * w), "bias = 0.5 x the bias link's weight")
	check(near(neat.to_net(neat.copy_genome(a)).nodes[1].bias, 0.5 * w), "a copy keeps the bias input")
	local child = neat.crossover(a, 2, a, 1, pop.options, pop.rng)
	check(near(neat.to_net(child).nodes[1].bias, 0.5 * w), "a child keeps the bias input")
	pop:tell({ 1, 2, 3, 4, 5, 6 })
	for _, c in ipairs(pop:genomes()) do
		for _, nd in ipairs(c.nodes) do
			if nd.kind == "bias" then check(nd.value == 0.5, "every next-generation genome keeps it") end
		end
	end
	check(neat.options_from_task({ NEAT_BIAS_INPUT = "0.5" }).bias_input == 0.5, "NEAT_BIAS_INPUT sets it")
end

function T.xor_is_solved()
	local solved, lines = 0, {}
	for seed = 1, 5 do
		local gen, evals, pop = run_xor(seed, 100)
		if gen then solved = solved + 1 end
		lines[#lines + 1] = string.format("seed %d: %s, %d evaluations, %d species", seed,
			gen and ("generation " .. gen) or "not solved", evals, #pop.species)
	end
	io.write("    XOR: " .. table.concat(lines, "; ") .. "\n")
	check(solved >= 4, "XOR solved for " .. solved .. " of 5 seeds")
end

return T

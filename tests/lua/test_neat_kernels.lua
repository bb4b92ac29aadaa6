-- Unit tests of evo.neat (sim/learn/lua_neat.c), the learning loop's
-- kernels in C, run by tests/sim/lua/test_lua_scripts.c (whose states have
-- evo.neat, as the loop's does): each against values worked out by hand
-- and against the Lua it replaces (neat.*_lua, serialize.dump_lua,
-- Rng.unit_lua), which must give the same numbers to the last bit.
local fast = package.loaded["evo.neat"]
local neat = require "learn.neat"
local random = require "learn.rng"
local serialize = require "learn.serialize"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local function genome(links)
	local g = { nodes = {}, links = {} }
	for _, l in ipairs(links) do
		g.links[#g.links + 1] = { innov = l[1], from = 0, to = 3, weight = l[2], enabled = true }
	end
	return g
end

local T = {}

function T.the_loop_state_has_the_kernels_and_the_methods_use_them()
	check(fast, "evo.neat is loaded")
	check(neat.distance == fast.distance, "neat.distance is C")
	check(neat.mutate_weights == fast.mutate_weights, "mutate_weights is C")
	check(serialize.dump == fast.dump, "serialize.dump is C")
	check(random.new(1).unit == fast.rng_unit, "rng:unit is C")
end

-- a: innovations 1, 2, 4; b: 1, 3, 4, 6, 7. Matching 1 (|0.5 - 1.5| = 1)
-- and 4 (|2 - 1| = 1): W = 1. Disjoint: 2 (a) and 3 (b). Excess: 6, 7.
-- Both below 20 genes: N = 1, so delta = 1*2 + 1*2 + 0.4*1 = 4.4; with
-- normalize_below 0, N = 5: 2/5 + 2/5 + 0.4 = 1.2.
function T.distance_of_hand_made_genomes()
	local a = genome{ { 1, 0.5 }, { 2, -1.0 }, { 4, 2.0 } }
	local b = genome{ { 1, 1.5 }, { 3, 0.0 }, { 4, 1.0 }, { 6, 0.25 }, { 7, 0.0 } }
	local o = { c1 = 1.0, c2 = 1.0, c3 = 0.4, normalize_below = 20 }
	check(math.abs(fast.distance(a, b, o) - 4.4) < 1e-12, "delta " .. fast.distance(a, b, o))
	check(fast.distance(a, b, o) == fast.distance(b, a, o), "symmetric")
	check(fast.distance(a, a, o) == 0, "a genome is at 0 from itself")
	o.normalize_below = 0
	check(math.abs(fast.distance(a, b, o) - 1.2) < 1e-12, "normalised " .. fast.distance(a, b, o))
	-- no matching gene: W is 0, not 0/0
	local c = genome{ { 9, 3.0 } }
	o.normalize_below = 20
	check(fast.distance(a, c, o) == 4, "3 disjoint + 1 excess " .. fast.distance(a, c, o))
	check(fast.distance(genome{}, genome{}, o) == 0, "two empty genomes")
	for _, x in ipairs{ a, b, c } do
		for _, y in ipairs{ a, b, c } do
			check(fast.distance(x, y, o) == neat.distance_lua(x, y, o), "C and Lua agree")
		end
	end
end

-- xoshiro256** seeded by splitmix64 from 42, as tests/lua/test_rng.lua
-- checks it word by word: the C and the Lua give the same stream.
function T.random_draws_are_the_lua_generators()
	local a, b = random.new(42), random.new(42)
	for _ = 1, 1000 do
		check(fast.rng_next(a) == b:next_lua(), "next")
		check(fast.rng_unit(a) == b:unit_lua(), "unit")
	end
	check(serialize.dump_lua(a:save()) == serialize.dump_lua(b:save()), "same state after")
	-- unit is the top 53 bits of next over 2^53
	local c, d = random.new(7), random.new(7)
	check(fast.rng_unit(c) == (d:next_lua() >> 11) / 2 ^ 53, "unit from next")
end

-- A population's genomes after a few generations (hidden nodes, disabled
-- links), and a copy of the generator state: the C and the Lua kernel
-- each run from the same state must make the same genome and leave the
-- generator in the same state.
local function grown_population()
	local pop = neat.new{ inputs = 3, outputs = 2, rng = random.new(5),
		options = { pop_size = 40, add_node_prob = 0.3, add_link_prob = 0.3 } }
	for _ = 1, 6 do
		local fit = {}
		for i, g in ipairs(pop:genomes()) do fit[i] = #g.links + (i % 3) end
		pop:tell(fit)
	end
	return pop
end

function T.crossover_and_weight_mutation_are_the_luas_draw_for_draw()
	local pop = grown_population()
	local gs, o = pop:genomes(), pop.options
	local r = random.new(99)
	for k = 1, #gs - 1 do
		local a, b = gs[k], gs[k + 1]
		for _, fits in ipairs{ { 3, 1 }, { 1, 3 }, { 2, 2 } } do
			for _, avg in ipairs{ 0, 1 } do
				o.mate_avg_prob = avg
				local r1, r2 = random.load(r:save()), random.load(r:save())
				local c1 = fast.crossover(a, fits[1], b, fits[2], o, r1)
				local c2 = neat.crossover_lua(a, fits[1], b, fits[2], o, r2)
				check(serialize.dump_lua(c1) == serialize.dump_lua(c2), "same child")
				check(serialize.dump_lua(r1:save()) == serialize.dump_lua(r2:save()), "same draws")
				r:unit()
			end
		end
		for _, scheme in ipairs{ "code", "paper" } do
			o.weight_mutation = scheme
			local g1, g2 = neat.copy_genome(a), neat.copy_genome(a)
			local r1, r2 = random.load(r:save()), random.load(r:save())
			fast.mutate_weights(g1, o, r1)
			neat.mutate_weights_lua(g2, o, r2)
			check(serialize.dump_lua(g1) == serialize.dump_lua(g2), "same weights " .. scheme)
			check(serialize.dump_lua(r1:save()) == serialize.dump_lua(r2:save()), "same draws")
		end
	end
	-- equal fitness without tie_smaller: the paper's crossover, left to Lua
	o.tie_smaller = false
	check(fast.crossover(gs[1], 1, gs[2], 1, o, random.new(1)) == nil, "left to Lua")
end

-- neat.breed (fast.breed, in C) and neat.breed_lua, each on its own copy
-- of the same population, make the same children with the same draws and
-- the same new innovations, whichever branch the options favour: copies,
-- crossovers, mates from other species, structural mutations (Lua's,
-- called back from C), toggles and re-enables.
function T.breeding_is_the_luas_draw_for_draw()
	local text = fast.dump(neat.save(grown_population(), true))
	local variants = {
		{},
		{ mutate_only_prob = 1 },
		{ mutate_only_prob = 0, mate_only_prob = 0 },
		{ mutate_only_prob = 0, mate_only_prob = 1 },
		{ interspecies_prob = 0.5, add_node_prob = 0.4, add_link_prob = 0.5 },
		{ toggle_prob = 0.5, reenable_prob = 0.5, weight_mutation = "paper" },
	}
	for vi, options in ipairs(variants) do
		local runs = {}
		for which, breed in ipairs{ neat.breed, neat.breed_lua } do
			local pop = neat.load(serialize.load(text, "t"))
			for k, v in pairs(options) do pop.options[k] = v end
			pop.gen_links, pop.gen_splits = {}, {}
			for i, g in ipairs(pop.population) do g.fitness = #g.links + (i % 3) end
			local children = { "before" }
			for si, s in ipairs(pop.species) do
				local sorted = {}
				for k, gi in ipairs(s.members) do sorted[k] = pop.population[gi] end
				breed(pop, children, sorted, 5 + si, math.min(#sorted, 1 + si % 3), pop.species,
					pop.population)
			end
			check(children[1] == "before", "children appended")
			table.remove(children, 1)
			runs[which] = fast.dump{ children = children, rng = pop.rng:save(), innov = pop.next_innov,
				node = pop.next_node, links = pop.gen_links, splits = pop.gen_splits }
		end
		check(runs[1] == runs[2], "variant " .. vi .. ": the same children, draws and innovations")
	end
	check(#neat.load(serialize.load(text, "t")).species > 2, "several species to mate across")
end

-- fast.add_link and fast.add_node (neat.mutate_add_link and _node in the
-- loop's state) and the Lua they replace, each on its own copy of the
-- same population, add the same genes and nodes with the same draws and
-- the same innovations, under every option that changes them.
function T.structural_mutations_are_the_luas_draw_for_draw()
	check(neat.mutate_add_link == fast.add_link, "add-link is C")
	local text = fast.dump(neat.save(grown_population(), true))
	local variants = {
		{},
		{ recurrent = true },
		{ recurrent = true, recur_only_prob = 0.5 },
		{ split_bias = true, split_older = false },
		{ add_link_tries = 1, weight_max = 1, new_link_power = 5 },
	}
	local added = { link = 0, node = 0 }
	for vi, options in ipairs(variants) do
		local runs = {}
		for which, fns in ipairs{ { fast.add_link, fast.add_node },
			{ neat.mutate_add_link_lua, neat.mutate_add_node_lua } } do
			local pop = neat.load(serialize.load(text, "t"))
			for k, v in pairs(options) do pop.options[k] = v end
			local got = {}
			for round = 1, 3 do
				for i, g in ipairs(pop.population) do
					local what = (i + round) % 2 + 1
					local r = fns[what](pop, g, pop.rng)
					got[#got + 1] = r == nil and "none" or r
					if which == 1 and r ~= nil then
						added[what == 1 and "link" or "node"] = added[what == 1 and "link" or "node"] + 1
					end
				end
			end
			runs[which] = fast.dump{ got = got, population = pop.population, rng = pop.rng:save(),
				innov = pop.next_innov, node = pop.next_node, links = pop.gen_links, splits = pop.gen_splits }
		end
		check(runs[1] == runs[2], "variant " .. vi .. ": the same genomes, draws and innovations")
	end
	check(added.link > 20 and added.node > 20, "links and nodes were added")
end

-- By hand: a genome of inputs 0, 1, bias 2 and output 3, linked 0 -> 3
-- and 2 -> 3. With every draw 0.25, add-node (split_older, fewer than 15
-- links) takes the first enabled link not from the bias, 0 -> 3 (0.25 <
-- 0.7): a new node 4 (next_node 3 + 1) between, genes 5 (0 -> 4, weight
-- 1) and 6 (4 -> 3, the old weight 0.5) after next_innov 4, the old link
-- off. Add-link then draws nodes[1 + floor(0.25 * 5)] = node 1 for both
-- ends; node 1 is an input, so no try adds a link.
function T.structural_mutations_by_hand()
	local g = { nodes = { { id = 0, kind = "input" }, { id = 1, kind = "input" }, { id = 2, kind = "bias" },
		{ id = 3, kind = "output", act = "identity" } }, links = {
		{ innov = 1, from = 2, to = 3, weight = 2.0, enabled = true },
		{ innov = 3, from = 0, to = 3, weight = 0.5, enabled = true } } }
	local o = {}
	for k, v in pairs(neat.defaults) do o[k] = v end
	local pop = { options = o, next_innov = 4, next_node = 3, gen_links = {}, gen_splits = {} }
	local quarter = { unit = function() return 0.25 end }
	check(fast.add_node(pop, g, quarter) == 4, "node 4")
	check(#g.links == 4 and g.links[2].innov == 3 and not g.links[2].enabled, "0 -> 3 switched off")
	local l5, l6 = g.links[3], g.links[4]
	check(l5.innov == 5 and l5.from == 0 and l5.to == 4 and l5.weight == 1.0 and l5.enabled, "gene 5")
	check(l6.innov == 6 and l6.from == 4 and l6.to == 3 and l6.weight == 0.5 and l6.enabled, "gene 6")
	check(#g.nodes == 5 and g.nodes[5].id == 4 and g.nodes[5].kind == "hidden"
		and g.nodes[5].act == o.activation, "hidden node 4")
	check(pop.next_innov == 6 and pop.next_node == 4 and pop.gen_splits["3"].node == 4, "registry")
	check(fast.add_link(pop, g, quarter) == nil and #g.links == 4, "no link into an input")
end

-- fast.to_net (neat.to_net in the loop's state) gives neat.to_net_lua's
-- table. By hand: inputs 0, 1, bias 2 of value 0.5, output 3, hidden 7;
-- the output becomes node 2, the hidden node 3; bias -> 3 (2.0) is the
-- output's bias 1.0, bias -> 7 (4.0, then 2.0) the hidden node's 3.0;
-- the disabled 1 -> 3 is left out, the integer weight 8 stays an integer.
function T.networks_of_genomes_are_the_luas()
	check(neat.to_net == fast.to_net, "to_net is C")
	for _, g in ipairs(grown_population():genomes()) do
		check(fast.dump(fast.to_net(g)) == fast.dump(neat.to_net_lua(g)), "the same network")
	end
	local g = { nodes = { { id = 0, kind = "input" }, { id = 1, kind = "input" },
		{ id = 2, kind = "bias", value = 0.5 }, { id = 3, kind = "output", act = "neat_sigmoid" },
		{ id = 7, kind = "hidden", act = "tanh" } }, links = {
		{ innov = 1, from = 0, to = 3, weight = 8, enabled = true },
		{ innov = 2, from = 1, to = 3, weight = 9.0, enabled = false },
		{ innov = 3, from = 2, to = 3, weight = 2.0, enabled = true },
		{ innov = 4, from = 0, to = 7, weight = 0.5, enabled = true },
		{ innov = 5, from = 7, to = 3, weight = -1.0, enabled = true },
		{ innov = 6, from = 2, to = 7, weight = 4.0, enabled = true },
		{ innov = 8, from = 2, to = 7, weight = 2.0, enabled = true } } }
	local net = fast.to_net(g)
	check(net.inputs == 2 and net.outputs == 1 and #net.outputs_ids == 1 and net.outputs_ids[1] == 2, "ids")
	check(#net.nodes == 2 and net.nodes[1].id == 2 and net.nodes[1].act == "neat_sigmoid"
		and net.nodes[1].bias == 1.0 and net.nodes[2].id == 3 and net.nodes[2].bias == 3.0, "nodes")
	check(#net.links == 3 and math.type(net.links[1].weight) == "integer" and net.links[1].weight == 8
		and net.links[2].from == 0 and net.links[2].to == 3 and net.links[3].from == 3
		and net.links[3].to == 2, "links")
	check(fast.dump(net) == fast.dump(neat.to_net_lua(g)), "the Lua's")
end

-- learn.neat loaded again without evo.neat: the pure Lua every kernel
-- replaces (its own learn.rng too), for whole generations.
local function pure_lua_neat()
	local saved = {}
	for _, name in ipairs{ "evo.neat", "learn.neat", "learn.rng", "learn.common", "learn.netfile" } do
		saved[name], package.loaded[name] = package.loaded[name], nil
	end
	local ok, slow, slow_rng = pcall(function() return require "learn.neat", require "learn.rng" end)
	for name, m in pairs(saved) do package.loaded[name] = m end
	check(ok, slow)
	return slow, slow_rng
end

-- Whole generations (tell: fitness, sharing, offspring counts, ranking,
-- breeding, speciation, the best so far) with the C kernels and with the
-- pure Lua, from the same seed and the same fitness: the same checkpoint,
-- byte for byte, after each one, under options that take every branch.
function T.generations_in_c_are_the_pure_luas()
	local slow, slow_rng = pure_lua_neat()
	check(slow ~= neat and slow.breed == slow.breed_lua and slow.to_net == slow.to_net_lua, "pure Lua")
	for _, options in ipairs{
		{ pop_size = 60, add_node_prob = 0.2, add_link_prob = 0.3 },
		{ pop_size = 40, target_species = 4, interspecies_prob = 0.3, recurrent = true,
			recur_only_prob = 0.4, toggle_prob = 0.2, reenable_prob = 0.2, stagnation = 3 },
		{ pop_size = 30, pop_stagnation = 2, delta_coding = true, rep_champion = false, split_older = false },
	} do
		local pops = {}
		for which, m in ipairs{ { neat, random }, { slow, slow_rng } } do
			pops[which] = m[1].new{ inputs = 3, outputs = 2, rng = m[2].new(11), options = options }
		end
		for gen = 1, 12 do
			local fit = {}
			for i, g in ipairs(pops[1]:genomes()) do fit[i] = (#g.links * 7 + i * gen) % 13 - 2 end
			for _, pop in ipairs(pops) do pop:tell(fit) end
			check(fast.dump(neat.save(pops[1], true)) == serialize.dump_lua(slow.save(pops[2], true)),
				"generation " .. gen .. ": the same population")
		end
	end
end

-- By hand, with a generator whose every draw is 0.25: the parent is
-- sorted[1 + floor(0.25 * 2)] = sorted[1]; 0.25 is not under
-- mutate_only_prob 0.2, so it mates, with sorted[1] again (no other
-- species: 0.25 >= 0.001); the child of a genome with itself is its copy,
-- always mutated. The weights (weight_mut_prob 1, "code"): 0.25 <
-- severe_prob makes it severe, and 0.25 < 0.7 perturbs each weight by
-- (0.25 * 2 - 1) * perturb_power = -1.5. With mutate_only_prob 0.5 the
-- copy is made directly, mutated the same.
function T.breeding_by_hand_with_a_fixed_generator()
	local a = { fitness = 2, nodes = { { id = 0, kind = "input" }, { id = 1, kind = "output", act = "identity" } },
		links = { { innov = 1, from = 0, to = 1, weight = 1.0, enabled = true },
			{ innov = 2, from = 0, to = 1, weight = -7.0, enabled = true } } }
	local b = { fitness = 1, nodes = a.nodes, links = { { innov = 1, from = 0, to = 1, weight = 5.0, enabled = true } } }
	local o = {}
	for k, v in pairs(neat.defaults) do o[k] = v end
	o.add_node_prob, o.add_link_prob, o.weight_mut_prob, o.mutate_only_prob = 0, 0, 1, 0.2
	for _, only in ipairs{ 0.2, 0.5 } do
		o.mutate_only_prob = only
		local pop = { options = o, rng = { unit = function() return 0.25 end } }
		local children = {}
		fast.breed(pop, children, { a, b }, 3, 2, { { members = { 1, 2 } } }, { a, b },
			function() error("no structural mutation") end)
		check(#children == 3, "three children")
		for _, c in ipairs(children) do
			check(c ~= a and #c.links == 2, "a's copy")
			check(c.links[1].weight == -0.5 and c.links[2].weight == -8.0, "weights 1.5 lower, clamped at -8")
		end
		check(a.links[1].weight == 1.0, "the parent unchanged")
	end
end

-- By hand: parent a (fitter) has genes 1, 2 (off), 4; b has 1, 3, 4.
-- Matching 1 and 4 come from either parent; 2 is a's disjoint gene, kept;
-- b's 3 is not inherited. A generator whose every draw is 0.25 picks a's
-- gene (0.25 < 0.5), averages (0.25 < mate_avg_prob 0.4), and keeps a
-- gene disabled in a parent enabled only if the draw >= disable_prob.
function T.crossover_by_hand_with_a_fixed_generator()
	local quarter = { unit = function() return 0.25 end }
	local a = { nodes = { { id = 0, kind = "input" }, { id = 1, kind = "output", act = "identity" } }, links = {
		{ innov = 1, from = 0, to = 1, weight = 1.0, enabled = true },
		{ innov = 2, from = 0, to = 1, weight = 2.0, enabled = false },
		{ innov = 4, from = 0, to = 1, weight = 4.0, enabled = true } } }
	local b = { nodes = { { id = 0, kind = "input" }, { id = 1, kind = "output", act = "identity" },
		{ id = 5, kind = "hidden", act = "identity" } }, links = {
		{ innov = 1, from = 0, to = 1, weight = 3.0, enabled = false },
		{ innov = 3, from = 0, to = 5, weight = 9.0, enabled = true },
		{ innov = 4, from = 0, to = 1, weight = 0.0, enabled = true } } }
	local o = { mate_avg_prob = 0.4, disable_prob = 0.75, tie_smaller = true }
	local c = fast.crossover(a, 2, b, 1, o, quarter)
	check(#c.links == 3 and c.links[1].innov == 1 and c.links[2].innov == 2 and c.links[3].innov == 4,
		"genes 1, 2, 4")
	check(c.links[1].weight == 2.0 and c.links[3].weight == 2.0, "matching weights averaged")
	check(c.links[1].enabled == false, "1 disabled in b: 0.25 < 0.75 keeps it off")
	check(c.links[2].weight == 2.0 and c.links[2].enabled == false, "a's disjoint gene as it is")
	check(#c.nodes == 2, "b's hidden node 5 is not needed")
	check(c.links[1] ~= a.links[1], "genes are copies")
	-- b fitter: its genes 1, 3, 4, and the node 5 gene 3 needs
	c = fast.crossover(a, 1, b, 2, o, quarter)
	check(#c.links == 3 and c.links[2].innov == 3 and #c.nodes == 3 and c.nodes[3].id == 5, "b's genes and node 5")
end

-- The checkpoint text: the same bytes as the Lua writer on what a
-- checkpoint holds and on the corners of the format.
function T.dump_is_the_lua_writers_text()
	check(fast.dump{ 1, 2.0, "a\n" } == 'return {1,2.0,"a\\\n",}\n', "by hand")
	check(fast.dump{ b = true, a = -0.0 } == "return {[\"a\"]=-0.0,[\"b\"]=true,}\n", "keys in order, -0.0")
	local corner = {
		1, 2.5, -0.0, 1 / 0, -1 / 0, 0 / 0, math.mininteger, math.maxinteger, 2 ^ 53, -(2 ^ 53) + 1,
		1e300, 5e-324, 3.0, "quote \" back \\ nl \n cr \r nul \0 one\0001 tab\t del\127", {},
		{ [1] = "a", [3] = "c" }, { [true] = 1, [2] = "n", x = "s", [1.5] = "f" },
		{ { { { deep = { 1, { 2 } } } } } },
	}
	check(fast.dump(corner) == serialize.dump_lua(corner), "corners")
	-- a map of more keys than a record has (sorted another way in C)
	local big = { [true] = 0, [0.5] = "h", [-3] = "m" }
	for i = 1, 40 do big["k" .. i], big[i * 7 % 41 + 0.25] = i, -i end
	check(fast.dump(big) == serialize.dump_lua(big), "a big map")
	local pop = grown_population()
	local saved = neat.save(pop, true)
	check(fast.dump(saved) == serialize.dump_lua(saved), "a population")
	check(serialize.load(fast.dump(saved), "t").next_innov == pop.next_innov, "reads back")
	local ok, err = pcall(fast.dump, { f = print })
	check(not ok and tostring(err):find("cannot save a function"), "refuses a function")
end

-- Species by hand, threshold 3, c1 = c2 = 1, c3 = 0.4, N = 1 (fewer than
-- 20 genes). The one old species' representative has genes 1, 2. g1 (1, 2,
-- weights 1 off): 0.4 -> species 1. g2 (3, 4, 5): 2 disjoint + 3 excess =
-- 5 -> opens species 2. g3 (g2 with one weight 0.5 off): 5 from the first,
-- 0.4 * 0.5 / 3 from g2 -> species 2. g4 (1, 9): 1 disjoint + 1 excess = 2
-- -> species 1. g5 (7): 3 from the first (not below 3), 4 from g2 ->
-- opens species 3.
function T.speciate_by_hand_and_as_the_lua_loop()
	local o = { c1 = 1.0, c2 = 1.0, c3 = 0.4, normalize_below = 20 }
	local rep = genome{ { 1, 0.0 }, { 2, 0.0 } }
	local gs = { genome{ { 1, 1.0 }, { 2, 1.0 } }, genome{ { 3, 0.0 }, { 4, 0.0 }, { 5, 0.0 } },
		genome{ { 3, 0.5 }, { 4, 0.0 }, { 5, 0.0 } }, genome{ { 1, 0.0 }, { 9, 0.0 } }, genome{ { 7, 0.0 } } }
	local home = fast.speciate(gs, { rep }, o, 3.0)
	check(#home == 5 and home[1] == 1 and home[2] == 2 and home[3] == 2 and home[4] == 1
		and home[5] == 3, "species 1 2 2 1 3")
	check(#fast.speciate({}, { rep }, o, 3.0) == 0, "no genome, no species")
	-- a grown population, against the Lua loop with neat.distance_lua
	local pop = grown_population()
	for _, t in ipairs{ 0.5, 1.0, 3.0 } do
		local reps = {}
		for k, sp in ipairs(pop.species) do reps[k] = sp.rep end
		local got = fast.speciate(pop:genomes(), reps, pop.options, t)
		for i, g in ipairs(pop:genomes()) do
			local want
			for k, r in ipairs(reps) do
				if neat.distance_lua(g, r, pop.options) < t then want = k break end
			end
			if not want then
				reps[#reps + 1] = g
				want = #reps
			end
			check(got[i] == want, "genome " .. i .. " at threshold " .. t)
		end
	end
end

-- A copy is the Lua copy's text; its genes are its own tables (a mutation
-- of the copy leaves the original alone), its nodes the original's, in a
-- list of its own.
function T.copy_genome_is_the_luas_with_shared_nodes()
	local g = grown_population():genomes()[1]
	local c = fast.copy_genome(g)
	check(serialize.dump_lua(c) == serialize.dump_lua(neat.copy_genome_lua(g)), "same text")
	check(c.links ~= g.links and c.links[1] ~= g.links[1], "genes copied")
	local w = g.links[1].weight
	c.links[1].weight = w + 1
	check(g.links[1].weight == w, "the original's weight stays")
	check(c.nodes ~= g.nodes and c.nodes[1] == g.nodes[1] and #c.nodes == #g.nodes, "nodes shared")
	check(neat.copy_genome == fast.copy_genome, "neat.copy_genome is C")
end

-- fast.mutate's first draws and weights are neat.mutate_lua's (1: add a
-- node, 2: add a link, 0: the weights, with chance weight_mut_prob);
-- fast.draws(rng, n) is n calls of rng:unit().
function T.mutation_draws_and_key_draws_are_the_luas()
	local pop = grown_population()
	local o = {}
	for k, v in pairs(pop.options) do o[k] = v end
	local r = random.new(7)
	local seen = {}
	for _, probs in ipairs{ { 0.5, 0.5, 0.9 }, { 0, 0, 1 }, { 0, 0, 0.5 }, { 1, 0, 1 } } do
		o.add_node_prob, o.add_link_prob, o.weight_mut_prob = probs[1], probs[2], probs[3]
		for _, g in ipairs(pop:genomes()) do
			local g1, g2 = neat.copy_genome(g), neat.copy_genome(g)
			local r1, r2 = random.load(r:save()), random.load(r:save())
			local what = fast.mutate(g1, o, r1)
			local want = 0
			if r2:unit_lua() < o.add_node_prob then want = 1
			elseif r2:unit_lua() < o.add_link_prob then want = 2
			elseif r2:unit_lua() < o.weight_mut_prob then neat.mutate_weights_lua(g2, o, r2) end
			check(what == want, "what " .. what .. " " .. want)
			seen[what] = true
			check(serialize.dump_lua(g1) == serialize.dump_lua(g2), "same weights")
			check(serialize.dump_lua(r1:save()) == serialize.dump_lua(r2:save()), "same draws")
			r:unit()
		end
	end
	check(seen[0] and seen[1] and seen[2], "every branch taken")
	local r1, r2 = random.new(3), random.new(3)
	local d = fast.draws(r1, 5)
	check(#d == 5, "five draws")
	for k = 1, 5 do check(d[k] == r2:unit_lua(), "draw " .. k) end
	check(#fast.draws(r1, 0) == 0 and r1:unit_lua() == r2:unit_lua(), "none drawn")
end

-- A genome's genes are one userdata of flat arrays: links[i] reads and
-- writes gene i in place, a weight keeps its Lua type (an integer
-- weight_max clamps to that integer, and the checkpoint writes it so),
-- added genes are sorted by innovation, and the text is the gene tables'.
function T.genes_are_flat_arrays_read_and_written_in_place()
	-- inputs 0, 1, bias 2, output 3: genes 1, 2, 3 from 0, 1, 2 to 3
	local g = neat.new{ inputs = 2, outputs = 1, rng = random.new(1), options = { pop_size = 1 } }:genomes()[1]
	check(type(g.links) == "userdata" and #g.links == 3, "three genes in a userdata")
	for k = 1, 3 do
		local l = g.links[k]
		check(l.innov == k and l.from == k - 1 and l.to == 3 and l.enabled == true, "gene " .. k)
		check(math.type(l.innov) == "integer" and math.abs(l.weight) <= 1, "gene " .. k .. "'s numbers")
	end
	check(g.links[4] == nil, "nothing past the end")
	check(g.links[1] == g.links[1] and g.links[1] ~= g.links[2], "a gene is itself, not another")
	g.links[2].weight, g.links[2].enabled = 8, false
	check(math.type(g.links[2].weight) == "integer" and g.links[2].enabled == false, "written in place")
	local one = fast.genes{ { innov = 1, from = 0, to = 3, weight = 0.5, enabled = true } }
	check(fast.dump(one) == 'return {{["enabled"]=true,["from"]=0,["innov"]=1,["to"]=3,["weight"]=0.5,},}\n',
		"the text of one gene " .. fast.dump(one))
	check(fast.dump(g) == serialize.dump_lua(g), "the Lua writer's text")
	check(fast.dump(g):find('["weight"]=8,', 1, true), "an integer weight written as one")
	fast.add_gene(g, { innov = 10, from = 1, to = 3, weight = 0.25, enabled = true })
	fast.add_gene(g, { innov = 7, from = 0, to = 3, weight = -0.25, enabled = false })
	fast.sort_genes(g)
	local innov = {}
	for i, l in ipairs(g.links) do innov[i] = l.innov end
	check(table.concat(innov, " ") == "1 2 3 7 10", "sorted by innovation: " .. table.concat(innov, " "))
	-- paths: 0 -> 4 -> 3 and 1 -> 3, walked over disabled genes too
	local h = { nodes = {}, links = fast.genes{
		{ innov = 1, from = 0, to = 4, weight = 1, enabled = false },
		{ innov = 2, from = 4, to = 3, weight = 1, enabled = true },
		{ innov = 3, from = 1, to = 3, weight = 1, enabled = true } } }
	check(fast.reaches(h, 0, 3) and fast.reaches(h, 2, 2) and fast.reaches(h, 0, 4), "paths found")
	check(not fast.reaches(h, 3, 0) and not fast.reaches(h, 1, 4) and not fast.reaches(h, 4, 0), "no path")
	-- a checkpoint's text reads back into genes that write the same text
	local pop = grown_population()
	local text = fast.dump(neat.save(pop, true))
	local back = neat.load(serialize.load(text, "t"))
	check(type(back:genomes()[1].links) == "userdata" and type(back.species[1].rep.links) == "userdata"
		and type(back.best.genome.links) == "userdata", "loaded genomes hold genes")
	check(fast.dump(neat.save(back, true)) == text, "the same text again")
	check(fast.dump(neat.save(pop)) == text, "a saved copy (plain tables) writes the same text")
	-- a table met twice is written twice, the same
	local shared = { id = 1, kind = "input" }
	local twice = { shared, { shared, n = shared }, shared }
	check(fast.dump(twice) == serialize.dump_lua(twice), "a shared table")
end

return T

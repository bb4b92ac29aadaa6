-- CMAES: the covariance matrix adaptation evolution strategy over the
-- weights of a fixed layered network (docs/learning.md), written from
-- N. Hansen, "The CMA Evolution Strategy: A Tutorial" (2016), with the
-- restarts of Auger & Hansen 2005 (IPOP-CMA-ES) and the diagonal variant of
-- Ros & Hansen 2008 (sep-CMA-ES).
--
--	local cmaes = require "learn.cmaes"
--	local random = require "learn.rng"
--	local pop = cmaes.new{ inputs = 6, outputs = 1, layers = 1, hidden = 6,
--		options = { bias = false }, rng = random.new(42) }
--	for gen = 1, 100 do
--		local fit = {}
--		for i, g in ipairs(pop:genomes()) do fit[i] = evaluate(cmaes.to_net(g)) end
--		pop:tell(fit)
--	end
--
-- The search. A generation samples lambda points x_k = m + sigma * B D z_k,
-- z_k ~ N(0, I), where C = B D^2 B^T is the covariance matrix; tell ranks
-- them (fitness is "higher is better", NaN the worst, ties by index) and
-- moves the mean to the weighted mean of the best mu, then updates the
-- evolution paths p_sigma and p_c, C (rank-one and rank-mu updates) and
-- sigma (cumulative step-size adaptation), all as the tutorial's
-- equations (its section "Algorithm Summary", with only positive weights).
-- B and D are recomputed from C (evo.linalg's eigendecomposition, in C)
-- every max(1, floor(1 / (10 n (c_1 + c_mu)))) generations, the tutorial's
-- lazy update; C stays exactly symmetric between.
--
-- The separable variant keeps C diagonal (B = I): c_1 and c_mu are
-- multiplied by (n + 2) / 3 as Ros & Hansen do, and a generation costs
-- O(lambda n) instead of O(n^2). CMAES_SEPARABLE auto uses it above
-- CMAES_SEPARABLE_ABOVE weights and says so on stderr.
--
-- Restarts (IPOP). After a generation, the run restarts from the initial
-- mean and sigma with a fresh C, the population doubled (CMAES_IPOP) or
-- not, when one of the tutorial's criteria holds: the best fitness of the
-- last 10 + ceil(30 n / lambda) generations is no better than before them
-- (stagnation), or that window's generation bests and the last
-- generation's fitnesses all lie within CMAES_TOLFUN (TolFun), or
-- sigma * max(sqrt(C_ii), |p_c,i|) < CMAES_TOLX * sigma0 for every i
-- (TolX), or the condition number of C passes 1e14. At most CMAES_RESTARTS
-- restarts; the best genome ever seen is kept across them.
--
-- The network (to_net). The layered network of learn.genetic (net_build's
-- ids and order, HIDDEN wide), hidden units tanh (or sigmoid) and outputs
-- sigmoid, with or without biases (a bias-free node has bias 0). With
-- CMAES_RECURRENT each hidden layer is an Elman layer: each of its units
-- also reads the previous step's value of every unit of its layer. Those
-- values are held by context nodes (identity activation, one per hidden
-- unit, ids after the hidden units) which core/src/net_compile.c orders
-- after every hidden unit: the first output reads the first context node
-- of each layer by a weight-0 link listed first, context node j reads
-- context node j+1 (weight 0) and its hidden unit (weight 1), and the last
-- also reads every unit of its layer (weight 0), so the depth-first order
-- reaches all the context nodes of a layer before any of its units and
-- places the units first. A unit's link from a context node is thus
-- backwards in the order and reads the value of the previous step: exactly
-- h(t) = act(W x(t) + U h(t-1) + b), h(0) = 0.
-- A genome lists, for each node in net_build's order (hidden layer 1, ...,
-- outputs), its bias (when CMAES_BIAS), the weights from the previous
-- layer in id order, then (recurrent hidden units) the weights from the
-- layer's units in id order. A weight beyond evo's fixed-point limit
-- (|w| < 128, evo/net.h) is clamped to +-127.99 in the network; the genome
-- keeps its value.
--
-- Determinism. Every draw goes through the given rng (learn.rng); the
-- eigendecomposition is deterministic; cmaes.save holds the whole state.
local common = require "learn.common"
local genetic = require "learn.genetic"
local netfile = require "learn.netfile"
local random = require "learn.rng"

local cmaes = {}

cmaes.defaults = {
	pop_size = 0, -- lambda; 0 (the default, not a value a task can give): 4 + floor(3 ln n)
	sigma = 0.5, -- the initial step size
	sigma_min = 0.0, -- a lower bound on sigma; 0: none
	restarts = 9, -- at most this many restarts
	ipop = true, -- a restart doubles lambda
	separable = "auto", -- "auto", "true" or "false"
	separable_above = 400, -- auto: separable above this many weights
	bias = true, -- every node has a bias
	hidden_act = "tanh", -- the hidden units' activation: "tanh" or "sigmoid"
	recurrent = false, -- Elman hidden layers
	tolfun = 1e-12, -- TolFun
	tolx = 1e-12, -- TolX, times the initial sigma
}

cmaes.task_keys = {
	POPSIZE = "pop_size",
	CMAES_POPSIZE = "pop_size",
	CMAES_SIGMA = "sigma",
	CMAES_SIGMA_MIN = "sigma_min",
	CMAES_RESTARTS = "restarts",
	CMAES_IPOP = "ipop",
	CMAES_SEPARABLE = "separable",
	CMAES_SEPARABLE_ABOVE = "separable_above",
	CMAES_BIAS = "bias",
	CMAES_HIDDEN_ACT = "hidden_act",
	CMAES_RECURRENT = "recurrent",
	CMAES_TOLFUN = "tolfun",
	CMAES_TOLX = "tolx",
}

local CHOICES = {
	separable = { auto = true, ["true"] = true, ["false"] = true },
	hidden_act = { tanh = true, sigmoid = true },
}

cmaes.ranges = {
	pop_size = common.POPULATION, sigma = { lo = 0, above = true },
	sigma_min = common.POSITIVE, restarts = { lo = 0, hi = 1000, int = true },
	separable_above = { lo = 0, hi = 2147483647, int = true },
	tolfun = common.POSITIVE, tolx = common.POSITIVE,
}

function cmaes.options_from_task(task)
	local o, unknown = common.options_from(task, "CMAES_", cmaes.task_keys, cmaes.defaults,
		common.choices(cmaes.task_keys, CHOICES), cmaes.ranges)
	local sigma = o.sigma or cmaes.defaults.sigma
	if o.sigma_min and o.sigma_min > sigma then
		error(string.format("CMAES_SIGMA_MIN: %s is more than the initial step size "
			.. "CMAES_SIGMA (%s)", tostring(o.sigma_min), tostring(sigma)), 0)
	end
	return o, unknown
end

---------------------------------------------------------------------------
-- The network

-- Number of weights of the network of shape g (a genome or new's args).
function cmaes.weight_count(n_in, n_out, layers, hidden, bias, recurrent)
	local w, prev, count = genetic.width(n_in, n_out, hidden), n_in, 0
	local b = bias and 1 or 0
	for _ = 1, layers do
		count = count + w * (prev + b + (recurrent and w or 0))
		prev = w
	end
	return count + n_out * (prev + b)
end

local WMAX = 127.99
local function clamp(x) return x > WMAX and WMAX or (x < -WMAX and -WMAX or x) end

-- Genome -> network table (learn.genetic's shape, plus context nodes when
-- recurrent; see the header).
function cmaes.to_net(g)
	local n_in, n_out, layers = g.inputs, g.outputs, g.layers
	local width = genetic.width(n_in, n_out, g.width)
	local w, bias, rec = g.weights, g.bias, g.recurrent
	assert(#w == cmaes.weight_count(n_in, n_out, layers, g.width, bias, rec),
		"to_net: wrong number of weights")
	local nodes, links, outputs_ids = {}, {}, {}
	local k = 0
	local function next_w()
		k = k + 1
		return clamp(w[k])
	end
	local ctx_first = n_in + n_out + layers * width
	-- the first output's ordering links to the context chains
	local out_links = {}
	if rec and layers > 0 then
		for l = 0, layers - 1 do
			out_links[#out_links + 1] = { from = ctx_first + l * width, to = n_in, weight = 0 }
		end
	end
	local prev_first, prev_count = 0, n_in
	for l = 0, layers do
		local hidden_layer = l < layers
		local count = hidden_layer and width or n_out
		local first = hidden_layer and n_in + n_out + l * width or n_in
		for j = 0, count - 1 do
			local id = first + j
			nodes[#nodes + 1] = { id = id, act = hidden_layer and g.hidden_act or "sigmoid",
				bias = bias and next_w() or 0 }
			if id == n_in then
				for _, lk in ipairs(out_links) do links[#links + 1] = lk end
			end
			for s = 0, prev_count - 1 do
				links[#links + 1] = { from = prev_first + s, to = id, weight = next_w() }
			end
			if rec and hidden_layer then
				for s = 0, count - 1 do
					links[#links + 1] = { from = ctx_first + l * width + s, to = id, weight = next_w() }
				end
			end
		end
		prev_first, prev_count = first, count
	end
	if rec then
		for l = 0, layers - 1 do
			local h, c = n_in + n_out + l * width, ctx_first + l * width
			for j = 0, width - 1 do
				nodes[#nodes + 1] = { id = c + j, act = "identity", bias = 0 }
				if j < width - 1 then
					links[#links + 1] = { from = c + j + 1, to = c + j, weight = 0 }
					links[#links + 1] = { from = h + j, to = c + j, weight = 1 }
				else
					for s = 0, width - 1 do
						links[#links + 1] = { from = h + s, to = c + j, weight = s == j and 1 or 0 }
					end
				end
			end
		end
	end
	for j = 0, n_out - 1 do outputs_ids[j + 1] = n_in + j end
	return { inputs = n_in, outputs = n_out, nodes = nodes, outputs_ids = outputs_ids, links = links }
end

cmaes.to_net_text = netfile.text

---------------------------------------------------------------------------
-- The strategy parameters (the tutorial's defaults)

-- The default parameters for dimension n and population lambda (and, when
-- separable, Ros & Hansen's c_1 and c_mu): a table of mu, weights, mueff,
-- cs, ds, cc, c1, cmu, chi_n (E||N(0, I)||) and the eigen-update gap.
function cmaes.parameters(n, lambda, separable)
	local mu = lambda // 2
	local weights, sum, sum2 = {}, 0, 0
	for i = 1, mu do
		weights[i] = math.log((lambda + 1) / 2) - math.log(i)
		sum = sum + weights[i]
	end
	for i = 1, mu do
		weights[i] = weights[i] / sum
		sum2 = sum2 + weights[i] * weights[i]
	end
	local mueff = 1 / sum2
	local p = { n = n, lambda = lambda, mu = mu, weights = weights, mueff = mueff }
	p.cs = (mueff + 2) / (n + mueff + 5)
	p.ds = 1 + 2 * math.max(0, math.sqrt((mueff - 1) / (n + 1)) - 1) + p.cs
	p.cc = (4 + mueff / n) / (n + 4 + 2 * mueff / n)
	p.c1 = 2 / ((n + 1.3) ^ 2 + mueff)
	p.cmu = math.min(1 - p.c1, 2 * (mueff - 2 + 1 / mueff) / ((n + 2) ^ 2 + mueff))
	if separable then
		local f = (n + 2) / 3
		p.c1 = p.c1 * f
		p.cmu = math.min(1 - p.c1, p.cmu * f)
	end
	p.chi_n = math.sqrt(n) * (1 - 1 / (4 * n) + 1 / (21 * n * n))
	p.eigen_gap = math.max(1, math.floor(1 / (10 * n * (p.c1 + p.cmu))))
	return p
end

function cmaes.default_lambda(n) return 4 + math.floor(3 * math.log(n)) end

---------------------------------------------------------------------------
-- The population

local Pop = {}
Pop.__index = Pop

-- Module-level: the separable-by-size message is said once per size.
local said = {}

-- A fresh strategy state (a start or a restart) with population lambda.
function Pop:start(lambda)
	local n = self.n
	self.lambda = lambda
	self.params = cmaes.parameters(n, lambda, self.separable)
	local m, pc, ps, D = {}, {}, {}, {}
	for i = 1, n do m[i], pc[i], ps[i], D[i] = 0.0, 0.0, 0.0, 1.0 end
	self.mean, self.pc, self.ps, self.D = m, pc, ps, D
	self.sigma = self.options.sigma
	if not self.separable then
		local C, B = {}, {}
		for i = 1, n * n do C[i], B[i] = 0.0, 0.0 end
		for i = 1, n do C[(i - 1) * n + i], B[(i - 1) * n + i] = 1.0, 1.0 end
		self.C, self.B = C, B
	else
		local C = {}
		for i = 1, n do C[i] = 1.0 end
		self.C, self.B = C, nil
	end
	self.eigen_generation = 0
	self.restart_generation = 0 -- generations since this start
	self.bests = {} -- each generation's best fitness since this start
	self:sample()
end

-- args: inputs, outputs, layers (default 1), hidden (HIDDEN), options, rng.
function cmaes.new(args)
	local o = common.merged(cmaes.defaults, args.options, "cmaes.new")
	local rng = args.rng or error("cmaes.new: an rng is required (learn.rng: random.new(seed))")
	local layers = args.layers or 1
	if o.recurrent and layers < 1 then
		error("CMAES_RECURRENT: the skill has no hidden layer (layers:0) to make recurrent", 0)
	end
	local n = cmaes.weight_count(args.inputs, args.outputs, layers, args.hidden, o.bias, o.recurrent)
	local separable = o.separable == "true"
	if o.separable == "auto" and n > o.separable_above then
		separable = true
		if not said[n] then
			said[n] = true
			io.stderr:write(string.format("CMAES: %d weights, more than %d: the separable (diagonal) "
				.. "CMA-ES; CMAES_SEPARABLE:false keeps the full covariance matrix, "
				.. "CMAES_SEPARABLE_ABOVE moves the limit\n", n, o.separable_above))
		end
	end
	local pop = setmetatable({
		options = o, inputs = args.inputs, outputs = args.outputs, layers = layers,
		width = args.hidden, rng = rng, generation = 0, evaluations = 0, species = {},
		n = n, separable = separable, restarts = 0, best = nil,
	}, Pop)
	local lambda = o.pop_size > 0 and o.pop_size or cmaes.default_lambda(n)
	pop.initial_lambda = lambda
	pop:start(lambda)
	return pop
end

-- B v, B an n x n matrix stored row-major.
local function times_B(B, n, v)
	local r = {}
	for i = 1, n do
		local s, row = 0.0, (i - 1) * n
		for j = 1, n do s = s + B[row + j] * v[j] end
		r[i] = s
	end
	return r
end

-- y = B D z (separable: D z).
local function transform(self, z)
	local n, D, B = self.n, self.D, self.B
	local dz = {}
	for j = 1, n do dz[j] = D[j] * z[j] end
	return B and times_B(B, n, dz) or dz
end

-- Draws the generation: ys (the steps y_k) and the genomes.
function Pop:sample()
	local n, rng, m, sigma = self.n, self.rng, self.mean, self.sigma
	local ys, popl = {}, {}
	for k = 1, self.lambda do
		local z = {}
		for i = 1, n do z[i] = rng:normal() end
		local y = transform(self, z)
		local x = {}
		for i = 1, n do x[i] = m[i] + sigma * y[i] end
		ys[k] = y
		popl[k] = { inputs = self.inputs, outputs = self.outputs, layers = self.layers,
			width = self.width, bias = self.options.bias, recurrent = self.options.recurrent,
			hidden_act = self.options.hidden_act, weights = x }
	end
	self.ys, self.population = ys, popl
end

function Pop:genomes() return self.population end

local better = genetic.better

-- C^(-1/2) y = B D^-1 B^T y.
local function inv_sqrt_times(self, y)
	local n, D, B = self.n, self.D, self.B
	local r = {}
	if not B then
		for i = 1, n do r[i] = y[i] / D[i] end
		return r
	end
	local t = {}
	for j = 1, n do
		local s = 0.0
		for i = 1, n do s = s + B[(i - 1) * n + j] * y[i] end
		t[j] = s / D[j]
	end
	return times_B(B, n, t)
end

-- B and D from C (evo.linalg); D is the square roots of C's eigenvalues.
function Pop:decompose()
	local linalg = require "evo.linalg"
	local values, vectors = linalg.eigh(self.n, self.C)
	local D = {}
	for i = 1, self.n do D[i] = math.sqrt(math.max(values[i], 1e-300)) end
	self.B, self.D = vectors, D
end

-- The restart criteria after a generation (see the header); the name of
-- the one that holds, or nil.
function Pop:should_restart(fitness)
	local n = self.n
	local window = 10 + math.ceil(30 * n / self.lambda)
	local bests, g = self.bests, #self.bests
	if g > window then
		local before, within = -math.huge, -math.huge
		for i = 1, g - window do if better(bests[i], before) then before = bests[i] end end
		for i = g - window + 1, g do if better(bests[i], within) then within = bests[i] end end
		if not better(within, before) then return "no improvement" end
	end
	if g >= window then
		local lo, hi = math.huge, -math.huge
		for i = g - window + 1, g do
			lo, hi = math.min(lo, bests[i]), math.max(hi, bests[i])
		end
		for _, f in ipairs(fitness) do lo, hi = math.min(lo, f), math.max(hi, f) end
		if hi - lo < self.options.tolfun then return "TolFun" end
	end
	local tolx = self.options.tolx * self.options.sigma
	local small = true
	for i = 1, n do
		local cii = self.separable and self.C[i] or self.C[(i - 1) * n + i]
		if self.sigma * math.max(math.sqrt(cii), math.abs(self.pc[i])) >= tolx then
			small = false
			break
		end
	end
	if small then return "TolX" end
	local dmax, dmin = 0, math.huge
	for i = 1, n do dmax, dmin = math.max(dmax, self.D[i]), math.min(dmin, self.D[i]) end
	if (dmax / dmin) ^ 2 > 1e14 then return "ConditionCov" end
	return nil
end

-- fitness[i] is the fitness of genomes()[i]: one generation of CMA-ES.
function Pop:tell(fitness)
	local popl, ys, n = self.population, self.ys, self.n
	assert(#fitness == #popl, "tell: one fitness per genome")
	self.evaluations = self.evaluations + #fitness
	local order = genetic.rank(fitness)
	local top = order[1]
	if not self.best or better(fitness[top], self.best.fitness) then
		self.best = { genome = common.deep_copy(popl[top]), fitness = fitness[top] }
	end
	local p = self.params
	local w, mu = p.weights, p.mu
	-- the weighted mean step and the new mean
	local yw = {}
	for i = 1, n do
		local s = 0.0
		for r = 1, mu do s = s + w[r] * ys[order[r]][i] end
		yw[i] = s
	end
	local m, sigma = self.mean, self.sigma
	for i = 1, n do m[i] = m[i] + sigma * yw[i] end
	-- step-size path
	local cs, ps = p.cs, self.ps
	local a = math.sqrt(cs * (2 - cs) * p.mueff)
	local cy = inv_sqrt_times(self, yw)
	local ps_norm2 = 0.0
	for i = 1, n do
		ps[i] = (1 - cs) * ps[i] + a * cy[i]
		ps_norm2 = ps_norm2 + ps[i] * ps[i]
	end
	local ps_norm = math.sqrt(ps_norm2)
	self.restart_generation = self.restart_generation + 1
	local g = self.restart_generation
	local hsig = ps_norm / math.sqrt(1 - (1 - cs) ^ (2 * g)) < (1.4 + 2 / (n + 1)) * p.chi_n
	-- covariance path
	local cc, pc = p.cc, self.pc
	local b = hsig and math.sqrt(cc * (2 - cc) * p.mueff) or 0.0
	for i = 1, n do pc[i] = (1 - cc) * pc[i] + b * yw[i] end
	-- covariance matrix
	local c1, cmu = p.c1, p.cmu
	local delta = hsig and 0.0 or cc * (2 - cc)
	local keep = 1 + c1 * delta - c1 - cmu
	local C = self.C
	if self.separable then
		for i = 1, n do
			local s = 0.0
			for r = 1, mu do
				local y = ys[order[r]][i]
				s = s + w[r] * y * y
			end
			C[i] = keep * C[i] + c1 * pc[i] * pc[i] + cmu * s
		end
	else
		local sel = {}
		for r = 1, mu do sel[r] = ys[order[r]] end
		for i = 1, n do
			local row = (i - 1) * n
			for j = i, n do
				local s = 0.0
				for r = 1, mu do s = s + w[r] * sel[r][i] * sel[r][j] end
				local v = keep * C[row + j] + c1 * pc[i] * pc[j] + cmu * s
				C[row + j] = v
				C[(j - 1) * n + i] = v
			end
		end
	end
	-- step size, then its lower bound
	sigma = sigma * math.exp((cs / p.ds) * (ps_norm / p.chi_n - 1))
	if sigma < self.options.sigma_min then sigma = self.options.sigma_min end
	self.sigma = sigma
	-- B and D
	if self.separable then
		for i = 1, n do self.D[i] = math.sqrt(math.max(C[i], 1e-300)) end
	elseif g - self.eigen_generation >= p.eigen_gap then
		self.eigen_generation = g
		self:decompose()
	end
	self.bests[#self.bests + 1] = fitness[top]
	self.generation = self.generation + 1
	local why = self:should_restart(fitness)
	if why and self.restarts < self.options.restarts then
		self.restarts = self.restarts + 1
		local lambda = self.options.ipop and math.min(2 * self.lambda, 10000) or self.lambda
		self.last_restart = { generation = self.generation, why = why, lambda = lambda }
		self:start(lambda)
	else
		self:sample()
	end
end

---------------------------------------------------------------------------
-- Checkpoints

function cmaes.save(pop, shared)
	return common.save(pop, "evo-cmaes-1", shared)
end

function cmaes.load(t, rng)
	return common.load(t, "evo-cmaes-1", Pop, rng, random.load)
end

-- The population's class (MAP-Elites' CMA-ME emitters are CMA-ES states).
cmaes.Pop = Pop

return cmaes

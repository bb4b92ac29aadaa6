-- Unit tests of lua/learn/cmaes.lua, run by tests/sim/lua/test_lua_scripts.c
-- (which registers evo.linalg, as the learning loop does). Each entry of
-- the returned table is one test; it fails by raising.
local cmaes = require "learn.cmaes"
local random = require "learn.rng"
local serialize = require "learn.serialize"
local linalg = require "evo.linalg"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local function near(a, b, tol, what)
	check(math.abs(a - b) <= tol, string.format("%s: %.17g, expected %.17g", what, a, b))
end

local T = {}

-- The tutorial's defaults (Hansen 2016, table 1, positive weights only)
-- for n = 42, worked out from its formulas outside evo:
-- lambda = 4 + floor(3 ln 42) = 4 + floor(11.21) = 15, mu = 7,
-- w_i = (ln 8 - ln i) / sum_j (ln 8 - ln j), mueff = 1 / sum w_i^2,
-- c_sigma = (mueff + 2) / (n + mueff + 5), d_sigma = 1 + c_sigma (the max
-- term is 0), c_c = (4 + mueff/n) / (n + 4 + 2 mueff/n),
-- c_1 = 2 / ((n + 1.3)^2 + mueff),
-- c_mu = 2 (mueff - 2 + 1/mueff) / ((n + 2)^2 + mueff).
function T.default_parameters_are_the_tutorials_for_n_42()
	check(cmaes.default_lambda(42) == 15, "lambda")
	local p = cmaes.parameters(42, 15)
	check(p.mu == 7, "mu")
	local w = { 0.34479619859202054, 0.22986413239468034, 0.16263318353883477,
		0.11493206619734017, 0.077932205084962236, 0.047701117341494591,
		0.022141096850667188 }
	for i = 1, 7 do near(p.weights[i], w[i], 1e-12, "w" .. i) end
	near(p.mueff, 4.5409152090759575, 1e-12, "mueff")
	near(p.cs, 0.12690723830849152, 1e-12, "c_sigma")
	near(p.ds, 1.1269072383084915, 1e-12, "d_sigma")
	near(p.cc, 0.088889047594612136, 1e-12, "c_c")
	near(p.c1, 0.0010641519109934998, 1e-12, "c_1")
	near(p.cmu, 0.0028457376094919236, 1e-12, "c_mu")
	-- a population of 15 from POPSIZE's default, 4 + floor(3 ln n)
	local pop = cmaes.new{ inputs = 6, outputs = 1, layers = 1, hidden = 6,
		options = { bias = false }, rng = random.new(1) }
	check(pop.n == 42 and #pop:genomes() == 15, "n = 42 weights, 15 genomes")
end

-- [[2,1,0],[1,2,1],[0,1,2]] has eigenvalues 2 - sqrt 2, 2, 2 + sqrt 2 with
-- eigenvectors (1, -sqrt 2, 1)/2, (1, 0, -1)/sqrt 2, (1, sqrt 2, 1)/2.
function T.eigh_of_a_hand_worked_3x3()
	local values, vectors = linalg.eigh(3, { 2, 1, 0, 1, 2, 1, 0, 1, 2 })
	local r2 = math.sqrt(2)
	local expect = {
		{ 2 - r2, { 0.5, -r2 / 2, 0.5 } }, { 2, { 1 / r2, 0, -1 / r2 } },
		{ 2 + r2, { 0.5, r2 / 2, 0.5 } } }
	for _, e in ipairs(expect) do
		local found = false
		for j = 1, 3 do
			if math.abs(values[j] - e[1]) < 1e-12 then
				found = true
				-- the same vector up to sign
				local dot = 0
				for i = 1, 3 do dot = dot + vectors[(i - 1) * 3 + j] * e[2][i] end
				near(math.abs(dot), 1, 1e-12, "eigenvector of " .. e[1])
			end
		end
		check(found, "eigenvalue " .. e[1])
	end
end

-- Minimise f (fitness -f) from the weights of a net of n weights: a
-- genome's weights are the point. Returns evaluations to reach f < target
-- (or nil), the population.
local function minimise(f, n_in, options, target, max_evals, seed)
	-- a layers:0 net with n_in inputs, 1 output, no bias has n_in weights
	local o = { bias = false, restarts = 0 }
	for k, v in pairs(options or {}) do o[k] = v end
	local pop = cmaes.new{ inputs = n_in, outputs = 1, layers = 0, options = o, rng = random.new(seed or 7) }
	while pop.evaluations < max_evals do
		local fit = {}
		for i, g in ipairs(pop:genomes()) do fit[i] = -f(g.weights) end
		pop:tell(fit)
		if -pop.best.fitness < target then return pop.evaluations, pop end
	end
	return nil, pop
end

local function sphere(x)
	local s = 0
	for _, v in ipairs(x) do s = s + v * v end
	return s
end

-- The sphere in 10-D, optimum at (1, ..., 1), from 0 with sigma 0.5:
-- CMA-ES's published cost to 1e-10 is about 1,500-1,700 evaluations for
-- n = 10 (evo: 1,490-1,690 over seeds 1-5). Between 1,000 and 2,500.
function T.converges_on_the_shifted_sphere()
	local evals = minimise(function(x)
		local s = 0
		for _, v in ipairs(x) do s = s + (v - 1) ^ 2 end
		return s
	end, 10, { sigma = 0.5 }, 1e-10, 2500)
	check(evals, "sphere 10-D not solved in 2,500 evaluations")
	check(evals > 1000, "suspiciously fast: " .. tostring(evals))
end

-- Rosenbrock in 10-D: the published cost of CMA-ES to 1e-10 is of the
-- order of 6,000-7,000 evaluations for n = 10 (Hansen & Ostermeier 2001;
-- evo: 5,860-7,210 over seeds 1-5). At most 10,000.
function T.converges_on_rosenbrock()
	local evals = minimise(function(x)
		local s = 0
		for i = 1, #x - 1 do s = s + 100 * (x[i] ^ 2 - x[i + 1]) ^ 2 + (x[i] - 1) ^ 2 end
		return s
	end, 10, { sigma = 0.5 }, 1e-10, 10000)
	check(evals, "Rosenbrock 10-D not solved in 10,000 evaluations")
end

-- A rotated ellipsoid (condition 1e6) in 8-D: the full covariance learns
-- the rotation; the order published is ~ 10 n^2 evaluations.
function T.converges_on_a_rotated_ellipsoid()
	local n = 8
	-- a fixed rotation: the eigenvectors of a symmetric matrix
	local a = {}
	for i = 1, n do for j = 1, n do a[(i - 1) * n + j] = 1 / (i + j - 1) + (i == j and 1 or 0) end end
	local _, R = linalg.eigh(n, a)
	local evals = minimise(function(x)
		local s = 0
		for i = 1, n do
			local y = 0
			for j = 1, n do y = y + R[(j - 1) * n + i] * x[j] end
			s = s + 1e6 ^ ((i - 1) / (n - 1)) * y * y
		end
		return s
	end, n, { sigma = 1 }, 1e-10, 8000)
	check(evals, "rotated ellipsoid not solved in 8,000 evaluations")
end

-- sigma never goes below CMAES_SIGMA_MIN, even on the sphere where it
-- would shrink to nothing.
function T.sigma_bound_holds()
	local _, pop = minimise(sphere, 5, { sigma = 1, sigma_min = 0.01 }, -1, 2000)
	check(pop.sigma >= 0.01, "sigma " .. pop.sigma)
	near(pop.sigma, 0.01, 0, "sigma sits on its bound")
end

-- A restart (here TolX on the sphere) doubles lambda with CMAES_IPOP, and
-- keeps it without.
function T.ipop_doubles_lambda_on_restart()
	local _, pop = minimise(sphere, 5, { sigma = 1, restarts = 1, tolx = 1e-6 }, -1, 3000)
	check(pop.restarts == 1, "one restart, found " .. pop.restarts)
	check(pop.lambda == 2 * cmaes.default_lambda(5), "lambda doubled: " .. pop.lambda)
	check(#pop:genomes() == pop.lambda, "the population has the new size")
	local _, same = minimise(sphere, 5, { sigma = 1, restarts = 1, tolx = 1e-6, ipop = false }, -1, 3000)
	check(same.restarts == 1 and same.lambda == cmaes.default_lambda(5), "without IPOP, lambda kept")
end

-- Above CMAES_SEPARABLE_ABOVE weights the diagonal variant runs, by size
-- or by key.
function T.separable_by_size_and_by_key()
	local small = cmaes.new{ inputs = 5, outputs = 1, layers = 1, options = {}, rng = random.new(1) }
	check(not small.separable and small.B, "36 weights: full covariance")
	local said = {}
	local stderr = io.stderr
	io.stderr = { write = function(_, ...) for _, x in ipairs{ ... } do said[#said + 1] = x end end }
	local ok, big = pcall(cmaes.new, { inputs = 5, outputs = 1, layers = 1,
		options = { separable_above = 20 }, rng = random.new(1) })
	io.stderr = stderr
	check(ok and big.separable and not big.B, "above 20: diagonal")
	check(table.concat(said) == "CMAES: 36 weights, more than 20: the separable (diagonal) CMA-ES; "
		.. "CMAES_SEPARABLE:false keeps the full covariance matrix, CMAES_SEPARABLE_ABOVE moves "
		.. "the limit\n", "the message: " .. table.concat(said))
	local forced = cmaes.new{ inputs = 5, outputs = 1, layers = 1,
		options = { separable = "false", separable_above = 20 }, rng = random.new(1) }
	check(not forced.separable, "CMAES_SEPARABLE:false keeps the full matrix")
	local evals = minimise(sphere, 20, { separable = "true", sigma = 1 }, 1e-10, 8000)
	check(evals, "separable CMA-ES solves the 20-D sphere")
end

-- A checkpoint mid-run (through serialize's text, as evo writes it)
-- continues bit for bit.
function T.save_load_continues_bit_exact()
	local function f(x)
		local s = 0
		for i = 1, #x - 1 do s = s + 100 * (x[i] ^ 2 - x[i + 1]) ^ 2 + (x[i] - 1) ^ 2 end
		return s
	end
	local function step(p)
		local fit = {}
		for i, g in ipairs(p:genomes()) do fit[i] = -f(g.weights) end
		p:tell(fit)
	end
	local a = cmaes.new{ inputs = 6, outputs = 1, layers = 0, options = { bias = false },
		rng = random.new(3) }
	for _ = 1, 25 do step(a) end
	local b = cmaes.load(serialize.load(serialize.dump(cmaes.save(a)), "checkpoint"))
	for _ = 1, 25 do step(a); step(b) end
	check(serialize.dump(cmaes.save(a)) == serialize.dump(cmaes.save(b)), "states differ")
end

function T.options_from_task_checks_keys()
	local o, unknown = cmaes.options_from_task { CMAES_SIGMA = "0.3", CMAES_BIAS = "false",
		CMAES_HIDDEN_ACT = "sigmoid", CMAES_NOPE = "1", POPSIZE = "20" }
	check(o.sigma == 0.3 and o.bias == false and o.hidden_act == "sigmoid" and o.pop_size == 20, "values")
	check(#unknown == 1 and unknown[1] == "CMAES_NOPE", "unknown CMAES_ keys")
	local function err(t)
		local ok, e = pcall(cmaes.options_from_task, t)
		check(not ok, "accepted")
		return e
	end
	check(err { CMAES_SIGMA = "0" }:match("^CMAES_SIGMA: expected a number above 0"), "sigma 0")
	check(err { CMAES_HIDDEN_ACT = "relu" }:match("^CMAES_HIDDEN_ACT: expected sigmoid, tanh"), "act")
	check(err { CMAES_SEPARABLE = "maybe" }:match("^CMAES_SEPARABLE: expected auto, false, true"), "sep")
	check(err { CMAES_SIGMA = "0.1", CMAES_SIGMA_MIN = "0.2" }:match("^CMAES_SIGMA_MIN: "), "min > sigma")
end

-- The network: bias-free nodes have bias 0; weights past the .net limit
-- are clamped in the network and kept in the genome.
function T.to_net_without_bias_and_clamped()
	local pop = cmaes.new{ inputs = 2, outputs = 1, layers = 1, hidden = 3,
		options = { bias = false }, rng = random.new(1) }
	local g = pop:genomes()[1]
	check(#g.weights == 3 * 2 + 1 * 3, "9 weights")
	g.weights[1] = 500
	local net = cmaes.to_net(g)
	check(#net.nodes == 4 and #net.links == 9, "4 nodes, 9 links")
	for _, nd in ipairs(net.nodes) do check(nd.bias == 0, "bias 0") end
	check(net.nodes[1].act == "tanh" and net.nodes[4].act == "sigmoid", "tanh hidden, sigmoid out")
	check(net.links[1].weight == 127.99 and g.weights[1] == 500, "clamped in the net only")
end

return T

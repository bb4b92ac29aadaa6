-- OPENENDED's environment generators (docs/openended.md): what a generator
-- file shares with the coevolution loop. The same file runs in two places:
-- in every worker's scene, where openended.env turns the generator into an
-- environment that builds, at each episode, the genome the loop chose
-- (scene:genome()); and in the loop (lua/learn/openended.lua), which calls
-- the generator's seed, mutate, size and valid on genomes.
--
-- A genome is plain data: a table of numbers, strings, booleans and such
-- tables. It travels as text (openended.encode), the same text for the
-- same genome, so the loop can tell a new environment from an old one.
local openended = {}

local function write(v, out)
	local t = type(v)
	if t == "number" then
		out[#out + 1] = math.type(v) == "integer" and tostring(v) or string.format("%.17g", v)
	elseif t == "string" then
		out[#out + 1] = string.format("%q", v)
	elseif t == "boolean" then
		out[#out + 1] = tostring(v)
	elseif t == "table" then
		local keys = {}
		for k in pairs(v) do
			if math.type(k) ~= "integer" or k < 1 or k > #v then keys[#keys + 1] = k end
		end
		table.sort(keys, function(a, b) return tostring(a) < tostring(b) end)
		out[#out + 1] = "{"
		for i = 1, #v do write(v[i], out); out[#out + 1] = "," end
		for _, k in ipairs(keys) do
			if type(k) ~= "string" or not k:match("^[%a_][%w_]*$") then
				error("a genome's keys are names, found " .. tostring(k), 3)
			end
			out[#out + 1] = k .. "="
			write(v[k], out)
			out[#out + 1] = ","
		end
		out[#out + 1] = "}"
	else
		error("a genome holds numbers, strings, booleans and tables, found a " .. t, 3)
	end
end

-- Genome -> text (a Lua table constructor, keys sorted).
function openended.encode(genome)
	local out = {}
	write(genome, out)
	return table.concat(out)
end

-- Text -> genome; `what` names the text in errors.
function openended.decode(text, what)
	local f, err = load("return " .. text, "=" .. (what or "genome"), "t", {})
	if not f then error(err, 0) end
	return f()
end

-- The environment of generator `gen` (docs/openended.md, "A generator"):
-- gen.init(scene, task) makes the bot, the goal and the rewards once;
-- at every episode gen.build(scene, genome) returns the episode's
-- obstacles and places what init made; the episode lasts gen.ticks(genome)
-- ticks at most (TICKLIM caps it) and is solved when gen.solved(scene,
-- bot). Outside an OPENENDED run (evo run of a DEMOSIM task) the genome
-- is gen.seed()'s. env.generator is gen.
openended.FUNCTIONS = { "seed", "mutate", "size", "valid", "ticks", "init", "build", "solved" }

function openended.env(gen)
	if type(gen) ~= "table" then
		error("openended.env(gen): gen is a table of the generator's functions (docs/openended.md), "
			.. "not a " .. type(gen), 2)
	end
	for _, f in ipairs(openended.FUNCTIONS) do
		if type(gen[f]) ~= "function" then
			error(string.format("openended.env(gen): the generator has no function %s "
				.. "(it needs %s: docs/openended.md)", f, table.concat(openended.FUNCTIONS, ", ")), 2)
		end
	end
	local env = { generator = gen }
	local genome, ticks, limit
	function env.init(scene, task)
		limit = tonumber(task.TICKLIM)
		gen.init(scene, task)
		scene:control(function(s) return s:tick() >= ticks end)
	end
	function env.obstacles(scene)
		local text = scene:genome()
		genome = text and openended.decode(text, "scene:genome()") or gen.seed()
		ticks = gen.ticks(genome)
		if math.type(ticks) ~= "integer" or ticks < 1 then
			error(string.format("the generator's ticks returned %s, not a whole number of ticks above 0",
				tostring(ticks)), 0)
		end
		if limit and limit < ticks then ticks = limit end
		return gen.build(scene, genome)
	end
	function env.solved(scene, bot) return gen.solved(scene, bot, genome) end
	return env
end

return openended

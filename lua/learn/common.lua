-- What every learning method shares: reading its settings from a task and
-- saving its whole state for a checkpoint. The methods' random generator
-- is learn.rng, and their .net writer learn.netfile.
local common = {}

-- A copy of plain data (numbers, strings, booleans, tables).
function common.deep_copy(v)
	-- a userdata that stands for plain data (evo.neat's genes) gives it
	local mt = type(v) == "userdata" and getmetatable(v)
	if mt and mt.__plain then return mt.__plain(v) end
	if type(v) ~= "table" then
		assert(type(v) ~= "function" and type(v) ~= "userdata", "save: not plain data")
		return v
	end
	local t = {}
	for k, x in pairs(v) do t[k] = common.deep_copy(x) end
	return t
end

-- The numbers an option takes: { lo, hi } (either may be nil), with
-- int = true for a whole number and above = true / below = true when the
-- bound itself is excluded. Its words, for messages: "a number from 0 to 1".
-- A method's options: its defaults, with the caller's options over them;
-- a name the defaults lack is an error naming `who` ("cmaes.new").
function common.merged(defaults, user, who)
	local o = {}
	for k, v in pairs(defaults) do o[k] = v end
	for k, v in pairs(user or {}) do
		if defaults[k] == nil then error(who .. ": unknown option " .. tostring(k), 0) end
		o[k] = v
	end
	return o
end

function common.range_text(r)
	local what = r.int and "a whole number" or "a number"
	local lo, hi = r.lo and string.format("%.17g", r.lo), r.hi and string.format("%.17g", r.hi)
	if lo and hi then
		if not r.above and not r.below then return what .. " from " .. lo .. " to " .. hi end
		return what .. (r.above and " above " or " of at least ") .. lo
			.. (r.below and " and below " or " and at most ") .. hi
	elseif lo then
		return what .. (r.above and " above " .. lo or " of " .. lo .. " or more")
	elseif hi then
		return what .. (r.below and " below " .. hi or " of " .. hi .. " or less")
	end
	return what
end

local function in_range(v, r)
	if v ~= v or v == math.huge or v == -math.huge then return false end
	if r.int and v ~= math.floor(v) then return false end
	if r.lo and (v < r.lo or (r.above and v == r.lo)) then return false end
	if r.hi and (v > r.hi or (r.below and v == r.hi)) then return false end
	return true
end

-- A value of .simbatch key `key` for an option whose default is `default`:
-- a number (finite, and within `range` when there is one), a boolean, or a
-- lower-case string that check(key, s) may refuse by raising. Messages
-- start with the key, so the caller can add where it is.
local function parse_value(key, default, value, check, range)
	local t = type(default)
	if t == "number" then
		local v = tonumber(value)
		local r = range or {}
		if not v or not in_range(v, r) then
			error(key .. ": expected " .. (range and common.range_text(r) or "a number") .. ", found '"
				.. tostring(value) .. "'", 0)
		end
		return v
	elseif t == "boolean" then
		if value == true or value == false then return value end
		local s = tostring(value):lower()
		if s == "1" or s == "true" or s == "yes" then return true end
		if s == "0" or s == "false" or s == "no" then return false end
		error(key .. ": expected true or false, found '" .. tostring(value) .. "'", 0)
	end
	local s = tostring(value):lower()
	if check then check(key, s, value) end
	return s
end

-- Options from a task table (.simbatch key -> value) through `keys` (key ->
-- option name) over `defaults`, each number within `ranges[name]` (option
-- name -> range, as range_text reads it). Returns the options and the
-- sorted list of keys starting with `prefix` that no option takes (the
-- caller warns); raises on a malformed value, the message starting with
-- the key.
function common.options_from(task, prefix, keys, defaults, check, ranges)
	local names = {}
	for k in pairs(task) do names[#names + 1] = k end
	table.sort(names, function(a, b) return tostring(a) < tostring(b) end)
	local opts, unknown = {}, {}
	for _, k in ipairs(names) do
		local name = keys[k]
		if name then
			opts[name] = parse_value(k, defaults[name], task[k], check, ranges and ranges[name])
		elseif type(k) == "string" and k:sub(1, #prefix) == prefix then
			unknown[#unknown + 1] = k
		end
	end
	return opts, unknown
end

-- A check for options_from: a key whose option (keys[key]) has a list
-- of words in `choices` (option name -> set of words) takes one of them;
-- else "KEY: expected a, b, found 'x'".
function common.choices(keys, choices)
	return function(key, s, value)
		local allowed = choices[keys[key]]
		if allowed and not allowed[s] then
			local list = {}
			for k in pairs(allowed) do list[#list + 1] = k end
			table.sort(list)
			error(key .. ": expected " .. table.concat(list, ", ") .. ", found '"
				.. tostring(value) .. "'", 0)
		end
	end
end

-- The learning methods and their modules; every module has the same
-- interface: options_from_task, new, genomes/tell, best, species,
-- save/load, to_net, to_net_text.
common.MODULES = { NEAT = "learn.neat", GENETIC = "learn.genetic", ANNEALING = "learn.annealing",
	CMAES = "learn.cmaes", NOVELTY = "learn.novelty", MAPELITES = "learn.mapelites" }

-- Where key `key` of a task is, for messages: "path:line", or "path" when
-- the key is not in the file. `lines` maps each key of the task to its line.
function common.where(path, lines, key)
	local line = key and lines[key]
	return path .. (line and ":" .. line or "")
end

-- A warning on a task, at the line of `key`, on stderr, in the form the
-- task reader's own warnings take (sim/mind/task.c): "warning: path:line: msg".
-- Under evo, the host prints it and counts it (evo check ends with the count).
function common.warning(path, lines, key, msg)
	local text = common.where(path, lines, key) .. ": " .. msg
	local host = package.loaded["evo.learn"]
	if host and host.warning then
		host.warning(text)
	else
		io.stderr:write("warning: ", text, "\n")
	end
end

-- The prefix of each method's own keys: the .simbatch reader keeps every
-- key that starts with one (core/src/parse_simbatch.c).
common.PREFIXES = { NEAT = "NEAT_", GENETIC = "GA_", ANNEALING = "SA_", CMAES = "CMAES_",
	NOVELTY = "NOVELTY_", MAPELITES = "MAPELITES_" }

-- Does `algo` read task key `key`: its own keys, and those of the other
-- method it builds on (NOVELTY reads NEAT's: algo.other_keys)?
function common.reads(algo, key)
	return algo.task_keys[key] ~= nil or (algo.other_keys ~= nil and algo.other_keys[key] ~= nil)
end

-- Levenshtein distance between two strings.
local function distance(a, b)
	local prev = {}
	for j = 0, #b do prev[j] = j end
	for i = 1, #a do
		local cur = { [0] = i }
		for j = 1, #b do
			local cost = a:byte(i) == b:byte(j) and 0 or 1
			cur[j] = math.min(prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost)
		end
		prev = cur
	end
	return prev[#b]
end

-- The key of `keys` (key -> anything) closest to `key`, the first in
-- sorted order among equals: the reader's "did you mean".
function common.closest(key, keys)
	local names = {}
	for k in pairs(keys) do names[#names + 1] = k end
	table.sort(names)
	local best, best_d
	for _, k in ipairs(names) do
		local d = distance(key, k)
		if not best_d or d < best_d then best, best_d = k, d end
	end
	return best
end

-- The options of `algo` (a method's module) from a task, as `evo run` and
-- `evo check` read them (quiet: without the warnings, for evo run's check
-- before it starts). The methods' messages start with the key; a
-- malformed value raises "path:line: KEY: ...". Every key the method
-- ignores is a warning at its line, in line order: a key with the
-- method's prefix that it does not know (with the closest it knows), a
-- key of another method, POPSIZE for a method without a population and
-- HIDDEN for NEAT, which grows its own hidden nodes.
function common.task_options(algo, task, path, lines, quiet)
	local ok, options, unknown = pcall(algo.options_from_task, task)
	if not ok then
		local key = tostring(options):match("^([%w_]+): ")
		error(common.where(path, lines, key) .. ": " .. tostring(options), 0)
	end
	local method = tostring(task.LEARNINGMETHOD or "NEAT"):upper()
	local warnings = {}
	local known = {}
	for name in pairs(algo.task_keys) do known[name] = true end
	for name in pairs(algo.other_keys or {}) do known[name] = true end
	for _, k in ipairs(unknown) do
		warnings[#warnings + 1] = { k, string.format("unknown key '%s' ignored; did you mean %s?", k,
			common.closest(k, known)) }
	end
	local unread = {}
	for _, k in ipairs(unknown) do unread[k] = true end
	for k in pairs(task) do
		if type(k) == "string" and not common.reads(algo, k) and not unread[k] then
			for other, prefix in pairs(common.PREFIXES) do
				if other ~= method and k:sub(1, #prefix) == prefix then
					warnings[#warnings + 1] = { k, string.format("%s ignored: it is a setting of "
						.. "%s, and this task trains with %s", k, other, method) }
				end
			end
			if k == "HIDDEN" and (method == "NEAT" or method == "NOVELTY") then
				warnings[#warnings + 1] = { k, "HIDDEN is the width of the hidden layers of "
					.. "GENETIC, ANNEALING and CMAES; NEAT grows its own and ignores it" }
			end
			if k == "POPSIZE" then
				warnings[#warnings + 1] = { k, string.format("POPSIZE ignored: %s has no population "
					.. "(it moves one network at a time)", method) }
			end
		end
	end
	table.sort(warnings, function(a, b)
		local la, lb = lines[a[1]] or 0, lines[b[1]] or 0
		if la ~= lb then return la < lb end
		return a[1] < b[1]
	end)
	if not quiet then
		for _, w in ipairs(warnings) do common.warning(path, lines, w[1], w[2]) end
	end
	return options
end

-- Two scores as text to print side by side: one decimal when that tells
-- them apart (or they are equal), else as many more as it takes, so that
-- "champion 1.2, current 1.2 ... replaced" cannot happen.
function common.two_scores(a, b)
	for d = 1, 15 do
		local sa, sb = string.format("%." .. d .. "f", a), string.format("%." .. d .. "f", b)
		if sa ~= sb or a == b then return sa, sb end
	end
	return string.format("%.17g", a), string.format("%.17g", b)
end

-- Ranges every method shares. A whole number has an upper bound that keeps
-- memory and time bounded, and that no real task meets: a population of at
-- most 10,000 networks (the task's POPSIZE takes as many,
-- core/src/parse_simbatch.c), a count that fits an int.
common.PROB = { lo = 0, hi = 1 } -- a probability
common.POSITIVE = { lo = 0 } -- a size of step, a weight of distance
common.COUNT = { lo = 1, hi = 2147483647, int = true } -- generations, a size
common.WHOLE = { lo = 0, hi = 2147483647, int = true } -- a count that may be 0
common.POPULATION = { lo = 1, hi = 10000, int = true } -- networks in a generation
common.WEIGHT_MAX = { lo = 0, hi = 128, above = true, below = true } -- .net needs |w| < 128

-- A population as a plain table tagged with `format`, its rng's state
-- included. With `shared`, the table holds the population's own tables
-- instead of copies: it is for writing out at once (a checkpoint of a
-- population of 1,000 is written every generation), before the
-- population changes again.
function common.save(pop, format, shared)
	local t = {}
	for k, v in pairs(pop) do
		if k ~= "rng" then t[k] = shared and v or common.deep_copy(v) end
	end
	t.rng = pop.rng.save and pop.rng:save() or error("save: the rng has no save()")
	t.format = format
	return t
end

-- The reverse of common.save: a population with metatable `class`. Give
-- `rng` to use another rng object; by default one restored with
-- rng_load(t.rng).
function common.load(t, format, class, rng, rng_load)
	if type(t) ~= "table" or t.format ~= format then
		error(string.format("the checkpoint holds %s, not %s: another learning method's, or an "
			.. "older evo's", type(t) == "table" and tostring(t.format) or type(t), format), 0)
	end
	local pop = setmetatable({}, class)
	for k, v in pairs(t) do
		if k ~= "rng" and k ~= "format" then pop[k] = common.deep_copy(v) end
	end
	pop.rng = rng or rng_load(t.rng)
	return pop
end

return common

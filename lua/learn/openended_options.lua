-- OPENENDED's own keys (docs/openended.md): their defaults and ranges, and
-- their check, which `evo check` and the loop (lua/learn/openended.lua)
-- both run: an unknown OPEN_ key, a value out of range or a LEARNINGMETHOD
-- other than NEAT stops at its line in the task file.
local common = require "learn.common"

local KEYS = {
	OPEN_ENVS = { 20, 1, 10000 }, OPEN_AGENTS = { 20, 1, 10000 },
	OPEN_ENV_BATCH = { 4, 1, 1000 }, OPEN_AGENT_BATCH = { 8, 1, 1000 },
	OPEN_RESOURCE = { 5, 1, 1000000 }, OPEN_BOOTSTRAP = { 20, 1, 10000 },
}

-- The task's OPEN_ options, each its value or its default, by key.
return function(task, path, lines)
	local function where(key) return common.where(path, lines, key) end
	local keys = {}
	for k in pairs(task) do
		if type(k) == "string" then keys[#keys + 1] = k end
	end
	table.sort(keys)
	for _, k in ipairs(keys) do
		if k:sub(1, 5) == "OPEN_" and not KEYS[k] then
			local names = {}
			for name in pairs(KEYS) do names[#names + 1] = name end
			table.sort(names)
			error(string.format("%s: unknown key %s (OPENENDED takes %s)", where(k), k,
				table.concat(names, ", ")), 0)
		end
	end
	if task.LEARNINGMETHOD and task.LEARNINGMETHOD:upper() ~= "NEAT" then
		error(string.format("%s: OPENENDED's agents are NEAT genomes: LEARNINGMETHOD must be "
			.. "NEAT or left out, found %s", where("LEARNINGMETHOD"), task.LEARNINGMETHOD), 0)
	end
	local o, names = {}, {}
	for key in pairs(KEYS) do names[#names + 1] = key end
	table.sort(names)
	for _, key in ipairs(names) do
		local d = KEYS[key]
		local v = task[key]
		local n = v == nil and d[1] or math.tointeger(tonumber(v))
		if not n or n < d[2] or n > d[3] then
			error(string.format("%s: %s must be a whole number from %d to %d, found '%s'",
				where(key), key, d[2], d[3], tostring(v)), 0)
		end
		o[key] = n
	end
	return o
end

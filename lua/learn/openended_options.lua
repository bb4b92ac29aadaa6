-- OPENENDED's own keys (docs/openended.md, "OPENENDED's parameters"):
-- their options, defaults and ranges in the shape of a learning method's
-- (task_keys, defaults, ranges, options_from_task), so docs and code are
-- checked against each other as the methods' are; and check, which `evo
-- check` and the loop (lua/learn/openended.lua) both run: an unknown
-- OPEN_ key, a value out of range or a LEARNINGMETHOD other than NEAT
-- stops at its line in the task file.
local common = require "learn.common"

local M = {}

M.defaults = {
	envs = 20,        -- environments kept
	agents = 20,      -- agents kept
	env_batch = 4,    -- new environments tried per batch
	agent_batch = 8,  -- new agents tried per batch
	resource = 5,     -- agents an environment may admit
	bootstrap = 20,   -- rounds of the bootstrap at most
	retention = 0,    -- batches between full retention checks (0: none)
}

M.task_keys = {
	OPEN_ENVS = "envs", OPEN_AGENTS = "agents", OPEN_ENV_BATCH = "env_batch",
	OPEN_AGENT_BATCH = "agent_batch", OPEN_RESOURCE = "resource",
	OPEN_BOOTSTRAP = "bootstrap", OPEN_RETENTION = "retention",
}

local SOME = { lo = 1, hi = 10000, int = true }
M.ranges = {
	envs = SOME, agents = SOME, bootstrap = SOME,
	env_batch = { lo = 1, hi = 1000, int = true },
	agent_batch = { lo = 1, hi = 1000, int = true },
	resource = common.COUNT,
	retention = { lo = 0, hi = 1000000, int = true },
}

function M.options_from_task(task)
	return common.options_from(task, "OPEN_", M.task_keys, M.defaults, nil, M.ranges)
end

-- The task's options (by option name, defaults filled in), or an error at
-- the line of the key at fault.
function M.check(task, path, lines)
	local ok, o, unknown = pcall(M.options_from_task, task)
	if not ok then
		local key = tostring(o):match("^([%w_]+): ")
		error(common.where(path, lines, key) .. ": " .. tostring(o), 0)
	end
	if unknown[1] then
		local names = {}
		for name in pairs(M.task_keys) do names[#names + 1] = name end
		table.sort(names)
		error(string.format("%s: unknown key %s; did you mean %s? (OPENENDED takes %s)",
			common.where(path, lines, unknown[1]), unknown[1],
			common.closest(unknown[1], M.task_keys), table.concat(names, ", ")), 0)
	end
	if task.LEARNINGMETHOD and task.LEARNINGMETHOD:upper() ~= "NEAT" then
		error(string.format("%s: OPENENDED's agents are NEAT genomes: LEARNINGMETHOD must be "
			.. "NEAT or left out, found %s", common.where(path, lines, "LEARNINGMETHOD"),
			task.LEARNINGMETHOD), 0)
	end
	local all = {}
	for k, v in pairs(M.defaults) do all[k] = v end
	for k, v in pairs(o) do all[k] = v end
	return all
end

return M

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
	develop = 15,     -- batches with no environment admitted before a skill is added (0: never)
	skill = "none",   -- the template of the skills added: a .ades of the mind folder
	focus = 10,       -- generations of a new skill's focused training
	max_skills = 3,   -- skills added at most
	progress = "admitted", -- what OPEN_DEVELOP waits for: any environment admitted, or a larger one
	retention = 0,    -- batches between full retention checks (0: none)
}

M.task_keys = {
	OPEN_ENVS = "envs", OPEN_AGENTS = "agents", OPEN_ENV_BATCH = "env_batch",
	OPEN_AGENT_BATCH = "agent_batch", OPEN_RESOURCE = "resource",
	OPEN_BOOTSTRAP = "bootstrap", OPEN_RETENTION = "retention",
	OPEN_DEVELOP = "develop", OPEN_SKILL = "skill", OPEN_FOCUS = "focus",
	OPEN_MAXSKILLS = "max_skills", OPEN_PROGRESS = "progress",
}

local SOME = { lo = 1, hi = 10000, int = true }
M.ranges = {
	envs = SOME, agents = SOME, bootstrap = SOME,
	env_batch = { lo = 1, hi = 1000, int = true },
	agent_batch = { lo = 1, hi = 1000, int = true },
	resource = common.COUNT,
	retention = { lo = 0, hi = 1000000, int = true },
	develop = { lo = 0, hi = 1000000, int = true },
	focus = { lo = 1, hi = 10000, int = true },
	max_skills = { lo = 0, hi = 50, int = true },
}

-- OPEN_SKILL names a file: it ends in .ades (lib/openended.lua reads it,
-- M.template, where the mind folder is known)
local progress_word = common.choices(M.task_keys, { progress = { admitted = true, largest = true } })
local function check_word(key, s, value)
	if key == "OPEN_SKILL" and not s:match("%.ades$") then
		error(key .. ": expected a file name ending in .ades, found '" .. s .. "'", 0)
	end
	progress_word(key, s, value)
end

function M.options_from_task(task)
	return common.options_from(task, "OPEN_", M.task_keys, M.defaults, check_word, M.ranges)
end

-- The template OPEN_SKILL names (a path in the mind folder `mind`, as the
-- task writes it, case kept): { name, text, inputs, outputs }, its name the
-- file's without .ades; or an error at the task's OPEN_SKILL line saying
-- what is wrong. A template is an ordinary neural .ades: its name, input:N
-- and N inputs, output:N and N outputs, neural.
function M.template(task, path, lines, mind)
	local file = task.OPEN_SKILL
	local at = common.where(path, lines, "OPEN_SKILL")
	if file:find("%.%.") or file:sub(1, 1) == "/" then
		error(string.format("%s: OPEN_SKILL %s: the template must be a file in the mind "
			.. "folder, named from it (e.g. Templates/Explore.ades)", at, file), 0)
	end
	local f = io.open(mind .. "/" .. file, "r")
	local text = f and f:read("a")
	if f then f:close() end
	if not text then
		error(string.format("%s: OPEN_SKILL %s: no such file in the mind folder %s",
			at, file, mind), 0)
	end
	local words = {}
	for w in text:gsub("#[^\n]*", ""):gmatch("%S+") do words[#words + 1] = w end
	local function bad(what)
		error(string.format("%s: OPEN_SKILL %s is not a skill template: %s (it must be "
			.. "a neural .ades: its name, input:N and N inputs, output:N and N outputs, "
			.. "neural)", at, file, what), 0)
	end
	local i, counts = 2, {}
	for _, part in ipairs{ "input", "output" } do
		local n = tonumber((words[i] or ""):match("^" .. part .. ":(%d+)$"))
		if not n then bad("no " .. part .. ":N where " .. tostring(words[i]) .. " is") end
		for k = 1, n do
			if not words[i + k] or not words[i + k]:match("^%u%u:") then
				bad(string.format("%s %d of %d is %s", part, k, n, tostring(words[i + k])))
			end
		end
		counts[part] = n
		i = i + n + 1
	end
	if counts.output < 1 then bad("no output") end
	if words[i] ~= "neural" then bad("not neural (found " .. tostring(words[i]) .. ")") end
	local name = file:match("([^/]+)%.ades$")
	if not name:match("^[%w_]+$") then bad("its file name is not a plain word") end
	return { name = name, text = text, inputs = counts.input, outputs = counts.output }
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
	-- the template, read where the mind folder is (Minds/X/Tasks/T.simbatch)
	local mind = path:match("^(.*)/Tasks/[^/]+$") or (path:match("^Tasks/[^/]+$") and ".")
	if task.OPEN_SKILL and mind and io then
		all.template = M.template(task, path, lines, mind)
	end
	return all
end

return M

-- Plain Lua data (tables of numbers, strings, booleans) to text and back,
-- exactly: floats keep every bit (%.17g, and inf/nan spelled out) and stay
-- floats (8.0 is written "8.0", not "8", which would load as the integer
-- 8; -0.0 keeps its sign), so a run resumed from a checkpoint goes on as if
-- it had never stopped.
--
-- A table whose keys are exactly 1 .. n is written as a list, {a,b,c,};
-- any other table as [key]=value pairs in a fixed key order, so the same
-- state always gives the same text. A checkpoint of a population of 1,000
-- is mostly lists and small records, and it is written every generation.
local serialize = {}

local format, mtype, tostring, type, pairs = string.format, math.type, tostring, type, pairs

local function number(x)
	if mtype(x) == "integer" then
		-- "-9223372036854775808" would read as minus a float
		return x == math.mininteger and "(-9223372036854775807-1)" or tostring(x)
	end
	if x ~= x then return "(0/0)" end
	if x == math.huge then return "(1/0)" end
	if x == -math.huge then return "(-1/0)" end
	local s = format("%.17g", x)
	if not s:find("[.eEn]") then s = s .. ".0" end
	return s
end

-- Keys of mixed types: by type name, then by value.
local function key_order(a, b)
	local ta, tb = type(a), type(b)
	if ta ~= tb then return ta < tb end
	return a < b
end

-- n when the table's keys are exactly 1 .. n, else nil.
local function list_length(v)
	local n = #v
	for i = 1, n do
		if v[i] == nil then return nil end
	end
	local count = 0
	for _ in pairs(v) do
		count = count + 1
		if count > n then return nil end
	end
	return n
end

-- Appends v's text to out, whose last filled index is n; returns the new one.
local function write(v, out, n)
	local t = type(v)
	if t == "number" then
		n = n + 1
		out[n] = number(v)
	elseif t == "string" then
		n = n + 1
		out[n] = format("%q", v)
	elseif t == "boolean" then
		n = n + 1
		out[n] = v and "true" or "false"
	elseif t == "table" then
		n = n + 1
		out[n] = "{"
		local len = list_length(v)
		if len then
			for i = 1, len do
				n = write(v[i], out, n) + 1
				out[n] = ","
			end
		else
			local keys, strings = {}, true
			for k in pairs(v) do
				keys[#keys + 1] = k
				if type(k) ~= "string" then strings = false end
			end
			if strings then table.sort(keys) else table.sort(keys, key_order) end
			for i = 1, #keys do
				local k = keys[i]
				n = n + 1
				out[n] = "["
				n = write(k, out, n) + 1
				out[n] = "]="
				n = write(v[k], out, n) + 1
				out[n] = ","
			end
		end
		n = n + 1
		out[n] = "}"
	else
		error("serialize: cannot save a " .. t, 3)
	end
	return n
end

function serialize.dump(v)
	local out = { "return " }
	local n = write(v, out, 1) + 1
	out[n] = "\n"
	return table.concat(out)
end

-- Refuses what dump cannot have written: anything but numbers, strings,
-- booleans and tables, and a table met twice (a cycle or a shared part).
local function check_plain(v, name, seen)
	local t = type(v)
	if t == "table" then
		if seen[v] then error(name .. ": not plain data: a table appears twice", 0) end
		seen[v] = true
		for k, x in pairs(v) do
			check_plain(k, name, seen)
			check_plain(x, name, seen)
		end
	elseif t ~= "number" and t ~= "string" and t ~= "boolean" then
		error(name .. ": not plain data: it holds a " .. t, 0)
	end
end

-- Read text made by dump; errors name the text `name` (a file's path).
-- The text runs with no globals at all, and may execute only as many VM
-- instructions as plain data of its length needs (fewer than one per
-- character), so a damaged or hand-edited file cannot hang the run.
function serialize.load(text, name)
	name = name or "checkpoint"
	local chunk, err = load(text, "=" .. name, "t", {})
	if not chunk then error(err, 0) end
	local budget, used = #text + 1000, 0
	local hook, mask, count = debug.gethook()
	debug.sethook(function()
		used = used + 1000
		if used > budget then error(name .. ": not plain data: it runs code", 0) end
	end, "", 1000)
	local ok, v = pcall(chunk)
	debug.sethook(hook, mask, count)
	if not ok then error(type(v) == "string" and v or name .. ": does not load", 0) end
	if v == nil then error(name .. ": holds no data", 0) end
	check_plain(v, name, {})
	return v
end

return serialize

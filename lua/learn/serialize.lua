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
	elseif t == "userdata" and getmetatable(v) and getmetatable(v).__plain then
		-- a userdata that stands for plain data (evo.neat's genes)
		n = write(getmetatable(v).__plain(v), out, n)
	else
		error("serialize: cannot save a " .. t, 3)
	end
	return n
end

function serialize.dump_lua(v)
	local out = { "return " }
	local n = write(v, out, 1) + 1
	out[n] = "\n"
	return table.concat(out)
end

-- The same text from C (evo.neat's dump, sim/learn/lua_neat.c) in the
-- states that have it, the learning loop's: a checkpoint of XOR's
-- population took longer to write in Lua than the generation to run.
local fast = package.loaded["evo.neat"]
serialize.dump = fast and fast.dump or serialize.dump_lua

-- Read text made by dump; errors name the text `name` (a file's path).
-- The text is read as data by evo's reader (evo.data, sim/lua/lua_data.c),
-- never run: it takes exactly what dump writes, in time linear in its
-- length, so a damaged or hostile file is refused at its line and cannot
-- hang the run or reach any library.
local data = require "evo.data"

function serialize.load(text, name)
	return data.read(text, name or "checkpoint")
end

return serialize

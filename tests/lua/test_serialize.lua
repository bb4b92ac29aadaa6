-- Unit tests of lua/learn/serialize.lua (the checkpoint's text), run by
-- tests/sim/lua/test_lua_scripts.c. Each entry is one test; it fails by raising.
local serialize = require "learn.serialize"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

-- Same value and same number subtype (integer or float), all the way down.
local function same(a, b, where)
	where = where or "value"
	check(type(a) == type(b), where .. ": " .. type(a) .. " became " .. type(b))
	if type(a) == "number" then
		check(math.type(a) == math.type(b), where .. ": " .. math.type(a) .. " became " .. math.type(b))
		if a ~= a then
			check(b ~= b, where .. ": NaN lost")
		else
			check(a == b and 1 / a == 1 / b, where .. string.format(": %.17g became %.17g", a, b))
		end
	elseif type(a) == "table" then
		for k, v in pairs(a) do same(v, b[k], where .. "[" .. tostring(k) .. "]") end
		for k in pairs(b) do check(a[k] ~= nil, where .. ": extra key " .. tostring(k)) end
	else
		check(a == b, where .. ": " .. tostring(a) .. " became " .. tostring(b))
	end
end

local T = {}

function T.numbers_keep_their_bits_and_their_subtype()
	local v = { 8.0, -0.0, 0.0, 3, -7, 0.1, 1 / 3, 1e300, -2.5e-310, 2 ^ 53, 1 / 0, -1 / 0, 0 / 0,
		math.maxinteger, math.mininteger, 123456789.0 }
	local back = serialize.load(serialize.dump(v), "numbers")
	same(v, back, "numbers")
end

function T.lists_are_written_without_keys()
	local text = serialize.dump { 1, 2.5, "x", true }
	check(text == 'return {1,2.5,"x",true,}\n', "a list: " .. text)
	check(serialize.dump {} == "return {}\n", "the empty table")
end

function T.other_tables_have_their_keys_in_a_fixed_order()
	-- Built in two insertion orders: the text must not depend on it.
	local a = { z = 1, a = { 1, 2 }, [2] = "two", [5] = "five" }
	local b = {}
	b[5] = "five"
	b.a = { 1, 2 }
	b[2] = "two"
	b.z = 1
	local text = serialize.dump(a)
	check(text == serialize.dump(b), "same table, same text")
	check(text == 'return {[2]="two",[5]="five",["a"]={1,2,},["z"]=1,}\n', "key order: " .. text)
	-- A list with a hole is not a list.
	local holed = { 1, nil, 3 }
	same(holed, serialize.load(serialize.dump(holed)), "holed")
end

function T.nested_data_round_trips_exactly()
	local v = { generation = 4, pop = { { weight = -8.0, innov = 12, enabled = false },
		{ weight = 0.30000000000000004, innov = 13, enabled = true } },
		name = 'quote " and \n newline', history = { best = { 1.0, 2.25 }, mean = {} } }
	local text = serialize.dump(v)
	same(v, serialize.load(text, "nested"), "nested")
	check(serialize.dump(serialize.load(text)) == text, "dump(load(dump)) is dump")
end

function T.what_is_not_plain_data_is_refused()
	local ok, err = pcall(serialize.dump, { f = print })
	check(not ok and err:find("cannot save a function", 1, true), "a function: " .. tostring(err))
	ok, err = pcall(serialize.load, "return {1,", "run/broken.lua")
	check(not ok and err:find("^run/broken.lua:1: "), "a broken text names itself and its line: " .. tostring(err))
end

function T.a_damaged_text_cannot_hang_or_smuggle_code()
	local cases = {
		{ "while true do end", "it runs code" },
		{ "local s = 0 for i = 1, 1e7 do s = s + i end return s", "it runs code" },
		{ "local t = {} t.x = t return t", "a table appears twice" },
		{ "return {f = function() end}", "it holds a function" },
		{ "return print", "holds no data" },
		{ "", "holds no data" },
	}
	for _, c in ipairs(cases) do
		local ok, err = pcall(serialize.load, c[1], "cp.lua")
		check(not ok and err == "cp.lua: " .. (c[2]:find("holds no") and "" or "not plain data: ") .. c[2],
			string.format("%q: %s", c[1], tostring(err)))
	end
	check(debug.gethook() == nil, "the instruction limit is lifted after a load")
	-- Plain data far longer than any budget slack still loads.
	local big = {}
	for i = 1, 200000 do big[i] = i % 7 end
	local back = serialize.load(serialize.dump(big), "big")
	check(#back == 200000 and back[200000] == 200000 % 7, "200,000 small integers load")
end

return T

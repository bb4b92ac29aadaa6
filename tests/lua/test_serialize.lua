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

-- A checkpoint is read as data, never run (sim/lua/lua_data.c): code, and
-- anything dump does not write, is refused at its line, at once.
function T.a_damaged_text_cannot_hang_or_smuggle_code()
	local cases = {
		{ "while true do end", 1, "'return' and a value" },
		{ "local s = 0 for i = 1, 1e7 do s = s + i end return s", 1, "'return' and a value" },
		{ "local t = {} t.x = t return t", 1, "'return' and a value" },
		{ "return {f = function() end}", 1, "a value" },
		{ "return {\n[\"f\"]=function() end,}", 2, "a value" },
		{ "return print", 1, "a value" },
		{ "", 1, "'return' and a value" },
		{ "return 1 2", 1, "the end of the text" },
		{ "return {[{}]=1,}", 1, "a key that is a number" },
		{ "return \"\\x41\"", 1, "one of the escapes %q writes" },
		-- issue 27: 45 bytes that kept --resume busy for over 20 s when
		-- the checkpoint ran as Lua (string methods through the string
		-- metatable)
		{ 'return ("a"):rep(400):find(".-.-.-.-b")', 1, "a value" },
		{ "return " .. string.rep("{", 65) .. string.rep("}", 65), 1, "nested at most 64 deep" },
	}
	for _, c in ipairs(cases) do
		local t0 = os.clock()
		local ok, err = pcall(serialize.load, c[1], "cp.lua")
		check(not ok and err:find("^cp.lua:" .. c[2] .. ": not plain data as evo writes it: expected ")
			and err:find(c[3], 1, true), string.format("%q: %s", c[1], tostring(err)))
		check(os.clock() - t0 < 0.5, string.format("%q refused at once", c[1]))
	end
	-- Plain data far longer than any budget slack still loads.
	local big = {}
	for i = 1, 200000 do big[i] = i % 7 end
	local back = serialize.load(serialize.dump(big), "big")
	check(#back == 200000 and back[200000] == 200000 % 7, "200,000 small integers load")
end

-- What dump writes comes back bit for bit: every escape %q writes, the
-- special numbers, keys of every kind.
function T.every_form_dump_writes_reads_back()
	local bytes = {}
	for i = 0, 255 do bytes[#bytes + 1] = string.char(i) end
	local v = {
		s = table.concat(bytes) .. "\0" .. "9\r\n\"\\",
		n = { 0 / 0, 1 / 0, -1 / 0, -0.0, 0.1, 1e300, 5e-324, math.mininteger, math.maxinteger, 8.0, -3 },
		[1.5] = true, [false] = "f", [7] = { {}, { {} } },
	}
	local text = serialize.dump(v)
	local back = serialize.load(text, "forms")
	check(back.s == v.s, "every byte")
	for i = 1, #v.n do
		local a, b = v.n[i], back.n[i]
		check(string.pack("n", a) == string.pack("n", b) and math.type(a) == math.type(b),
			string.format("number %d: %s and %s", i, tostring(a), tostring(b)))
	end
	check(back[1.5] == true and back[false] == "f" and #back[7][2][1] == 0, "keys of every kind")
	check(serialize.dump(back) == text, "dump(load(dump)) is dump")
end

return T

-- Unit tests of lua/learn/rng.lua, the generator every learning method
-- draws from, run by tests/sim/lua/test_lua_scripts.c. Each entry of the
-- returned table is one test; it fails by raising.
local random = require "learn.rng"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local T = {}

function T.rng_is_deterministic_and_uniform()
	local a, b = random.new(7), random.new(7)
	local sum, sum2 = 0, 0
	for _ = 1, 10000 do
		local u = a:unit()
		check(u == b:unit(), "same seed, same draws")
		check(u >= 0 and u < 1, "unit in [0, 1)")
		sum = sum + u
		local z = a:normal()
		b:normal()
		sum2 = sum2 + z * z
	end
	check(math.abs(sum / 10000 - 0.5) < 0.02, "mean of unit near 0.5")
	check(math.abs(sum2 / 10000 - 1) < 0.1, "variance of normal near 1")
	check(random.new(8):unit() ~= random.new(7):unit(), "other seed, other draws")
	local c = random.load(a:save())
	check(c:unit() == a:unit(), "saved state continues the same sequence")
end

-- The stream itself, pinned: every run and checkpoint of every method
-- depends on it, so a change to the generator must show here. (These are
-- the values the generator gave when it lived in learn.neat.)
function T.the_stream_is_pinned()
	local r = random.new(1)
	check(r:next() == -5480124913605472059, "1st word")
	check(r:next() == -8846382939111011094, "2nd word")
	check(r:next() == -7856363154187860716, "3rd word")
	check(string.format("%.17g", r:unit()) == "0.39132860204190445", "unit")
	check(string.format("%.17g", r:normal()) == "0.95829714609573535", "normal")
	local s = r:save()
	check(s[1] == -7007604880863269844 and s[2] == 5268438290654635862
		and s[3] == -524709404661998345 and s[4] == -7669143912136817750, "state")
	check(random.new(-5):next() == 8791545028755928964, "negative seed")
	check(random.new(0):next() == -7355399402456485196, "seed 0")
	check(not pcall(random.new, 1.5), "a seed that is not an integer is refused")
end

return T

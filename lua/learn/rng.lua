-- The random generator every learning method draws from: xoshiro256**
-- seeded by splitmix64, on Lua 5.4's 64-bit integers (wrapping arithmetic,
-- logical shifts). A run makes one from its seed; its state is four words,
-- which a checkpoint holds (rng:save(), random.load).
--
--	local random = require "learn.rng"
--	local rng = random.new(42)
--	local u, z = rng:unit(), rng:normal()
--	local again = random.load(rng:save()) -- goes on with the same draws
--
-- The learning methods never use math.random: the same seed gives the same
-- run, bit for bit.
local random = {}

local Rng = {}
Rng.__index = Rng

local function rotl(x, k) return (x << k) | (x >> (64 - k)) end

function Rng:next()
	local s = self.s
	local result = rotl(s[2] * 5, 7) * 9
	local t = s[2] << 17
	s[3] = s[3] ~ s[1]
	s[4] = s[4] ~ s[2]
	s[2] = s[2] ~ s[3]
	s[1] = s[1] ~ s[4]
	s[3] = s[3] ~ t
	s[4] = rotl(s[4], 45)
	return result
end

-- Uniform in [0, 1) with 53 random bits.
function Rng:unit() return (self:next() >> 11) * (1.0 / 9007199254740992.0) end

-- evo.neat has both in C (sim/learn/lua_neat.c), on the same four words:
-- where the state has it (the learning loop's), they are the ones used.
local fast = package.loaded["evo.neat"]
Rng.next_lua, Rng.unit_lua = Rng.next, Rng.unit -- the reference, for tests
if fast then
	Rng.next, Rng.unit = fast.rng_next, fast.rng_unit
end

-- Standard normal by Box-Muller; no cached second value, so the state is
-- only the four words.
function Rng:normal()
	local u1 = 1.0 - self:unit()
	local u2 = self:unit()
	return math.sqrt(-2 * math.log(u1)) * math.cos(2 * math.pi * u2)
end
Rng.normal_lua = Rng.normal -- the reference, for tests
if fast then Rng.normal = fast.rng_normal end

-- The state, as plain data for a checkpoint.
function Rng:save() return { self.s[1], self.s[2], self.s[3], self.s[4] } end

-- A generator seeded from the integer `seed`.
function random.new(seed)
	local x = math.tointeger(seed) or error("learn.rng: seed must be an integer")
	local s = {}
	for i = 1, 4 do
		x = x + 0x9e3779b97f4a7c15
		local z = x
		z = (z ~ (z >> 30)) * 0xbf58476d1ce4e5b9
		z = (z ~ (z >> 27)) * 0x94d049bb133111eb
		s[i] = z ~ (z >> 31)
	end
	return setmetatable({ s = s }, Rng)
end

-- A generator that goes on from a state rng:save() gave.
function random.load(t) return setmetatable({ s = { t[1], t[2], t[3], t[4] } }, Rng) end

-- The class, for a kernel that takes only this generator (mapelites.isoline).
random.Rng = Rng

return random

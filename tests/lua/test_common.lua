-- Unit tests of the options machinery the learning methods share
-- (lua/learn/common.lua), run by tests/sim/lua/test_lua_scripts.c over every
-- method in common.MODULES. Each entry of the returned table is one test;
-- it fails by raising.
local common = require "learn.common"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

-- Options that take any finite number, so have no range.
local ANY_FINITE = { ["learn.neat"] = { bias_input = true } }

local T = {}

-- Scores printed side by side differ when the scores do.
function T.two_scores_show_the_difference()
	local a, b = common.two_scores(1.21, 1.34)
	check(a == "1.2" and b == "1.3", "one decimal: " .. a .. ", " .. b)
	a, b = common.two_scores(1.2345, 1.2)
	check(a == "1.23" and b == "1.20", "two decimals: " .. a .. ", " .. b)
	a, b = common.two_scores(1.26, 1.24)
	check(a == "1.3" and b == "1.2", "rounded apart: " .. a .. ", " .. b)
	a, b = common.two_scores(1.2345, 1.2301)
	check(a == "1.234" and b == "1.230", "three decimals: " .. a .. ", " .. b)
	a, b = common.two_scores(5, 5)
	check(a == "5.0" and b == "5.0", "equal: " .. a .. ", " .. b)
	a, b = common.two_scores(1.0, 1.0 + 2^-52)
	check(a ~= b, "one ulp apart: " .. a .. ", " .. b)
end

function T.every_numeric_option_has_a_range()
	for _, path in pairs(common.MODULES) do
		local m = require(path)
		local free = ANY_FINITE[path] or {}
		for name, v in pairs(m.defaults) do
			if type(v) == "number" and not free[name] then
				check(m.ranges[name], path .. ": " .. name .. " has a range")
			end
		end
	end
end

-- Every whole number has an upper bound: a count that reaches an
-- allocation or a loop (a population, the tries of an add-link mutation)
-- cannot take all memory or time.
function T.every_whole_number_option_is_bounded()
	for _, path in pairs(common.MODULES) do
		local m = require(path)
		for name, r in pairs(m.ranges) do
			if r.int then check(r.hi, path .. ": " .. name .. " has an upper bound") end
		end
	end
end

-- A value at the bound is taken.
function T.values_at_the_bounds_are_taken()
	for _, c in ipairs {
		{ "learn.neat", "NEAT_POPSIZE", "10000", "pop_size", 10000 },
		{ "learn.neat", "NEAT_ADD_LINK_TRIES", "1000", "add_link_tries", 1000 },
		{ "learn.neat", "NEAT_ADD_LINK_TRIES", "0", "add_link_tries", 0 },
		{ "learn.genetic", "GA_TOURNAMENT", "10000", "tournament", 10000 },
		{ "learn.annealing", "SA_STEPS_PER_GENERATION", "10000", "steps_per_generation", 10000 },
	} do
		local o = require(c[1]).options_from_task({ [c[2]] = c[3] })
		check(o[c[4]] == c[5], c[2] .. ":" .. c[3] .. " gives " .. tostring(o[c[4]]))
	end
end

-- Out of range, not finite, or not whole where a count is meant: refused
-- at the key, with what it takes.
function T.values_out_of_range_are_refused_with_what_the_key_takes()
	for _, c in ipairs {
		{ "learn.neat", "NEAT_SURVIVAL", "20", "a number above 0 and at most 1" },
		{ "learn.neat", "NEAT_SURVIVAL", "0", "a number above 0 and at most 1" },
		{ "learn.neat", "NEAT_ADD_NODE_PROB", "-0.1", "a number from 0 to 1" },
		{ "learn.neat", "NEAT_C3", "-1", "a number of 0 or more" },
		{ "learn.neat", "NEAT_WEIGHT_MAX", "128", "a number above 0 and below 128" },
		{ "learn.neat", "NEAT_TARGET_SPECIES", "2.5", "a whole number from 0 to 2147483647" },
		{ "learn.neat", "NEAT_STAGNATION", "0", "a whole number from 1 to 2147483647" },
		{ "learn.neat", "NEAT_POPSIZE", "99999999999", "a whole number from 1 to 10000" },
		{ "learn.neat", "POPSIZE", "10001", "a whole number from 1 to 10000" },
		{ "learn.neat", "NEAT_ADD_LINK_TRIES", "99999999999", "a whole number from 0 to 1000" },
		{ "learn.neat", "NEAT_ADD_LINK_TRIES", "1001", "a whole number from 0 to 1000" },
		{ "learn.genetic", "GA_POPSIZE", "10001", "a whole number from 1 to 10000" },
		{ "learn.genetic", "GA_ELITISM", "10001", "a whole number from 0 to 10000" },
		{ "learn.annealing", "SA_STEPS_PER_GENERATION", "10001", "a whole number from 1 to 10000" },
		{ "learn.neat", "NEAT_PERTURB_POWER", "1e999", "a number of 0 or more" },
		{ "learn.neat", "NEAT_BIAS_INPUT", "inf", "a number" },
		{ "learn.genetic", "GA_MUTATION_RATE", "10", "a number from 0 to 1" },
		{ "learn.genetic", "GA_TOURNAMENT", "0", "a whole number from 1 to 10000" },
		{ "learn.annealing", "SA_ALPHA", "1.5", "a number above 0 and at most 1" },
		{ "learn.annealing", "SA_T0", "-1", "a number of 0 or more" },
	} do
		local ok, msg = pcall(require(c[1]).options_from_task, { [c[2]] = c[3] })
		local want = c[2] .. ": expected " .. c[4] .. ", found '" .. c[3] .. "'"
		check(not ok and msg == want, c[2] .. ":" .. c[3] .. ": " .. tostring(msg))
	end
end

return T

-- Unit tests of lua/learn/netfile.lua, the .net writer every learning
-- method uses, run by tests/sim/lua/test_lua_scripts.c. Each entry of the
-- returned table is one test; it fails by raising.
local netfile = require "learn.netfile"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local T = {}

-- Comment lines first; numbers as the Q16 value evo runs, written exactly,
-- no exponent, no trailing zeros, and no "-0".
function T.text_is_pinned()
	local net = { inputs = 1, outputs = 1, outputs_ids = { 1 },
		nodes = { { id = 1, act = "sigmoid", bias = -0.0000001 } },
		links = { { from = 0, to = 1, weight = 1e-7 }, { from = 0, to = 1, weight = -2.5000004 },
			{ from = 0, to = 1, weight = 127.9999999 } } }
	local text = netfile.text(net, "a\nb")
	check(text == "# a\n# b\ninputs:1\noutputs:1\nnode:1:sigmoid:0\noutput:1\n"
		.. "link:0:1:0\nlink:0:1:-2.5\nlink:0:1:128\n", text)
	check(netfile.text(net):sub(1, 9) == "inputs:1\n", "no comment, no # line")
end

-- A weight is written as the Q16 value evo ran, so the file gives it back:
-- 0.001533508 is 100.49998 Q16 steps, run as 100 (100/65536 =
-- 0.00152587890625), where six decimals (0.001534, 100.53 steps) would
-- read back as 101; 0.53 is 34734.08 steps, run as 34734 (34734/65536 =
-- 0.529998779296875); -0.53 as -34734.
function T.a_weight_is_the_q16_value_evo_ran()
	local net = { inputs = 1, outputs = 1, outputs_ids = { 1 },
		nodes = { { id = 1, act = "sigmoid", bias = 0.53 } },
		links = { { from = 0, to = 1, weight = 0.001533508 }, { from = 0, to = 1, weight = -0.53 } } }
	local text = netfile.text(net)
	check(text == "inputs:1\noutputs:1\nnode:1:sigmoid:0.529998779296875\noutput:1\n"
		.. "link:0:1:0.00152587890625\nlink:0:1:-0.529998779296875\n", text)
end

-- The methods' to_net_text is this writer.
function T.every_method_writes_with_it()
	local common = require "learn.common"
	for _, path in pairs(common.MODULES) do
		check(require(path).to_net_text == netfile.text, path)
	end
end

return T

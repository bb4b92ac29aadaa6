-- Unit tests of lua/learn/netfile.lua, the .net writer every learning
-- method uses, run by tests/sim/lua/test_lua_scripts.c. Each entry of the
-- returned table is one test; it fails by raising.
local netfile = require "learn.netfile"

local function check(cond, msg)
	if not cond then error(msg or "check failed", 2) end
end

local T = {}

-- Comment lines first; numbers with at most 6 decimals, no exponent, no
-- trailing zeros, and no "-0".
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

-- The methods' to_net_text is this writer; MAPELITES's writes each weight
-- as its exact Q16 value (an elite replayed from its file must end in its
-- own cell).
function T.every_method_writes_with_it()
	local common = require "learn.common"
	local net = { inputs = 1, outputs = 1, outputs_ids = { 1 },
		nodes = { { id = 1, act = "sigmoid", bias = 0.1 } },
		links = { { from = 0, to = 1, weight = 1.5 / 65536 } } }
	for method, path in pairs(common.MODULES) do
		local write = require(path).to_net_text
		if method == "MAPELITES" then
			check(write(net, "c") == netfile.text(net, "c", true), path)
			check(write(net):find("link:0:1:0.000030517578125\n", 1, true), path)
		else
			check(write == netfile.text, path)
		end
	end
end

return T

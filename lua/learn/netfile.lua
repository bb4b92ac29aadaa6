-- A network as evo's .net text (the format core/src/parse_net.c reads), for
-- every learning method: its best networks, its champion.
--
-- A network is the table the methods' to_net give and the host's evaluate
-- takes: { inputs, outputs, nodes = { {id, act, bias}, ... }, outputs_ids,
-- links = { {from, to, weight}, ... } }, listed in the order they are
-- written.
local netfile = {}

-- A decimal the .net reader accepts: no exponent, no leading '+'.
local function decimal(x)
	local s = string.format("%.6f", x):gsub("0+$", ""):gsub("%.$", "")
	if s == "-0" then s = "0" end
	return s
end

-- x as the Q16.16 value evo runs (evo_net_weight_q16: x * 65536 rounded
-- to nearest, ties away from zero, within +-(128 - 2^-16)), written
-- exactly: every multiple of 2^-16 has at most 16 decimal places, so the
-- .net reader gets the very weight the network was scored with (%.6f
-- would move a weight near a rounding boundary by one step of 2^-16).
local LIM = 128 * 65536 - 1
local function exact_q16(x)
	local s = x * 65536.0
	local q
	if s ~= s then
		q = 0
	else
		local t = s < 0 and s - 0.5 or s + 0.5
		q = t < 0 and math.ceil(t) or math.floor(t)
		q = q > LIM and LIM or (q < -LIM and -LIM or q)
	end
	local str = string.format("%.16f", q / 65536.0):gsub("0+$", ""):gsub("%.$", "")
	if str == "-0" then str = "0" end
	return str
end
netfile.exact_q16 = exact_q16

-- The .net text of `net`, with each line of `comment` (if any) first as a
-- "# " line; with `exact`, every bias and weight the Q16.16 value it runs
-- as (exact_q16), else to 6 decimal places.
function netfile.text(net, comment, exact)
	local decimal = exact and exact_q16 or decimal
	local out = {}
	if comment then
		for line in (comment .. "\n"):gmatch("(.-)\n") do out[#out + 1] = "# " .. line end
	end
	out[#out + 1] = "inputs:" .. net.inputs
	out[#out + 1] = "outputs:" .. net.outputs
	for _, nd in ipairs(net.nodes) do
		out[#out + 1] = string.format("node:%d:%s:%s", nd.id, nd.act, decimal(nd.bias))
	end
	for _, id in ipairs(net.outputs_ids) do out[#out + 1] = "output:" .. id end
	for _, l in ipairs(net.links) do
		out[#out + 1] = string.format("link:%d:%d:%s", l.from, l.to, decimal(l.weight))
	end
	return table.concat(out, "\n") .. "\n"
end

-- The network of a .net text (netfile.text's, or one written by hand), for
-- host.evaluate; `name` names it in errors. The C side checks the network
-- itself when it is evaluated; this reads the lines.
function netfile.parse(text, name)
	local net = { nodes = {}, outputs_ids = {}, links = {} }
	local n = 0
	for line in (text .. "\n"):gmatch("(.-)\r?\n") do
		n = n + 1
		local f = {}
		for part in line:gsub("#.*", ""):gmatch("[^:%s]+") do f[#f + 1] = part end
		local k = f[1]
		local bad
		if k == "inputs" or k == "outputs" then
			net[k] = math.tointeger(tonumber(f[2]))
			bad = not net[k]
		elseif k == "node" then
			local id, bias = math.tointeger(tonumber(f[2])), tonumber(f[4])
			bad = not (id and f[3] and bias)
			net.nodes[#net.nodes + 1] = { id = id, act = f[3], bias = bias }
		elseif k == "output" then
			local id = math.tointeger(tonumber(f[2]))
			bad = not id
			net.outputs_ids[#net.outputs_ids + 1] = id
		elseif k == "link" then
			local from, to, w = math.tointeger(tonumber(f[2])), math.tointeger(tonumber(f[3])), tonumber(f[4])
			bad = not (from and to and w)
			net.links[#net.links + 1] = { from = from, to = to, weight = w }
		elseif k then
			bad = true
		end
		if bad then error(string.format("%s:%d: not a line of a .net: '%s'", name, n, line), 0) end
	end
	if not net.inputs or not net.outputs then
		error(name .. ": a .net needs inputs:N and outputs:M", 0)
	end
	return net
end

return netfile

-- A network as evo's .net text (the format core/src/parse_net.c reads), for
-- every learning method: its best networks, its champion.
--
-- A network is the table the methods' to_net give and the host's evaluate
-- takes: { inputs, outputs, nodes = { {id, act, bias}, ... }, outputs_ids,
-- links = { {from, to, weight}, ... } }, listed in the order they are
-- written.
local netfile = {}

-- A decimal the .net reader accepts: no exponent, no leading '+'. It is the
-- Q16 value evo ran (evo_q16_from_double: x * 65536 rounded half away from
-- zero) written exactly, q / 65536 having at most 16 decimals, so a network
-- read back from its file scores what it scored in training, to the bit
-- (six decimals were not enough: one in thirty weights came back one Q16
-- step off, enough to change a maze robot's path).
local function decimal(x)
	local v = x * 65536
	if v == v and v > -2 ^ 31 and v < 2 ^ 31 then
		x = (v < 0 and math.ceil(v - 0.5) or math.floor(v + 0.5)) / 65536
	end
	local s = string.format("%.16f", x):gsub("0+$", ""):gsub("%.$", "")
	if s == "-0" then s = "0" end
	return s
end

-- The .net text of `net`, with each line of `comment` (if any) first as a
-- "# " line.
function netfile.text(net, comment)
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

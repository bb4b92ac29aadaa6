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

return netfile

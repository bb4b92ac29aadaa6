-- Plain Lua data (tables of numbers, strings, booleans) to text and back,
-- exactly: floats keep every bit (%.17g, and inf/nan spelled out), so a
-- run resumed from a checkpoint goes on as if it had never stopped.
local serialize = {}

local function number(x)
	if math.type(x) == "integer" then return string.format("%d", x) end
	if x ~= x then return "(0/0)" end
	if x == math.huge then return "(1/0)" end
	if x == -math.huge then return "(-1/0)" end
	return string.format("%.17g", x)
end

local function write(v, out)
	local t = type(v)
	if t == "number" then
		out[#out + 1] = number(v)
	elseif t == "string" then
		out[#out + 1] = string.format("%q", v)
	elseif t == "boolean" then
		out[#out + 1] = tostring(v)
	elseif t == "table" then
		out[#out + 1] = "{"
		-- Keys in a fixed order: the same state always gives the same text.
		local keys = {}
		for k in pairs(v) do keys[#keys + 1] = k end
		table.sort(keys, function(a, b)
			local ta, tb = type(a), type(b)
			if ta ~= tb then return ta < tb end
			return a < b
		end)
		for _, k in ipairs(keys) do
			out[#out + 1] = "["
			write(k, out)
			out[#out + 1] = "]="
			write(v[k], out)
			out[#out + 1] = ","
		end
		out[#out + 1] = "}"
	else
		error("serialize: cannot save a " .. t, 3)
	end
end

function serialize.dump(v)
	local out = { "return " }
	write(v, out)
	out[#out + 1] = "\n"
	return table.concat(out)
end

-- Read text made by dump; it runs with no globals at all.
function serialize.load(text, name)
	local chunk, err = load(text, name or "checkpoint", "t", {})
	if not chunk then error(err, 2) end
	return chunk()
end

return serialize

-- Helpers shared by the built-in environments.
local arena = {}

-- A square border of touching cylinders around [-half, half]^2. The
-- cylinders are static obstacles like any other, so the proximity sensors
-- see them (EvoAgents' border walls were invisible to the sensors).
function arena.border(scene, half, radius)
	radius = radius or 2
	local step = 2 * radius
	for v = -half, half, step do
		scene:cylinder{ x = v, y = -half, radius = radius }
		scene:cylinder{ x = v, y = half, radius = radius }
		if v > -half and v < half then
			scene:cylinder{ x = -half, y = v, radius = radius }
			scene:cylinder{ x = half, y = v, radius = radius }
		end
	end
end

-- A random point in [-r, r]^2 at least `gap` away from every point of
-- `avoid` (a list of {x, y}), from the scene's seeded randomness.
function arena.random_point(scene, r, avoid, gap)
	for _ = 1, 1000 do
		local x, y = scene:random(-r, r), scene:random(-r, r)
		local ok = true
		for _, p in ipairs(avoid or {}) do
			if (x - p[1]) ^ 2 + (y - p[2]) ^ 2 < gap * gap then ok = false end
		end
		if ok then return x, y end
	end
	error("arena.random_point: no free point found", 2)
end

return arena

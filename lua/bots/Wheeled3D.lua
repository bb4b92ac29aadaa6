-- Wheeled3D: a small wheeled robot for the 3D world (docs/world3d.md).
-- A box chassis 0.4 x 0.3 x 0.08 m of 2 kg, its centre at its wheels' axle
-- height (0.08 m); two wheels of radius 0.08 m at its sides, MotL on the
-- left and MotR on the right, each turned at up to 15 rad/s (1.2 m/s) with
-- up to 2 N m; a frictionless caster under its back; and eight proximity
-- rays S1..S8 of 3 m, 0.1 m above the ground, fanned around it from the
-- chassis' rim (angles counter-clockwise from ahead, as seen from above).
local HX, HY = 0.2, 0.15
local ANGLES = { 0, 25, 60, 110, 180, -110, -60, -25 }

-- where a ray at angle a (degrees) leaves the chassis' rim
local function rim(a)
	local c, s = math.cos(math.rad(a)), math.sin(math.rad(a))
	local t = math.min(math.abs(c) > 1e-9 and HX / math.abs(c) or math.huge,
		math.abs(s) > 1e-9 and HY / math.abs(s) or math.huge)
	return t * c, t * s
end

return {
	hull = {
		shape = "box", hx = HX, hy = HY, hz = 0.04, mass = 2, friction = 0.3,
		z = 0.08,
		caster = { x = -0.15, y = 0, z = -0.04, radius = 0.04 },
	},
	build = function(bot)
		for i, a in ipairs(ANGLES) do
			local x, y = rim(a)
			bot:proximity{ name = "S" .. i, x = x, y = y, z = 0.02, yaw = a,
				range = 3 }
		end
		bot:wheel{ name = "MotL", y = 0.18, radius = 0.08, width = 0.04,
			max_rate = 15, max_torque = 2 }
		bot:wheel{ name = "MotR", y = -0.18, radius = 0.08, width = 0.04,
			max_rate = 15, max_torque = 2 }
	end,
}

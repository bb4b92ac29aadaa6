-- EPuck3D: the e-puck-like robot of lua/bots/EPuck.lua in the 3D world
-- (lua/lib/epuck.lua says where each figure comes from; docs/world3d.md).
-- A box hull 70 mm square and 40 mm high of 150 g, its centre at the axle's
-- height, a frictionless caster under its back; two wheels of radius
-- 20.5 mm, 53 mm apart (MotL on the left, MotR on the right), turned at up
-- to 0.128 / 0.0205 = 6.24 rad/s; the same sensors: IR0..IR7 (4 cm rays,
-- angles counter-clockwise here, so IR0 at -17 degrees is ahead-right),
-- L0..L7, G1..G3, R1, B1, V1, R2, B2, V2, NB; and the broadcasts TX1, TX2.
local E = require("lib.epuck")

local H = E.RADIUS -- the hull's half side

return {
	hull = {
		shape = "box", hx = H, hy = H, hz = 0.02, mass = E.MASS,
		friction = 0.3, z = E.WHEEL_RADIUS,
		caster = { x = -0.025, y = 0, z = -0.0105, radius = 0.01 },
	},
	build = function(bot)
		for i, a in ipairs(E.IR_ANGLES) do
			local r = math.rad(-a)
			local x, y = E.RADIUS * math.cos(r), E.RADIUS * math.sin(r)
			bot:proximity{ name = "IR" .. (i - 1), x = x, y = y, yaw = -a,
				range = E.IR_RANGE, arc = 15, rays = 3,
				sees = { "bots", "obstacles", "objects" } }
			bot:light{ name = "L" .. (i - 1), x = x, y = y, yaw = -a,
				aperture = 45 }
		end
		for i, y in ipairs(E.GROUND_Y) do
			bot:ground{ name = "G" .. i, x = E.GROUND_X, y = -y }
		end
		for k = 1, 2 do
			bot:rab{ name = "R" .. k, range = E.RAB_RANGE, slot = k }
			bot:rab{ name = "B" .. k, range = E.RAB_RANGE, slot = k,
				read = "bearing" }
			bot:rab{ name = "V" .. k, range = E.RAB_RANGE, slot = k,
				read = "value" }
		end
		bot:rab{ name = "NB", range = E.RAB_RANGE, read = "count" }
		local rate = E.MAX_SPEED / E.WHEEL_RADIUS
		bot:wheel{ name = "MotL", y = E.AXLE / 2, radius = E.WHEEL_RADIUS,
			width = 0.004, mass = 0.005, max_rate = rate, max_torque = 0.05 }
		bot:wheel{ name = "MotR", y = -E.AXLE / 2, radius = E.WHEEL_RADIUS,
			width = 0.004, mass = 0.005, max_rate = rate, max_torque = 0.05 }
		bot:broadcast{ name = "TX1" }
		bot:broadcast{ name = "TX2" }
	end,
}

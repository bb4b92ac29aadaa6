-- EPuck: an e-puck-like robot for the 2D world, at its published size
-- (lua/lib/epuck.lua says where each figure comes from; docs/world.md,
-- "EPuck"). A disc 70 mm across of 150 g; two speed wheels MotL and MotR
-- 53 mm apart, each up to 0.128 m/s; eight IR proximity sensors IR0..IR7 on
-- its rim, 4 cm long, at +-17, +-46, +-90 and +-150 degrees (+ to the
-- right, as evo's 2D frame turns); eight light sensors L0..L7 at the same
-- places; three ground sensors G1..G3 under its front; and swarm
-- communication: it broadcasts TX1 and TX2 and hears its two nearest
-- neighbours within 0.8 m (R1, B1, V1 and R2, B2, V2: range, bearing and
-- first value) and how many there are (NB, of 10).
local E = require("lib.epuck")

local area = math.pi * E.RADIUS * E.RADIUS

return {
	body = {
		shape = "circle", radius = E.RADIUS, density = E.MASS / area,
		friction = 0, linear_damping = 0, angular_damping = 0, sleep = false,
	},
	build = function(bot)
		for i, a in ipairs(E.IR_ANGLES) do
			local r = math.rad(a)
			local x, y = E.RADIUS * math.cos(r), E.RADIUS * math.sin(r)
			bot:proximity{ name = "IR" .. (i - 1), x = x, y = y, angle = a,
				range = E.IR_RANGE, arc = 15, rays = 3, deadzone = 0 }
			bot:light{ name = "L" .. (i - 1), x = x, y = y, angle = a,
				aperture = 45 }
		end
		for i, y in ipairs(E.GROUND_Y) do
			bot:ground{ name = "G" .. i, x = E.GROUND_X, y = y }
		end
		for k = 1, 2 do
			bot:rab{ name = "R" .. k, range = E.RAB_RANGE, slot = k }
			bot:rab{ name = "B" .. k, range = E.RAB_RANGE, slot = k,
				read = "bearing" }
			bot:rab{ name = "V" .. k, range = E.RAB_RANGE, slot = k,
				read = "value" }
		end
		bot:rab{ name = "NB", range = E.RAB_RANGE, read = "count" }
		bot:speed_wheel{ name = "MotL", y = -E.AXLE / 2, max_speed = E.MAX_SPEED }
		bot:speed_wheel{ name = "MotR", y = E.AXLE / 2, max_speed = E.MAX_SPEED }
		bot:broadcast{ name = "TX1" }
		bot:broadcast{ name = "TX2" }
	end,
}

-- Blimp3D: a propeller-driven robot for the 3D world, an underwater or
-- blimp-like body (docs/world3d.md). A sphere of radius 0.3 m and 4 kg
-- that floats at 99 % of its weight, buoyed 0.1 m above its centre (so it
-- rights itself), held back by drag. Two propellers at its back corners,
-- M1 on the left and M2 on the right, each pushing up to 6 N ahead and
-- 20 degrees up: both ahead climb and go forward, both neutral sink
-- slowly, one more than the other turns it. It sees with the tutorial's
-- sensors: S1 and S2, proximity rays of 5 m ahead-left and ahead-right,
-- and the target sensor TARG_AZIM (TargetSensor:1, the azimuth) and
-- TARG_ELEV (TargetSensor:2, the elevation), with DIST, the distance to
-- the target over 10 m. The environment points the target sensors at its
-- target with bot:target.
local TILT = math.rad(20)

return {
	hull = {
		shape = "sphere", radius = 0.3, mass = 4, friction = 0.3, z = 3,
		buoyancy = 0.99, cob = { 0, 0, 0.1 },
		drag_linear = 2, drag_quadratic = 4, drag_angular = 1.5,
	},
	build = function(bot)
		bot:proximity{ name = "S1", x = 0.28, y = 0.1, yaw = 20, range = 5 }
		bot:proximity{ name = "S2", x = 0.28, y = -0.1, yaw = -20, range = 5 }
		bot:target_sensor{ name = "TARG_AZIM", axis = 1 }
		bot:target_sensor{ name = "TARG_ELEV", axis = 2 }
		bot:distance{ name = "DIST", scale = 10 }
		local axis = { math.cos(TILT), 0, math.sin(TILT) }
		bot:propeller{ name = "M1", x = -0.3, y = 0.3, axis = axis, max_thrust = 6 }
		bot:propeller{ name = "M2", x = -0.3, y = -0.3, axis = axis, max_thrust = 6 }
	end,
}

-- KheperaxBot: Kheperax's robot (the JAX rewrite of libfastsim; docs/world.md,
-- "The mazes"), at evo's scale of 1/0.015 (its radius of 0.015 becomes 1 m):
-- - three lasers from the centre at -45, 0 and 45 degrees, range 0.2 (13.33
--   m): distance / range, 1 when clear;
-- - two bumpers, BUMP_LEFT over (-90, 0] degrees and BUMP_RIGHT over [0, 90),
--   true when a wall comes within the robot's radius (plus 5 % for Box2D's
--   contact skin);
-- - two wheels 2 radii apart, each moving (2c - 1) * 0.025 a step (50 m/s).
-- Box2D moves it, not Kheperax's kinematics: with friction 1 against the
-- walls it stops while it drives into one, where Kheperax's robot freezes
-- for good.
local S = 1 / 0.015
local PER_STEP = 30

return {
	body = { shape = "circle", radius = 1, density = 1, friction = 1,
		linear_damping = 0, angular_damping = 0, sleep = false },
	build = function(bot)
		for _, l in ipairs({ { "LASER_LEFT", -45 }, { "LASER_FRONT", 0 },
				{ "LASER_RIGHT", 45 } }) do
			bot:proximity{ name = l[1], angle = l[2], range = 0.2 * S, arc = 0,
				rays = 1, deadzone = 0, sees = { "obstacles" } }
		end
		bot:bumper{ name = "BUMP_LEFT", angle = -45, arc = 45, reach = 1.05,
			sees = { "obstacles" } }
		bot:bumper{ name = "BUMP_RIGHT", angle = 45, arc = 45, reach = 1.05,
			sees = { "obstacles" } }
		bot:speed_wheel{ name = "MotL", x = 0, y = -1, max_speed = 0.025 * S * PER_STEP }
		bot:speed_wheel{ name = "MotR", x = 0, y = 1, max_speed = 0.025 * S * PER_STEP }
	end,
}

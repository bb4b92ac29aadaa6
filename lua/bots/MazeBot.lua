-- MazeBot: the robot of the novelty-search mazes (Lehman & Stanley 2011;
-- docs/world.md, "The mazes"), at evo's scale of 1/8 (its radius of 8
-- becomes 1 m, its rangefinders' 100 become 12.5 m):
-- - six rangefinders from the centre at -90, -45, 0, 45, 90 and 180 degrees
--   (negative to the left), one ray each: distance / 12.5, 1 when clear;
-- - four pie-slice radars towards the goal (front, right, back, left, 90
--   degrees each), true when the goal lies in that slice; the environment
--   points them at its goal;
-- - two outputs, as the paper's robot: TURN and SPEED change the turn rate
--   and the speed by (2c - 1) * 0.5 degree (unit) per step each step, within
--   3 degrees (units) a step. At 30 steps a second: 15 degrees/s and 1.875 m/s
--   per step, at most 90 degrees/s and 11.25 m/s.
-- It collides as Lehman's maze simulator's robot: a step that would bring
-- its centre within its radius of a wall is undone (it stays where it was,
-- turned as commanded), so it neither slides along a wall nor is pushed
-- off one (body collision "undo", docs/world.md, "The mazes").
local RANGE = 100 / 8
local PER_STEP = 30 -- evo's world steps 30 times a simulated second

return {
	body = { shape = "circle", radius = 1, density = 1, friction = 0,
		linear_damping = 0, angular_damping = 0, sleep = false,
		collision = "undo" },
	build = function(bot)
		local finders = { { "RF_LEFT", -90 }, { "RF_FRONT_LEFT", -45 },
			{ "RF_FRONT", 0 }, { "RF_FRONT_RIGHT", 45 }, { "RF_RIGHT", 90 },
			{ "RF_BACK", 180 } }
		for _, f in ipairs(finders) do
			bot:proximity{ name = f[1], angle = f[2], range = RANGE, arc = 0,
				rays = 1, deadzone = 0, sees = { "obstacles" } }
		end
		local radars = { { "RAD_FRONT", 0 }, { "RAD_RIGHT", 90 },
			{ "RAD_BACK", 180 }, { "RAD_LEFT", -90 } }
		for _, r in ipairs(radars) do
			bot:radar{ name = r[1], angle = r[2], arc = 45 }
		end
		bot:drive{ name = "TURN", turn = true, max_speed = 3 * PER_STEP,
			accel = 0.5 * PER_STEP }
		bot:drive{ name = "SPEED", max_speed = 3 / 8 * PER_STEP,
			accel = 0.5 / 8 * PER_STEP }
	end,
}

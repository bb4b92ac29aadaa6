-- EXP3D_Avoid: roam a 10 x 10 m walled floor, uneven and cluttered with
-- boxes and cylinders, without touching anything (the 3D EXP_Avoid;
-- docs/world3d.md). Every episode lays out anew, from the layout seed (the
-- same for every candidate of a generation), 24 obstacles none within 1 m
-- of the start, and 10 bumps of the ground 2 to 5 cm high and 0.7 to 1.5 m
-- across (caps of buried spheres: the robot drives over them, its rays
-- pass over them, touching them is no collision).
-- Scored as the Avoid example's Roam:
--   +1 per m/s of speed along the heading (about +0.04 a tick flat out),
--   -0.2 every tick the robot touches something,
--   -0.05 * sum(0.25 - v) over the rays reading 0.25 or less
--        (something within 0.75 m).
local env = {}
local HALF = 5

function env.init(scene, task)
	-- the walls: boxes 0.1 m thick, 0.4 m high
	for _, s in ipairs({ -1, 1 }) do
		scene:box{ x = s * (HALF + 0.05), y = 0, z = 0.2, hx = 0.05, hy = HALF + 0.1, hz = 0.2 }
		scene:box{ x = 0, y = s * (HALF + 0.05), z = 0.2, hx = HALF + 0.1, hy = 0.05, hz = 0.2 }
	end
	local bot = scene:bot{ x = 0, y = 0 }
	scene:reward("ForwardSpeed", { bot = bot, k = 1 / 30 })
	scene:reward("PunishOnCollision", { bot = bot, k = -0.2 })
	scene:reward("SensorUnderThreshold", { bot = bot, sensors = bot:sensors("proximity"),
		threshold = 0.25, k = -0.05 })
	scene:control("NextOnTimeout", { bot = bot, ticks = tonumber(task.TICKLIM) or 1800 })
end

function env.reset(scene, episode)
	for _ = 1, 24 do
		local x, y
		repeat
			x, y = scene:layout_random(-HALF + 0.4, HALF - 0.4), scene:layout_random(-HALF + 0.4, HALF - 0.4)
		until x * x + y * y > 1
		if scene:layout_random() < 0.5 then
			scene:obstacle{ shape = "cylinder", x = x, y = y, z = 0.2,
				radius = scene:layout_random(0.1, 0.3), height = 0.4 }
		else
			local h = scene:layout_random(0.1, 0.3)
			scene:obstacle{ shape = "box", x = x, y = y, z = 0.2, hx = h, hy = h, hz = 0.2,
				yaw = scene:layout_random(0, 90) }
		end
	end
	for _ = 1, 10 do
		local x, y
		repeat
			x, y = scene:layout_random(-HALF + 0.5, HALF - 0.5), scene:layout_random(-HALF + 0.5, HALF - 0.5)
		until x * x + y * y > 1.5 * 1.5
		local h, r = scene:layout_random(0.02, 0.05), scene:layout_random(3, 6)
		scene:obstacle{ shape = "sphere", ground = true, x = x, y = y, z = h - r, radius = r }
	end
	-- a start heading of the layout's
	local bot = scene:get_bot("bot1")
	bot:place{ x = 0, y = 0, yaw = scene:layout_random(-180, 180) }
end

return env

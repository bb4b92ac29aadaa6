-- EvoAgents' round robot, as BotType8 and BotType6 build it: ten proximity
-- sensors on the rim, object and drop-zone trackers, two wheels and a
-- claw (docs/world.md). The two models differ only in what their proximity
-- sensors are called: S1..S10 on BotType8, US_1..US_10 (the tutorial's
-- ultrasound sensors) on BotType6.
--
-- The trackers (DISTOBJ, RADOBJ, ACTOBJ, SENSDZ, DISTDZ, RADDZ, ACTDZ) look at
-- nothing until the environment points them at something with
-- bot:target(name, element) -- the objects ones default to the nearest
-- active object.
local S_ANGLES = { 0, 22.5, 45, 90, 135, 180, 225, 270, 315, 337.5 }

local round_bot = {}

-- A bot model whose proximity sensors are named prefix .. 1 .. prefix .. 10.
function round_bot.model(prefix)
	return {
		body = {
			shape = "circle", radius = 1.0, density = 2, friction = 0,
			linear_damping = 5, angular_damping = 20, sleep = false,
		},
		build = function(bot)
			for i, a in ipairs(S_ANGLES) do
				local r = math.rad(a)
				bot:proximity{ name = prefix .. i, x = math.cos(r), y = math.sin(r),
					angle = a, range = 12, arc = 6, rays = 9, deadzone = 0.005 }
			end
			bot:movement{ name = "DOF" }
			bot:presence{ name = "ACTOBJ", target = "nearest_object" }
			bot:distance{ name = "DISTOBJ", target = "nearest_object", scale = 100 }
			bot:bearing{ name = "RADOBJ", target = "nearest_object" }
			bot:object_detector{ name = "SENSOBJ", x = 1, y = 0, reach = 1.5 }
			bot:presence{ name = "ACTDZ" }
			bot:distance{ name = "DISTDZ", scale = 100 }
			bot:bearing{ name = "RADDZ" }
			bot:zone{ name = "SENSDZ" }
			bot:random{ name = "RANDOM" }
			bot:holding{ name = "HOLDING" }
			-- Wheels push along the heading with (2v - 1) * 80.
			bot:wheel{ name = "MotL", x = 0, y = -1, max_force = 80 }
			bot:wheel{ name = "MotR", x = 0, y = 1, max_force = 80 }
			bot:claw{ name = "EMAG", x = 1, y = 0, reach = 1.5 }
		end,
	}
end

return round_bot

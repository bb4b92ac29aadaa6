-- TeamBot: EvoAgents' round robot for team tasks (docs/teams.md): the body,
-- the ten proximity sensors S1..S10 (which see obstacles and every other
-- bot) and the two wheels of BotType8, with trackers of the nearest bot of
-- another team (OPPACT present, OPPDIST distance, OPPRAD bearing) and of
-- the nearest teammate (MATEACT, MATEDIST, MATERAD), found through the
-- world's broad phase within 160 m.
local S_ANGLES = { 0, 22.5, 45, 90, 135, 180, 225, 270, 315, 337.5 }

return {
	body = {
		shape = "circle", radius = 1.0, density = 2, friction = 0,
		linear_damping = 5, angular_damping = 20, sleep = false,
	},
	build = function(bot)
		for i, a in ipairs(S_ANGLES) do
			local r = math.rad(a)
			bot:proximity{ name = "S" .. i, x = math.cos(r), y = math.sin(r),
				angle = a, range = 12, arc = 6, rays = 9, deadzone = 0.005 }
		end
		bot:presence{ name = "OPPACT", target = "nearest_opponent" }
		bot:distance{ name = "OPPDIST", target = "nearest_opponent", scale = 60 }
		bot:bearing{ name = "OPPRAD", target = "nearest_opponent" }
		bot:presence{ name = "MATEACT", target = "nearest_teammate" }
		bot:distance{ name = "MATEDIST", target = "nearest_teammate", scale = 60 }
		bot:bearing{ name = "MATERAD", target = "nearest_teammate" }
		bot:wheel{ name = "MotL", x = 0, y = -1, max_force = 80 }
		bot:wheel{ name = "MotR", x = 0, y = 1, max_force = 80 }
	end,
}

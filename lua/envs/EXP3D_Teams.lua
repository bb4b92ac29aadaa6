-- EXP3D_Teams: every team of a 3D team task (DEMO3DSIMMULTI,
-- LEARN3DSIMMULTI; docs/teams.md) roams one 8 x 8 m walled floor with four
-- pillars, its bots in a row of their own, 1 m apart, facing +x. Every bot
-- of a team is paid for itself, and so for its team (a team's reward is
-- what its bots earned):
--   +1 per m/s of speed along the heading (about +0.04 a tick flat out),
--   -0.2 every tick it touches something (a wall, a pillar, another bot).
-- The episode ends at TICKLIM. Each episode turns every bot to a heading
-- of the layout seed's, within 30 degrees of +x.
local env = {}
local HALF = 4

function env.init(scene, task)
	for _, s in ipairs({ -1, 1 }) do
		scene:box{ x = s * (HALF + 0.05), y = 0, z = 0.2, hx = 0.05, hy = HALF + 0.1, hz = 0.2 }
		scene:box{ x = 0, y = s * (HALF + 0.05), z = 0.2, hx = HALF + 0.1, hy = 0.05, hz = 0.2 }
		scene:cylinder{ x = 1.5 * s, y = 1.5, z = 0.2, radius = 0.3, height = 0.4 }
		scene:cylinder{ x = 1.5 * s, y = -1.5, z = 0.2, radius = 0.3, height = 0.4 }
	end
	local teams = scene:teams()
	for t, team in ipairs(teams) do
		local y = (t - (#teams + 1) / 2) * 2.5
		for i = 1, team.size do
			scene:bot{ team = team.name, x = -3 + (i - 1), y = y }
		end
		scene:reward("ForwardSpeed", { team = team.name, k = 1 / 30 })
		scene:reward("PunishOnCollision", { team = team.name, k = -0.2 })
	end
	scene:control("NextOnTimeout", { ticks = tonumber(task.TICKLIM) or 600 })
end

function env.reset(scene)
	for _, bot in ipairs(scene:bots()) do
		bot:place{ yaw = scene:layout_random(-30, 30) }
	end
end

return env

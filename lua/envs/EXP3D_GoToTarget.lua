-- EXP3D_GoToTarget: reach a target floating in open water or air (the 3D
-- go-to-target; docs/world3d.md). The robot starts 3 m above the ground
-- facing ahead; each episode puts the target 3 to 6 m away, anywhere
-- around, 1 to 5 m above the ground, from the layout seed (the same for
-- every candidate of a generation). Paid 10 for every metre it closes on
-- the target (ClosingOnTarget); the episode ends within 0.5 m of it, or
-- at TICKLIM.
local env = {}
local target

function env.init(scene, task)
	target = scene:target{ name = "target", x = 4, y = 0, z = 3, radius = 0.2 }
	local bot = scene:bot{ x = 0, y = 0 }
	for _, s in ipairs({ "TARG_AZIM", "TARG_ELEV", "DIST" }) do
		bot:target(s, target)
	end
	scene:reward("ClosingOnTarget", { bot = bot, target = target, k = 10 })
	scene:control("NextOnTimeout", { bot = bot, ticks = tonumber(task.TICKLIM) or 900 })
	scene:control("NextOnSensorBelow", { bot = bot, sensor = "DIST", threshold = 0.05 })
end

function env.reset(scene, episode)
	local a = math.rad(scene:layout_random(-180, 180))
	local r = scene:layout_random(3, 6)
	target:place{ x = r * math.cos(a), y = r * math.sin(a), z = scene:layout_random(1, 5) }
end

return env

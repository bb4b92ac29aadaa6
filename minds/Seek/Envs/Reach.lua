-- Reach: the Seek example's environment. EXP_GTO (lua/lib/gto.lua): an
-- object in a bordered arena of +-50, paid for closing on it (ClosingOnTarget,
-- k 1) and for having it within the claw's reach (SENSOBJ), -1 a tick
-- touching anything; once reached, the object moves elsewhere. Reach adds
-- -1 a tick driving backwards (without it, the best networks NEAT found
-- backed towards the objects, steering with one wheel), and the metric
-- `reached`, the objects the bot reached in the episode, which evo run
-- prints on each episode's line and learning logs in log.csv.
local env = require("lib.gto"){ collision = -1 }
local init, post_step = env.init, env.post_step

function env.init(scene, task)
	init(scene, task)
	-- -1 a tick backing: the claw and the object detector are in front
	scene:reward("ForwardMotion", { bot = env.bot, k = 0, k2 = -1 })
	env.reached = scene:metric("reached")
end

-- lib.gto's post_step moves a reached object: count it first
function env.post_step(scene)
	if env.bot:value(env.detectors[1]) > 0.5 then env.reached:add() end
	post_step(scene)
end

return env

-- EXP3D_Waypoints: fly a course of waypoints, one after the other (a 3D
-- environment with a Lua reward, a Lua control and post_step;
-- docs/world3d.md, "Rewards and controls of your own"). The target marks
-- the next waypoint; the trained GoToTarget skill chases it. The first
-- waypoint is the start gate, where the robot begins.
-- Scored by a Lua reward:
--   +10 for each waypoint the robot comes within 0.5 m of,
--   -0.01 every tick (the clock);
-- post_step then moves the target to the next waypoint and counts it in
-- the metric `waypoints`, and a Lua control ends the episode once the last
-- is passed (or at TICKLIM).
local env = {}

local WAYPOINTS = {
	{ 0, 0, 3 }, -- the start gate: the robot starts inside it
	{ 4, 0, 3 },
	{ 5, 4, 4 },
	{ 1, 5, 2.5 },
}
local REACH, PAY, CLOCK = 0.5, 10, -0.01

local target, bot, passed
local next_wp -- the waypoint the target marks
local hit -- the reward saw the robot reach it this tick
local done -- every waypoint passed

local function place(i)
	local w = WAYPOINTS[i]
	target:place{ x = w[1], y = w[2], z = w[3] }
end

function env.init(scene, task)
	target = scene:target{ name = "target", x = 0, y = 0, z = 3, radius = 0.2 }
	bot = scene:bot{ x = 0, y = 0 }
	for _, s in ipairs({ "TARG_AZIM", "TARG_ELEV", "DIST" }) do
		bot:target(s, target)
	end
	scene:reward(function()
		local bx, by, bz = bot:pos()
		local tx, ty, tz = target:pos()
		local d = math.sqrt((tx - bx) ^ 2 + (ty - by) ^ 2 + (tz - bz) ^ 2)
		hit = not done and d < REACH
		return CLOCK + (hit and PAY or 0)
	end)
	scene:control(function() return done end)
	scene:control("NextOnTimeout", { bot = bot, ticks = tonumber(task.TICKLIM) or 1800 })
	passed = scene:metric("waypoints")
end

function env.reset(scene, episode)
	next_wp, hit, done = 1, false, false
	place(1)
end

-- after the rewards of each tick: a waypoint reached gives way to the next
function env.post_step(scene)
	if not hit then
		return
	end
	hit = false
	passed:add()
	if next_wp == #WAYPOINTS then
		done = true
	else
		next_wp = next_wp + 1
		place(next_wp)
	end
end

return env

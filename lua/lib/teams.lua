-- Helpers for environments with teams (docs/teams.md): make every team's
-- bots, and scatter bots at random free places each episode.
local arena = require "lib.arena"

local teams = {}

-- Every team of the task, one row of `spacing` metres between bots per
-- team, rows `spacing` apart, centred on (x, y). Returns the list of all
-- the bots made and a table team name -> its bots. In a one-agent task
-- (no teams), one bot of the task's BOTMODEL at (x, y).
function teams.spawn(scene, opts)
	opts = opts or {}
	local x0, y0, spacing = opts.x or 0, opts.y or 0, opts.spacing or 4
	local all, by_team = {}, {}
	local list = scene:teams()
	if #list == 0 then
		all[1] = scene:bot{ x = x0, y = y0 }
		return all, by_team
	end
	for t, team in ipairs(list) do
		by_team[team.name] = {}
		local y = y0 + (t - (#list + 1) / 2) * spacing
		for i = 1, team.size do
			local x = x0 + (i - (team.size + 1) / 2) * spacing
			local b = scene:bot{ team = team.name, x = x, y = y }
			all[#all + 1] = b
			by_team[team.name][#by_team[team.name] + 1] = b
		end
	end
	return all, by_team
end

-- Place each bot of `bots` at a random point of [-r, r]^2 at least `gap`
-- from the points of `taken` (a list of {x, y}, which grows) and from one
-- another, facing a random way; from the episode's seeded randomness.
function teams.scatter(scene, bots, r, taken, gap)
	for _, b in ipairs(bots) do
		local x, y = arena.random_point(scene, r, taken, gap)
		b:place(x, y, scene:random(0, 360))
		taken[#taken + 1] = { x, y }
	end
	return taken
end

return teams

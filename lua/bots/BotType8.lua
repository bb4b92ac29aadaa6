-- BotType8: EvoAgents' round robot with ten proximity sensors S1..S10,
-- object and drop-zone trackers, two wheels and a claw (lua/lib/round_bot.lua,
-- docs/world.md).
return require("lib.round_bot").model("S")

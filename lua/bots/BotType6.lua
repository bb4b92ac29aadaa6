-- BotType6: the tutorial's robot, the round robot of BotType8 with its ten
-- proximity sensors named US_1..US_10, as the tutorial's T6-NEAT mind names
-- them (lua/lib/round_bot.lua, docs/world.md).
return require("lib.round_bot").model("US_")

-- EXP_GTO: go to an object. The bot is rewarded for closing on the nearest
-- object and for having it within reach of its claw (docs/world.md).
return require("lib.gto"){ collision = -1 }

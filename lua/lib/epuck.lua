-- The e-puck's published figures, shared by the 2D (lua/bots/EPuck.lua) and
-- 3D (lua/bots/EPuck3D.lua) models (docs/world.md, "EPuck"). Lengths in
-- metres.
--
-- Where they come from:
-- - a body 70 mm across (e-puck.org's specifications; Mondada et al., "The
--   e-puck, a robot designed for education in engineering", 2009), 150 g
--   (the Webots user guide's e-puck table);
-- - wheels of 41 mm diameter, 53 mm apart (e-puck.org's mechanics page);
-- - a top speed of 1000 motor steps a second, and 1000 steps are 12.8 cm
--   of travel (e-puck.org's page on the IR proximity sensors): 0.128 m/s;
-- - eight IR proximity sensors IR0..IR7 around the body, at 17, 46, 90 and
--   150 degrees to the right of ahead and the same to the left (the
--   placement figure of e-puck.org's IR page; EPFL's Enki simulator places
--   them at 16 to 18, 45, 90 and 142 to 150 degrees, its wheels 51 mm
--   apart, its top speed 12.8 cm/s), seeing obstacles within about 4 cm
--   (the Webots user guide); the same sensors measure ambient light;
-- - the ground-sensor extension: three IR sensors under the front, in a
--   line across it (the Webots user guide, e-puck_line).
local epuck = {}

epuck.RADIUS = 0.035
epuck.MASS = 0.15
epuck.WHEEL_RADIUS = 0.0205
epuck.AXLE = 0.053
epuck.MAX_SPEED = 0.128
epuck.IR_RANGE = 0.04
-- degrees to the right of ahead, IR0..IR7
epuck.IR_ANGLES = { 17, 46, 90, 150, -150, -90, -46, -17 }
-- the ground sensors: ahead of the centre, across the front
epuck.GROUND_X = 0.03
epuck.GROUND_Y = { -0.01, 0, 0.01 }
-- range and bearing (the e-puck's range-and-bearing board reaches about a
-- metre): the two nearest neighbours' range, bearing and first value
epuck.RAB_RANGE = 0.8

return epuck

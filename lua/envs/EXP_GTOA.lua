-- EXP_GTOA: go to an object while avoiding obstacles: EXP_GTO in a field
-- of cylinders (the tutorial's default grid: size 1 + up to 2, spacing 18),
-- with a penalty for touching them (docs/world.md).
return require("lib.gto"){
	collision = -5,
	grid = { x0 = -45, y0 = -45, x1 = 45, y1 = 45, spacing = 18, jitter = 4,
		min_size = 1, size_variability = 2, clearance = 3 },
}

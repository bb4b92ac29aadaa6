/* The tutorial's obstacle grid (evo_grid_def in sim/world2d/scene.h), rebuilt
 * at every reset from the grid seed. */
#include <math.h>
#include <string.h>

#include "base/rng.h"
#include "world2d/scene.h"
#include "world2d/scene_internal.h"

/* Distance from (x, y) to the nearest thing the grid must keep clear of
 * (bot starts, zones, objects), less that thing's own size. */
static double clear_distance(const evo_scene *sc, double x, double y)
{
	double best = INFINITY;
	for (int i = 0; i < sc->n_bots; i++) {
		const evo_bot *b = &sc->bot[i];
		double d = hypot(x - b->def.x, y - b->def.y) - b->radius;
		best = d < best ? d : best;
	}
	for (int i = 0; i < sc->n_elements; i++) {
		const evo_element *e = &sc->element[i];
		double size = e->kind == EVO_PIECE_ZONE ? e->size * M_SQRT2
			      : e->kind == EVO_PIECE_OBJECT ? e->size
							   : -1;
		if (size < 0)
			continue;
		double d = hypot(x - e->x, y - e->y) - size;
		best = d < best ? d : best;
	}
	return best;
}

/* The tutorial's grid: one obstacle per cell, jittered, of random size.
 * An obstacle that would reach within `clearance` of a start, a zone or an
 * object is left out (EvoAgents let one sit on the start). */
static void build_grid(evo_scene *sc, uint64_t seed)
{
	const evo_grid_def *g = &sc->grid;
	if (!g->enabled || !(g->spacing > 0))
		return;
	evo_rng r = evo_rng_seed(seed);
	for (double y = g->y0; y <= g->y1 + 1e-9; y += g->spacing) {
		for (double x = g->x0; x <= g->x1 + 1e-9; x += g->spacing) {
			/* Draw every number whether or not the cell is used,
			 * so one cell's fate never shifts the others. */
			double ox = x + evo_rng_range(&r, -g->jitter, g->jitter);
			double oy = y + evo_rng_range(&r, -g->jitter, g->jitter);
			double size =
				g->min_size + g->size_variability * evo_rng_unit(&r);
			double angle = evo_rng_range(&r, 0, M_PI);
			int box = g->boxes == 1 ||
				  (g->boxes == 2 && evo_rng_unit(&r) < 0.5);
			double extent = box ? size * M_SQRT2 : size;
			if (clear_distance(sc, ox, oy) - extent < g->clearance)
				continue;
			evo_obstacle o;
			memset(&o, 0, sizeof o);
			o.shape = box ? EVO_SHAPE_BOX : EVO_SHAPE_CIRCLE;
			o.x = ox;
			o.y = oy;
			o.angle = box ? angle : 0;
			o.radius = size;
			o.half_w = o.half_h = size;
			if (evo_scene_add_obstacle(sc, &o) < 0)
				return;
		}
	}
}

void evo_grid_rebuild(evo_scene *sc, uint64_t seed, int world_new)
{
	/* The elements' obstacles come back first, with the same indices. */
	if (world_new || sc->grid.enabled ||
	    sc->n_obstacles != sc->n_fixed_obstacles) {
		int n = sc->n_fixed_obstacles;
		if (!world_new)
			sc->be->clear_statics(sc->bw);
		sc->n_obstacles = 0;
		for (int i = 0; i < n; i++) {
			evo_obstacle o = sc->obstacle[i];
			evo_scene_add_obstacle(sc, &o);
		}
		build_grid(sc, seed);
	}
}

/* Element queries (sim/world2d/query.h): where a target is, which object is
 * within reach, whether a zone holds a point. The sensors, the actuators
 * and the rewards ask these; they only read the scene. */
#include "world2d/query.h"

#include <math.h>

void evo_bot_to_world(const evo_scene *sc, int bot, double bx, double by,
		      double *wx, double *wy)
{
	const evo_bot *b = &sc->bot[bot];
	*wx = b->x + b->c * bx - b->s * by;
	*wy = b->y + b->s * bx + b->c * by;
}

int evo_scene_target_pos(const evo_scene *sc, int bot, int target, double *x,
			 double *y)
{
	if (target >= 0 && target < sc->n_elements) {
		const evo_element *e = &sc->element[target];
		if (!e->active)
			return 0;
		*x = e->x;
		*y = e->y;
		return 1;
	}
	if (target != EVO_TARGET_NEAREST_OBJECT || bot < 0 || bot >= sc->n_bots)
		return 0;
	const evo_bot *b = &sc->bot[bot];
	double best = INFINITY;
	for (int k = 0; k < sc->n_objects; k++) {
		const evo_element *e = &sc->element[sc->object[k]];
		if (!e->active || e->held_by >= 0)
			continue;
		double d = hypot(e->x - b->x, e->y - b->y);
		if (d < best) {
			best = d;
			*x = e->x;
			*y = e->y;
		}
	}
	return best < INFINITY;
}

int evo_scene_object_in_reach(const evo_scene *sc, double px, double py,
			      double ux, double uy, double reach, double arc)
{
	double cos_arc = cos(arc);
	double best = INFINITY;
	int found = -1;
	for (int k = 0; k < sc->n_objects; k++) {
		const evo_element *e = &sc->element[sc->object[k]];
		if (!e->active || e->held_by >= 0)
			continue;
		double ox = e->x - px, oy = e->y - py;
		double dist = hypot(ox, oy);
		double gap = dist - e->size;
		if (gap > reach || gap >= best)
			continue;
		if (ox * ux + oy * uy < dist * cos_arc)
			continue;
		best = gap;
		found = sc->object[k];
	}
	return found;
}

int evo_zone_contains(const evo_element *z, double x, double y)
{
	if (z->kind != EVO_ELEM_ZONE || !z->active)
		return 0;
	double c = cos(z->angle), s = sin(z->angle);
	double dx = x - z->x, dy = y - z->y;
	double lx = c * dx + s * dy, ly = -s * dx + c * dy;
	return fabs(lx) <= z->size && fabs(ly) <= z->size;
}

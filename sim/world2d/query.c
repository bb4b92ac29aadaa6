/* Element queries (sim/world2d/query.h): where a target is, which object is
 * within reach, whether a zone holds a point. The sensors, the actuators
 * and the rewards ask these; they only read the scene. */
#include "world2d/query.h"

#include <math.h>
#include <stdlib.h>

#include "world2d/scene_internal.h"

void evo_bot_to_world(const evo_scene *sc, int bot, double bx, double by,
		      double *wx, double *wy)
{
	const evo_bot *b = &sc->bot[bot];
	*wx = b->x + b->c * bx - b->s * by;
	*wy = b->y + b->s * bx + b->c * by;
}

int evo_scene_bot_of_body(const evo_scene *sc, int index)
{
	int o = index >= 0 && index < sc->cap_body_owner ? sc->body_owner[index]
							 : -1;
	return o >= 0 ? o : -1;
}

int evo_scene_object_of_body(const evo_scene *sc, int index)
{
	int o = index >= 0 && index < sc->cap_body_owner ? sc->body_owner[index]
							 : -1;
	return o <= -2 ? -o - 2 : -1;
}

#define NEAR_CAP 64

/* The nearest bot whose body's category meets mask, other than `bot`,
 * within EVO_TEAM_SEARCH of it: the broad phase is asked for squares
 * around the bot, 10 m across at first and twice as large each time,
 * until one holds a bot no farther than the square's half side (none
 * outside can then be nearer). Never a walk through all the bots. */
static int nearest_bot(const evo_scene *sc, int bot, uint16_t mask, double *x,
		       double *y)
{
	const evo_bot *b = &sc->bot[bot];
	evo_shape_info local[NEAR_CAP];
	for (double r = 5;; r *= 2) {
		if (r > EVO_TEAM_SEARCH)
			r = EVO_TEAM_SEARCH;
		evo_shape_info *s = local;
		int n = evo_scene_query(sc, b->x - r, b->y - r, b->x + r,
					b->y + r, mask, local, NEAR_CAP);
		if (n > NEAR_CAP) {
			evo_shape_info *big = malloc((size_t)n * sizeof *big);
			if (big) {
				s = big;
				n = evo_scene_query(sc, b->x - r, b->y - r,
						    b->x + r, b->y + r, mask,
						    big, n);
			} else {
				n = NEAR_CAP;
			}
		}
		double best = INFINITY;
		for (int i = 0; i < n; i++) {
			if (s[i].body.index == b->body.index ||
			    evo_scene_bot_of_body(sc, s[i].body.index) < 0)
				continue;
			double dx = s[i].x - b->x, dy = s[i].y - b->y;
			double d = dx * dx + dy * dy;
			if (d < best) {
				best = d;
				*x = s[i].x;
				*y = s[i].y;
			}
		}
		if (s != local)
			free(s);
		if (best <= r * r || (r >= EVO_TEAM_SEARCH && best < INFINITY))
			return 1;
		if (r >= EVO_TEAM_SEARCH)
			return 0;
	}
}

int evo_scene_target_pos(const evo_scene *sc, int bot, int target, double *x,
			 double *y)
{
	if ((target == EVO_TARGET_NEAREST_OPPONENT ||
	     target == EVO_TARGET_NEAREST_TEAMMATE) &&
	    bot >= 0 && bot < sc->n_bots) {
		int team = sc->bot[bot].team;
		uint16_t own = team >= 0 ? EVO_CAT_TEAM(team) : 0;
		uint16_t mask = target == EVO_TARGET_NEAREST_TEAMMATE
				    ? own
				    : (uint16_t)(EVO_CAT_TEAMS & ~own);
		return mask && nearest_bot(sc, bot, mask, x, y);
	}
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
		/* the squared distance orders them as the distance does, at
		 * a fraction of hypot's cost (this runs for every tracker of
		 * every bot, every tick) */
		double dx = e->x - b->x, dy = e->y - b->y;
		double d = dx * dx + dy * dy;
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
	if (z->kind != EVO_PIECE_ZONE || !z->active)
		return 0;
	double c = cos(z->angle), s = sin(z->angle);
	double dx = x - z->x, dy = y - z->y;
	double lx = c * dx + s * dy, ly = -s * dx + c * dy;
	return fabs(lx) <= z->size && fabs(ly) <= z->size;
}

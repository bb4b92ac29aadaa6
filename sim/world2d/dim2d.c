/* The 2D scene as the scene model (sim/scene/core.h) asks of it: its
 * evo_scene_dim, with the checks of rewards and controls only 2D makes
 * (a target may be the nearest object, opponent or teammate; Collect
 * needs a zone), and the tick's parts
 * (sensors.c, and step.c's act and read-back), which sim/scene/tick.c
 * runs in their order; and what a task's simulation reads of it: its
 * reset, a bot's sensors and actuators, the arena its obstacles span. */
#include <math.h>
#include <stddef.h>

#include "world2d/scene.h"
#include "world2d/scene_internal.h"
#include "world2d/sensors.h"

/* ---- the checks at adding ------------------------------------------------ */

/* A 2D target is an element, none, or the nearest object, opponent or
 * teammate. */
static int target_ok(evo_scene_core *c, int target, const char *what)
{
	return evo_scene_check_target((evo_scene *)c, target, what);
}

static int zone(const evo_scene *sc, int target)
{
	return target >= 0 && sc->element[target].kind == EVO_PIECE_ZONE;
}

static int check_reward(evo_scene_core *c, const evo_reward_def *d)
{
	if (d->kind == EVO_RW_COLLECT && !zone((evo_scene *)c, d->target))
		return evo_fail(&c->err, "reward Collect needs a zone");
	return 0;
}

/* ---- the tick ------------------------------------------------------------ */

static void sense(evo_scene_core *c)
{
	evo_sense_all((evo_scene *)c);
}

/* ---- what a task's simulation reads ---------------------------------------
 */

static int reset(evo_scene_core *c, uint64_t grid_seed, uint64_t episode_seed)
{
	evo_scene_reset((evo_scene *)c, grid_seed, episode_seed);
	return 0;
}

/* Widen b (x0, y0, x1, y1) to hold the box of half sizes hx, hy at x, y. */
static void widen(double *b, double x, double y, double hx, double hy)
{
	b[0] = fmin(b[0], x - hx);
	b[1] = fmin(b[1], y - hy);
	b[2] = fmax(b[2], x + hx);
	b[3] = fmax(b[3], y + hy);
}

/* The elements' and walls' obstacles and the obstacle grid's area. */
static void arena(const evo_scene_core *c, double *b)
{
	const evo_scene *sc = (const evo_scene *)c;
	for (int i = 0; i < sc->n_fixed_obstacles; i++) {
		const evo_obstacle *o = &sc->obstacle[i];
		double cs = fabs(cos(o->angle)), sn = fabs(sin(o->angle));
		if (o->shape == EVO_SHAPE_CIRCLE) {
			widen(b, o->x, o->y, o->radius, o->radius);
		} else if (o->shape == EVO_SHAPE_SEGMENT) {
			/* a wall: (x, y) is one end, not its middle */
			widen(b, o->x, o->y, 0, 0);
			widen(b, o->x2, o->y2, 0, 0);
		} else
			widen(b, o->x, o->y, cs * o->half_w + sn * o->half_h,
			      sn * o->half_w + cs * o->half_h);
	}
	if (sc->grid.enabled) {
		const evo_grid_def *g = &sc->grid;
		widen(b, (g->x0 + g->x1) / 2, (g->y0 + g->y1) / 2,
		      fabs(g->x1 - g->x0) / 2, fabs(g->y1 - g->y0) / 2);
	}
}

/* ---- the table ----------------------------------------------------------- */

const evo_scene_dim evo_scene_dim_2d = {
    .name = "2D",
    .dims = EVO_DIM_2D,
    /* rewards and controls: how they read it, what they may name */
    .score = &evo_score_ops_2d,
    .check_target = target_ok,
    .check_reward = check_reward,
    /* the tick: one physics step, no fault (Box2D reports none) */
    .sense = sense,
    .act = evo_scene_act,
    .read_back = evo_scene_read_back,
    /* what a task's simulation reads */
    .reset = reset,
    .arena = arena,
};

/* The 3D scene as the scene model (sim/scene/core.h) asks of it: its
 * evo_scene_dim, with what a 3D target may be (an element, or none),
 * NextOnTimeout's shift, and the tick's
 * parts (sensors3d.c, actuators3d.c, step3d.c's read-back and fault),
 * which sim/scene/tick.c runs in their order: contacts counted over the
 * tick's substeps, a body that explodes ending the episode; and what a
 * task's simulation reads of it: its reset, a bot's sensors and
 * actuators, the arena its obstacles span. */
#include <math.h>
#include <stddef.h>

#include "world3d/scene3d.h"
#include "world3d/scene3d_internal.h"

/* ---- the checks at adding ------------------------------------------------ */

/* A target of a 3D reward or control: an element, or none. */
static int check_target(evo_scene_core *c, int target, const char *what)
{
	if (target == EVO_TARGET_NONE ||
	    (target >= 0 && target < ((evo_scene3d *)c)->n_elements))
		return 0;
	return evo_fail(&c->err, "%s: no element %d", what, target);
}

/* ---- the tick ------------------------------------------------------------ */

static void sense(evo_scene_core *c)
{
	evo_scene3d_sense((evo_scene3d *)c);
}

/* Contacts are counted over the tick's substeps. */
static void begin(evo_scene_core *c)
{
	evo_scene3d *sc = (evo_scene3d *)c;
	for (int i = 0; i < sc->n_bots; i++)
		sc->bot[i].touching = 0;
}

static int substeps(const evo_scene_core *c)
{
	return ((const evo_scene3d *)c)->def.substeps;
}

static void act(evo_scene_core *c)
{
	evo_scene3d *sc = (evo_scene3d *)c;
	for (int i = 0; i < sc->n_bots; i++)
		evo_bot3d_act(sc, i);
}

static void after_substep(evo_scene_core *c)
{
	evo_scene3d *sc = (evo_scene3d *)c;
	for (int i = 0; i < sc->n_bots; i++)
		sc->bot[i].touching +=
		    sc->be->touching(sc->bw, sc->bot[i].body);
}

/* ---- what a task's simulation reads ---------------------------------------
 */

static int reset(evo_scene_core *c, uint64_t grid_seed, uint64_t episode_seed)
{
	return evo_scene3d_reset((evo_scene3d *)c, grid_seed, episode_seed);
}

/* The static boxes, cylinders and spheres that are not ground: widen b
 * (x0, y0, x1, y1) over each. */
static void arena(const evo_scene_core *c, double *b)
{
	const evo_scene3d *sc = (const evo_scene3d *)c;
	for (int i = 0; i < sc->n_elements; i++) {
		const evo_element_def *d = &sc->element[i].def;
		if (!evo_element_is_solid(d->kind) || d->ground)
			continue;
		double cs = fabs(cos(d->yaw)), sn = fabs(sin(d->yaw));
		double hx = d->radius, hy = d->radius;
		if (d->kind == EVO_PIECE_BOX) {
			hx = cs * d->half[0] + sn * d->half[1];
			hy = sn * d->half[0] + cs * d->half[1];
		}
		b[0] = fmin(b[0], d->pos[0] - hx);
		b[1] = fmin(b[1], d->pos[1] - hy);
		b[2] = fmax(b[2], d->pos[0] + hx);
		b[3] = fmax(b[3], d->pos[1] + hy);
	}
}

/* ---- the table ----------------------------------------------------------- */

const evo_scene_dim evo_scene_dim_3d = {
    .name = "3D",
    .dims = EVO_DIM_3D,
    /* rewards and controls: how they read it, what they may name */
    .score = &evo_score_ops_3d,
    .check_target = check_target,
    .timeout_shift = 1,
    /* the tick: sensing, then before the physics */
    .sense = sense,
    .begin = begin,
    .substeps = substeps,
    .act = act,
    /* after each physics step, after the last, or when a body exploded */
    .after_substep = after_substep,
    .read_back = evo_scene3d_read_back,
    .fault = evo_scene3d_fault,
    /* what a task's simulation reads */
    .reset = reset,
    .arena = arena,
};

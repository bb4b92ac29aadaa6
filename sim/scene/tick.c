/* The tick of a scene of either dimension, in its order, once
 * (sim/scene/core.h, DESIGN.md's tick): the sensing, then, after the
 * caller wrote the commands, the actuators and the physics, the poses
 * read back, and the scoring. Each dimension gives its parts through its
 * evo_scene_dim (world2d/step.c, world3d/step3d.c). */
#include "scene/core.h"

#include <stdio.h>

void evo_core_sense(evo_scene_core *c)
{
	c->dim->sense(c);
}

/* A body exploded in the physics step that ended tick c->tick: the
 * dimension says which, and the step pays the penalty. */
static int fault(evo_scene_core *c, const evo_bfault *f)
{
	double penalty = 0;
	if (c->dim->fault)
		penalty = c->dim->fault(c, f);
	else
		snprintf(c->fault, sizeof c->fault,
			 "the %s physics failed at tick %ld", c->dim->name,
			 c->tick);
	c->step_reward = penalty;
	c->episode_reward += penalty;
	return 1;
}

int evo_core_step(evo_scene_core *c)
{
	const evo_scene_dim *d = c->dim;
	if (c->fault[0])
		return 1;
	if (c->keeps_touches && c->be->forget_touches)
		c->be->forget_touches(c->bw);
	if (d->begin)
		d->begin(c);
	int n = d->substeps ? d->substeps(c) : 1;
	for (int s = 0; s < n; s++) {
		d->act(c);
		evo_bfault f;
		if (c->be->step(c->bw, &f)) {
			c->tick++;
			return fault(c, &f);
		}
		if (d->after_substep)
			d->after_substep(c);
	}
	c->tick++;
	d->read_back(c);
	/* rewards, the post-step hook, controls */
	return evo_core_score(c);
}

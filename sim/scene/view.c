/* A scene's bots as a task's simulation and the scoring read them, the
 * same in 2D and 3D (sim/scene/core.h): the sensors' last samples, the
 * actuators' commands, the sensors nothing reads, and what a bot
 * touched (NextOnCollisionWithTarget). */
#include "scene/core.h"

#include <math.h>

void evo_bot_read_sensors(const evo_bot *b, const int *map, unsigned n,
			  double *out)
{
	for (unsigned i = 0; i < n; i++)
		out[i] = b->sensor[map[i]].value;
}

void evo_bot_write_actuators(evo_bot *b, const int *map, unsigned n,
			     const double *in)
{
	for (unsigned i = 0; i < n; i++)
		b->actuator[map[i]].command = in[i];
}

void evo_core_wake_scored(evo_scene_core *c)
{
	for (int i = 0; i < c->n_rewards; i++) {
		const evo_reward_def *d = &c->reward[i].def;
		for (int k = 0; k < d->n_sensors; k++)
			c->bot[d->bot].sensor[d->sensor[k]].idle = 0;
	}
	for (int i = 0; i < c->n_controls; i++) {
		const evo_control_def *d = &c->control[i].def;
		if (d->sensor >= 0)
			c->bot[d->bot].sensor[d->sensor].idle = 0;
	}
}

int evo_core_n_bots(const void *core)
{
	return ((const evo_scene_core *)core)->n_bots;
}

double evo_core_sensor(const void *core, int bot, int s)
{
	const evo_bot *b = &((const evo_scene_core *)core)->bot[bot];
	return s >= 0 && s < b->n_sensors ? b->sensor[s].value : NAN;
}

/* A zone or target has no body, and an object set off no contacts: they
 * are never touched (core.c refuses them as the control's target). */
int evo_core_touching(const void *core, int bot, int target)
{
	const evo_scene_core *c = core;
	if (target < 0 || target >= c->n_elements)
		return 0;
	const evo_element *e = &c->element[target];
	evo_body_id body = c->bot[bot].body;
	if (e->kind == EVO_PIECE_OBJECT)
		return e->active && c->be->touching_body(c->bw, body, e->body);
	if (evo_element_is_solid(e->kind))
		return c->be->touching_obstacle(c->bw, body,
						c->first_static + e->obstacle);
	return 0;
}

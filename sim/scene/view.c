/* A scene's bots as a task's simulation and the scoring read them, the
 * same in 2D and 3D (sim/scene/core.h): the sensors' last samples, the
 * actuators' commands, the sensors nothing reads. */
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

/* A scene's bots seen from outside their dimension (sim/scene/core.h): a
 * bot's figures, read from the one evo_bot (scene/bot.h), and its sensors
 * and actuators as arrays of structs whose names and values lie at
 * offsets its dimension gives (evo_parts), so that a task's simulation
 * binds, reads and writes them, and the scoring reads a sensor, the same
 * way in 2D and 3D. */
#include "scene/core.h"

#include <math.h>

#include "scene/store.h"

/* Field by field: tasksim reads a view of each agent every tick. */
void evo_core_bot(const evo_scene_core *c, int bot, evo_bot_view *v)
{
	evo_bot *b = &c->bot[bot];
	v->name = b->name;
	v->team = b->team;
	v->collisions = b->collisions;
	v->reward = &b->reward;
	v->now[0] = b->pos[0];
	v->now[1] = b->pos[1];
	v->start[0] = b->start[0];
	v->start[1] = b->start[1];
	c->dim->parts(c, bot, &v->sensors, &v->actuators);
}

const char *evo_parts_name(const evo_parts *p, int i)
{
	return p->base + (size_t)i * p->stride + p->name_at;
}

int evo_parts_find(const evo_parts *p, const char *name)
{
	return evo_store_find(p->base, p->n, p->stride, p->name_at, name);
}

static double *value(const evo_parts *p, int i)
{
	return (double *)(void *)(p->base + (size_t)i * p->stride +
				  p->value_at);
}

void evo_parts_read(const evo_parts *p, const int *map, unsigned n, double *out)
{
	for (unsigned i = 0; i < n; i++)
		out[i] = *value(p, map[i]);
}

void evo_parts_write(const evo_parts *p, const int *map, unsigned n,
		     const double *in)
{
	for (unsigned i = 0; i < n; i++)
		*value(p, map[i]) = in[i];
}

void evo_parts_set_idle(const evo_parts *p, int i, int idle)
{
	if (p->idle_at)
		*(int *)(void *)(p->base + (size_t)i * p->stride + p->idle_at) =
		    idle;
}

void evo_core_wake_scored(evo_scene_core *c)
{
	evo_bot_view v;
	for (int i = 0; i < c->n_rewards; i++) {
		const evo_reward_def *d = &c->reward[i].def;
		evo_core_bot(c, d->bot, &v);
		for (int k = 0; k < d->n_sensors; k++)
			evo_parts_set_idle(&v.sensors, d->sensor[k], 0);
	}
	for (int i = 0; i < c->n_controls; i++) {
		const evo_control_def *d = &c->control[i].def;
		evo_core_bot(c, d->bot, &v);
		if (d->sensor >= 0)
			evo_parts_set_idle(&v.sensors, d->sensor, 0);
	}
}

int evo_core_n_bots(const void *core)
{
	return ((const evo_scene_core *)core)->n_bots;
}

/* Its parts alone: the rewards read a sensor every tick. */
double evo_core_sensor(const void *core, int bot, int s)
{
	const evo_scene_core *c = core;
	evo_parts sensors, actuators;
	c->dim->parts(c, bot, &sensors, &actuators);
	return s >= 0 && s < sensors.n ? *value(&sensors, s) : NAN;
}

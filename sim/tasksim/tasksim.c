/* A task's simulation: scene + Lua environment + mind (sim/tasksim/tasksim.h). */
#include "tasksim/tasksim.h"

#include <stdlib.h>
#include <string.h>

#include "mind/trace.h"

/* "did you mean" over a bot's sensor or actuator names. */
static const char *closest(const char *word, const evo_bot *b, int sensors)
{
	const char *names[256];
	int n = sensors ? b->n_sensors : b->n_actuators;
	if (n > 256)
		n = 256;
	for (int i = 0; i < n; i++)
		names[i] = sensors ? b->sensor[i].name : b->actuator[i].name;
	const char *c = evo_closest_name(word, names, (size_t)n, NULL);
	return c ? c : "";
}

/* Sensors nothing reads are not sampled: the mind reads the botdesc's,
 * rewards and controls name theirs, and a script's bot:value wakes the one
 * it asks for. */
static void mark_idle(evo_sim *s)
{
	evo_scene *sc = s->scene;
	evo_bot *b = &sc->bot[s->bot];
	for (int i = 0; i < b->n_sensors; i++)
		b->sensor[i].idle = 1;
	for (unsigned i = 0; i < s->mind->botdesc->n_sensors; i++)
		b->sensor[s->sensor_map[i]].idle = 0;
	for (int i = 0; i < sc->n_rewards; i++) {
		const evo_reward_def *d = &sc->reward[i].def;
		for (int k = 0; k < d->n_sensors; k++)
			sc->bot[d->bot].sensor[d->sensor[k]].idle = 0;
	}
	for (int i = 0; i < sc->n_controls; i++) {
		const evo_control_def *d = &sc->control[i].def;
		if (d->sensor >= 0)
			sc->bot[d->bot].sensor[d->sensor].idle = 0;
	}
}

/* Bind botdesc names to the bot's sensors and actuators. A name the bot
 * model lacks is the botdesc's error, reported at its line. */
static int bind(evo_sim *s, const evo_mindfolder *mind, evo_err *err)
{
	const evo_bot *b = &s->scene->bot[s->bot];
	const evo_botdesc *d = mind->botdesc;
	const char *model = evo_lua_bot_path(s->lua);
	for (unsigned i = 0; i < d->n_sensors; i++) {
		int k = evo_bot_find_sensor(b, d->sensor[i].name);
		if (k < 0)
			return evo_fail(err,
					"%s/%s.botdesc:%u: sensor '%s' is not "
					"on the bot (model %s); closest: %s",
					mind->root, mind->bot_name,
					d->sensor[i].line, d->sensor[i].name,
					model, closest(d->sensor[i].name, b, 1));
		s->sensor_map[i] = k;
	}
	for (unsigned i = 0; i < d->n_actuators; i++) {
		int k = evo_bot_find_actuator(b, d->actuator[i].name);
		if (k < 0)
			return evo_fail(err,
					"%s/%s.botdesc:%u: actuator '%s' is not "
					"on the bot (model %s); closest: %s",
					mind->root, mind->bot_name,
					d->actuator[i].line,
					d->actuator[i].name, model,
					closest(d->actuator[i].name, b, 0));
		s->actuator_map[i] = k;
	}
	return 0;
}

int evo_sim_set_mind(evo_sim *s, const evo_mindfolder *mind, evo_err *err)
{
	size_t need = evo_state_size(&mind->mind);
	free(s->state_mem);
	s->state_mem = aligned_alloc(8, (need + 7) & ~(size_t)7);
	s->state = NULL;
	if (!s->state_mem)
		return evo_fail(err, "out of memory");
	evo_status st = evo_state_init(&mind->mind, s->state_mem,
				       (need + 7) & ~(size_t)7, &s->state);
	if (st != EVO_OK)
		return evo_fail(err, "mind state: %s", evo_status_str(st));
	s->mind = mind;
	if (bind(s, mind, err))
		return -1;
	mark_idle(s);
	return 0;
}

evo_sim *evo_sim_create(const evo_mindfolder *mind, const evo_simbatch *task,
			const char *task_path, evo_err *err)
{
	evo_sim *s = calloc(1, sizeof *s);
	if (!s) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	s->task = task;
	s->scene = evo_scene_create();
	if (!s->scene) {
		evo_fail(err, "cannot create a physics world");
		free(s);
		return NULL;
	}
	const char *env = evo_simbatch_get(task, "ENV");
	const char *model = evo_simbatch_get(task, "BOTMODEL");
	if (!env || !model) {
		evo_fail(err, "%s: a simulated task needs ENV and BOTMODEL",
			 task_path);
		evo_sim_destroy(s);
		return NULL;
	}
	evo_lua_def ld = {
		.scene = s->scene,
		.mind_dir = mind->root,
		.botmodel = model,
		.task = task,
	};
	s->lua = evo_lua_create(&ld, err);
	if (!s->lua || evo_lua_init_env(s->lua, env, err) ||
	    evo_sim_set_mind(s, mind, err)) {
		evo_sim_destroy(s);
		return NULL;
	}
	return s;
}

void evo_sim_destroy(evo_sim *s)
{
	if (!s)
		return;
	evo_lua_destroy(s->lua);
	evo_scene_destroy(s->scene);
	free(s->state_mem);
	free(s);
}

int evo_sim_reset(evo_sim *s, int episode, uint64_t grid_seed,
		  uint64_t episode_seed, evo_err *err)
{
	evo_scene_reset(s->scene, grid_seed, episode_seed);
	evo_state_reset(&s->mind->mind, s->state);
	s->episode = episode;
	return evo_lua_reset(s->lua, episode, err);
}

int evo_sim_tick(evo_sim *s, evo_err *err)
{
	evo_scene *sc = s->scene;
	evo_bot *b = &sc->bot[s->bot];
	const evo_mind *m = &s->mind->mind;
	evo_scene_sense(sc);
	for (unsigned i = 0; i < m->n_sensors; i++)
		s->sensors[i] =
			evo_q16_from_sensor(b->sensor[s->sensor_map[i]].value);
	evo_mind_step(m, s->state, s->sensors, s->actuators);
	for (unsigned i = 0; i < m->n_actuators; i++)
		b->actuator[s->actuator_map[i]].command =
			evo_q16_to_double(s->actuators[i]);
	if (s->trace)
		evo_trace_tick(s->trace, sc->tick, m, s->sensors, s->actuators,
			       s->state);
	int r = evo_scene_step(sc);
	if (r < 0)
		evo_fail(err, "%s", sc->err.msg);
	return r;
}

void evo_sim_sense(evo_sim *s, double *values)
{
	const evo_bot *b = &s->scene->bot[s->bot];
	evo_scene_sense(s->scene);
	for (unsigned i = 0; i < s->mind->mind.n_sensors; i++)
		values[i] = b->sensor[s->sensor_map[i]].value;
}

int evo_sim_act(evo_sim *s, const double *commands, evo_err *err)
{
	evo_bot *b = &s->scene->bot[s->bot];
	for (unsigned i = 0; i < s->mind->mind.n_actuators; i++)
		b->actuator[s->actuator_map[i]].command = commands[i];
	int r = evo_scene_step(s->scene);
	if (r < 0)
		evo_fail(err, "%s", s->scene->err.msg);
	return r;
}

void evo_sim_trace_header(evo_sim *s)
{
	evo_trace_header(s->trace, s->mind);
}

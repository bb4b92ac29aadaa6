/* A task's simulation: scene + Lua environment + the minds of its agents
 * (sim/tasksim/tasksim.h). */
#include "tasksim/tasksim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "mind/trace.h"

_Static_assert(EVO_MAX_TEAMS <= EVO_SCENE_MAX_TEAMS,
	       "a task's teams fit a scene's");

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

/* The same over a 3D bot's. */
static const char *closest3d(const char *word, const evo_bot3d *b, int sensors)
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

/* Bind a one-agent 3D task's botdesc names to its bot's sensors and
 * actuators. */
static int bind3d(evo_sim *s, evo_sim_team *tm, evo_err *err)
{
	const evo_bot3d *b = &s->scene3d->bot[0];
	const evo_mindfolder *mind = tm->mind;
	const evo_botdesc *d = mind->botdesc;
	const char *model = evo_lua_bot_path(s->lua);
	for (unsigned i = 0; i < d->n_sensors; i++) {
		int k = evo_bot3d_find_sensor(b, d->sensor[i].name);
		if (k < 0)
			return evo_fail(err,
					"%s/%s.botdesc:%u: sensor '%s' is not "
					"on the bot (model %s); closest: %s",
					mind->root, mind->bot_name,
					d->sensor[i].line, d->sensor[i].name,
					model,
					closest3d(d->sensor[i].name, b, 1));
		tm->sensor_map[i] = k;
	}
	for (unsigned i = 0; i < d->n_actuators; i++) {
		int k = evo_bot3d_find_actuator(b, d->actuator[i].name);
		if (k < 0)
			return evo_fail(
			    err,
			    "%s/%s.botdesc:%u: actuator '%s' is not "
			    "on the bot (model %s); closest: %s",
			    mind->root, mind->bot_name, d->actuator[i].line,
			    d->actuator[i].name, model,
			    closest3d(d->actuator[i].name, b, 0));
		tm->actuator_map[i] = k;
	}
	return 0;
}

/* Sensors nothing reads are not sampled: the minds read the botdesc's,
 * rewards and controls name theirs, and a script's bot:value wakes the one
 * it asks for. In a one-agent task only the agent's bot is marked, as it
 * always was; in a team task, every bot, so a bot no mind drives senses
 * nothing. */
static void mark_idle(evo_sim *s)
{
	evo_scene *sc = s->scene;
	for (int k = 0; k < sc->n_bots; k++) {
		if (!s->has_teams && k != s->bot)
			continue;
		evo_bot *b = &sc->bot[k];
		for (int i = 0; i < b->n_sensors; i++)
			b->sensor[i].idle = 1;
	}
	for (int a = 0; a < s->n_agents; a++) {
		const evo_sim_agent *ag = &s->agent[a];
		const evo_sim_team *tm = &s->team[ag->team];
		evo_bot *b = &sc->bot[ag->bot];
		for (unsigned i = 0; i < tm->mind->botdesc->n_sensors; i++)
			b->sensor[tm->sensor_map[i]].idle = 0;
	}
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

/* After a botdesc error, where the team is: " (team Red, T.simbatch:3)". */
static void team_suffix(const evo_sim *s, const evo_sim_team *tm, char *out,
			size_t cap)
{
	if (s->has_teams)
		snprintf(out, cap, " (team %s, %s:%u)", tm->name, s->task_path,
			 (unsigned)tm->line);
	else
		out[0] = 0;
}

/* Bind botdesc names to bot's sensors and actuators into the team's maps
 * (first: fill them; later bots: check they agree). A name the bot model
 * lacks is the botdesc's error, reported at its line. */
static int bind(evo_sim *s, evo_sim_team *tm, int bot, int first, evo_err *err)
{
	if (s->scene3d)
		return bind3d(s, tm, err);
	const evo_bot *b = &s->scene->bot[bot];
	const evo_mindfolder *mind = tm->mind;
	const evo_botdesc *d = mind->botdesc;
	const char *model = evo_lua_bot_path(s->lua);
	char where[1200];
	team_suffix(s, tm, where, sizeof where);
	for (unsigned i = 0; i < d->n_sensors; i++) {
		int k = evo_bot_find_sensor(b, d->sensor[i].name);
		if (k < 0)
			return evo_fail(err,
					"%s/%s.botdesc:%u: sensor '%s' is not "
					"on the bot (model %s); closest: %s%s",
					mind->root, mind->bot_name,
					d->sensor[i].line, d->sensor[i].name,
					model, closest(d->sensor[i].name, b, 1),
					where);
		if (!first && k != tm->sensor_map[i])
			return evo_fail(err,
					"bot %s: its sensor '%s' is not where "
					"its team's first bot has it: the "
					"environment changed one bot of the "
					"team%s",
					b->name, d->sensor[i].name, where);
		tm->sensor_map[i] = k;
	}
	for (unsigned i = 0; i < d->n_actuators; i++) {
		int k = evo_bot_find_actuator(b, d->actuator[i].name);
		if (k < 0)
			return evo_fail(
			    err,
			    "%s/%s.botdesc:%u: actuator '%s' is not "
			    "on the bot (model %s); closest: %s%s",
			    mind->root, mind->bot_name, d->actuator[i].line,
			    d->actuator[i].name, model,
			    closest(d->actuator[i].name, b, 0), where);
		if (!first && k != tm->actuator_map[i])
			return evo_fail(
			    err,
			    "bot %s: its actuator '%s' is not where "
			    "its team's first bot has it%s",
			    b->name, d->actuator[i].name, where);
		tm->actuator_map[i] = k;
	}
	return 0;
}

/* A fresh state for agent a under its mind (the memory grows as needed:
 * networks of another candidate may need more). */
static int agent_state(evo_sim_agent *a, evo_err *err)
{
	size_t need = (evo_state_size(&a->mind->mind) + 7) & ~(size_t)7;
	if (need > a->state_cap) {
		free(a->state_mem);
		a->state_mem = aligned_alloc(8, need);
		a->state_cap = a->state_mem ? need : 0;
	}
	a->state = NULL;
	if (!a->state_mem)
		return evo_fail(err, "out of memory");
	evo_status st = evo_state_init(&a->mind->mind, a->state_mem,
				       a->state_cap, &a->state);
	if (st != EVO_OK)
		return evo_fail(err, "mind state: %s", evo_status_str(st));
	return 0;
}

/* The first agent's view, as a one-agent task has it. */
static void first_agent_view(evo_sim *s)
{
	s->mind = s->team[0].mind;
	s->bot = s->agent[0].bot;
	s->state = s->agent[0].state;
	memcpy(s->sensor_map, s->team[0].sensor_map, sizeof s->sensor_map);
	memcpy(s->actuator_map, s->team[0].actuator_map,
	       sizeof s->actuator_map);
}

int evo_sim_set_team_mind(evo_sim *s, int team, const evo_mindfolder *mind,
			  evo_err *err)
{
	if (team < 0 || team >= s->n_teams)
		return evo_fail(err, "no team %d", team);
	evo_sim_team *tm = &s->team[team];
	tm->mind = mind;
	for (int k = 0; k < tm->size; k++) {
		evo_sim_agent *a = &s->agent[tm->first + k];
		a->mind = mind;
		if (bind(s, tm, a->bot, k == 0, err) || agent_state(a, err))
			return -1;
	}
	first_agent_view(s);
	if (s->scene)
		mark_idle(s);
	return 0;
}

int evo_sim_set_agent_mind(evo_sim *s, int agent, const evo_mindfolder *mind,
			   evo_err *err)
{
	if (agent < 0 || agent >= s->n_agents)
		return evo_fail(err, "no agent %d", agent);
	evo_sim_agent *a = &s->agent[agent];
	if (mind->names_hash != s->team[a->team].mind->names_hash)
		return evo_fail(err,
				"agent %d: a mind of other sensors, actuators "
				"or variables than its team's",
				agent);
	a->mind = mind;
	if (agent_state(a, err))
		return -1;
	first_agent_view(s);
	return 0;
}

int evo_sim_set_mind(evo_sim *s, const evo_mindfolder *mind, evo_err *err)
{
	return evo_sim_set_team_mind(s, 0, mind, err);
}

/* Lay out the teams and their agents: team k's agents are its bots in
 * the scene's order. A team task's environment must have made each team
 * its SIZE bots. */
static int make_agents(evo_sim *s, evo_err *err)
{
	evo_scene *sc = s->scene;
	int n = 0;
	if (s->scene3d && s->has_teams)
		return evo_fail(err, "%s: 3D tasks have one agent, no teams",
				s->task_path);
	for (int k = 0; k < s->n_teams; k++)
		n += s->team[k].size;
	s->agent = calloc((size_t)n, sizeof *s->agent);
	if (!s->agent)
		return evo_fail(err, "out of memory");
	s->n_agents = n;
	if (!s->has_teams) {
		s->agent[0].bot = 0;
		s->agent[0].team = 0;
		return 0;
	}
	int next = 0;
	for (int k = 0; k < s->n_teams; k++) {
		evo_sim_team *tm = &s->team[k];
		int made = 0;
		tm->first = next;
		for (int b = 0; b < sc->n_bots; b++)
			if (sc->bot[b].team == k && made < tm->size) {
				s->agent[next].bot = b;
				s->agent[next].team = k;
				next++;
				made++;
			}
		if (made != tm->size)
			return evo_fail(err,
					"%s:%u: TEAM %s: the environment made "
					"%d of its %d bots (%s): each team's "
					"bots come from scene:bot{team = "
					"\"%s\"} (docs/teams.md)",
					s->task_path, (unsigned)tm->line,
					tm->name, made, tm->size,
					evo_lua_env_path(s->lua), tm->name);
	}
	return 0;
}

/* The common part of both constructors: the scene, its Lua environment
 * and the agents of s->team[0 .. n_teams). */
static evo_sim *build(evo_sim *s, const evo_simbatch *task,
		      const char *task_path, const char *mind_dir,
		      const char *model, const evo_lua_team *lt, evo_err *err)
{
	s->task = task;
	snprintf(s->task_path, sizeof s->task_path, "%s", task_path);
	const char *type = evo_simbatch_get(task, "TYPE");
	if (type && evo_sim_type_is_3d(type)) {
		evo_scene3d_def d3 = evo_default_scene3d_def();
		s->scene3d = evo_scene3d_create(&d3);
	} else {
		s->scene = evo_scene_create();
	}
	if (!s->scene && !s->scene3d) {
		evo_fail(err, "cannot create a physics world");
		evo_sim_destroy(s);
		return NULL;
	}
	const char *env = evo_simbatch_get(task, "ENV");
	if (!env || (!s->has_teams && !model)) {
		evo_fail(err, "%s: a simulated task needs ENV and BOTMODEL",
			 task_path);
		evo_sim_destroy(s);
		return NULL;
	}
	evo_lua_def ld = {
	    .scene = s->scene,
	    .scene3d = s->scene3d,
	    .mind_dir = mind_dir,
	    .botmodel = model,
	    .task = task,
	    .teams = lt,
	    .n_teams = s->has_teams ? s->n_teams : 0,
	    .task_path = task_path,
	};
	s->lua = evo_lua_create(&ld, err);
	if (!s->lua || evo_lua_init_env(s->lua, env, err) ||
	    make_agents(s, err)) {
		evo_sim_destroy(s);
		return NULL;
	}
	for (int k = 0; k < s->n_teams; k++)
		if (evo_sim_set_team_mind(s, k, s->team[k].mind, err)) {
			evo_sim_destroy(s);
			return NULL;
		}
	return s;
}

evo_sim *evo_sim_create(const evo_mindfolder *mind, const evo_simbatch *task,
			const char *task_path, evo_err *err)
{
	evo_sim *s = calloc(1, sizeof *s);
	if (s)
		s->team = calloc(1, sizeof *s->team);
	if (!s || !s->team) {
		free(s);
		evo_fail(err, "out of memory");
		return NULL;
	}
	s->n_teams = 1;
	s->team[0].mind = mind;
	s->team[0].size = 1;
	return build(s, task, task_path, mind->root,
		     evo_simbatch_get(task, "BOTMODEL"), NULL, err);
}

evo_sim *evo_sim_create_task(const evo_task *t, const char *task_path,
			     evo_err *err)
{
	if (t->n_teams == 0)
		return evo_sim_create(t->mind, t->sb, task_path, err);
	evo_sim *s = calloc(1, sizeof *s);
	if (s)
		s->team = calloc((size_t)t->n_teams, sizeof *s->team);
	if (!s || !s->team) {
		free(s);
		evo_fail(err, "out of memory");
		return NULL;
	}
	evo_lua_team lt[EVO_MAX_TEAMS];
	s->has_teams = 1;
	s->n_teams = t->n_teams;
	for (int k = 0; k < t->n_teams; k++) {
		const evo_team *tm = &t->team[k];
		snprintf(s->team[k].name, sizeof s->team[k].name, "%s",
			 tm->name);
		s->team[k].mind = tm->mind;
		s->team[k].size = tm->size;
		s->team[k].line = tm->line;
		lt[k].name = tm->name;
		lt[k].botmodel = tm->botmodel;
		lt[k].mind_dir = tm->mind->root;
		lt[k].size = tm->size;
	}
	if (!build(s, t->sb, task_path, t->mind->root, NULL, lt, err))
		return NULL;
	/* members with networks of their own */
	for (int k = 0; k < t->n_teams; k++)
		for (int i = 0; t->team[k].member && i < t->team[k].size; i++)
			if (t->team[k].member[i] &&
			    evo_sim_set_agent_mind(s, s->team[k].first + i,
						   t->team[k].member[i], err)) {
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
	evo_scene3d_destroy(s->scene3d);
	for (int a = 0; a < s->n_agents; a++)
		free(s->agent[a].state_mem);
	free(s->agent);
	free(s->team);
	free(s);
}

int evo_sim_reset(evo_sim *s, int episode, uint64_t grid_seed,
		  uint64_t episode_seed, evo_err *err)
{
	if (s->scene3d) {
		if (evo_scene3d_reset(s->scene3d, grid_seed, episode_seed))
			return evo_fail(err, "%s", s->scene3d->err.msg);
	} else {
		evo_scene_reset(s->scene, grid_seed, episode_seed);
	}
	for (int a = 0; a < s->n_agents; a++)
		evo_state_reset(&s->agent[a].mind->mind, s->agent[a].state);
	s->episode = episode;
	return evo_lua_reset(s->lua, episode, err);
}

int evo_sim_agent_of_bot(const evo_sim *s, int bot)
{
	for (int a = 0; a < s->n_agents; a++)
		if (s->agent[a].bot == bot)
			return a;
	return -1;
}

/* One agent's mind: read its bot's sensors, step, write its actuators. */
static void step_agent(evo_sim *s, const evo_sim_agent *a, evo_q16 *in,
		       evo_q16 *out)
{
	const evo_sim_team *tm = &s->team[a->team];
	evo_bot *b = &s->scene->bot[a->bot];
	const evo_mind *m = &a->mind->mind;
	for (unsigned i = 0; i < m->n_sensors; i++)
		in[i] = evo_q16_from_sensor(b->sensor[tm->sensor_map[i]].value);
	evo_mind_step(m, a->state, in, out);
	for (unsigned i = 0; i < m->n_actuators; i++)
		b->actuator[tm->actuator_map[i]].command =
		    evo_q16_to_double(out[i]);
	if (s->trace && s->has_teams)
		evo_trace_tick_bot(s->trace, s->scene->tick, b->name, m, in,
				   out, a->state);
	else if (s->trace)
		evo_trace_tick(s->trace, s->scene->tick, m, in, out, a->state);
}

/* The one agent of a 3D task: the same mind step on its 3D bot. */
static int tick3d(evo_sim *s)
{
	evo_scene3d *sc = s->scene3d;
	evo_bot3d *b = &sc->bot[0];
	const evo_sim_agent *a = &s->agent[0];
	const evo_mind *m = &a->mind->mind;
	evo_scene3d_sense(sc);
	for (unsigned i = 0; i < m->n_sensors; i++)
		s->sensors[i] =
		    evo_q16_from_sensor(b->sensor[s->sensor_map[i]].value);
	evo_mind_step(m, a->state, s->sensors, s->actuators);
	for (unsigned i = 0; i < m->n_actuators; i++)
		b->actuator[s->actuator_map[i]].command =
		    evo_q16_to_double(s->actuators[i]);
	if (s->trace)
		evo_trace_tick(s->trace, sc->tick, m, s->sensors, s->actuators,
			       a->state);
	return evo_scene3d_step(sc);
}

int evo_sim_tick(evo_sim *s, evo_err *err)
{
	if (s->scene3d)
		return tick3d(s);
	evo_scene *sc = s->scene;
	evo_scene_sense(sc);
	step_agent(s, &s->agent[0], s->sensors, s->actuators);
	evo_q16 in[EVO_MAX_SENSORS], out[EVO_MAX_ACTUATORS];
	for (int a = 1; a < s->n_agents; a++)
		step_agent(s, &s->agent[a], in, out);
	int r = evo_scene_step(sc);
	if (r < 0)
		evo_fail(err, "%s", sc->err.msg);
	return r;
}

void evo_sim_sense(evo_sim *s, double *values)
{
	if (s->scene3d) {
		const evo_bot3d *b3 = &s->scene3d->bot[0];
		evo_scene3d_sense(s->scene3d);
		for (unsigned i = 0; i < s->mind->mind.n_sensors; i++)
			values[i] = b3->sensor[s->sensor_map[i]].value;
		return;
	}
	const evo_bot *b = &s->scene->bot[s->bot];
	evo_scene_sense(s->scene);
	for (unsigned i = 0; i < s->mind->mind.n_sensors; i++)
		values[i] = b->sensor[s->sensor_map[i]].value;
}

int evo_sim_act(evo_sim *s, const double *commands, evo_err *err)
{
	if (s->scene3d) {
		evo_bot3d *b3 = &s->scene3d->bot[0];
		for (unsigned i = 0; i < s->mind->mind.n_actuators; i++)
			b3->actuator[s->actuator_map[i]].command = commands[i];
		return evo_scene3d_step(s->scene3d);
	}
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
	if (!s->has_teams) {
		evo_trace_header(s->trace, s->mind);
		return;
	}
	fprintf(s->trace, "evo-trace 3\n");
	for (int k = 0; k < s->n_teams; k++) {
		const evo_sim_team *tm = &s->team[k];
		const char *bots[EVO_TEAM_MAX_SIZE];
		for (int i = 0; i < tm->size; i++)
			bots[i] =
			    s->scene->bot[s->agent[tm->first + i].bot].name;
		evo_trace_team_header(s->trace, tm->name, tm->mind, bots,
				      tm->size);
	}
}

int evo_sim_type_is_3d(const char *type)
{
	return strcasecmp(type, "DEMO3DSIM") == 0 ||
	       strcasecmp(type, "LEARN3DSIM") == 0;
}

double evo_sim_episode_reward(const evo_sim *s)
{
	return s->scene3d ? s->scene3d->episode_reward
			  : s->scene->episode_reward;
}

long evo_sim_ticks(const evo_sim *s)
{
	return s->scene3d ? s->scene3d->tick : s->scene->tick;
}

int evo_sim_collisions(const evo_sim *s, int agent)
{
	int bot = s->agent[agent].bot;
	return s->scene3d ? s->scene3d->bot[bot].collisions
			  : s->scene->bot[bot].collisions;
}

int evo_sim_n_metrics(const evo_sim *s)
{
	return s->scene3d ? 0 : s->scene->n_metrics;
}

const char *evo_sim_metric_name(const evo_sim *s, int k)
{
	return s->scene3d ? "" : s->scene->metric[k].name;
}

double evo_sim_metric(const evo_sim *s, int k)
{
	return s->scene3d ? 0 : s->scene->metric[k].value;
}

/* Widen b (x0, y0, x1, y1) to hold the box of half sizes hx, hy at x, y. */
static void widen(double *b, double x, double y, double hx, double hy)
{
	b[0] = fmin(b[0], x - hx);
	b[1] = fmin(b[1], y - hy);
	b[2] = fmax(b[2], x + hx);
	b[3] = fmax(b[3], y + hy);
}

/* The arena's bounds on the ground plane (evo_sim_behaviour's); 0, or -1
 * when the environment built no static obstacle. */
static int arena_bounds(const evo_sim *s, double *b)
{
	b[0] = b[1] = INFINITY;
	b[2] = b[3] = -INFINITY;
	if (s->scene3d) {
		const evo_scene3d *sc = s->scene3d;
		for (int i = 0; i < sc->n_elements; i++) {
			const evo_element3d_def *d = &sc->element[i].def;
			if (d->kind > EVO3D_ELEM_SPHERE || d->ground)
				continue;
			double c = fabs(cos(d->yaw)), sn = fabs(sin(d->yaw));
			if (d->kind == EVO3D_ELEM_BOX)
				widen(b, d->pos[0], d->pos[1],
				      c * d->half[0] + sn * d->half[1],
				      sn * d->half[0] + c * d->half[1]);
			else
				widen(b, d->pos[0], d->pos[1], d->radius,
				      d->radius);
		}
	} else {
		const evo_scene *sc = s->scene;
		for (int i = 0; i < sc->n_fixed_obstacles; i++) {
			const evo_obstacle *o = &sc->obstacle[i];
			double c = fabs(cos(o->angle)), sn = fabs(sin(o->angle));
			if (o->shape == EVO_SHAPE_CIRCLE) {
				widen(b, o->x, o->y, o->radius, o->radius);
			} else if (o->shape == EVO_SHAPE_SEGMENT) {
				/* a wall: (x, y) is one end, not its middle */
				widen(b, o->x, o->y, 0, 0);
				widen(b, o->x2, o->y2, 0, 0);
			} else
				widen(b, o->x, o->y,
				      c * o->half_w + sn * o->half_h,
				      sn * o->half_w + c * o->half_h);
		}
		if (sc->grid.enabled) {
			const evo_grid_def *g = &sc->grid;
			widen(b, (g->x0 + g->x1) / 2, (g->y0 + g->y1) / 2,
			      fabs(g->x1 - g->x0) / 2, fabs(g->y1 - g->y0) / 2);
		}
	}
	return b[2] > b[0] && b[3] > b[1] ? 0 : -1;
}

static double unit(double v)
{
	return v < 0 ? 0 : v > 1 ? 1 : v;
}

int evo_sim_behaviour(evo_sim *s, double *out, evo_err *err)
{
	int n = evo_lua_behaviour(s->lua, s->bot, out, EVO_SIM_MAX_BEHAVIOUR,
				  err);
	if (n)
		return n;
	double x, y, x0, y0;
	if (s->scene3d) {
		const evo_bot3d *b = &s->scene3d->bot[s->bot];
		x = b->pos[0], y = b->pos[1];
		x0 = b->start[0], y0 = b->start[1];
	} else {
		const evo_bot *b = &s->scene->bot[s->bot];
		x = b->x, y = b->y;
		x0 = b->def.x, y0 = b->def.y;
	}
	double box[4];
	if (arena_bounds(s, box)) {
		box[0] = x0 - 5, box[1] = y0 - 5;
		box[2] = x0 + 5, box[3] = y0 + 5;
	}
	out[0] = unit((x - box[0]) / (box[2] - box[0]));
	out[1] = unit((y - box[1]) / (box[3] - box[1]));
	return 2;
}

int evo_sim_solved(evo_sim *s, int *solved, evo_err *err)
{
	int rc = evo_lua_solved(s->lua, s->bot, solved, err);
	if (rc == 0)
		*solved = -1;
	return rc < 0 ? -1 : 0;
}

const char *evo_sim_fault(const evo_sim *s)
{
	return s->scene3d ? s->scene3d->fault : "";
}

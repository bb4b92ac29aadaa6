/* A task's simulation: scene + Lua environment + the minds of its agents
 * (sim/tasksim/tasksim.h). */
#include "tasksim/tasksim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "mind/names.h"
#include "mind/trace.h"

_Static_assert(EVO_MAX_TEAMS <= EVO_SCENE_MAX_TEAMS,
	       "a task's teams fit a scene's");

/* "did you mean" over a bot's sensor or actuator names. */
static const char *closest(const evo_sim *s, const char *word, int bot,
			   int sensors)
{
	const char *names[256];
	const evo_bot *b = &s->core->bot[bot];
	int n = sensors ? b->n_sensors : b->n_actuators;
	n = n > 256 ? 256 : n;
	for (int i = 0; i < n; i++)
		names[i] = sensors ? b->sensor[i].name : b->actuator[i].name;
	const char *c = evo_closest_name(word, names, (size_t)n, NULL);
	return c ? c : "";
}

/* Sensors nothing reads are not sampled: the minds read the botdesc's,
 * rewards and controls name theirs, and a script's bot:value wakes the one
 * it asks for. In a one-agent task only the agent's bot is marked, as it
 * always was; in a team task, every bot, so a bot no mind drives senses
 * nothing. */
static void mark_idle(evo_sim *s)
{
	for (int k = 0; k < s->core->n_bots; k++) {
		if (!s->has_teams && k != s->bot)
			continue;
		evo_bot *b = &s->core->bot[k];
		for (int i = 0; i < b->n_sensors; i++)
			b->sensor[i].idle = 1;
	}
	for (int a = 0; a < s->n_agents; a++) {
		const evo_sim_agent *ag = &s->agent[a];
		const evo_sim_team *tm = &s->team[ag->team];
		evo_bot *b = &s->core->bot[ag->bot];
		for (unsigned i = 0; i < tm->mind->botdesc->n_sensors; i++)
			b->sensor[tm->sensor_map[i]].idle = 0;
	}
	evo_core_wake_scored(s->core);
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
	const evo_bot *b = &s->core->bot[bot];
	const char *bot_name = b->name;
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
					model,
					closest(s, d->sensor[i].name, bot, 1),
					where);
		if (!first && k != tm->sensor_map[i])
			return evo_fail(err,
					"bot %s: its sensor '%s' is not where "
					"its team's first bot has it: the "
					"environment changed one bot of the "
					"team%s",
					bot_name, d->sensor[i].name, where);
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
			    closest(s, d->actuator[i].name, bot, 0), where);
		if (!first && k != tm->actuator_map[i])
			return evo_fail(
			    err,
			    "bot %s: its actuator '%s' is not where "
			    "its team's first bot has it%s",
			    bot_name, d->actuator[i].name, where);
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

static int bot_team(const evo_sim *s, int bot)
{
	return s->core->bot[bot].team;
}

/* Lay out the teams and their agents: team k's agents are its bots in
 * the scene's order. A team task's environment must have made each team
 * its SIZE bots. */
static int make_agents(evo_sim *s, evo_err *err)
{
	int n = 0;
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
		for (int b = 0; b < s->core->n_bots; b++)
			if (bot_team(s, b) == k && made < tm->size) {
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
		s->core = s->scene3d ? &s->scene3d->core : NULL;
	} else {
		s->scene = evo_scene_create();
		s->core = s->scene ? &s->scene->core : NULL;
	}
	if (!s->core) {
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
	/* a misspelt ENV or BOTMODEL at the task's line, with the name
	 * meant, before the environment runs (it was reported at the line
	 * of the environment that made the bot) */
	if (evo_task_check_script(task, task_path, "ENV", "environment",
				  mind_dir, "Envs", evo_lua_dir(), "envs",
				  err) ||
	    (!s->has_teams &&
	     evo_task_check_script(task, task_path, "BOTMODEL", "bot model",
				   mind_dir, "Bots", evo_lua_dir(), "bots",
				   err))) {
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
	if (s->core->dim->reset(s->core, grid_seed, episode_seed))
		return evo_fail(err, "%s", s->core->err.msg);
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
	const evo_mind *m = &a->mind->mind;
	double v[EVO_MAX_SENSORS + EVO_MAX_ACTUATORS];
	evo_bot *b = &s->core->bot[a->bot];
	evo_bot_read_sensors(b, tm->sensor_map, m->n_sensors, v);
	for (unsigned i = 0; i < m->n_sensors; i++)
		in[i] = evo_q16_from_sensor(v[i]);
	evo_mind_step(m, a->state, in, out);
	for (unsigned i = 0; i < m->n_actuators; i++)
		v[i] = evo_q16_to_double(out[i]);
	evo_bot_write_actuators(b, tm->actuator_map, m->n_actuators, v);
	if (s->trace && s->has_teams)
		evo_trace_tick_bot(s->trace, s->core->tick, b->name, m, in, out,
				   a->state);
	else if (s->trace)
		evo_trace_tick(s->trace, s->core->tick, m, in, out, a->state);
}

/* Steps 3 to 5 of the tick: 1 when the episode ends, 0 when it goes on,
 * -1 with err set (a hook failed). */
static int step(evo_sim *s, evo_err *err)
{
	int r = evo_core_step(s->core);
	if (r < 0)
		evo_fail(err, "%s", s->core->err.msg);
	return r;
}

int evo_sim_tick(evo_sim *s, evo_err *err)
{
	evo_core_sense(s->core);
	step_agent(s, &s->agent[0], s->sensors, s->actuators);
	evo_q16 in[EVO_MAX_SENSORS], out[EVO_MAX_ACTUATORS];
	for (int a = 1; a < s->n_agents; a++)
		step_agent(s, &s->agent[a], in, out);
	return step(s, err);
}

void evo_sim_sense(evo_sim *s, double *values)
{
	evo_core_sense(s->core);
	evo_bot_read_sensors(&s->core->bot[s->bot], s->sensor_map,
			     s->mind->mind.n_sensors, values);
}

int evo_sim_act(evo_sim *s, const double *commands, evo_err *err)
{
	evo_bot_write_actuators(&s->core->bot[s->bot], s->actuator_map,
				s->mind->mind.n_actuators, commands);
	return step(s, err);
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
			    evo_sim_bot_name(s, s->agent[tm->first + i].bot);
		evo_trace_team_header(s->trace, tm->name, tm->mind, bots,
				      tm->size);
	}
}

int evo_sim_type_is_3d(const char *type)
{
	return strcasecmp(type, "DEMO3DSIM") == 0 ||
	       strcasecmp(type, "LEARN3DSIM") == 0 ||
	       strcasecmp(type, "DEMO3DSIMMULTI") == 0 ||
	       strcasecmp(type, "LEARN3DSIMMULTI") == 0;
}

double evo_sim_episode_reward(const evo_sim *s)
{
	return s->core->episode_reward;
}

long evo_sim_ticks(const evo_sim *s)
{
	return s->core->tick;
}

int evo_sim_collisions(const evo_sim *s, int agent)
{
	return s->core->bot[s->agent[agent].bot].collisions;
}

int evo_sim_n_metrics(const evo_sim *s)
{
	return s->core->n_metrics;
}

const char *evo_sim_metric_name(const evo_sim *s, int k)
{
	return s->core->metric[k].name;
}

double evo_sim_metric(const evo_sim *s, int k)
{
	return s->core->metric[k].value;
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
	const evo_bot *b = &s->core->bot[s->bot];
	double x = b->pos[0], y = b->pos[1], x0 = b->start[0], y0 = b->start[1];
	/* the arena's bounds on the ground plane, if the environment built
	 * a static obstacle */
	double box[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
	s->core->dim->arena(s->core, box);
	if (!(box[2] > box[0] && box[3] > box[1])) {
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
	return s->core->fault;
}

double evo_sim_team_reward(const evo_sim *s, int team)
{
	return s->core->team_reward[team];
}

int evo_sim_winner(const evo_sim *s)
{
	return s->core->winner;
}

const char *evo_sim_bot_name(const evo_sim *s, int bot)
{
	return s->core->bot[bot].name;
}

double evo_sim_bot_reward(const evo_sim *s, int bot)
{
	return s->core->bot[bot].reward;
}

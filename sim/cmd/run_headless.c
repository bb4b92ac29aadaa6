/* `evo run` without a window (cmd/run_internal.h): each episode's seeds,
 * the trace file, the line that ends an episode (teams, metrics, the
 * outcome), DEMOSIM headless and DEMOREMOTESIM against a remote
 * simulator. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/run_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/fileio.h"
#include "base/number.h"
#include "base/rng.h"
#include "lua/lua_evo.h"
#include "mind/trace.h"
#include "remote/session.h"

/* The seeds of episode e: the grid's and the rest's, from (seed, e). */
uint64_t evo_run_grid_seed(uint64_t seed, long e)
{
	evo_rng r = evo_rng_for(seed, 1, (uint64_t)e, 0);
	return evo_rng_next(&r);
}

uint64_t evo_run_episode_seed(uint64_t seed, long e)
{
	evo_rng r = evo_rng_for(seed, 2, (uint64_t)e, 0);
	return evo_rng_next(&r);
}

int evo_run_trace_open(trace_file *t, const char *path, evo_err *err)
{
	memset(t, 0, sizeof *t);
	if (!path)
		return 0;
	t->path = path;
	int fd = evo_create_beside(path, t->tmp, sizeof t->tmp, err);
	if (fd < 0)
		return -1;
	t->f = fdopen(fd, "w");
	if (!t->f) {
		evo_fail(err, "%s: cannot create: %s", t->tmp, strerror(errno));
		close(fd);
		unlink(t->tmp);
		return -1;
	}
	return 0;
}

int evo_run_trace_close(trace_file *t, int keep, evo_err *err)
{
	if (!t->f)
		return 0;
	int bad =
	    ferror(t->f) | (fflush(t->f) != 0) | (fsync(fileno(t->f)) != 0);
	bad |= fclose(t->f) != 0;
	t->f = NULL;
	if (keep && !bad && rename(t->tmp, t->path) == 0)
		return 0;
	unlink(t->tmp);
	if (keep)
		return evo_fail(err, "%s: cannot save the trace: %s", t->path,
				strerror(errno));
	return 0;
}

/* 1 when the scene has a reward of kind k (a Collect makes deliveries,
 * a Gather gatherings). */
static int has_reward(const evo_scene_core *c, evo_reward_kind k)
{
	for (int i = 0; i < c->n_rewards; i++)
		if (c->reward[i].def.kind == k)
			return 1;
	return 0;
}

/* A team task's lines after its episode's (docs/teams.md): each team's
 * reward, each bot's own, and whether it won. */
static void print_teams(const evo_sim *s)
{
	for (int k = 0; s->has_teams && k < s->n_teams; k++) {
		const evo_sim_team *tm = &s->team[k];
		printf("  team %s: reward %.6f (", tm->name,
		       evo_sim_team_reward(s, k));
		for (int i = 0; i < tm->size; i++) {
			int b = s->agent[tm->first + i].bot;
			printf("%s%s %.6f", i ? ", " : "", evo_sim_bot_name(s, b),
			       evo_sim_bot_reward(s, b));
		}
		printf(")%s\n", evo_sim_winner(s) == k ? ", won" : "");
	}
}

/* The environment's own metrics at the end of an episode line, in the
 * order it declared them: ", in_zone 123.000000". Nothing when it has
 * none, so such a line is as it always was. */
static void print_metrics(const evo_sim *s)
{
	char v[64];
	for (int i = 0; i < evo_sim_n_metrics(s); i++)
		printf(", %s %s", evo_sim_metric_name(s, i),
		       evo_number_text(v, sizeof v, evo_sim_metric(s, i), 1));
}

/* What the episode did, when the environment says it (docs/lua.md, "What
 * an episode did"): ", behaviour (0.2, 0.25)" for env.behaviour and
 * ", solved" or ", not solved" for env.solved, for a one-agent task.
 * Nothing when it has neither, so such a line is as it always was. */
static int print_outcome(evo_sim *s, evo_err *err)
{
	double b[EVO_SIM_MAX_BEHAVIOUR];
	char text[64];
	int solved;
	if (s->has_teams)
		return 0;
	int n =
	    evo_lua_behaviour(s->lua, s->bot, b, EVO_SIM_MAX_BEHAVIOUR, err);
	if (n < 0)
		return -1;
	for (int k = 0; k < n; k++)
		printf("%s%s%s", k ? ", " : ", behaviour (",
		       evo_number_text(text, sizeof text, b[k], 0),
		       k == n - 1 ? ")" : "");
	int rc = evo_lua_solved(s->lua, s->bot, &solved, err);
	if (rc > 0)
		printf(solved ? ", solved" : ", not solved");
	return rc < 0 ? -1 : 0;
}

/* The line that ends episode e after t ticks, the same headless, in the
 * viewer and under --record: its reward, collision ticks, deliveries,
 * metrics and what it did; a 3D episode's fault, if anything broke;
 * every team's counts. */
int evo_run_print_episode(evo_sim *s, long e, long t, evo_err *err)
{
	/* the agents' counts: the one agent's, or every team's */
	const evo_scene_core *c = s->core;
	int collisions = 0, delivered = 0, gathered = 0;
	for (int a = 0; a < s->n_agents; a++) {
		const evo_bot *b = &c->bot[s->agent[a].bot];
		collisions += b->collisions;
		delivered += b->delivered;
		gathered += b->gathered;
	}
	printf("episode %ld: reward %.6f over %ld ticks, %d collision "
	       "ticks",
	       e, c->episode_reward, t, collisions);
	/* deliveries and gatherings only where a reward can make them (2D's
	 * Collect and Gather) */
	if (has_reward(c, EVO_RW_COLLECT))
		printf(", %d delivered", delivered);
	if (has_reward(c, EVO_RW_GATHER))
		printf(", %d gathered", gathered);
	print_metrics(s);
	if (print_outcome(s, err))
		return -1;
	printf("\n");
	if (c->fault[0]) /* a body that exploded (3D) */
		printf("  fault: %s\n", c->fault);
	print_teams(s);
	fflush(stdout);
	return 0;
}

int evo_run_headless(evo_sim *s, const run_opts *o, uint64_t seed, evo_err *err)
{
	for (long e = 1; e <= o->episodes && !evo_cmd_stop_requested; e++) {
		if (evo_sim_reset(s, (int)e, evo_run_grid_seed(seed, e),
				  evo_run_episode_seed(seed, e), err))
			return -1;
		long t = 0;
		int r = 0;
		while (!evo_cmd_stop_requested &&
		       (o->ticks == 0 || t < o->ticks)) {
			r = evo_sim_tick(s, err);
			t++;
			if (r != 0)
				break;
		}
		/* a script stopped by the signal fails its tick */
		if (r < 0)
			return evo_cmd_stop_requested ? 0 : -1;
		if (evo_run_print_episode(s, e, t, err))
			return -1;
	}
	return 0;
}

void *evo_run_mind_state(const evo_mind *m, evo_state **state, evo_err *err)
{
	size_t need = (evo_state_size(m) + 7) & ~(size_t)7;
	void *mem = aligned_alloc(8, need);
	if (!mem) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	if (evo_state_init(m, mem, need, state) != EVO_OK) {
		free(mem);
		evo_fail(err, "mind state: cannot lay it out");
		return NULL;
	}
	return mem;
}

/* DEMOREMOTESIM: the mind here, the world in a remote simulator driven in
 * lockstep; the same episodes, seeds and lines as DEMOSIM headless. */
int evo_run_remote_sim(const evo_task *task, const run_opts *o, uint64_t seed,
		       FILE *trace, evo_err *err)
{
	evo_remote_opts ro;
	if (evo_remote_opts_from_task(task->sb, o->task, EVO_REMOTE_SIMULATOR,
				      &ro, err))
		return -1;
	ro.stop = &evo_cmd_stop_requested;
	const evo_mind *m = &task->mind->mind;
	evo_state *state = NULL;
	void *mem = evo_run_mind_state(m, &state, err);
	if (!mem)
		return -1;
	evo_remotes *r = evo_remote_connect(task->mind, &ro, err);
	if (!r) {
		free(mem);
		/* a stop while waiting for a remote ends the run, as it would
		 * end a DEMOSIM */
		return evo_cmd_stop_requested ? 0 : -1;
	}
	const evo_wire_hello *h = &r->r[0]->hello;
	printf("remote %s: %s, %d environment%s\n", h->name,
	       h->kind == EVO_REMOTE_SIMULATOR ? "simulator" : "robot",
	       (int)h->environments, h->environments == 1 ? "" : "s");
	if (trace)
		evo_trace_header(trace, task->mind);
	int rc = 0;
	double in[EVO_MAX_SENSORS], out[EVO_MAX_ACTUATORS];
	evo_q16 qin[EVO_MAX_SENSORS], qout[EVO_MAX_ACTUATORS];
	for (long e = 1; e <= o->episodes && !evo_cmd_stop_requested && rc == 0;
	     e++) {
		evo_state_reset(m, state);
		if (evo_remote_reset(r, 0, e, evo_run_grid_seed(seed, e),
				     evo_run_episode_seed(seed, e), err)) {
			rc = -1;
			break;
		}
		long t = 0;
		int end = 0;
		while (!evo_cmd_stop_requested &&
		       (o->ticks == 0 || t < o->ticks)) {
			evo_remote_sensors(r->r[0], 0, in);
			for (unsigned i = 0; i < m->n_sensors; i++)
				qin[i] = evo_q16_from_sensor(in[i]);
			evo_mind_step(m, state, qin, qout);
			for (unsigned i = 0; i < m->n_actuators; i++)
				out[i] = evo_q16_to_double(qout[i]);
			if (trace)
				evo_trace_tick(trace, t, m, qin, qout, state);
			end = evo_remote_step(r, 0, out, err);
			t++;
			if (end != 0)
				break;
		}
		if (end < 0) {
			/* a stop while waiting is a stop, not a failure */
			rc = evo_cmd_stop_requested ? 0 : -1;
			break;
		}
		printf("episode %ld: reward %.6f over %ld ticks", e,
		       evo_remote_reward(r->r[0], 0), t);
		/* what the simulator says the episode did, when it says */
		const evo_wire_sensors *last = &r->r[0]->env[0].sensors;
		for (unsigned k = 0; k < last->n_behaviour; k++)
			printf("%s%.6f%s", k ? ", " : ", behaviour (",
			       last->behaviour[k],
			       k + 1 == last->n_behaviour ? ")" : "");
		printf("\n");
		fflush(stdout);
	}
	evo_remotes_close(r);
	free(mem);
	return rc;
}

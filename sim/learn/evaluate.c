/* The LEARNSIM evaluator (evaluate.h): a pool of POSIX threads, each with
 * its own mind folder and simulation, fed from one batch counter. */
#define _POSIX_C_SOURCE 200809L
#include "learn/evaluate.h"

#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "base/fileio.h"
#include "learn/evaluate_remote.h"
#include "learn/literature.h"
#include "mind/task.h"
#include "tasksim/tasksim.h"
#include "world2d/scene.h"

/* Stream tags of evo_rng_for (evaluate.h); `evo run` uses 1 and 2. */
enum { TAG_GRID = 3, TAG_EPISODE = 4 };

#define MAX_THREADS EVO_EVAL_MAX_THREADS

typedef struct worker {
	struct evo_evaluator *ev;
	pthread_t thread;
	int started;
	evo_task task;	  /* its own mind folder */
	evo_sim *sim;	  /* its own world and Lua state */
	int skill;	  /* the learning skill's index in task.mind */
	evo_lit_task lit; /* ENV names a literature task: no sim */
	evo_lit_protocol proto; /* the double pole's POLEPROTOCOL */
	/* team tasks: each team's learning skill in its mind (-1: none),
	 * each learning team's members' own minds (heterogeneous), and the
	 * version of the teams' networks it runs */
	int team_skill[EVO_MAX_TEAMS];
	evo_mindfolder **member[EVO_MAX_TEAMS];
	unsigned long nets_seen;
	int last_team; /* the team its last batch trained, -1 at first */
	evo_netdesc *own_net[EVO_MAX_TEAMS]; /* each team's network as loaded */
} worker;

/* What one evaluation of a team gives, summed over its repetitions. */
typedef struct unit_result {
	double team_fitness;
	long collisions;
	int wins;
	double metric[EVO_SCENE_MAX_METRICS];
} unit_result;

struct evo_evaluator {
	char *task_path;
	const evo_eval_def *def; /* while evo_evaluator_create runs */
	int threads, reps;
	long ticks;
	int n_metrics; /* worker 0's scene holds their names */
	uint64_t seed;
	unsigned n_in, n_out;
	worker *w;
	evo_remote_eval *remote; /* LEARNREMOTESIM: no workers */
	evo_eval_spread spread;	 /* .evaluate NULL: none */
	/* team tasks (docs/teams.md): the teams' networks set by
	 * evo_evaluator_set_team_net (NULL: their own), bumped version */
	int n_teams;
	int heterogeneous, own_fitness;
	evo_netdesc *team_net[EVO_MAX_TEAMS];
	unsigned long nets_version;
	char *genome; /* evo_evaluator_set_genome's, NULL: none */

	/* Everything below is guarded by mu. A batch is announced by
	 * bumping batch_id; each worker counts itself out in `busy`, and
	 * the caller waits for busy == 0, so no evaluation outlives its
	 * batch. */
	pthread_mutex_t mu;
	pthread_cond_t start_cv, done_cv;
	unsigned long batch_id;
	int quit;
	int busy;
	/* one thread: the only worker runs on the caller's thread, with no
	 * hand-off to another thread and back for each batch */
	int inline_worker;
	const evo_netdesc *const *cand;
	int n, gen, next;
	int first; /* the batch index of cand[0] (evo_evaluate_part) */
	evo_eval_result *res;
	/* a team batch: the learning team, the groups, what each group and
	 * each member gave */
	int team;
	const int *groups;
	unit_result *unit;
	double *own;
	int failed;
	evo_err err; /* the first failure */
};

uint64_t evo_eval_grid_seed(uint64_t seed, int gen, int rep)
{
	evo_rng r = evo_rng_for(seed, (uint64_t)TAG_GRID << 32 | (uint32_t)gen,
				(uint64_t)rep, 0);
	return evo_rng_next(&r);
}

uint64_t evo_eval_episode_seed(uint64_t seed, int gen, int cand, int rep)
{
	evo_rng r =
	    evo_rng_for(seed, (uint64_t)TAG_EPISODE << 32 | (uint32_t)gen,
			(uint64_t)cand, (uint64_t)rep);
	return evo_rng_next(&r);
}

/* At the end of repetition r: add what the episode did to res's
 * behaviour, and fold whether it solved the task into *all_solved (1
 * while every repetition so far did, 0 once one did not, -1 when the
 * environment has no solved function). Every episode's behaviour has as
 * many values as the first one's. */
static int episode_outcome(worker *w, evo_eval_result *res, int *all_solved,
			   int r, evo_err *err)
{
	double b[EVO_SIM_MAX_BEHAVIOUR];
	int solved;
	int n = evo_sim_behaviour(w->sim, b, err);
	if (n < 0 || evo_sim_solved(w->sim, &solved, err)) {
		evo_err inner = *err;
		return evo_fail(err, "repetition %d, at its end: %s", r + 1,
				inner.msg);
	}
	if (r > 0 && n != res->n_behaviour)
		return evo_fail(err,
				"repetition %d, at its end: %s: env.behaviour "
				"returned %d values, where repetition 1's "
				"returned %d: a behaviour has the same size "
				"every episode",
				r + 1, evo_lua_env_path(w->sim->lua), n,
				res->n_behaviour);
	res->n_behaviour = n;
	for (int k = 0; k < n; k++)
		res->behaviour[k] += b[k];
	if (solved < 0)
		*all_solved = -1;
	else if (*all_solved >= 0)
		*all_solved = *all_solved && solved;
	return 0;
}

/* Candidate i on worker w: bind it, run the reps, sum the rewards. */
static int evaluate_one(worker *w, int i, evo_eval_result *res, evo_err *err)
{
	evo_evaluator *ev = w->ev;
	memset(res, 0, sizeof *res);
	if (w->lit) {
		/* Deterministic and seedless: one run, whatever EVALREP. */
		evo_lit_result r;
		if (evo_lit_evaluate(w->lit, w->proto, ev->cand[i], &r, err))
			return -1;
		res->fitness = r.fitness;
		res->solved = r.solved;
		return 0;
	}
	evo_mindfolder *l = w->task.mind;
	*l->net[w->skill] = *ev->cand[i];
	if (evo_mindfolder_rebuild(l, err) || evo_sim_set_mind(w->sim, l, err))
		return -1;
	if (w->sim->lua)
		evo_lua_set_genome(w->sim->lua, ev->genome);
	int c = ev->first + i; /* its index in the whole batch */
	int all_solved = 1;
	for (int r = 0; r < ev->reps; r++) {
		if (evo_sim_reset(
			w->sim, r + 1, evo_eval_grid_seed(ev->seed, ev->gen, r),
			evo_eval_episode_seed(ev->seed, ev->gen, c, r), err)) {
			evo_err inner = *err;
			return evo_fail(err, "repetition %d, at its start: %s",
					r + 1, inner.msg);
		}
		for (long t = 0; t < ev->ticks; t++) {
			int st = evo_sim_tick(w->sim, err);
			if (st < 0) {
				evo_err inner = *err;
				return evo_fail(err, "repetition %d, tick %ld: %s",
						r + 1, t, inner.msg);
			}
			if (st > 0)
				break;
		}
		res->fitness += evo_sim_episode_reward(w->sim);
		res->collisions += evo_sim_collisions(w->sim, 0);
		for (int k = 0; k < ev->n_metrics; k++)
			res->metric[k] += evo_sim_metric(w->sim, k);
		if (episode_outcome(w, res, &all_solved, r, err))
			return -1;
	}
	for (int k = 0; k < ev->n_metrics; k++)
		res->metric[k] /= ev->reps;
	for (int k = 0; k < res->n_behaviour; k++)
		res->behaviour[k] /= ev->reps;
	res->solved = all_solved > 0;
	return 0;
}

/* Before a team batch: every team but the one that learns runs its
 * network of evo_evaluator_set_team_net, or its own as loaded (a team
 * that learned in an earlier batch still holds a candidate), whenever
 * those changed or another team learns than in w's last batch. */
static int apply_team_nets(worker *w, evo_err *err)
{
	evo_evaluator *ev = w->ev;
	if (w->nets_seen == ev->nets_version && w->last_team == ev->team)
		return 0;
	for (int t = 0; t < ev->n_teams; t++) {
		if (t == ev->team || w->team_skill[t] < 0)
			continue;
		const evo_netdesc *net =
		    ev->team_net[t] ? ev->team_net[t] : w->own_net[t];
		evo_mindfolder *m = w->task.team[t].mind;
		*m->net[w->team_skill[t]] = *net;
		if (evo_mindfolder_rebuild(m, err) ||
		    evo_sim_set_team_mind(w->sim, t, m, err))
			return -1;
	}
	w->nets_seen = ev->nets_version;
	w->last_team = ev->team;
	return 0;
}

/* Evaluation j of a team batch on worker w: the learning team's members
 * run their candidates, the repetitions run, and what the team and each
 * member earned is kept in unit[j] and own[j * size ..]. */
static int evaluate_team_unit(worker *w, int j, evo_err *err)
{
	evo_evaluator *ev = w->ev;
	int t = ev->team;
	const evo_sim_team *st = &w->sim->team[t];
	int size = st->size;
	const int *g = ev->groups + (size_t)j * size;
	int k = w->team_skill[t];
	if (!ev->heterogeneous) {
		evo_mindfolder *m = w->task.team[t].mind;
		*m->net[k] = *ev->cand[g[0]];
		if (evo_mindfolder_rebuild(m, err) ||
		    evo_sim_set_team_mind(w->sim, t, m, err))
			return -1;
	} else {
		for (int i = 0; i < size; i++) {
			evo_mindfolder *m = w->member[t][i];
			*m->net[k] = *ev->cand[g[i]];
			if (evo_mindfolder_rebuild(m, err) ||
			    evo_sim_set_agent_mind(w->sim, st->first + i, m,
						   err))
				return -1;
		}
	}
	unit_result *u = &ev->unit[j];
	double *own = ev->own + (size_t)j * size;
	memset(u, 0, sizeof *u);
	for (int i = 0; i < size; i++)
		own[i] = 0;
	const evo_simscene *ws = w->sim->world;
	const void *sc = w->sim->sc;
	for (int r = 0; r < ev->reps; r++) {
		if (evo_sim_reset(
			w->sim, r + 1, evo_eval_grid_seed(ev->seed, ev->gen, r),
			evo_eval_episode_seed(ev->seed, ev->gen, j, r), err)) {
			evo_err inner = *err;
			return evo_fail(err, "repetition %d, at its start: %s",
					r + 1, inner.msg);
		}
		for (long tk = 0; tk < ev->ticks; tk++) {
			int st2 = evo_sim_tick(w->sim, err);
			if (st2 < 0) {
				evo_err inner = *err;
				return evo_fail(err,
						"repetition %d, tick %ld: %s",
						r + 1, tk, inner.msg);
			}
			if (st2 > 0)
				break;
		}
		u->team_fitness += ws->team_reward(sc, t);
		u->wins += ws->winner(sc) == t;
		for (int i = 0; i < size; i++) {
			int b = w->sim->agent[st->first + i].bot;
			own[i] += ws->bot_reward(sc, b);
			u->collisions += ws->collisions(sc, b);
		}
		for (int m = 0; m < ev->n_metrics; m++)
			u->metric[m] += ws->metric(sc, m);
	}
	for (int m = 0; m < ev->n_metrics; m++)
		u->metric[m] /= ev->reps;
	return 0;
}

static long simbatch_number(const evo_simbatch *sb, const char *key,
			    long fallback)
{
	const char *v = evo_simbatch_get(sb, key);
	if (!v)
		return fallback;
	char *end;
	errno = 0;
	long n = strtol(v, &end, 10);
	/* The parser already checked whole numbers > 0. */
	return *end || errno || n <= 0 ? fallback : n;
}

/* A team task's worker: every team's learning skill, a mind of its own
 * for each member of a heterogeneous learning team, and the scene of
 * every team. */
static int load_teams(evo_evaluator *ev, worker *w, evo_err *err)
{
	evo_task *t = &w->task;
	for (int k = 0; k < t->n_teams; k++) {
		const evo_team *tm = &t->team[k];
		w->team_skill[k] =
		    tm->learning_skill[0]
			? evo_mindfolder_skill(tm->mind, tm->learning_skill)
			: -1;
		if (w->team_skill[k] >= 0 && !tm->mind->net[w->team_skill[k]])
			w->team_skill[k] = -1;
		if (w->team_skill[k] >= 0) {
			w->own_net[k] = malloc(sizeof *w->own_net[k]);
			if (!w->own_net[k])
				return evo_fail(err, "out of memory");
			*w->own_net[k] = *tm->mind->net[w->team_skill[k]];
		}
		if (!tm->learns || !t->heterogeneous)
			continue;
		w->member[k] = calloc((size_t)tm->size, sizeof *w->member[k]);
		if (!w->member[k])
			return evo_fail(err, "out of memory");
		evo_mindfolder_opts opts = {
		    .master = tm->master,
		    .learning_skill = tm->learning_skill,
		    .seed = t->seed,
		};
		for (int i = 0; i < tm->size; i++)
			if (!(w->member[k][i] = evo_mindfolder_load(
				  tm->mind->root, &opts, err)))
				return -1;
	}
	(void)ev;
	w->last_team = -1;
	w->skill = w->team_skill[t->learning[0]];
	w->sim = evo_sim_create_task(t, ev->task_path, err);
	return w->sim ? 0 : -1;
}

/* Load worker k's own copy of the task and build its simulation. */
static int worker_load(evo_evaluator *ev, worker *w, evo_err *err)
{
	evo_task_opts to = {.nets = ev->def->nets, .n_nets = ev->def->n_nets};
	if (evo_task_load_opts(ev->task_path, &to, &w->task, err))
		return -1;
	if (w->task.n_teams > 0 && strncmp(w->task.type, "LEARN", 5) == 0)
		return load_teams(ev, w, err);
	const char *learn = ev->def->learning_skill
				? ev->def->learning_skill
				: evo_simbatch_get(w->task.sb, "LEARNINGSKILL");
	int learns = strncmp(w->task.type, "LEARN", 5) == 0 ||
		     strcmp(w->task.type, "OPENENDED") == 0;
	if (!learns || !learn)
		return evo_fail(err,
				"%s: not a learning task (TYPE %s): the "
				"evaluator needs LEARNINGSKILL",
				ev->task_path, w->task.type);
	w->skill = evo_mindfolder_skill(w->task.mind, learn);
	if (w->skill < 0 || !w->task.mind->net[w->skill])
		return evo_fail(err, "%s: LEARNINGSKILL %s has no network",
				ev->task_path, learn);
	w->lit = evo_lit_task_named(evo_simbatch_get(w->task.sb, "ENV"));
	const char *proto = evo_simbatch_get(w->task.sb, "POLEPROTOCOL");
	if (proto && w->lit != EVO_LIT_DPV && w->lit != EVO_LIT_DPNV)
		return evo_fail(err,
				"%s: POLEPROTOCOL is a setting of the "
				"double-pole tasks (ENV DPV or DPNV); this "
				"task's ENV is %s",
				ev->task_path,
				evo_simbatch_get(w->task.sb, "ENV"));
	/* the key table let through NEAT and GOMEZ only */
	w->proto = (evo_lit_protocol)evo_lit_protocol_named(proto);
	if (w->lit) {
		const evo_ades *a = &w->task.mind->skill[w->skill];
		if (a->n_in != evo_lit_n_in(w->lit) || a->n_out != 1)
			return evo_fail(err,
					"%s: ENV %s needs a LEARNINGSKILL with "
					"%u inputs and 1 output; %s has %u and "
					"%u",
					ev->task_path,
					evo_simbatch_get(w->task.sb, "ENV"),
					evo_lit_n_in(w->lit), learn,
					(unsigned)a->n_in, (unsigned)a->n_out);
		return 0;
	}
	w->sim = evo_sim_create(w->task.mind, w->task.sb, ev->task_path, err);
	return w->sim ? 0 : -1;
}

/* Worker w's share of the batch: a team task's networks of other teams
 * first, then candidates (a team batch: evaluations) taken one by one
 * until the batch is empty or has failed. With `locked`, ev->mu is held
 * on entry and exit and let go around each evaluation; without, w is the
 * only worker and runs on the caller's thread (evaluator_inline). */
static void work_batch(worker *w, int locked)
{
	evo_evaluator *ev = w->ev;
	evo_err e = {{0}};
	int rc;
	if (ev->groups && !ev->failed) {
		if (locked)
			pthread_mutex_unlock(&ev->mu);
		rc = apply_team_nets(w, &e);
		if (locked)
			pthread_mutex_lock(&ev->mu);
		if (rc && !ev->failed) {
			ev->failed = 1;
			evo_fail(&ev->err, "generation %d: %s", ev->gen, e.msg);
		}
	}
	while (!ev->failed && ev->next < ev->n) {
		int i = ev->next++;
		if (locked)
			pthread_mutex_unlock(&ev->mu);
		evo_eval_result r;
		rc = ev->groups ? evaluate_team_unit(w, i, &e)
				: evaluate_one(w, i, &r, &e);
		if (locked)
			pthread_mutex_lock(&ev->mu);
		if (rc == 0) {
			if (!ev->groups)
				ev->res[i] = r;
		} else if (!ev->failed) {
			ev->failed = 1;
			evo_fail(&ev->err, "generation %d, %s %d: %s", ev->gen,
				 ev->groups ? "team" : "candidate",
				 ev->first + i, e.msg);
		}
	}
}

static void *worker_main(void *arg)
{
	worker *w = arg;
	evo_evaluator *ev = w->ev;
	unsigned long seen = 0;
	evo_err e = {{0}};
	int rc = worker_load(ev, w, &e);
	pthread_mutex_lock(&ev->mu);
	if (rc && !ev->failed) {
		ev->failed = 1;
		ev->err = e;
	}
	if (--ev->busy == 0)
		pthread_cond_signal(&ev->done_cv);
	for (;;) {
		while (!ev->quit && ev->batch_id == seen)
			pthread_cond_wait(&ev->start_cv, &ev->mu);
		if (ev->quit)
			break;
		seen = ev->batch_id;
		work_batch(w, 1);
		if (--ev->busy == 0)
			pthread_cond_signal(&ev->done_cv);
	}
	pthread_mutex_unlock(&ev->mu);
	return NULL;
}

/* Every worker's environment declared the same metrics as worker 0's, in
 * the same order: a candidate's metrics must not depend on the worker
 * that ran it. An init that decides by os.clock() could differ. */
static int check_metrics(evo_evaluator *ev, evo_err *err)
{
	if (ev->w[0].lit)
		return 0;
	const evo_sim *first = ev->w[0].sim;
	int n = evo_sim_n_metrics(first);
	for (int k = 1; k < ev->threads; k++) {
		const evo_sim *sk = ev->w[k].sim;
		int same = evo_sim_n_metrics(sk) == n;
		for (int i = 0; same && i < n; i++)
			same = !strcmp(evo_sim_metric_name(sk, i),
				       evo_sim_metric_name(first, i));
		if (!same)
			return evo_fail(err,
					"%s: the environment declared other "
					"metrics in worker %d than in worker "
					"1: its init must declare the same "
					"ones every time",
					ev->task_path, k + 1);
	}
	ev->n_metrics = n;
	return 0;
}

/* 1 when the task at path is a LEARNREMOTESIM task: its TYPE, read
 * without loading its mind. */
static int remote_task(const char *path)
{
	size_t len;
	evo_err e;
	char *text;
	if (evo_read_file(path, &text, &len, &e))
		return 0;
	evo_simbatch *sb = malloc(sizeof *sb);
	evo_diag d;
	int remote = sb &&
		     evo_simbatch_parse(text, len, path, sb, &d) == EVO_OK &&
		     evo_simbatch_get(sb, "TYPE") &&
		     strcasecmp(evo_simbatch_get(sb, "TYPE"),
				"LEARNREMOTESIM") == 0;
	free(sb);
	free(text);
	return remote;
}

/* Repetitions, ticks and the skill's shape of a remote evaluator. */
static int remote_settings(evo_evaluator *ev, const evo_eval_def *def,
			   evo_err *err)
{
	evo_task t;
	if (evo_task_load(def->task_path, &t, err))
		return -1;
	ev->reps = def->reps ? def->reps
			     : (int)simbatch_number(t.sb, "EVALREP", 1);
	ev->ticks = def->ticks ? def->ticks
			       : simbatch_number(t.sb, "TICKLIM", 1000);
	const char *learn = evo_simbatch_get(t.sb, "LEARNINGSKILL");
	int k = learn ? evo_mindfolder_skill(t.mind, learn) : -1;
	if (k >= 0) {
		ev->n_in = t.mind->skill[k].n_in;
		ev->n_out = t.mind->skill[k].n_out;
	}
	evo_task_free(&t);
	ev->threads = evo_remote_eval_envs(ev->remote);
	return 0;
}

evo_evaluator *evo_evaluator_create(const evo_eval_def *def, evo_err *err)
{
	if (!def || !def->task_path) {
		evo_fail(err, "evaluator: no task");
		return NULL;
	}
	if (def->threads < 0 || def->threads > MAX_THREADS || def->reps < 0 ||
	    def->ticks < 0) {
		evo_fail(err,
			 "evaluator: threads must be 0..%d, reps and ticks "
			 ">= 0 (0: the task's)",
			 MAX_THREADS);
		return NULL;
	}
	evo_evaluator *ev = calloc(1, sizeof *ev);
	if (!ev) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	ev->seed = def->seed;
	if (def->spread)
		ev->spread = *def->spread;
	if (remote_task(def->task_path)) {
		if (!(ev->remote = evo_remote_eval_create(def->task_path, err)) ||
		    remote_settings(ev, def, err))
			goto fail_remote;
		return ev;
	}
	int threads = def->threads;
	if (threads == 0) {
		long c = sysconf(_SC_NPROCESSORS_ONLN);
		threads = c < 1 ? 1 : c > MAX_THREADS ? MAX_THREADS : (int)c;
	}
	ev->threads = threads;
	ev->def = def;
	ev->task_path = strdup(def->task_path);
	ev->w = calloc((size_t)threads, sizeof *ev->w);
	pthread_mutex_init(&ev->mu, NULL);
	pthread_cond_init(&ev->start_cv, NULL);
	pthread_cond_init(&ev->done_cv, NULL);
	if (!ev->task_path || !ev->w) {
		evo_fail(err, "out of memory");
		goto fail;
	}
	/* Each worker loads its task on its own thread: glibc then takes
	 * its world, Lua state and mind from that thread's malloc arena, so
	 * two workers' objects never share a cache line. One worker runs on
	 * the caller's thread. */
	ev->inline_worker = threads == 1;
	if (ev->inline_worker) {
		ev->w[0].ev = ev;
		if (worker_load(ev, &ev->w[0], &ev->err))
			ev->failed = 1;
	}
	ev->busy = ev->inline_worker ? 0 : threads;
	for (int k = 0; !ev->inline_worker && k < threads; k++) {
		ev->w[k].ev = ev;
		int rc = pthread_create(&ev->w[k].thread, NULL, worker_main,
					&ev->w[k]);
		if (rc) {
			pthread_mutex_lock(&ev->mu);
			ev->busy -= threads - k;
			if (!ev->failed) {
				ev->failed = 1;
				evo_fail(&ev->err,
					 "evaluator: cannot start a thread: %s",
					 strerror(rc));
			}
			pthread_mutex_unlock(&ev->mu);
			break;
		}
		ev->w[k].started = 1;
	}
	pthread_mutex_lock(&ev->mu);
	while (ev->busy > 0)
		pthread_cond_wait(&ev->done_cv, &ev->mu);
	int failed = ev->failed;
	if (failed)
		*err = ev->err;
	pthread_mutex_unlock(&ev->mu);
	ev->def = NULL;
	if (failed)
		goto fail;
	if (check_metrics(ev, err))
		goto fail;
	const evo_simbatch *sb = ev->w[0].task.sb;
	ev->reps = ev->w[0].lit ? 1
		   : def->reps	? def->reps
				: (int)simbatch_number(sb, "EVALREP", 1);
	ev->ticks =
	    def->ticks ? def->ticks : simbatch_number(sb, "TICKLIM", 1000);
	const evo_ades *a = &ev->w[0].task.mind->skill[ev->w[0].skill];
	ev->n_in = a->n_in;
	ev->n_out = a->n_out;
	ev->n_teams = ev->w[0].task.n_teams;
	ev->heterogeneous = ev->w[0].task.heterogeneous;
	ev->own_fitness = ev->w[0].task.own_fitness;
	return ev;
fail:
	evo_evaluator_destroy(ev);
	return NULL;
fail_remote:
	evo_remote_eval_destroy(ev->remote);
	free(ev);
	return NULL;
}

void evo_evaluator_destroy(evo_evaluator *ev)
{
	if (!ev)
		return;
	if (ev->remote) {
		evo_remote_eval_destroy(ev->remote);
		free(ev);
		return;
	}
	pthread_mutex_lock(&ev->mu);
	ev->quit = 1;
	pthread_cond_broadcast(&ev->start_cv);
	pthread_mutex_unlock(&ev->mu);
	for (int k = 0; ev->w && k < ev->threads; k++) {
		worker *w = &ev->w[k];
		if (w->started)
			pthread_join(w->thread, NULL);
		evo_sim_destroy(w->sim);
		for (int t = 0; t < EVO_MAX_TEAMS; t++) {
			for (int i = 0;
			     w->member[t] && i < w->task.team[t].size; i++)
				evo_mindfolder_free(w->member[t][i]);
			free(w->member[t]);
			free(w->own_net[t]);
		}
		if (w->task.sb || w->task.mind)
			evo_task_free(&w->task);
	}
	pthread_cond_destroy(&ev->done_cv);
	pthread_cond_destroy(&ev->start_cv);
	pthread_mutex_destroy(&ev->mu);
	for (int t = 0; t < EVO_MAX_TEAMS; t++)
		free(ev->team_net[t]);
	free(ev->w);
	free(ev->task_path);
	free(ev->genome);
	free(ev);
}

const char *evo_evaluator_env_path(const evo_evaluator *ev)
{
	if (!ev->w || ev->threads < 1 || !ev->w[0].sim || !ev->w[0].sim->lua)
		return NULL;
	return evo_lua_env_path(ev->w[0].sim->lua);
}

int evo_evaluator_set_genome(evo_evaluator *ev, const char *genome,
			     evo_err *err)
{
	char *copy = NULL;
	if (genome) {
		size_t n = strlen(genome) + 1;
		copy = malloc(n);
		if (!copy)
			return evo_fail(err, "no memory for a genome of %zu "
					     "bytes",
					n);
		memcpy(copy, genome, n);
	}
	free(ev->genome);
	ev->genome = copy;
	return 0;
}

const char *evo_evaluator_genome(const evo_evaluator *ev)
{
	return ev->genome;
}

int evo_evaluator_threads(const evo_evaluator *ev)
{
	return ev->threads;
}

int evo_evaluator_reps(const evo_evaluator *ev)
{
	return ev->reps;
}

long evo_evaluator_ticks(const evo_evaluator *ev)
{
	return ev->ticks;
}

unsigned evo_evaluator_n_in(const evo_evaluator *ev)
{
	return ev->n_in;
}

unsigned evo_evaluator_n_out(const evo_evaluator *ev)
{
	return ev->n_out;
}

int evo_evaluator_n_metrics(const evo_evaluator *ev)
{
	return ev->n_metrics;
}

int evo_evaluator_remotes(const evo_evaluator *ev)
{
	return ev->remote ? evo_remote_eval_sims(ev->remote) : 0;
}

const char *evo_evaluator_metric_name(const evo_evaluator *ev, int k)
{
	return k >= 0 && k < ev->n_metrics
		   ? evo_sim_metric_name(ev->w[0].sim, k)
		   : NULL;
}

int evo_evaluator_deferred_success(const evo_evaluator *ev)
{
	return !ev->remote && ev->w[0].lit == EVO_LIT_DPNV;
}

/* With ev->mu held and the batch's fields set: the workers run it; the
 * batch's pointers are cleared after. Nonzero when an evaluation failed
 * (*err says why). */
static int run_batch(evo_evaluator *ev, evo_err *err)
{
	ev->failed = 0;
	ev->err.msg[0] = 0;
	if (ev->inline_worker) {
		work_batch(&ev->w[0], 0);
	} else {
		ev->busy = ev->threads;
		ev->batch_id++;
		pthread_cond_broadcast(&ev->start_cv);
		while (ev->busy > 0)
			pthread_cond_wait(&ev->done_cv, &ev->mu);
	}
	int failed = ev->failed;
	if (failed)
		*err = ev->err;
	ev->cand = NULL;
	ev->res = NULL;
	ev->groups = NULL;
	ev->unit = NULL;
	ev->own = NULL;
	return failed;
}

/* The candidates' shapes, checked before any worker starts, so a wrong
 * candidate is named the same way whatever the thread count; first: the
 * batch index of candidates[0]. */
static int check_shapes(const evo_evaluator *ev,
			const evo_netdesc *const *candidates, int first, int n,
			evo_err *err)
{
	const char *skill =
	    ev->remote ? "LEARNINGSKILL"
		       : ev->w[0].task.mind->skill[ev->w[0].skill].name;
	for (int i = 0; i < n; i++) {
		const evo_netdesc *c = candidates[i];
		if (!c)
			return evo_fail(err, "candidate %d: no network",
					first + i);
		if (c->n_in != ev->n_in || c->n_out != ev->n_out)
			return evo_fail(err,
					"candidate %d: the network has %u "
					"inputs and %u outputs; skill %s has "
					"%u inputs and %u outputs",
					first + i, (unsigned)c->n_in,
					(unsigned)c->n_out, skill, ev->n_in,
					ev->n_out);
	}
	return 0;
}

int evo_evaluate_part(evo_evaluator *ev, const evo_netdesc *const *candidates,
		      int first, int n, int gen, evo_eval_result *res,
		      evo_err *err)
{
	if (n < 0 || first < 0 || (n > 0 && (!candidates || !res)))
		return evo_fail(err, "evaluate: no candidates or no result "
				     "array");
	if (ev->remote || ev->n_teams > 0)
		return evo_fail(err, "evaluate: a part of a batch is for a "
				     "one-agent task in-process");
	if (check_shapes(ev, candidates, first, n, err))
		return -1;
	if (n == 0)
		return 0;
	pthread_mutex_lock(&ev->mu);
	ev->cand = candidates;
	ev->n = n;
	ev->gen = gen;
	ev->next = 0;
	ev->first = first;
	ev->res = res;
	int failed = run_batch(ev, err);
	ev->first = 0;
	pthread_mutex_unlock(&ev->mu);
	return failed ? -1 : 0;
}

int evo_evaluate(evo_evaluator *ev, const evo_netdesc *const *candidates, int n,
		 int gen, evo_eval_result *res, evo_err *err)
{
	if (n < 0 || (n > 0 && (!candidates || !res)))
		return evo_fail(err, "evaluate: no candidates or no result "
				     "array");
	if (check_shapes(ev, candidates, 0, n, err))
		return -1;
	if (n == 0)
		return 0;
	if (ev->n_teams > 0) {
		/* a homogeneous evaluation of each candidate by the first
		 * learning team */
		int t = ev->w[0].task.learning[0];
		int size = ev->w[0].task.team[t].size;
		int *groups = malloc((size_t)n * size * sizeof *groups);
		if (!groups)
			return evo_fail(err, "out of memory");
		for (int i = 0; i < n; i++)
			for (int m = 0; m < size; m++)
				groups[(size_t)i * size + m] = i;
		int rc = evo_evaluate_teams(ev, t, candidates, n, groups, n,
					    gen, res, err);
		free(groups);
		return rc;
	}
	if (ev->remote) {
		int rc = evo_remote_eval_run(ev->remote, candidates, n, gen,
					     ev->seed, ev->reps, ev->ticks, res,
					     err);
		if (rc) {
			evo_err inner = *err;
			evo_fail(err, "generation %d: %s", gen, inner.msg);
		}
		return rc;
	}
	if (ev->spread.evaluate)
		return ev->spread.evaluate(ev->spread.ctx, ev, candidates, n,
					   gen, res, err);
	return evo_evaluate_part(ev, candidates, 0, n, gen, res, err);
}

/* ---- team tasks -----------------------------------------------------------
 */

int evo_evaluator_n_teams(const evo_evaluator *ev)
{
	return ev->remote ? 0 : ev->n_teams;
}

int evo_evaluator_team_size(const evo_evaluator *ev, int team)
{
	return team >= 0 && team < evo_evaluator_n_teams(ev)
		   ? ev->w[0].task.team[team].size
		   : 0;
}

static const evo_ades *team_skill(const evo_evaluator *ev, int team)
{
	if (team < 0 || team >= evo_evaluator_n_teams(ev) ||
	    ev->w[0].team_skill[team] < 0)
		return NULL;
	return &ev->w[0].task.team[team].mind->skill[ev->w[0].team_skill[team]];
}

unsigned evo_evaluator_team_n_in(const evo_evaluator *ev, int team)
{
	const evo_ades *a = team_skill(ev, team);
	return a ? a->n_in : 0;
}

unsigned evo_evaluator_team_n_out(const evo_evaluator *ev, int team)
{
	const evo_ades *a = team_skill(ev, team);
	return a ? a->n_out : 0;
}

int evo_evaluator_set_team_net(evo_evaluator *ev, int team,
			       const evo_netdesc *net, evo_err *err)
{
	const evo_ades *a = team_skill(ev, team);
	if (!a)
		return evo_fail(err, "team %d has no learning skill to set",
				team);
	if (net->n_in != a->n_in || net->n_out != a->n_out)
		return evo_fail(err,
				"team %s: a network of %u inputs and %u "
				"outputs for skill %s of %u and %u",
				ev->w[0].task.team[team].name,
				(unsigned)net->n_in, (unsigned)net->n_out,
				a->name, (unsigned)a->n_in, (unsigned)a->n_out);
	if (!ev->team_net[team] &&
	    !(ev->team_net[team] = malloc(sizeof *ev->team_net[team])))
		return evo_fail(err, "out of memory");
	/* workers are idle between batches: no lock is needed for the
	 * net, and the version is read under the batch's lock */
	*ev->team_net[team] = *net;
	pthread_mutex_lock(&ev->mu);
	ev->nets_version++;
	pthread_mutex_unlock(&ev->mu);
	return 0;
}

int evo_evaluate_teams(evo_evaluator *ev, int team,
		       const evo_netdesc *const *candidates, int n,
		       const int *groups, int n_groups, int gen,
		       evo_eval_result *res, evo_err *err)
{
	const evo_ades *a = team_skill(ev, team);
	if (!a || !ev->w[0].task.team[team].learns)
		return evo_fail(err, "team %d is not a learning team", team);
	int size = ev->w[0].task.team[team].size;
	if (n < 1 || n_groups < 1 || !candidates || !groups || !res)
		return evo_fail(err, "evaluate: no candidates or no teams");
	for (int i = 0; i < n; i++) {
		const evo_netdesc *c = candidates[i];
		if (!c)
			return evo_fail(err, "candidate %d: no network", i);
		if (c->n_in != a->n_in || c->n_out != a->n_out)
			return evo_fail(err,
					"candidate %d: the network has %u "
					"inputs and %u outputs; skill %s has "
					"%u inputs and %u outputs",
					i, (unsigned)c->n_in,
					(unsigned)c->n_out, a->name,
					(unsigned)a->n_in, (unsigned)a->n_out);
	}
	/* each candidate's first evaluation and member, in order */
	int *first = malloc((size_t)n * sizeof *first);
	unit_result *unit = calloc((size_t)n_groups, sizeof *unit);
	double *own = calloc((size_t)n_groups * size, sizeof *own);
	if (!first || !unit || !own) {
		free(first);
		free(unit);
		free(own);
		return evo_fail(err, "out of memory");
	}
	for (int i = 0; i < n; i++)
		first[i] = -1;
	for (long k = 0; k < (long)n_groups * size; k++) {
		int c = groups[k];
		if (c < 0 || c >= n) {
			free(first);
			free(unit);
			free(own);
			return evo_fail(err,
					"team %ld, member %ld: no candidate %d",
					k / size, k % size, c);
		}
		if (first[c] < 0)
			first[c] = (int)(k / size);
	}
	for (int i = 0; i < n; i++)
		if (first[i] < 0) {
			free(first);
			free(unit);
			free(own);
			return evo_fail(err, "candidate %d is in no team", i);
		}
	pthread_mutex_lock(&ev->mu);
	ev->cand = candidates;
	ev->n = n_groups;
	ev->gen = gen;
	ev->next = 0;
	ev->res = NULL;
	ev->team = team;
	ev->groups = groups;
	ev->unit = unit;
	ev->own = own;
	int failed = run_batch(ev, err);
	pthread_mutex_unlock(&ev->mu);
	/* Each candidate's result from its first evaluation, worked out
	 * here, in order: nothing depends on which worker ran what. */
	for (int i = 0; i < n && !failed; i++) {
		int j = first[i];
		const unit_result *u = &unit[j];
		evo_eval_result *r = &res[i];
		memset(r, 0, sizeof *r);
		r->group = j;
		r->team_fitness = u->team_fitness;
		r->wins = u->wins;
		r->collisions = u->collisions;
		memcpy(r->metric, u->metric, sizeof r->metric);
		if (!ev->own_fitness) {
			r->fitness = u->team_fitness;
		} else {
			double sum = 0;
			int members = 0;
			for (int m = 0; m < size; m++)
				if (groups[(size_t)j * size + m] == i) {
					sum += own[(size_t)j * size + m];
					members++;
				}
			r->fitness = sum / members;
		}
	}
	free(first);
	free(unit);
	free(own);
	return failed ? -1 : 0;
}

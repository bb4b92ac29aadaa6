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
#include "learn/evaluate_internal.h"
#include "learn/evaluate_remote.h"
#include "learn/literature.h"
#include "mind/task.h"
#include "tasksim/tasksim.h"
#include "world2d/scene.h"

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

void eval_begin_batch(evo_evaluator *ev, const evo_netdesc *const *cand,
		      int n, int gen)
{
	pthread_mutex_lock(&ev->mu);
	ev->cand = cand;
	ev->n = n;
	ev->gen = gen;
	ev->next = 0;
}

int eval_run_episode(evo_sim *sim, uint64_t seed, int gen, int cand, int r,
		     long ticks, evo_err *err)
{
	if (evo_sim_reset(sim, r + 1, evo_eval_grid_seed(seed, gen, r),
			  evo_eval_episode_seed(seed, gen, cand, r), err)) {
		evo_err inner = *err;
		return evo_fail(err, "repetition %d, at its start: %s", r + 1,
				inner.msg);
	}
	for (long t = 0; t < ticks; t++) {
		int st = evo_sim_tick(sim, err);
		if (st < 0) {
			evo_err inner = *err;
			return evo_fail(err, "repetition %d, tick %ld: %s",
					r + 1, t, inner.msg);
		}
		if (st > 0)
			break;
	}
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
		if (eval_run_episode(w->sim, ev->seed, ev->gen, c, r, ev->ticks,
				     err))
			return -1;
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

/* Load worker k's own copy of the task and build its simulation. */
static int worker_load(evo_evaluator *ev, worker *w, evo_err *err)
{
	evo_task_opts to = {.nets = ev->def->nets, .n_nets = ev->def->n_nets};
	if (evo_task_load_opts(ev->task_path, &to, &w->task, err))
		return -1;
	if (w->task.n_teams > 0 && strncmp(w->task.type, "LEARN", 5) == 0)
		return eval_load_teams(ev, w, err);
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
		rc = eval_apply_team_nets(w, &e);
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
		rc = ev->groups ? eval_evaluate_team_unit(w, i, &e)
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

const evo_eval_settings *evo_evaluator_settings(const evo_evaluator *ev)
{
	return &ev->settings;
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
int eval_run_batch(evo_evaluator *ev, evo_err *err)
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
	eval_begin_batch(ev, candidates, n, gen);
	ev->first = first;
	ev->res = res;
	int failed = eval_run_batch(ev, err);
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

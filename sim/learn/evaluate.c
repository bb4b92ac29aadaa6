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
} worker;

struct evo_evaluator {
	char *task_path;
	int threads, reps;
	long ticks;
	int n_metrics; /* worker 0's scene holds their names */
	uint64_t seed;
	unsigned n_in, n_out;
	worker *w;
	evo_remote_eval *remote; /* LEARNREMOTESIM: no workers */

	/* Everything below is guarded by mu. A batch is announced by
	 * bumping batch_id; each worker counts itself out in `busy`, and
	 * the caller waits for busy == 0, so no evaluation outlives its
	 * batch. */
	pthread_mutex_t mu;
	pthread_cond_t start_cv, done_cv;
	unsigned long batch_id;
	int quit;
	int busy;
	const evo_netdesc *const *cand;
	int n, gen, next;
	evo_eval_result *res;
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

/* Candidate i on worker w: bind it, run the reps, sum the rewards. */
static int evaluate_one(worker *w, int i, evo_eval_result *res, evo_err *err)
{
	evo_evaluator *ev = w->ev;
	memset(res, 0, sizeof *res);
	if (w->lit) {
		/* Deterministic and seedless: one run, whatever EVALREP. */
		evo_lit_result r;
		if (evo_lit_evaluate(w->lit, ev->cand[i], &r, err))
			return -1;
		res->fitness = r.fitness;
		res->solved = r.solved;
		return 0;
	}
	evo_mindfolder *l = w->task.mind;
	*l->net[w->skill] = *ev->cand[i];
	if (evo_mindfolder_rebuild(l, err) || evo_sim_set_mind(w->sim, l, err))
		return -1;
	const evo_bot *bot = &w->sim->scene->bot[w->sim->bot];
	for (int r = 0; r < ev->reps; r++) {
		if (evo_sim_reset(
			w->sim, r + 1, evo_eval_grid_seed(ev->seed, ev->gen, r),
			evo_eval_episode_seed(ev->seed, ev->gen, i, r), err)) {
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
		res->fitness += w->sim->scene->episode_reward;
		res->collisions += bot->collisions;
		for (int k = 0; k < ev->n_metrics; k++)
			res->metric[k] += w->sim->scene->metric[k].value;
	}
	for (int k = 0; k < ev->n_metrics; k++)
		res->metric[k] /= ev->reps;
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
	if (evo_task_load(ev->task_path, &w->task, err))
		return -1;
	const char *learn = evo_simbatch_get(w->task.sb, "LEARNINGSKILL");
	if (strncmp(w->task.type, "LEARN", 5) != 0 || !learn)
		return evo_fail(err,
				"%s: not a learning task (TYPE %s): the "
				"evaluator needs LEARNINGSKILL",
				ev->task_path, w->task.type);
	w->skill = evo_mindfolder_skill(w->task.mind, learn);
	if (w->skill < 0 || !w->task.mind->net[w->skill])
		return evo_fail(err, "%s: LEARNINGSKILL %s has no network",
				ev->task_path, learn);
	w->lit = evo_lit_task_named(evo_simbatch_get(w->task.sb, "ENV"));
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
		/* Take candidates until the batch is empty or has failed. */
		while (!ev->failed && ev->next < ev->n) {
			int i = ev->next++;
			pthread_mutex_unlock(&ev->mu);
			evo_eval_result r;
			rc = evaluate_one(w, i, &r, &e);
			pthread_mutex_lock(&ev->mu);
			if (rc == 0) {
				ev->res[i] = r;
			} else if (!ev->failed) {
				ev->failed = 1;
				evo_fail(&ev->err, "generation %d, candidate %d: %s",
					 ev->gen, i, e.msg);
			}
		}
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
	const evo_scene *first = ev->w[0].sim->scene;
	for (int k = 1; k < ev->threads; k++) {
		const evo_scene *sc = ev->w[k].sim->scene;
		int same = sc->n_metrics == first->n_metrics;
		for (int i = 0; same && i < sc->n_metrics; i++)
			same = !strcmp(sc->metric[i].name, first->metric[i].name);
		if (!same)
			return evo_fail(err,
					"%s: the environment declared other "
					"metrics in worker %d than in worker "
					"1: its init must declare the same "
					"ones every time",
					ev->task_path, k + 1);
	}
	ev->n_metrics = first->n_metrics;
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
	 * two workers' objects never share a cache line. */
	ev->busy = threads;
	for (int k = 0; k < threads; k++) {
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
		if (w->task.sb || w->task.mind)
			evo_task_free(&w->task);
	}
	pthread_cond_destroy(&ev->done_cv);
	pthread_cond_destroy(&ev->start_cv);
	pthread_mutex_destroy(&ev->mu);
	free(ev->w);
	free(ev->task_path);
	free(ev);
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
	return k >= 0 && k < ev->n_metrics ? ev->w[0].sim->scene->metric[k].name
					   : NULL;
}

int evo_evaluator_deferred_success(const evo_evaluator *ev)
{
	return !ev->remote && ev->w[0].lit == EVO_LIT_DPNV;
}

int evo_evaluate(evo_evaluator *ev, const evo_netdesc *const *candidates, int n,
		 int gen, evo_eval_result *res, evo_err *err)
{
	if (n < 0 || (n > 0 && (!candidates || !res)))
		return evo_fail(err, "evaluate: no candidates or no result "
				     "array");
	/* Shapes are checked here, before any worker starts, so a wrong
	 * candidate is named the same way whatever the thread count. */
	const char *skill =
	    ev->remote ? "LEARNINGSKILL"
		       : ev->w[0].task.mind->skill[ev->w[0].skill].name;
	for (int i = 0; i < n; i++) {
		const evo_netdesc *c = candidates[i];
		if (!c)
			return evo_fail(err, "candidate %d: no network", i);
		if (c->n_in != ev->n_in || c->n_out != ev->n_out)
			return evo_fail(err,
					"candidate %d: the network has %u "
					"inputs and %u outputs; skill %s has "
					"%u inputs and %u outputs",
					i, (unsigned)c->n_in,
					(unsigned)c->n_out, skill, ev->n_in,
					ev->n_out);
	}
	if (n == 0)
		return 0;
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
	pthread_mutex_lock(&ev->mu);
	ev->cand = candidates;
	ev->n = n;
	ev->gen = gen;
	ev->next = 0;
	ev->res = res;
	ev->failed = 0;
	ev->err.msg[0] = 0;
	ev->busy = ev->threads;
	ev->batch_id++;
	pthread_cond_broadcast(&ev->start_cv);
	while (ev->busy > 0)
		pthread_cond_wait(&ev->done_cv, &ev->mu);
	int failed = ev->failed;
	if (failed)
		*err = ev->err;
	ev->cand = NULL;
	ev->res = NULL;
	pthread_mutex_unlock(&ev->mu);
	return failed ? -1 : 0;
}

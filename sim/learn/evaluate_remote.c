/* LEARNREMOTESIM's evaluations over remote simulators
 * (sim/learn/evaluate_remote.h). */
#define _POSIX_C_SOURCE 200809L
#include "learn/evaluate_remote.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mind/task.h"
#include "remote/session.h"

/* Seconds evo listens for more simulators after the first answers. */
#define FIND_WINDOW 1.0

/* One environment of one simulator, with a mind of its own. */
typedef struct slot {
	int ri, env;
	evo_task task; /* its own mind folder, the candidate in it */
	int skill;
	void *mem;
	size_t mem_size;
	evo_state *state;
	long job; /* the episode it runs, -1 when free */
	int built_gen, built_cand; /* whose mind it holds, -1: none */
	long t;	  /* commands sent in that episode */
	int dead;
} slot;

struct evo_remote_eval {
	char *task_path;
	evo_task task; /* for the remote keys and the botdesc */
	evo_remotes *remotes;
	slot *slot;
	int n_slots;
	/* the episodes of a batch: job j is repetition j % reps of candidate
	 * j / reps; `queue` holds the ones to (re)start */
	long *queue;
	long n_queue;
	double *reward;
	/* each job's behaviour, from the episode's last sensors_t: job j's
	 * n_behav[j] values at behaviour[j * EVO_WIRE_MAX_BEHAVIOUR] */
	double *behaviour;
	int *n_behav;
	long n_jobs;
};

static int slot_load(evo_remote_eval *re, slot *s, evo_err *err)
{
	if (evo_task_load(re->task_path, &s->task, err))
		return -1;
	const char *learn = evo_simbatch_get(s->task.sb, "LEARNINGSKILL");
	s->skill = learn ? evo_mindfolder_skill(s->task.mind, learn) : -1;
	if (s->skill < 0 || !s->task.mind->net[s->skill])
		return evo_fail(err, "%s: LEARNINGSKILL %s has no network",
				re->task_path, learn ? learn : "(none)");
	s->job = -1;
	s->built_gen = s->built_cand = -1;
	return 0;
}

evo_remote_eval *evo_remote_eval_create(const char *task_path, evo_err *err)
{
	evo_remote_eval *re = calloc(1, sizeof *re);
	if (!re || !(re->task_path = strdup(task_path))) {
		free(re);
		evo_fail(err, "out of memory");
		return NULL;
	}
	evo_remote_opts ro;
	if (evo_task_load(task_path, &re->task, err) ||
	    evo_remote_opts_from_task(re->task.sb, task_path,
				      EVO_REMOTE_SIMULATOR, &ro, err))
		goto fail;
	ro.lose_silent = 1;
	re->remotes = evo_remotes_open(re->task.mind, &ro, err);
	if (!re->remotes || evo_remotes_find(re->remotes, FIND_WINDOW, err))
		goto fail;
	int n = 0;
	for (int i = 0; i < re->remotes->n; i++)
		n += re->remotes->r[i]->hello.environments;
	re->slot = calloc((size_t)n, sizeof *re->slot);
	if (!re->slot) {
		evo_fail(err, "out of memory");
		goto fail;
	}
	for (int i = 0; i < re->remotes->n; i++) {
		const evo_wire_hello *h = &re->remotes->r[i]->hello;
		for (int e = 0; e < h->environments; e++) {
			slot *s = &re->slot[re->n_slots++];
			s->ri = i;
			s->env = e;
			if (slot_load(re, s, err))
				goto fail;
		}
		printf("remote %s: simulator, %d environment%s\n", h->name,
		       (int)h->environments, h->environments == 1 ? "" : "s");
	}
	fflush(stdout);
	return re;
fail:
	evo_remote_eval_destroy(re);
	return NULL;
}

void evo_remote_eval_destroy(evo_remote_eval *re)
{
	if (!re)
		return;
	for (int i = 0; i < re->n_slots; i++) {
		evo_task_free(&re->slot[i].task);
		free(re->slot[i].mem);
	}
	free(re->slot);
	evo_remotes_close(re->remotes);
	if (re->task.sb || re->task.mind)
		evo_task_free(&re->task);
	free(re->queue);
	free(re->reward);
	free(re->behaviour);
	free(re->n_behav);
	free(re->task_path);
	free(re);
}

int evo_remote_eval_envs(const evo_remote_eval *re)
{
	return re->n_slots;
}

int evo_remote_eval_sims(const evo_remote_eval *re)
{
	return re->remotes->n;
}

/* Bind candidate cand into slot s's mind and start episode job. */
static int start(evo_remote_eval *re, slot *s, long job,
		 const evo_netdesc *cand, int gen, int cand_i, int rep,
		 uint64_t seed, evo_err *err)
{
	evo_mindfolder *l = s->task.mind;
	if (s->built_gen != gen || s->built_cand != cand_i) {
		/* another candidate: its network into the image */
		s->built_gen = s->built_cand = -1;
		*l->net[s->skill] = *cand;
		if (evo_mindfolder_rebuild(l, err))
			return -1;
		size_t need = (evo_state_size(&l->mind) + 7) & ~(size_t)7;
		if (need > s->mem_size) {
			free(s->mem);
			s->mem = aligned_alloc(8, need);
			s->mem_size = s->mem ? need : 0;
			if (!s->mem)
				return evo_fail(err, "out of memory");
		}
		if (evo_state_init(&l->mind, s->mem, s->mem_size, &s->state) !=
		    EVO_OK)
			return evo_fail(err, "mind state: cannot lay it out");
		s->built_gen = gen;
		s->built_cand = cand_i;
	} else {
		evo_state_reset(&l->mind, s->state);
	}
	s->job = job;
	s->t = 0;
	return evo_remotes_send_reset(re->remotes, s->ri, s->env, rep + 1,
				      evo_eval_grid_seed(seed, gen, rep),
				      evo_eval_episode_seed(seed, gen, cand_i,
							    rep),
				      err);
}

/* One tick of slot s's mind on the sensors that came, and its commands
 * sent. */
static int think(evo_remote_eval *re, slot *s, evo_err *err)
{
	const evo_mind *m = &s->task.mind->mind;
	double in[EVO_MAX_SENSORS], out[EVO_MAX_ACTUATORS];
	evo_q16 qin[EVO_MAX_SENSORS], qout[EVO_MAX_ACTUATORS];
	evo_remote_sensors(re->remotes->r[s->ri], s->env, in);
	for (unsigned i = 0; i < m->n_sensors; i++)
		qin[i] = evo_q16_from_sensor(in[i]);
	evo_mind_step(m, s->state, qin, qout);
	for (unsigned i = 0; i < m->n_actuators; i++)
		out[i] = evo_q16_to_double(qout[i]);
	s->t++;
	return evo_remotes_send_command(re->remotes, s->ri, s->env, out, err);
}

static slot *slot_of(evo_remote_eval *re, int ri, int env)
{
	for (int i = 0; i < re->n_slots; i++)
		if (re->slot[i].ri == ri && re->slot[i].env == env)
			return &re->slot[i];
	return NULL;
}

/* Candidate i's behaviour: the mean of its repetitions', which a
 * simulator sent with each episode's last sensors_t, as many values each
 * time (none: no behaviour). */
_Static_assert(EVO_WIRE_MAX_BEHAVIOUR == EVO_SIM_MAX_BEHAVIOUR,
	       "a behaviour over the wire is one evo keeps");

static int behaviour_of(const evo_remote_eval *re, int i, int reps,
			evo_eval_result *res, evo_err *err)
{
	long j0 = (long)i * reps;
	int d = re->n_behav[j0];
	for (int r = 1; r < reps; r++)
		if (re->n_behav[j0 + r] != d)
			return evo_fail(err,
					"candidate %d: the simulators sent a "
					"behaviour of %d values in repetition "
					"1 and %d in repetition %d: a "
					"behaviour has the same size every "
					"episode",
					i, d, re->n_behav[j0 + r], r + 1);
	res->n_behaviour = d;
	for (int r = 0; r < reps; r++)
		for (int k = 0; k < d; k++)
			res->behaviour[k] +=
			    re->behaviour[(j0 + r) * EVO_WIRE_MAX_BEHAVIOUR +
					  k];
	for (int k = 0; k < d; k++)
		res->behaviour[k] /= reps;
	return 0;
}

int evo_remote_eval_run(evo_remote_eval *re, const evo_netdesc *const *cand,
			int n, int gen, uint64_t seed, int reps, long ticks,
			evo_eval_result *res, evo_err *err)
{
	long jobs = (long)n * reps;
	if (jobs > re->n_jobs) {
		free(re->queue);
		free(re->reward);
		free(re->behaviour);
		free(re->n_behav);
		re->queue = malloc((size_t)jobs * sizeof *re->queue);
		re->reward = malloc((size_t)jobs * sizeof *re->reward);
		re->behaviour = malloc((size_t)jobs * EVO_WIRE_MAX_BEHAVIOUR *
				       sizeof *re->behaviour);
		re->n_behav = malloc((size_t)jobs * sizeof *re->n_behav);
		re->n_jobs = re->queue && re->reward && re->behaviour &&
				     re->n_behav
				 ? jobs
				 : 0;
		if (!re->n_jobs)
			return evo_fail(err, "out of memory");
	}
	/* the queue is taken from its end: job 0 first */
	re->n_queue = jobs;
	for (long j = 0; j < jobs; j++)
		re->queue[j] = jobs - 1 - j;
	long done = 0;
	for (int i = 0; i < re->n_slots; i++)
		re->slot[i].job = -1;
	while (done < jobs) {
		for (int i = 0; i < re->n_slots && re->n_queue; i++) {
			slot *s = &re->slot[i];
			if (s->dead || s->job >= 0)
				continue;
			long j = re->queue[--re->n_queue];
			int c = (int)(j / reps), r = (int)(j % reps);
			if (start(re, s, j, cand[c], gen, c, r, seed, err)) {
				evo_err inner = *err;
				return evo_fail(err,
						"candidate %d, repetition %d: %s",
						c, r + 1, inner.msg);
			}
		}
		int ri, env;
		int rc = evo_remotes_wait(re->remotes, &ri, &env, err);
		if (rc < 0)
			return -1;
		if (rc == 1) {
			/* its episodes start over elsewhere */
			int live = 0;
			for (int i = 0; i < re->n_slots; i++) {
				slot *s = &re->slot[i];
				if (s->ri == ri && !s->dead) {
					s->dead = 1;
					if (s->job >= 0)
						re->queue[re->n_queue++] =
						    s->job;
					s->job = -1;
				}
				live += !s->dead;
			}
			if (!live)
				return evo_fail(
				    err,
				    "every remote simulator is lost (the last, "
				    "%s, went silent or restarted); the run "
				    "stops at its last finished generation",
				    re->remotes->r[ri]->hello.name);
			continue;
		}
		slot *s = slot_of(re, ri, env);
		if (!s || s->job < 0)
			continue;
		const evo_wire_sensors *m = &re->remotes->r[ri]->env[env].sensors;
		if (s->t > 0 && (m->done || s->t >= ticks)) {
			re->reward[s->job] = m->reward;
			re->n_behav[s->job] = (int)m->n_behaviour;
			memcpy(re->behaviour + s->job * EVO_WIRE_MAX_BEHAVIOUR,
			       m->behaviour,
			       m->n_behaviour * sizeof *m->behaviour);
			s->job = -1;
			done++;
			continue;
		}
		if (think(re, s, err))
			return -1;
	}
	/* summed in repetition order, as one process sums them */
	for (int i = 0; i < n; i++) {
		memset(&res[i], 0, sizeof res[i]);
		for (int r = 0; r < reps; r++)
			res[i].fitness += re->reward[(long)i * reps + r];
		if (behaviour_of(re, i, reps, &res[i], err))
			return -1;
	}
	return 0;
}

/* The evaluator of LEARNSIM: runs batches of candidate networks for a
 * task's LEARNINGSKILL on a pool of worker threads.
 *
 * The pool is created once; each worker owns its own loaded mind folder
 * (the task's MASTERSKILL hierarchy with the other skills' saved networks)
 * and its own simulation (own Box2D world, own Lua state), so workers
 * share nothing but the batch counter. A candidate is copied into the
 * worker's net slot of the learning skill, the mind image is rebuilt and
 * rebound, and the repetitions run.
 *
 * Fitness: res[i].fitness is the sum over the `reps` repetitions of the
 * episode reward (scene->episode_reward) of candidate i, each episode
 * ending when a control function ends it or after `ticks` ticks;
 * res[i].collisions sums the ticks the learning bot spent touching
 * something.
 *
 * Metrics: the environment's own (docs/lua.md, "Metrics of your own"),
 * declared in its init and so the same in every worker. res[i].metric[k]
 * is metric k's value at the end of an episode, averaged over the
 * repetitions: where fitness sums, a metric is a mean, comparable with
 * what `evo run` prints for one episode.
 *
 * Seeds: each repetition of each candidate runs with seeds that depend on
 * the run's seed, the generation, the candidate and the repetition only
 * (sim/learn/eval_seeds.h), so results do not depend on the number of
 * threads.
 *
 * Literature tasks: when the task's ENV is XOR, DPV or DPNV the workers
 * build no simulation and score each candidate once with sim/learn/literature.h
 * (seedless and deterministic; EVALREP and TICKLIM do not apply), and
 * res[i].solved says whether candidate i met the task's success
 * criterion.
 *
 * Team tasks (LEARN2DSIMMULTI): every worker builds every team; a batch
 * trains one team's learning skill (evo_evaluate_teams), the other teams
 * running their networks. DPNV's success is decided after the batch, on one
 * candidate the caller picks (evo_evaluator_deferred_success): its solved flags
 * stay 0 here. */
#ifndef EVO_EVALUATE_H
#define EVO_EVALUATE_H

#include <stdint.h>

#include "base/err.h"
#include "evo/evo.h"
#include "learn/eval_seeds.h"
#include "mind/mindfolder.h"
#include "tasksim/tasksim.h"
#include "world2d/scene.h"

typedef struct evo_evaluator evo_evaluator;
typedef struct evo_eval_def evo_eval_def;

/* Where a batch may be spread beyond this process's workers: cluster
 * runs over MPI (sim/cluster/). evaluate is called by evo_evaluate in
 * place of the workers, for a one-agent task in-process (not a team task,
 * not LEARNREMOTESIM), with the same arguments and contract; it runs the
 * share it keeps with evo_evaluate_part. NULL in evo_eval_def: this
 * process's workers run every batch. */
typedef struct evo_eval_spread {
	int (*evaluate)(void *ctx, evo_evaluator *ev,
			const evo_netdesc *const *candidates, int n, int gen,
			evo_eval_result *res, evo_err *err);
	/* The caller made its evaluator anew as def says (OPENENDED's
	 * development, evo.grow): the others must follow before the next
	 * batch. ev is the new one. NULL: nothing to do. 0, or -1 with err
	 * set. */
	int (*remake)(void *ctx, evo_evaluator *ev, const evo_eval_def *def,
		      evo_err *err);
	void *ctx;
} evo_eval_spread;

/* More workers than this is a typo, not a machine. */
#define EVO_EVAL_MAX_THREADS EVO_MAX_THREADS /* the task's THREADS' bound */

struct evo_eval_def {
	const char *task_path; /* a LEARN* .simbatch; copied */
	int threads;	       /* workers, 0..EVO_EVAL_MAX_THREADS; 0: the
				* number of online cores (at most the max) */
	uint64_t seed;	       /* the run seed */
	int reps;	       /* repetitions; 0: EVALREP, else 1 */
	long ticks;	       /* ticks per episode at most; 0: TICKLIM,
				* else 1000 */
	const evo_eval_spread *spread; /* NULL: none; copied */
	/* LEARNSIMCONTINUOUS (docs/learning.md): the skill the candidates
	 * run as, instead of LEARNINGSKILL (NULL: LEARNINGSKILL), and
	 * networks the other skills run instead of their Skills/ ones (read
	 * while evo_evaluator_create runs) */
	const char *learning_skill;
	const evo_net_choice *nets;
	unsigned n_nets;
};

/* Load the task once per worker and start the workers. Returns NULL with
 * err set (the task's own file:line message) when the task does not load,
 * its simulation cannot be built, or a thread cannot start. */
evo_evaluator *evo_evaluator_create(const evo_eval_def *def, evo_err *err);

/* Stop and join the workers, free everything. NULL is allowed. */
void evo_evaluator_destroy(evo_evaluator *ev);

/* What an evaluator settled on, after the defaults: its threads (the
 * environments a batch runs on at once), the episodes of a candidate and
 * the ticks of an episode; the learning skill's inputs and outputs, which
 * a candidate must match; how many metrics the environment declared (0
 * for literature tasks). The fields, once: evo_eval_settings, and the
 * evaluator's own struct, which reads them by their names too. */
#define EVO_EVAL_SETTINGS_FIELDS                                               \
	int threads, reps;                                                     \
	long ticks;                                                            \
	unsigned n_in, n_out;                                                  \
	int n_metrics;

typedef struct evo_eval_settings {
	EVO_EVAL_SETTINGS_FIELDS
} evo_eval_settings;

/* Valid while ev lives. */
const evo_eval_settings *evo_evaluator_settings(const evo_evaluator *ev);

/* LEARNREMOTESIM: the remote simulators in use (their environments are
 * the settings' threads); 0 for an evaluator of threads. */
int evo_evaluator_remotes(const evo_evaluator *ev);

/* The name of the environment's metric k, in the order it declared
 * them. */
const char *evo_evaluator_metric_name(const evo_evaluator *ev, int k);

/* Evaluate candidates[0 .. n-1] (not owned; read while the call runs) in
 * generation gen, filling res[0 .. n-1]. Returns when the whole batch is
 * done. Returns 0, or -1 with err set to "candidate I: why" (a network
 * whose inputs or outputs do not fit the skill, a network the mind image
 * refuses, a script error); then res is unspecified, and the other
 * workers stopped at their next candidate. Not reentrant: one batch at a
 * time per evaluator. */
int evo_evaluate(evo_evaluator *ev, const evo_netdesc *const *candidates, int n,
		 int gen, evo_eval_result *res, evo_err *err);

/* Evaluate on this process's workers candidates[0 .. n-1] as candidates
 * first .. first+n-1 of generation gen's batch (their seeds and the
 * names in messages are those), filling res[0 .. n-1]: a part of a batch
 * gives what the whole batch gives for those candidates. A one-agent task
 * in-process only; as evo_evaluate otherwise. */
int evo_evaluate_part(evo_evaluator *ev, const evo_netdesc *const *candidates,
		      int first, int n, int gen, evo_eval_result *res,
		      evo_err *err);

/* OPENENDED (docs/openended.md): every episode of the batches to come
 * runs with genome (copied; NULL: none) as its environment genome, which
 * the environment reads with scene:genome(). Between batches only.
 * 0, or -1 with err set (out of memory). */
int evo_evaluator_set_genome(evo_evaluator *ev, const char *genome,
			     evo_err *err);

/* The environment genome the next batch runs with (NULL: none); valid
 * until the next evo_evaluator_set_genome. A cluster's rank 0 sends it
 * to the other ranks (sim/cluster/). */
const char *evo_evaluator_genome(const evo_evaluator *ev);

/* The path of the environment script worker 0 loaded, or NULL (a
 * literature task, remote simulators). */
const char *evo_evaluator_env_path(const evo_evaluator *ev);

/* ---- team tasks (LEARN2DSIMMULTI, docs/teams.md) ---------------------- */

/* The task's teams: 0 for a one-agent task. */
int evo_evaluator_n_teams(const evo_evaluator *ev);
/* Team k's size, and its learning skill's inputs and outputs (0 when it
 * has no learning skill). */
int evo_evaluator_team_size(const evo_evaluator *ev, int team);
unsigned evo_evaluator_team_n_in(const evo_evaluator *ev, int team);
unsigned evo_evaluator_team_n_out(const evo_evaluator *ev, int team);

/* From the next batch on, team `team` runs net as its learning skill's
 * network (co-evolution: a team whose turn it is not runs the best its
 * last turn found). Copied. 0, or -1 with err set (a net that does not
 * fit the skill). */
int evo_evaluator_set_team_net(evo_evaluator *ev, int team,
			       const evo_netdesc *net, evo_err *err);

/* Evaluate candidates[0 .. n-1] as members of team `team`, in n_groups
 * evaluations: in evaluation j, member m of the team runs candidate
 * groups[j * size + m] (size: the team's). Evaluation j, repetition r of
 * generation g is seeded as candidate j would be (eval_seeds.h).
 * res[c] for each candidate c, from the first evaluation it is in: its
 * fitness is that team's reward summed over the repetitions, or with
 * TEAMFITNESS:OWN the reward of c's own bot (the mean over its bots when
 * it runs several), summed over the repetitions; collisions, metrics and
 * wins are the team's. A candidate in no evaluation is an error. */
int evo_evaluate_teams(evo_evaluator *ev, int team,
		       const evo_netdesc *const *candidates, int n,
		       const int *groups, int n_groups, int gen,
		       evo_eval_result *res, evo_err *err);

/* 1 when the task decides success after a generation, on one candidate:
 * DPNV, where the paper gives one network per generation the 100,000-step
 * and generalisation test (evo_lit_dpnv_check). The learning loop picks
 * that network, as its method says (docs/learning.md). */
int evo_evaluator_deferred_success(const evo_evaluator *ev);

#endif

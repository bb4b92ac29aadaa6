/* evo — private to the evaluator (sim/learn/evaluate.c and
 * evaluate_teams.c): a worker thread's state, the evaluator's, and what
 * the team tasks' file gives the pool. No other file may use it. */
#ifndef EVO_EVALUATE_INTERNAL_H
#define EVO_EVALUATE_INTERNAL_H

#include <pthread.h>

#include "learn/evaluate.h"
#include "learn/evaluate_remote.h"
#include "learn/literature.h"
#include "mind/task.h"

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
	/* the settings (evaluate.h), by their own names too; worker 0's
	 * scene holds the metrics' names */
	union {
		evo_eval_settings settings;
		struct {
			EVO_EVAL_SETTINGS_FIELDS
		};
	};
	uint64_t seed;
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

/* the pool (evaluate.c) */
/* A batch begun: the pool's lock taken (eval_run_batch's caller frees
 * it), its n units of candidates cand of generation gen, none taken
 * yet. */
void eval_begin_batch(evo_evaluator *ev, const evo_netdesc *const *cand,
		      int n, int gen);
int eval_run_batch(evo_evaluator *ev, evo_err *err);

/* Repetition r (0-based) of unit `cand` of the batch (a candidate, or a
 * team task's unit) run on sim: reset with eval_seeds.h's seeds of
 * generation gen, then ticked until the environment ends the episode or
 * `ticks` pass. 0, or -1 with err saying which repetition and tick. */
int eval_run_episode(evo_sim *sim, uint64_t seed, int gen, int cand, int r,
		     long ticks, evo_err *err);

/* team tasks (evaluate_teams.c) */
int eval_apply_team_nets(worker *w, evo_err *err);
int eval_evaluate_team_unit(worker *w, int j, evo_err *err);
int eval_load_teams(evo_evaluator *ev, worker *w, evo_err *err);

#endif

/* LEARNREMOTESIM's evaluations (docs/remote.md, docs/learning.md): the
 * candidates' episodes spread over every environment of every remote
 * simulator that answers on the task's URL, in lockstep, from one thread.
 *
 * An evaluation is a function of its candidate and its seeds only (the
 * seeds of eval_seeds.h), so which simulator ran it does not matter: the
 * same seed gives the same fitness whatever the number of simulators, and
 * a simulator lost in the middle of a batch (silent for REMOTETIMEOUT, or
 * restarted) costs only the episodes it was running, which start over on
 * another. With none left, the batch fails and the run stops at its last
 * checkpoint, which --resume continues. Private to learn/. */
#ifndef EVO_EVALUATE_REMOTE_H
#define EVO_EVALUATE_REMOTE_H

#include "base/err.h"
#include "evo/evo.h"
#include "learn/eval_seeds.h"

typedef struct evo_remote_eval evo_remote_eval;

/* Load the task (one mind per environment, made as they are found), find
 * the simulators: the first to answer, then every other that answers
 * within a second. NULL with err set. */
evo_remote_eval *evo_remote_eval_create(const char *task_path, evo_err *err);
void evo_remote_eval_destroy(evo_remote_eval *re);

/* Environments and simulators in use. */
int evo_remote_eval_envs(const evo_remote_eval *re);
int evo_remote_eval_sims(const evo_remote_eval *re);

/* As evo_evaluate, with the run's seed, repetitions and tick limit. */
int evo_remote_eval_run(evo_remote_eval *re, const evo_netdesc *const *cand,
			int n, int gen, uint64_t seed, int reps, long ticks,
			evo_eval_result *res, evo_err *err);

#endif

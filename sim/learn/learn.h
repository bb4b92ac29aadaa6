/* evo — LEARNSIM: train a task's LEARNINGSKILL inside its hierarchy.
 * The loop is Lua (lua/learn/learnsim.lua), the evaluation C on worker
 * threads (sim/learn/evaluate.h). docs/learning.md. */
#ifndef EVO_LEARN_H
#define EVO_LEARN_H

#include <stdint.h>

#include "base/err.h"
#include "learn/evaluate.h"
#include "mind/task.h"

typedef struct evo_learn_opts {
	uint64_t seed;
	int threads;	     /* 0: one per core */
	const char *run_dir; /* NULL: <mind>/Runs/<task>-seed<N> */
	int resume;	     /* go on from the run folder's checkpoint */
	int generations;     /* 0: NUMGEN */
	long ticks;	     /* ticks per episode at most; 0: TICKLIM */
	int no_save;	     /* the champion stays in the run folder:
			      * Skills/ is left as it is (--no-save) */
	const char *argv0;   /* evo as it was run, for the resume hint;
			      * NULL: "evo" */
	/* where batches go beyond this process (cluster runs,
	 * sim/cluster/); NULL: its own worker threads */
	const evo_eval_spread *spread;
} evo_learn_opts;

/* Run the learning task; prints one line per generation, writes the run
 * folder, saves the champion into the skill's folder (a network there it
 * replaces is kept in the run folder as replaced-SKILL.net), unless
 * no_save. Returns 0 or -1 with err set. */
int evo_learn_run(const char *task_path, evo_task *task,
		  const evo_learn_opts *o, evo_err *err);

/* Check a LEARNSIM task's learning options as evo_learn_run reads them,
 * without training: unknown keys are warnings on stderr, a value an
 * option cannot take an error at its line. Returns 0 or -1 with err set. */
int evo_learn_check(const char *task_path, evo_task *task, evo_err *err);

#endif

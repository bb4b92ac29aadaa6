/* evo — the options of a learning run (evo run's command line), apart
 * from learn.h so that the run folder's record of them (runopts.h) and
 * the loop (learn.c) both read them without including each other. */
#ifndef EVO_LEARN_OPTS_H
#define EVO_LEARN_OPTS_H

#include <stdint.h>

#include "learn/evaluate.h"

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

#endif

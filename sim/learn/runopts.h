/* evo — what a learning run's folder remembers of the options that shape
 * it, so that `evo run --resume` goes on with the same run.
 *
 * A fresh run writes RUN/options.txt: its seed, --ticks and --generations
 * (0: the task's TICKLIM and NUMGEN) and --no-save. --resume restores
 * each one not given again, and refuses a --seed or --ticks given
 * otherwise. --threads and
 * the number of MPI ranks are not kept: they do not change a run's
 * results (docs/learning.md, "Stopping and resuming"). */
#ifndef EVO_RUNOPTS_H
#define EVO_RUNOPTS_H

#include <stdint.h>

#include "base/err.h"
#include "learn/learn_opts.h"
#include "mind/task.h"

typedef struct evo_run_record {
	int found; /* 0: the folder has no options.txt (no run, or one made
		    * before evo kept it) */
	uint64_t seed;
	long ticks;	 /* 0: the task's TICKLIM */
	int generations; /* 0: the task's NUMGEN */
	int no_save;
} evo_run_record;

/* The run folder of a learning run: o->run_dir, else
 * MIND/Runs/TASK-seedN. 0 or -1 with err. */
int evo_learn_run_dir(const char *task_path, const evo_task *task,
		      const evo_learn_opts *o, char *dir, size_t cap,
		      evo_err *err);

/* Read DIR/options.txt into r (r->found 0 when there is none). A line
 * it cannot read is an error at DIR/options.txt:LINE. 0 or -1. */
int evo_run_record_read(const char *dir, evo_run_record *r, evo_err *err);

/* Write DIR/options.txt for the options o. 0 or -1 with err. */
int evo_run_record_write(const char *dir, const evo_learn_opts *o,
			 evo_err *err);

/* --resume: restore into o each option of DIR's record that was not
 * given on the command line (o->ticks, o->generations 0; seed_given 0),
 * and refuse a --seed or --ticks given with another value than the run
 * was started with: the generations to come would be scored otherwise.
 * --generations may change (the run ends at another generation, as when
 * NUMGEN is raised). No record: o as it is. 0 or -1 with err. */
int evo_run_record_restore(const char *dir, evo_learn_opts *o, int seed_given,
			   evo_err *err);

/* The options of o as a command line says them, " --seed N --ticks N
 * ...", for the hint that says how to resume. */
void evo_run_record_args(const evo_learn_opts *o, char *buf, size_t cap);

#endif

/* A task: a parsed .simbatch and the mind folder it runs.
 *
 * The mind folder is the folder that holds the Tasks/ folder the .simbatch
 * sits in (Minds/Agent/Tasks/T.simbatch runs Minds/Agent), so a task runs
 * from any working directory, Tasks/ itself included. A .simbatch outside a Tasks/ folder names its
 * mind with ROOTFOLDER, relative to the working directory, as EvoAgents
 * did. docs/formats.md, .simbatch. */
#ifndef EVO_TASK_H
#define EVO_TASK_H

#include "base/err.h"
#include "evo/evo.h"
#include "mind/mindfolder.h"

typedef struct evo_task {
	evo_simbatch *sb;
	const char *type; /* TYPE, upper-cased (an entry of evo_task_types) */
	evo_mindfolder *mind;
	uint64_t seed; /* the run's: evo_task_opts' seed, else SEED, else 1 */
} evo_task;

/* What a command line changes in a task (`evo run`'s options). */
typedef struct evo_task_opts {
	int seed_set; /* --seed given: seed replaces the task's SEED */
	uint64_t seed;
	/* --net SKILL=SOURCE: networks run instead of the skills' own
	 * (mind/mindfolder.h, evo_net_choice) */
	const evo_net_choice *nets;
	unsigned n_nets;
} evo_task_opts;

/* Parse path, check the keys its TYPE needs, load its mind folder.
 * Warnings (unknown keys) go to stderr. Returns 0, or -1 with err set. */
int evo_task_load(const char *path, evo_task *t, evo_err *err);

/* The same, with a command line's changes (o may be NULL). */
int evo_task_load_opts(const char *path, const evo_task_opts *o, evo_task *t,
		       evo_err *err);

void evo_task_free(evo_task *t);

#endif

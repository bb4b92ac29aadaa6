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
} evo_task;

/* Parse path, check the keys its TYPE needs, load its mind folder.
 * Warnings (unknown keys) go to stderr. Returns 0, or -1 with err set. */
int evo_task_load(const char *path, evo_task *t, evo_err *err);

void evo_task_free(evo_task *t);

#endif

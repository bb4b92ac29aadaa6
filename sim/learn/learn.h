/* evo — LEARNSIM: train a task's LEARNINGSKILL inside its hierarchy.
 * The loop is Lua (lua/learn/learnsim.lua), the evaluation C on worker
 * threads (sim/learn/evaluate.h). docs/learning.md. */
#ifndef EVO_LEARN_H
#define EVO_LEARN_H

#include <stdint.h>

#include "base/err.h"
#include "learn/evaluate.h"
#include "learn/learn_opts.h"
#include "mind/task.h"

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

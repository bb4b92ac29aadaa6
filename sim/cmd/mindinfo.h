/* evo — what `evo info`, `evo tick` and `evo check` say of a mind beyond a
 * trained mind folder: an exported mind image (.bin) on its own, and a
 * hierarchy whose neural skills are not all trained yet; and which task
 * types `evo run` runs, which `evo check` asks first. */
#ifndef EVO_MINDINFO_H
#define EVO_MINDINFO_H

#include <stddef.h>
#include <stdio.h>

#include "base/err.h"
#include "evo/mind.h"
#include "mind/mindfolder.h"
#include "mind/task.h"

/* A path that names a mind image file (.bin, any case). */
int evo_is_image_path(const char *path);

/* Read and open the mind image at path with the names hash it carries:
 * *buf (free it) holds it, m views it. 0 or -1 with err ("path: why"). */
int evo_image_load(const char *path, void **buf, evo_mind *m, evo_err *err);

/* evo info of an image: counts, then each skill in tick order with its
 * kind, inputs and outputs, network size and sub-skills, from the image's
 * own name table. */
void evo_image_info(const char *path, const evo_mind *m);

/* 1 when `evo run` runs tasks of this TYPE (DEMOSIM, LEARNSIM,
 * DEMOREMOTESIM, DEMOREMOTE), which `evo check` also asks. */
int evo_run_supports(const char *type);

/* What `evo check` adds to loading the task: a type `evo run` runs; for
 * LEARNSIM the learning options; and, where the task runs in the 2D
 * world, the scene built as `evo run` builds it, so that a misspelled
 * BOTMODEL, ENV or botdesc sensor name fails here. 0 or -1 with err. */
int evo_task_check(const char *path, evo_task *task, evo_err *err);

/* The neural skills of l that have no network yet (l->untrained): none
 * prints nothing and returns 0; else says which, the bottom-up order to
 * train the hierarchy in, and for each such skill a task of the mind
 * folder's Tasks/ that trains it (LEARNINGSKILL) and passes evo check
 * (SKILL-NEAT first, then the fewest warnings), or that none does, and
 * returns their number. */
int evo_untrained_report(const evo_mindfolder *l, FILE *f);

/* The number of neural skills of l with no network yet. */
int evo_untrained_count(const evo_mindfolder *l);

#endif

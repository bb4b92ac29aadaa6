/* `evo run TASK.simbatch`: run a task. DEMOSIM shows the task's
 * environment in the viewer in real time, or with --headless / -nog runs
 * it as fast as it can and prints each episode's reward. docs/running.md. */
#ifndef EVO_RUN_H
#define EVO_RUN_H

#include <stdio.h>

/* argv[1] is "run". Returns the process exit status. */
int evo_run_main(int argc, char **argv);

/* What `evo run --help` prints. */
void evo_run_usage(FILE *f);

#endif

/* `evo serve TASK.simbatch`: the task's 2D world served as a remote
 * simulator over LCM, for an `evo run` of a remote task to drive
 * (docs/remote.md). Runs until SIGINT or SIGTERM. */
#ifndef EVO_SERVE_H
#define EVO_SERVE_H

#include <stdio.h>

/* Environments one `evo serve` runs at most. */
#define EVO_REMOTE_SERVE_MAX_ENVS 64

/* argv[1] is "serve". Returns the process exit status. */
int evo_serve_main(int argc, char **argv);

/* What `evo serve --help` prints. */
void evo_serve_usage(FILE *f);

#endif

/* The tests' `evo serve`: started in the background and waited for,
 * stopped with SIGTERM, and the episode lines of a run in a form a
 * remote run's and a local one's compare in. */
#ifndef EVO_TEST_SERVE_H
#define EVO_TEST_SERVE_H

#include <stddef.h>
#include <sys/types.h>

/* `evo serve TASK OPTS`, its output in the file LOG, started and ready
 * (its " serves " line printed; at most 30 s). */
pid_t cli_serve_start(const char *task, const char *opts, const char *log);

/* SIGTERM (SIGKILL after 10 s); the exit status (-1: it did not exit, a
 * crash), and how long it took in *secs. */
int cli_serve_stop(pid_t pid, double *secs);

/* The episode lines of text up to their tick counts, one a line, into
 * lines: without what a local run adds after the ticks (collision
 * counts) or a remote one (the behaviour), so that the two compare. */
void cli_episode_lines(const char *text, char *lines, size_t cap);

#endif

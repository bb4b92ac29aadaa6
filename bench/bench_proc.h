/* What the benchmarks share to time work and run evo: a monotonic clock
 * and a shell command's exit status. */
#ifndef EVO_BENCH_PROC_H
#define EVO_BENCH_PROC_H

#include <stdlib.h>
#include <sys/wait.h>
#include <time.h>

/* Seconds on the monotonic clock. */
static inline double bench_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Runs cmd with the shell: its exit status, or -1 when it did not exit. */
static inline int bench_sh(const char *cmd)
{
	int st = system(cmd);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

#endif

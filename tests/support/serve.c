/* The tests' `evo serve` (tests/support/serve.h). */
#define _POSIX_C_SOURCE 200809L
#include "support/serve.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "support/cli.h"

static double mono(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

pid_t cli_serve_start(const char *task, const char *opts, const char *log)
{
	char cmd[4096];
	unlink(log);
	snprintf(cmd, sizeof cmd, "exec %s serve %s %s >%s 2>&1", cli_evo,
		 task, opts, log);
	pid_t pid = fork();
	if (pid == 0) {
		signal(SIGINT, SIG_DFL);
		signal(SIGTERM, SIG_DFL);
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	double limit = mono() + 30;
	for (;;) {
		char *t = cli_read("%s", log);
		int ready = t && strstr(t, " serves ");
		free(t);
		if (ready || mono() > limit)
			break;
		struct timespec ms = {0, 5000000};
		nanosleep(&ms, NULL);
	}
	return pid;
}

int cli_serve_stop(pid_t pid, double *secs)
{
	double t0 = mono();
	kill(pid, SIGTERM);
	int st = 0;
	while (waitpid(pid, &st, WNOHANG) != pid) {
		if (mono() - t0 > 10) {
			kill(pid, SIGKILL);
			waitpid(pid, &st, 0);
			break;
		}
		struct timespec ms = {0, 2000000};
		nanosleep(&ms, NULL);
	}
	*secs = mono() - t0;
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

void cli_episode_lines(const char *text, char *lines, size_t cap)
{
	size_t k = 0;
	lines[0] = 0;
	/* episode lines only: a drop's sentence says "of episode 2" too */
	for (const char *p = strncmp(text, "episode ", 8) == 0
				 ? text
				 : strstr(text, "\nepisode ");
	     p; p = strstr(p + 1, "\nepisode ")) {
		if (*p == '\n')
			p++;
		const char *end = strstr(p, " ticks");
		if (!end || k + (size_t)(end - p) + 8 >= cap)
			break;
		k += (size_t)snprintf(lines + k, cap - k, "%.*s ticks\n",
				      (int)(end - p), p);
	}
}

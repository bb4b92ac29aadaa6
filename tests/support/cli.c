/* Helpers for tests that drive the evo program (tests/support/cli.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "base/fileio.h"

char cli_evo[256];
char cli_tmp[128];

const char *cli_tmp_root(void)
{
	const char *t = getenv("TMPDIR");
	return t && t[0] ? t : "/tmp";
}

int cli_setup(const char *name)
{
	const char *b = getenv("EVO_BUILD");
	snprintf(cli_evo, sizeof cli_evo, "%s/evo", b && b[0] ? b : "build");
	int n = snprintf(cli_tmp, sizeof cli_tmp, "%s/evo-test-%s-XXXXXX",
			 cli_tmp_root(), name);
	if (n < 0 || (size_t)n >= sizeof cli_tmp) {
		printf("TMPDIR %s: too long for the tests' folders\n",
		       cli_tmp_root());
		cli_tmp[0] = 0;
		return -1;
	}
	if (!mkdtemp(cli_tmp)) {
		perror("mkdtemp");
		return -1;
	}
	return 0;
}

void cli_cleanup(void)
{
	if (cli_tmp[0] && cli_sh("rm -rf %s", cli_tmp) != 0)
		printf("could not remove %s\n", cli_tmp);
}

static int status_of(int st)
{
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

int cli_sh(const char *fmt, ...)
{
	char cmd[4096];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(cmd, sizeof cmd, fmt, ap);
	va_end(ap);
	return status_of(system(cmd));
}

int cli_capture(char *out, size_t cap, const char *fmt, ...)
{
	char cmd[4096];
	va_list ap;
	va_start(ap, fmt);
	int n = vsnprintf(cmd, sizeof cmd - 8, fmt, ap);
	va_end(ap);
	if (n < 0 || (size_t)n >= sizeof cmd - 8)
		return -1;
	strcat(cmd, " 2>&1");
	FILE *p = popen(cmd, "r");
	if (!p)
		return -1;
	size_t got = fread(out, 1, cap - 1, p);
	out[got] = 0;
	return status_of(pclose(p));
}

char *cli_read(const char *fmt, ...)
{
	char path[1024], *data;
	size_t len;
	evo_err err;
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(path, sizeof path, fmt, ap);
	va_end(ap);
	return evo_read_file(path, &data, &len, &err) ? NULL : data;
}

int cli_write(const char *text, const char *fmt, ...)
{
	char path[1024];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(path, sizeof path, fmt, ap);
	va_end(ap);
	FILE *f = fopen(path, "w");
	if (!f) {
		perror(path);
		return -1;
	}
	int ok = fputs(text, f) >= 0;
	return fclose(f) == 0 && ok ? 0 : -1;
}

int cli_count_lines(const char *text, const char *prefix)
{
	int n = 0;
	size_t len = strlen(prefix);
	for (const char *l = text; l && *l;) {
		n += strncmp(l, prefix, len) == 0;
		l = strchr(l, '\n');
		l = l ? l + 1 : NULL;
	}
	return n;
}

char *cli_fitness_log(const char *run_dir)
{
	char *data = cli_read("%s/log.csv", run_dir);
	if (!data)
		return NULL;
	char *w = data;
	for (char *line = data; *line;) {
		char *end = strchr(line, '\n');
		size_t n = end ? (size_t)(end - line) : strlen(line);
		/* generation .. solved, up to the 7th comma; then skip seconds
		 * and elapsed, and keep the environment's metrics after them */
		size_t keep = 0, skip;
		int commas = 0;
		while (keep < n && commas < 7)
			commas += line[keep++] == ',';
		for (skip = keep; skip < n && commas < 9; skip++)
			commas += line[skip] == ',';
		memmove(w, line, keep);
		w += keep;
		if (commas == 9) {
			memmove(w, line + skip, n - skip);
			w += n - skip;
		}
		*w++ = '\n';
		line += n + (end ? 1 : 0);
	}
	*w = 0;
	return data;
}

static double mono(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int has_mark(const char *path, const char *mark)
{
	char *t = cli_read("%s", path);
	int yes = t && strstr(t, mark);
	free(t);
	return yes;
}

int cli_stop(const char *cmd, const char *ready, const char *mark,
	     double delay, int sig, int *status, double *seconds)
{
	*status = 0;
	*seconds = -1;
	pid_t pid = fork();
	if (pid < 0)
		return -1;
	if (pid == 0) {
		/* Even if this test itself runs in the background. */
		signal(SIGINT, SIG_DFL);
		signal(SIGTERM, SIG_DFL);
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	struct timespec ms = {0, 1000000};
	int ended = 0;
	double limit = mono() + 60;
	while (!has_mark(ready, mark) && mono() < limit &&
	       !(ended = waitpid(pid, status, WNOHANG) == pid))
		nanosleep(&ms, NULL);
	limit = mono() + delay;
	while (!ended && mono() < limit &&
	       !(ended = waitpid(pid, status, WNOHANG) == pid))
		nanosleep(&ms, NULL);
	if (ended)
		return -1;
	double t0 = mono();
	kill(pid, sig);
	limit = t0 + 10;
	while (!(ended = waitpid(pid, status, WNOHANG) == pid) &&
	       mono() < limit)
		nanosleep(&ms, NULL);
	*seconds = mono() - t0;
	if (!ended) {
		kill(pid, SIGKILL);
		waitpid(pid, status, 0);
		return -1;
	}
	return 0;
}

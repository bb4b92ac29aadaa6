/* LEARNSIM end to end (sim/learn.c, lua/learn/learnsim.lua): the same
 * seed gives the same log with one thread and with two; a run killed with
 * SIGKILL in the middle of a generation and resumed ends with the same log
 * and champion as a run never interrupted; the champion lands in the
 * skill's folder with a learning curve in the run folder. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "fileio.h"
#include "harness.h"

static char evo_bin[256];
static char tmpdir[128];

static int sh(const char *cmd)
{
	int st = system(cmd);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* A copy of the Avoid example with a small LEARNSIM task, so training
 * never touches minds/ and runs in seconds. */
static void make_mind(const char *name)
{
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "mkdir -p %s/%s && cp -r minds/Avoid %s/%s/ && "
		 "printf 'TYPE:LEARNSIM\\nBOTMODEL:BotType8\\nMASTERSKILL:Avoid\\n"
		 "LEARNINGSKILL:Avoid\\nENV:EXP_Avoid\\nLEARNINGMETHOD:NEAT\\n"
		 "NUMGEN:%d\\nEVALREP:2\\nTICKLIM:150\\nNEAT_POPSIZE:24\\n' "
		 "> %s/%s/Avoid/Tasks/Small.simbatch",
		 tmpdir, name, tmpdir, name, 6, tmpdir, name);
	CHECK_EQ_INT(sh(cmd), 0);
}

/* The log without its two time columns. */
static char *fitness_log(const char *run)
{
	char path[512], *data;
	size_t len;
	evo_err err;
	snprintf(path, sizeof path, "%s/log.csv", run);
	if (evo_read_file(path, &data, &len, &err))
		return NULL;
	char *out = data, *w = data;
	for (char *line = data; *line;) {
		char *end = strchr(line, '\n');
		size_t n = end ? (size_t)(end - line) : strlen(line);
		/* keep up to the 6th comma */
		size_t keep = 0;
		int commas = 0;
		while (keep < n && commas < 6)
			commas += line[keep++] == ',';
		memmove(w, line, keep);
		w += keep;
		*w++ = '\n';
		line += n + (end ? 1 : 0);
	}
	*w = 0;
	return out;
}

static char *read_text(const char *path)
{
	char *data;
	size_t len;
	evo_err err;
	return evo_read_file(path, &data, &len, &err) ? NULL : data;
}

static int train(const char *name, const char *extra)
{
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "%s run %s/%s/Avoid/Tasks/Small.simbatch --seed 11 --run "
		 "%s/%s/run %s > %s/%s/out.txt 2>&1",
		 evo_bin, tmpdir, name, tmpdir, name, extra, tmpdir, name);
	return sh(cmd);
}

static char *log_of(const char *name)
{
	char run[256];
	snprintf(run, sizeof run, "%s/%s/run", tmpdir, name);
	return fitness_log(run);
}

static char *champion_of(const char *name)
{
	char path[256];
	snprintf(path, sizeof path, "%s/%s/Avoid/Skills/Avoid/Avoid.net",
		 tmpdir, name);
	return read_text(path);
}

TEST(one_thread_and_two_give_the_same_log)
{
	make_mind("t1");
	make_mind("t2");
	CHECK_EQ_INT(train("t1", "--threads 1"), 0);
	CHECK_EQ_INT(train("t2", "--threads 2"), 0);
	char *a = log_of("t1"), *b = log_of("t2");
	CHECK(a && b);
	if (a && b) {
		CHECK_CONTAINS(a, "\n5,");
		CHECK_EQ_STR(a, b);
	}
	char *ca = champion_of("t1"), *cb = champion_of("t2");
	CHECK(ca && cb);
	if (ca && cb) {
		CHECK_CONTAINS(ca, "trained by evo: NEAT, seed 11");
		CHECK_EQ_STR(ca, cb);
	}
	char png[256];
	snprintf(png, sizeof png, "%s/t1/run/curve.png", tmpdir);
	CHECK(evo_file_exists(png));
	snprintf(png, sizeof png, "%s/t1/run/best/gen-0005.net", tmpdir);
	CHECK(evo_file_exists(png));
	free(a);
	free(b);
	free(ca);
	free(cb);
}

/* Rows in the run's log.csv so far (header excluded). */
static int rows(const char *name)
{
	char path[256];
	snprintf(path, sizeof path, "%s/%s/run/log.csv", tmpdir, name);
	char *t = read_text(path);
	int n = -1;
	for (const char *p = t; p && *p; p++)
		n += *p == '\n';
	free(t);
	return n;
}

TEST(killed_and_resumed_run_ends_as_an_uninterrupted_one)
{
	make_mind("k");
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/k/Avoid/Tasks/Small.simbatch --seed 11 "
		 "--threads 2 --run %s/k/run > %s/k/out1.txt 2>&1",
		 evo_bin, tmpdir, tmpdir, tmpdir);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	/* Wait for generation 2 to be logged, then kill at once: the run is
	 * inside generation 3's evaluations (or just past them). */
	struct timespec ms = {0, 2000000};
	for (int i = 0; i < 20000 && rows("k") < 3; i++)
		nanosleep(&ms, NULL);
	CHECK(rows("k") >= 3);
	kill(pid, SIGKILL);
	int st;
	waitpid(pid, &st, 0);
	CHECK(WIFSIGNALED(st));
	int before = rows("k");
	CHECK(before < 6); /* it really was interrupted */
	CHECK_EQ_INT(train("k", "--threads 2 --resume"), 0);
	char *a = log_of("t2"), *b = log_of("k");
	CHECK(a && b);
	if (a && b)
		CHECK_EQ_STR(b, a);
	char *ca = champion_of("t2"), *cb = champion_of("k");
	CHECK(ca && cb);
	if (ca && cb)
		CHECK_EQ_STR(cb, ca);
	char out[256];
	snprintf(out, sizeof out, "%s/k/out.txt", tmpdir);
	char *text = read_text(out);
	CHECK(text && strstr(text, "resuming after generation"));
	free(text);
	free(a);
	free(b);
	free(ca);
	free(cb);
}

TEST(unknown_method_is_a_clear_error)
{
	make_mind("m");
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "sed -i 's/LEARNINGMETHOD:NEAT/LEARNINGMETHOD:BOGUS/' "
		 "%s/m/Avoid/Tasks/Small.simbatch",
		 tmpdir);
	CHECK_EQ_INT(sh(cmd), 0);
	CHECK_EQ_INT(train("m", ""), 1);
	char out[256];
	snprintf(out, sizeof out, "%s/m/out.txt", tmpdir);
	char *text = read_text(out);
	CHECK(text && strstr(text, "Small.simbatch:6: LEARNINGMETHOD must be NEAT, GENETIC or ANNEALING, found 'BOGUS'"));
	free(text);
}

int main(void)
{
	const char *b = getenv("EVO_BUILD");
	snprintf(evo_bin, sizeof evo_bin, "%s/evo", b && b[0] ? b : "build");
	snprintf(tmpdir, sizeof tmpdir, "/tmp/evo-test-learn-XXXXXX");
	if (!mkdtemp(tmpdir))
		return 1;
	RUN(one_thread_and_two_give_the_same_log);
	RUN(killed_and_resumed_run_ends_as_an_uninterrupted_one);
	RUN(unknown_method_is_a_clear_error);
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
	if (sh(cmd) != 0)
		printf("could not remove %s\n", tmpdir);
	return test_summary();
}

/* A learning run's folder, log and progress line (sim/learn/runlog.c). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/fileio.h"
#include "harness.h"
#include "learn/runlog.h"

static char dir[128];

static evo_gen_stats stats(int g)
{
	evo_gen_stats s = {
		.generation = g,
		.generations = 10,
		.best = 1.0 + g,
		.mean = 0.5 * g,
		.best_ever = 1.0 + g,
		.species = 3,
		.evaluations = 150,
		.seconds = 0.5,
		.elapsed = 0.5 * (g + 1),
	};
	return s;
}

static char *read_log(void)
{
	char path[256], *data = NULL;
	size_t len;
	evo_err err;
	snprintf(path, sizeof path, "%s/run/log.csv", dir);
	if (evo_read_file(path, &data, &len, &err))
		return NULL;
	return data;
}

TEST(log_has_a_row_per_generation_with_exact_values)
{
	char run[256];
	snprintf(run, sizeof run, "%s/run", dir);
	evo_runlog log;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_runlog_open(&log, run, 0, &err), 0);
	for (int g = 0; g < 4; g++) {
		evo_gen_stats s = stats(g);
		s.best = 0.1 * g; /* not exact in binary */
		CHECK_EQ_INT(evo_runlog_add(&log, &s, &err), 0);
	}
	evo_runlog_close(&log);
	char *text = read_log();
	CHECK(text != NULL);
	if (!text)
		return;
	CHECK(strncmp(text, "generation,best,mean", 20) == 0);
	CHECK_CONTAINS(text, "\n3,0.30000000000000004,1.5,");
	int rows = 0;
	for (const char *p = text; *p; p++)
		rows += *p == '\n';
	CHECK_EQ_INT(rows, 5);
	free(text);
}

/* Resuming from generation 2 keeps rows 0 and 1 and drops the rest; the
 * new rows' elapsed time adds to theirs. */
TEST(resume_keeps_rows_before_the_checkpoint)
{
	char run[256];
	snprintf(run, sizeof run, "%s/run", dir);
	evo_runlog log;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_runlog_open(&log, run, 2, &err), 0);
	evo_gen_stats s = stats(2);
	CHECK_EQ_INT(evo_runlog_add(&log, &s, &err), 0);
	evo_runlog_close(&log);
	char *text = read_log();
	CHECK(text != NULL);
	if (!text)
		return;
	CHECK_CONTAINS(text, "\n0,");
	CHECK_CONTAINS(text, "\n1,");
	CHECK_CONTAINS(text, "\n2,3,1,3,3,150,");
	CHECK(strstr(text, "\n3,") == NULL);
	/* the elapsed column goes on from the last row kept (1.0 s) with
	 * this process's 1.5 s, instead of starting again */
	CHECK_CONTAINS(text, "\n2,3,1,3,3,150,0,0.500,2.500\n");
	free(text);
}

TEST(files_are_saved_whole)
{
	char run[256], path[300];
	snprintf(run, sizeof run, "%s/run", dir);
	evo_runlog log;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_runlog_open(&log, run, 0, &err), 0);
	CHECK_EQ_INT(evo_runlog_save(&log, "best/gen-0000.net", "inputs:1\n", 9,
				     &err),
		     0);
	snprintf(path, sizeof path, "%s/best/gen-0000.net", run);
	CHECK(evo_file_exists(path));
	evo_runlog_close(&log);
	CHECK_EQ_INT(evo_runlog_open(&log, "/proc/no/such/run", 0, &err), -1);
	CHECK_CONTAINS(err.msg, "cannot create");
	evo_runlog_close(&log);
}

/* A fresh run's claim: the folder is created and locked; an earlier
 * run's files move whole to the first free .N, the lock stays; a folder
 * that holds no run is left as it is. (Two processes and the lock:
 * tests/sim/learn/test_learn.c.) */
TEST(claim_locks_and_an_earlier_run_moves_aside)
{
	char run[256], path[400];
	snprintf(run, sizeof run, "%s/claimed", dir);
	evo_err err = {{0}};
	int fd = evo_runlog_claim(run, &err);
	CHECK(fd >= 0);
	snprintf(path, sizeof path, "%s/.lock", run);
	CHECK(evo_file_exists(path));
	/* nothing to move yet */
	CHECK_EQ_INT(evo_runlog_set_aside(run, &err), 0);
	snprintf(path, sizeof path, "%s.1", run);
	CHECK(!evo_file_exists(path));
	/* an earlier run, and a .1 already taken by another */
	evo_runlog log;
	CHECK_EQ_INT(evo_runlog_open(&log, run, 0, &err), 0);
	evo_gen_stats s = stats(0);
	CHECK_EQ_INT(evo_runlog_add(&log, &s, &err), 0);
	CHECK_EQ_INT(evo_runlog_save(&log, "best/gen-0000.net", "inputs:1\n",
				     9, &err),
		     0);
	evo_runlog_close(&log);
	snprintf(path, sizeof path, "%s.1", run);
	CHECK_EQ_INT(mkdir(path, 0755), 0);
	CHECK_EQ_INT(evo_runlog_set_aside(run, &err), 0);
	CHECK_EQ_STR(err.msg, "");
	snprintf(path, sizeof path, "%s.2/log.csv", run);
	CHECK(evo_file_exists(path));
	snprintf(path, sizeof path, "%s.2/best/gen-0000.net", run);
	CHECK(evo_file_exists(path));
	snprintf(path, sizeof path, "%s.2/.lock", run);
	CHECK(!evo_file_exists(path));
	snprintf(path, sizeof path, "%s/log.csv", run);
	CHECK(!evo_file_exists(path));
	snprintf(path, sizeof path, "%s/best", run);
	CHECK(!evo_file_exists(path));
	snprintf(path, sizeof path, "%s/.lock", run);
	CHECK(evo_file_exists(path));
	if (fd >= 0)
		close(fd);
	CHECK_EQ_INT(evo_runlog_claim("/proc/no/such/run", &err), -1);
	CHECK_CONTAINS(err.msg, "cannot create");
}

TEST(progress_line_on_a_terminal_and_off)
{
	char buf[256];
	evo_gen_stats s = stats(4);
	evo_progress_format(buf, sizeof buf, &s, 0);
	CHECK_EQ_STR(buf, "gen 4/10  best 5  mean 2  species 3  300 eval/s  "
			  "elapsed 0:03  ETA 0:03");
	evo_progress_format(buf, sizeof buf, &s, 1);
	CHECK(strncmp(buf, "[##########..........] gen 4/10", 31) == 0);
	/* Resumed after generation 3: one generation in 2.5 s, five to go. */
	s.first = 4;
	evo_progress_format(buf, sizeof buf, &s, 0);
	CHECK_CONTAINS(buf, "elapsed 0:03  ETA 0:13");
	s.first = 0;
	/* Solvers show. */
	s.solved = 2;
	evo_progress_format(buf, sizeof buf, &s, 0);
	CHECK_CONTAINS(buf, "species 3  solved 2  300 eval/s");
	s.solved = 0;
	s.generations = 0;
	s.species = 0;
	evo_progress_format(buf, sizeof buf, &s, 1);
	CHECK_EQ_STR(buf, "gen 4  best 5  mean 2  300 eval/s  elapsed 0:03  "
			  "ETA -");
}

int main(void)
{
	snprintf(dir, sizeof dir, "/tmp/evo-runlog-XXXXXX");
	if (!mkdtemp(dir))
		return 1;
	RUN(log_has_a_row_per_generation_with_exact_values);
	RUN(resume_keeps_rows_before_the_checkpoint);
	RUN(files_are_saved_whole);
	RUN(claim_locks_and_an_earlier_run_moves_aside);
	RUN(progress_line_on_a_terminal_and_off);
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
	if (system(cmd) != 0)
		printf("could not remove %s\n", dir);
	return test_summary();
}

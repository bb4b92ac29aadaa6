/* A learning run's folder, log and progress line (sim/learn/runlog.c); a
 * run folder that came with a shared mind folder writes through no link
 * it ships, and a log row that does not start with its generation is
 * refused at its line. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/fileio.h"
#include "harness.h"
#include "support/cli.h"
#include "support/alloc_fail.h"
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
	CHECK_EQ_INT(evo_runlog_open(&log, run, 0, NULL, 0, &err), 0);
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
	CHECK_EQ_INT(evo_runlog_open(&log, run, 2, NULL, 0, &err), 0);
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

/* After its first row a process appends each row to log.csv instead of
 * recreating the file (the same file from row to row); a row a killed
 * run left half written, without its newline, is dropped on --resume. */
TEST(rows_are_appended_and_a_half_row_is_dropped_on_resume)
{
	char run[256], path[300];
	snprintf(run, sizeof run, "%s/run", dir);
	snprintf(path, sizeof path, "%s/log.csv", run);
	FILE *f = fopen(path, "a");
	CHECK(f != NULL);
	if (!f)
		return;
	fputs("3,4,1.5,4,3,15", f); /* killed in the middle of row 3 */
	fclose(f);
	evo_runlog log;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_runlog_open(&log, run, 3, NULL, 0, &err), 0);
	struct stat st[3];
	for (int g = 3; g < 6; g++) {
		evo_gen_stats s = stats(g);
		CHECK_EQ_INT(evo_runlog_add(&log, &s, &err), 0);
		CHECK_EQ_INT(stat(path, &st[g - 3]), 0);
	}
	evo_runlog_close(&log);
	CHECK(st[1].st_ino == st[0].st_ino && st[2].st_ino == st[0].st_ino);
	char *text = read_log();
	CHECK(text != NULL);
	if (!text)
		return;
	int rows = 0;
	for (const char *p = text; *p; p++)
		rows += *p == '\n';
	CHECK_EQ_INT(rows, 7); /* the header and generations 0 to 5 */
	CHECK_CONTAINS(text, "\n2,3,1,3,3,150,0,0.500,2.500\n3,4,1.5,4,3,150,");
	CHECK_CONTAINS(text, "\n5,6,2.5,6,3,150,");
	free(text);
}

TEST(files_are_saved_whole)
{
	char run[256], path[300];
	snprintf(run, sizeof run, "%s/run", dir);
	evo_runlog log;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_runlog_open(&log, run, 0, NULL, 0, &err), 0);
	CHECK_EQ_INT(evo_runlog_save(&log, "best/gen-0000.net", "inputs:1\n", 9,
				     &err),
		     0);
	snprintf(path, sizeof path, "%s/best/gen-0000.net", run);
	CHECK(evo_file_exists(path));
	evo_runlog_close(&log);
	CHECK_EQ_INT(evo_runlog_open(&log, "/proc/no/such/run", 0, NULL, 0, &err), -1);
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
	CHECK_EQ_INT(evo_runlog_open(&log, run, 0, NULL, 0, &err), 0);
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

/* A log of the metered run so far, and its header line. */
static char *read_metered(void)
{
	char path[256], *data = NULL;
	size_t len;
	evo_err err;
	snprintf(path, sizeof path, "%s/metered/log.csv", dir);
	if (evo_read_file(path, &data, &len, &err))
		return NULL;
	return data;
}

TEST(metric_columns_follow_the_others)
{
	char run[256];
	snprintf(run, sizeof run, "%s/metered", dir);
	const char *names[] = {"in_zone", "delivered"};
	evo_runlog log;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_runlog_open(&log, run, 0, names, 2, &err), 0);
	for (int g = 0; g < 3; g++) {
		evo_gen_stats s = stats(g);
		double m[2] = {30 + g, 0.1 * g};
		s.metrics = m;
		CHECK_EQ_INT(evo_runlog_add(&log, &s, &err), 0);
	}
	/* a row without them is refused */
	evo_gen_stats s = stats(3);
	CHECK_EQ_INT(evo_runlog_add(&log, &s, &err), -1);
	CHECK_CONTAINS(err.msg, "a log row without its 2 metrics");
	evo_runlog_close(&log);
	char *text = read_metered();
	CHECK(text != NULL);
	if (!text)
		return;
	CHECK(strncmp(text,
		      "generation,best,mean,best_ever,species,evaluations,"
		      "solved,seconds,elapsed,metric:in_zone,metric:delivered\n"
		      "0,1,0,1,3,150,0,0.500,0.500,30,0\n"
		      "1,2,0.5,2,3,150,0,0.500,1.000,31,0.10000000000000001\n"
		      "2,3,1,3,3,150,0,0.500,1.500,32,0.20000000000000001\n",
		      400) == 0);
	free(text);
}

/* Resuming from generation 2 with a metric gone (delivered) and one new
 * (travelled): every earlier column stays, the new one comes last, empty
 * in the rows kept; the gone one is empty in the new rows; a warning says
 * each. elapsed is found among the columns, not taken as the last. */
TEST(resume_keeps_every_metric_column)
{
	char run[256], errs[256];
	snprintf(run, sizeof run, "%s/metered", dir);
	snprintf(errs, sizeof errs, "%s/stderr.txt", dir);
	const char *names[] = {"travelled", "in_zone"};
	evo_runlog log;
	evo_err err = {{0}};
	fflush(stderr);
	int saved = dup(2);
	CHECK(freopen(errs, "w", stderr) != NULL);
	int rc = evo_runlog_open(&log, run, 2, names, 2, &err);
	fflush(stderr);
	dup2(saved, 2);
	close(saved);
	CHECK_EQ_INT(rc, 0);
	evo_gen_stats s = stats(2);
	double m[2] = {7.25, 44};
	s.metrics = m;
	CHECK_EQ_INT(evo_runlog_add(&log, &s, &err), 0);
	evo_runlog_close(&log);
	char *text = read_metered();
	CHECK(text != NULL);
	if (text)
		CHECK_EQ_STR(text,
			     "generation,best,mean,best_ever,species,"
			     "evaluations,solved,seconds,elapsed,"
			     "metric:in_zone,metric:delivered,"
			     "metric:travelled\n"
			     "0,1,0,1,3,150,0,0.500,0.500,30,0,\n"
			     "1,2,0.5,2,3,150,0,0.500,1.000,31,"
			     "0.10000000000000001,\n"
			     "2,3,1,3,3,150,0,0.500,2.500,44,,7.25\n");
	free(text);
	char path[256], *said = NULL;
	size_t len;
	snprintf(path, sizeof path, "%s", errs);
	CHECK_EQ_INT(evo_read_file(path, &said, &len, &err), 0);
	if (said) {
		CHECK_CONTAINS(said, "metered/log.csv: warning: the environment "
				     "now reports metric:travelled, which the "
				     "earlier rows lack: their cells are left "
				     "empty\n");
		CHECK_CONTAINS(said, "metered/log.csv: warning: the environment "
				     "no longer reports metric:delivered: its "
				     "cells in the new rows are left empty\n");
	}
	free(said);
	/* The same metrics again: nothing to say, the log as it was. */
	const char *same[] = {"in_zone", "delivered", "travelled"};
	CHECK_EQ_INT(evo_runlog_open(&log, run, 3, same, 3, &err), 0);
	evo_runlog_close(&log);
	/* evo_runlog_open keeps the text in memory; the next add saves it */
	CHECK_EQ_INT(evo_runlog_open(&log, run, 3, same, 3, &err), 0);
	CHECK_EQ_INT(log.n_columns, 3);
	CHECK_EQ_INT(log.column_metric[2], 2);
	CHECK_CONTAINS(log.csv, "2,3,1,3,3,150,0,0.500,2.500,44,,7.25\n");
	CHECK(log.elapsed_before == 2.5);
	evo_runlog_close(&log);
}

/* Moving an earlier run aside copies each of its file names; when memory
 * runs out there, the run is refused with a message and the earlier run
 * stays where it was, whole. */
TEST(out_of_memory_while_moving_aside_keeps_the_earlier_run)
{
	char run[256], path[400];
	snprintf(run, sizeof run, "%s/oom", dir);
	evo_err err = {{0}};
	int fd = evo_runlog_claim(run, &err);
	CHECK(fd >= 0);
	evo_runlog log;
	CHECK_EQ_INT(evo_runlog_open(&log, run, 0, NULL, 0, &err), 0);
	evo_gen_stats s = stats(0);
	CHECK_EQ_INT(evo_runlog_add(&log, &s, &err), 0);
	CHECK_EQ_INT(evo_runlog_save(&log, "best/gen-0000.net", "inputs:1\n",
				     9, &err),
		     0);
	evo_runlog_close(&log);
	for (int nth = 1; nth <= 2; nth++) {
		alloc_fail_strdup(nth);
		CHECK_EQ_INT(evo_runlog_set_aside(run, &err), -1);
		alloc_fail_strdup(0);
		CHECK_EQ_STR(err.msg, "out of memory");
		snprintf(path, sizeof path, "%s/log.csv", run);
		CHECK(evo_file_exists(path));
		snprintf(path, sizeof path, "%s/best/gen-0000.net", run);
		CHECK(evo_file_exists(path));
		snprintf(path, sizeof path, "%s.1", run);
		CHECK(!evo_file_exists(path));
	}
	if (fd >= 0)
		close(fd);
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
	/* The method's own figures (MAP-Elites's coverage) follow. */
	s.note = "coverage 0.0523  qd_score 257.1";
	evo_progress_format(buf, sizeof buf, &s, 0);
	CHECK_CONTAINS(buf, "species 3  coverage 0.0523  qd_score 257.1  300 "
			    "eval/s");
	s.note = NULL;
	/* a NaN is "nan", whatever its sign bit */
	s.mean = -NAN;
	evo_progress_format(buf, sizeof buf, &s, 0);
	CHECK_CONTAINS(buf, "best 5  mean nan  species");
	s.mean = 2;
	s.generations = 0;
	s.species = 0;
	evo_progress_format(buf, sizeof buf, &s, 1);
	CHECK_EQ_STR(buf, "gen 4  best 5  mean 2  300 eval/s  elapsed 0:03  "
			  "ETA -");
}

/* A mind folder's Runs/X ships .lock as a link to a file of the user's
 * that does not exist yet, and best as a link to a folder of the user's:
 * the claim makes .lock itself and creates nothing through the link; the
 * log is refused with best named, and nothing lands in the user's folder. */
TEST(a_run_folder_writes_through_no_link_it_ships)
{
	char run[256], path[400], victim[300], their[300];
	snprintf(run, sizeof run, "%s/shipped", dir);
	snprintf(victim, sizeof victim, "%s/made-through-lock", dir);
	snprintf(their, sizeof their, "%s/users-folder", dir);
	CHECK_EQ_INT(mkdir(run, 0755), 0);
	CHECK_EQ_INT(mkdir(their, 0755), 0);
	snprintf(path, sizeof path, "%s/.lock", run);
	CHECK_EQ_INT(symlink(victim, path), 0);
	evo_err err = {{0}};
	int fd = evo_runlog_claim(run, &err);
	CHECK(fd >= 0);
	CHECK_EQ_STR(err.msg, "");
	CHECK(access(victim, F_OK) != 0);
	struct stat st;
	CHECK(lstat(path, &st) == 0 && S_ISREG(st.st_mode));
	if (fd >= 0)
		close(fd);
	snprintf(path, sizeof path, "%s/best", run);
	CHECK_EQ_INT(symlink(their, path), 0);
	evo_runlog log;
	CHECK_EQ_INT(evo_runlog_open(&log, run, 0, NULL, 0, &err), -1);
	CHECK_CONTAINS(err.msg, path);
	CHECK_CONTAINS(err.msg, "is a symbolic link");
	evo_runlog_close(&log);
	snprintf(path, sizeof path, "%s/gen-0000.net", their);
	CHECK(access(path, F_OK) != 0);
}

/* --resume keeps the rows before the checkpoint by their generation: a
 * row that does not start with one ("x", "-1", 2^64, "1e3", "7abc") is
 * no row of evo's, and is refused at its line, not taken for
 * generation 0 or a wrapped-round one. */
TEST(a_log_row_without_its_generation_is_refused_at_its_line)
{
	static const char *const bad[] = {
	    "x,1,1,1,0,1,0,0.1,0.1",
	    "-1,1,1,1,0,1,0,0.1,0.1",
	    "18446744073709551617,1,1,1,0,1,0,0.1,0.1",
	    "1e3,1,1,1,0,1,0,0.1,0.1",
	    "7abc,1,1,1,0,1,0,0.1,0.1",
	    " 1,1,1,1,0,1,0,0.1,0.1",
	};
	char run[256], path[300];
	snprintf(run, sizeof run, "%s/damaged", dir);
	mkdir(run, 0755);
	snprintf(path, sizeof path, "%s/log.csv", run);
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		char text[400];
		snprintf(text, sizeof text,
			 "generation,best,mean,best_ever,species,evaluations,"
			 "solved,seconds,elapsed\n"
			 "0,1,1,1,0,1,0,0.1,0.1\n%s\n",
			 bad[k]);
		CHECK_EQ_INT(cli_write(text, "%s", path), 0);
		evo_runlog log;
		evo_err err = {{0}};
		CHECK_EQ_INT(evo_runlog_open(&log, run, 5, NULL, 0, &err), -1);
		char where[320];
		snprintf(where, sizeof where, "%s:3: expected a row", path);
		CHECK_CONTAINS(err.msg, where);
		CHECK_CONTAINS(err.msg, bad[k]);
		evo_runlog_close(&log);
	}
}

int main(void)
{
	snprintf(dir, sizeof dir, "%s/evo-runlog-XXXXXX", cli_tmp_root());
	if (!mkdtemp(dir))
		return 1;
	RUN(log_has_a_row_per_generation_with_exact_values);
	RUN(resume_keeps_rows_before_the_checkpoint);
	RUN(rows_are_appended_and_a_half_row_is_dropped_on_resume);
	RUN(files_are_saved_whole);
	RUN(claim_locks_and_an_earlier_run_moves_aside);
	RUN(metric_columns_follow_the_others);
	RUN(resume_keeps_every_metric_column);
	RUN(out_of_memory_while_moving_aside_keeps_the_earlier_run);
	RUN(progress_line_on_a_terminal_and_off);
	RUN(a_run_folder_writes_through_no_link_it_ships);
	RUN(a_log_row_without_its_generation_is_refused_at_its_line);
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
	if (system(cmd) != 0)
		printf("could not remove %s\n", dir);
	return test_summary();
}

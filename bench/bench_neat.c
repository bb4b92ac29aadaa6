/* make bench: NEAT on the literature tasks beside the NEAT paper's figures
 * (Stanley & Miikkulainen 2002, section 4):
 *
 *   XOR   100 runs: mean evaluations to solve 4,755, 0 failures;
 *   DPV   double pole with velocities: mean evaluations 3,600;
 *   DPNV  without velocities, 20 runs: mean evaluations 33,184, mean
 *         generalisation of the solutions 286 of 625.
 *
 * Each run is `evo run` on a fresh copy of the example task
 * (minds/XOR/Tasks/XOR-NEAT.simbatch, minds/DoublePole/Tasks/DPV-NEAT,
 * minds/DoublePoleNV/Tasks/DPNV-NEAT) with --seed s for s = 1 .. N, so
 * it is exactly what a user gets. A run stops in the generation where a
 * candidate solves the task (the log's `solved` column); its
 * evaluations are the sum of log.csv's evaluations column, and a run that
 * reaches NUMGEN unsolved is a failure. Means are over the solved runs.
 * DPNV's generalisation is that of each solved run's champion, recomputed
 * here from the saved network (sim/learn/literature.h).
 *
 * Bar (issue 4): at least as good as the paper on all three (means no
 * higher, no XOR failure, generalisation no lower); exit 1 otherwise.
 *
 * Speed (issue 28): XOR's runs are timed in CPU seconds of the processes
 * (getrusage of the children: evo from its start to its end, one thread,
 * --threads 1), and neat-python 2.0.0 (the build's venv, make deps) runs
 * its own XOR example (bench/neat_python_xor.py and .cfg: population 150,
 * solved at fitness 3.9) on the same seeds in the same run, timed the same
 * way. Both rates are evaluations per CPU second; the bar is evo at
 * 50,000 or more and at least 4 times neat-python's, else exit 1.
 *
 * The mean generalisation is printed with its standard error (the
 * standard deviation over the runs / sqrt(runs)): one run's figure varies
 * by about 50 starts, so a 20-run mean is only good to about ±11.
 *
 * usage: bench_neat [--seeds N] [--only xor|dpv|dpnv]
 *   --seeds N  N runs of each task (seeds 1 .. N); without it, the
 *              paper's counts: 100 for XOR and DPV, 20 for DPNV */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>

#include "bench_proc.h"
#include "base/fileio.h"
#include "base/number.h"
#include "learn/literature.h"

static char evo_bin[256];
static char venv[256];
static char tmpdir[128];

/* The speed bar: evaluations per CPU second of evo's XOR, and evo's over
 * neat-python's. */
#define SPEED_BAR 50000.0
#define SPEED_RATIO 4.0

/* CPU seconds (user and system) of the finished children so far. */
static double children_cpu(void)
{
	struct rusage ru;
	getrusage(RUSAGE_CHILDREN, &ru);
	return (double)ru.ru_utime.tv_sec + (double)ru.ru_utime.tv_usec * 1e-6 +
	       (double)ru.ru_stime.tv_sec + (double)ru.ru_stime.tv_usec * 1e-6;
}

typedef struct task {
	const char *name;   /* what the table says */
	const char *only;   /* --only's word */
	const char *mind;   /* folder under minds/ */
	const char *skill;  /* the learning skill */
	const char *file;   /* the task under Tasks/ */
	double paper_evals; /* the paper's mean evaluations */
	int paper_general;  /* DPNV: the paper's mean generalisation */
	int max_seeds;	    /* the paper's number of runs */
	int threads;	    /* evo's --threads, 0: its default */
} task;

static const task tasks[] = {
    {"XOR", "xor", "XOR", "XOR", "XOR-NEAT", 4755, 0, 100, 1},
    {"DPV (velocities)", "dpv", "DoublePole", "Balance", "DPV-NEAT", 3600, 0,
     100, 0},
    {"DPNV (no velocities)", "dpnv", "DoublePoleNV", "Balance", "DPNV-NEAT",
     33184, 286, 20, 0},
};

/* One run: 0 and *evals, *solved, *cpu (CPU seconds of the evo run), or
 * -1 when evo itself failed. */
static int run_once(const task *t, int seed, long *evals, int *solved,
		    int *general, double *cpu)
{
	char cmd[2048], threads[32] = "";
	snprintf(cmd, sizeof cmd,
		 "rm -rf %s/m %s/run && mkdir -p %s/m && cp -r minds/%s %s/m/",
		 tmpdir, tmpdir, tmpdir, t->mind, tmpdir);
	if (bench_sh(cmd) != 0) {
		fprintf(stderr, "bench_neat: could not copy minds/%s to %s\n",
			t->mind, tmpdir);
		return -1;
	}
	if (t->threads > 0)
		snprintf(threads, sizeof threads, " --threads %d", t->threads);
	/* exec: the time counted is evo's, from its start */
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/m/%s/Tasks/%s.simbatch --seed %d%s --run "
		 "%s/run > %s/out.txt 2>&1",
		 evo_bin, tmpdir, t->mind, t->file, seed, threads, tmpdir,
		 tmpdir);
	double c0 = children_cpu();
	int rc = bench_sh(cmd);
	*cpu = children_cpu() - c0;
	if (rc != 0) {
		fprintf(stderr,
			"bench_neat: %s seed %d: evo run failed; see "
			"%s/out.txt\n",
			t->name, seed, tmpdir);
		return -1;
	}
	char path[512], *data;
	size_t len;
	evo_err err;
	snprintf(path, sizeof path, "%s/run/log.csv", tmpdir);
	if (evo_read_file(path, &data, &len, &err)) {
		fprintf(stderr, "bench_neat: %s\n", err.msg);
		return -1;
	}
	/* generation,best,mean,best_ever,species,evaluations,solved,... */
	*evals = 0;
	*solved = 0;
	char *line = strchr(data, '\n'); /* skip the header */
	while (line && line[1]) {
		line++;
		double col[7];
		if (sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &col[0],
			   &col[1], &col[2], &col[3], &col[4], &col[5],
			   &col[6]) == 7) {
			*evals += (long)col[5];
			*solved = col[6] > 0;
		}
		line = strchr(line, '\n');
	}
	free(data);
	*general = -1;
	if (*solved && t->paper_general) {
		snprintf(path, sizeof path, "%s/m/%s/Skills/%s/%s.net", tmpdir,
			 t->mind, t->skill, t->skill);
		static evo_netdesc d;
		evo_diag diag;
		if (evo_read_file(path, &data, &len, &err)) {
			fprintf(stderr, "bench_neat: %s\n", err.msg);
			return -1;
		}
		evo_status st = evo_netdesc_parse(data, len, path, &d, &diag);
		free(data);
		if (st != EVO_OK) {
			fprintf(stderr, "bench_neat: %s\n", diag.msg);
			return -1;
		}
		*general = evo_lit_generalisation(&d, 0, &err);
	}
	return 0;
}

/* What a task's runs added up to: evaluations of all runs, solved or
 * not, and their CPU seconds. */
typedef struct totals {
	long evals;
	double cpu;
} totals;

/* Run a task over seeds 1 .. n and print its line; returns 1 when it
 * meets the paper's bar, 0 when not, -1 on an error. */
static int bench_task(const task *t, int n, totals *all)
{
	long sum = 0;
	int solved_runs = 0, failures = 0;
	double general_sum = 0, general_sq = 0;
	double t0 = bench_now();
	all->evals = 0;
	all->cpu = 0;
	for (int s = 1; s <= n; s++) {
		long evals;
		int solved, general;
		double cpu;
		if (run_once(t, s, &evals, &solved, &general, &cpu))
			return -1;
		all->evals += evals;
		all->cpu += cpu;
		if (solved) {
			solved_runs++;
			sum += evals;
			if (general >= 0) {
				general_sum += general;
				general_sq += (double)general * general;
			}
		} else {
			failures++;
		}
	}
	double secs = bench_now() - t0;
	double mean = solved_runs ? (double)sum / solved_runs : 0;
	printf("%-22s %3d runs  mean evaluations %9.0f (paper %6.0f)  "
	       "failures %3d",
	       t->name, n, mean, t->paper_evals, failures);
	int ok = solved_runs > 0 && mean <= t->paper_evals && failures == 0;
	if (t->paper_general) {
		double g = solved_runs ? general_sum / solved_runs : 0;
		double se = 0;
		if (solved_runs > 1) {
			double var = (general_sq - solved_runs * g * g) /
				     (solved_runs - 1);
			se = sqrt(var > 0 ? var : 0) / sqrt(solved_runs);
		}
		printf("  generalisation %5.1f/625 ±%.1f (paper %d)", g, se,
		       t->paper_general);
		ok = ok && g >= t->paper_general;
	}
	printf("  %.0f s  %s\n", secs, ok ? "ok" : "BELOW THE PAPER");
	fflush(stdout);
	return ok;
}

/* neat-python's XOR example on seeds 1 .. n: its evaluations, solved runs
 * and CPU seconds; 0, or -1 when it could not run. */
static int neat_python(int n, totals *all, int *solved_runs)
{
	all->evals = 0;
	all->cpu = 0;
	*solved_runs = 0;
	for (int s = 1; s <= n; s++) {
		char cmd[1024], path[512], *data;
		size_t len;
		evo_err err;
		snprintf(cmd, sizeof cmd,
			 "exec %s/bin/python bench/neat_python_xor.py "
			 "bench/neat_python_xor.cfg %d > %s/py.txt 2>&1",
			 venv, s, tmpdir);
		double c0 = children_cpu();
		int rc = bench_sh(cmd);
		all->cpu += children_cpu() - c0;
		snprintf(path, sizeof path, "%s/py.txt", tmpdir);
		if (rc != 0 || evo_read_file(path, &data, &len, &err)) {
			fprintf(stderr,
				"bench_neat: neat-python seed %d failed (make "
				"deps installs it in %s); see %s\n",
				s, venv, path);
			return -1;
		}
		long evals;
		int solved;
		int got = sscanf(data, "evaluations %ld solved %d", &evals,
				 &solved);
		free(data);
		if (got != 2) {
			fprintf(stderr, "bench_neat: neat-python seed %d: no "
					"result line in %s\n",
				s, path);
			return -1;
		}
		all->evals += evals;
		*solved_runs += solved;
	}
	return 0;
}

/* The speed lines: evo's XOR beside neat-python's on the same seeds;
 * returns 1 when evo meets the bar, 0 when not, -1 on an error. */
static int bench_speed(const totals *evo, int n)
{
	totals py;
	int py_solved;
	if (neat_python(n, &py, &py_solved))
		return -1;
	double r_evo = evo->cpu > 0 ? (double)evo->evals / evo->cpu : 0;
	double r_py = py.cpu > 0 ? (double)py.evals / py.cpu : 0;
	printf("XOR speed, %d runs, evaluations per CPU second of the "
	       "processes:\n",
	       n);
	printf("  evo (1 thread)        %9ld evaluations %7.2f s  %8.0f /s\n",
	       evo->evals, evo->cpu, r_evo);
	printf("  neat-python 2.0.0     %9ld evaluations %7.2f s  %8.0f /s  "
	       "(%d of %d solved)\n",
	       py.evals, py.cpu, r_py, py_solved, n);
	int ok = r_evo >= SPEED_BAR && r_evo >= SPEED_RATIO * r_py;
	printf("  evo / neat-python %.1f; bar: evo at least %.0f /s and "
	       "%.0f x neat-python  %s\n",
	       r_py > 0 ? r_evo / r_py : 0, SPEED_BAR, SPEED_RATIO,
	       ok ? "ok" : "BELOW THE BAR");
	fflush(stdout);
	return ok;
}

int main(int argc, char **argv)
{
	int seeds = 0, seeds_given = 0; /* not given: each task's paper count */
	const char *only = NULL;
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--seeds") == 0 && i + 1 < argc) {
			long long v;
			seeds = evo_parse_whole(argv[++i], NULL, 1, 100000, &v)
				    ? 0
				    : (int)v;
			seeds_given = 1;
		} else if (strcmp(argv[i], "--only") == 0 && i + 1 < argc)
			only = argv[++i];
		else {
			fprintf(stderr, "usage: bench_neat [--seeds N] "
					"[--only xor|dpv|dpnv]\n");
			return 2;
		}
	}
	if (seeds_given && seeds < 1) {
		fprintf(stderr, "bench_neat: --seeds wants a whole number "
				"from 1 to 100000\n");
		return 2;
	}
	const char *b = getenv("EVO_BUILD");
	snprintf(evo_bin, sizeof evo_bin, "%s/evo", b && b[0] ? b : "build");
	const char *v = getenv("EVO_VENV");
	snprintf(venv, sizeof venv, "%s", v && v[0] ? v : "build/venv");
	snprintf(tmpdir, sizeof tmpdir, "/tmp/evo-bench-neat-XXXXXX");
	if (!mkdtemp(tmpdir)) {
		perror("bench_neat: mkdtemp");
		return 1;
	}
	printf("NEAT on the literature tasks (Stanley & Miikkulainen 2002); "
	       "bar: the paper's figures\n");
	int rc = 0;
	for (size_t k = 0; k < sizeof tasks / sizeof tasks[0]; k++) {
		const task *t = &tasks[k];
		if (only && strcmp(only, t->only) != 0)
			continue;
		int n = seeds_given ? seeds : t->max_seeds;
		totals all;
		int ok = bench_task(t, n, &all);
		if (ok != 1)
			rc = 1;
		if (ok >= 0 && strcmp(t->only, "xor") == 0 &&
		    bench_speed(&all, n) != 1)
			rc = 1;
	}
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
	if (bench_sh(cmd) != 0)
		fprintf(stderr, "bench_neat: could not remove %s\n", tmpdir);
	return rc;
}

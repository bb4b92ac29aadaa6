/* make bench: cluster runs over Open MPI on this machine (docs/cluster.md),
 * each figure beside its baseline in the same run.
 *
 * 1. Efficiency of two ranks against one for evaluations of about 10 ms
 *    (the Avoid example, two episodes of at most TICKS ticks a candidate,
 *    POP candidates a generation): the evaluation seconds of a LEARNSIM
 *    run with `mpirun -np 1` (one thread) over twice those of `mpirun -np
 *    2` (one thread a rank), both runs of a round back to back, the
 *    median of the rounds' figures. Bar (issue 21): at least 0.9 on two
 *    cores. Beside it, in the same rounds, the efficiency of one rank of
 *    two threads against one thread: what the machine's cores give
 *    without any message.
 * 2. The dispatch rate: evaluations per second at `-np 4` (one thread a
 *    rank) of a batch of XOR networks, which cost a few microseconds
 *    each, so what is measured is the messages; beside it, `-np 1`'s
 *    rate, where no message is sent.
 *
 * Times are the log's per-generation evaluation seconds (log.csv's
 * `seconds`, the time evo.evaluate took), generation 0 left out (it
 * waits for the other ranks to load the task). evo is $EVO_BUILD/evo
 * (default build/evo). Runs as root (the OMPI_ALLOW_RUN_AS_ROOT
 * variables) and with more ranks than cores (--oversubscribe).
 *
 * usage: bench_cluster [--rounds N] */
#define _POSIX_C_SOURCE 200809L
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/number.h"

#define BAR	 0.9
#define TICKS	 1500
#define POP	 120
#define GENS	 5
#define XOR_POP	 10000
#define XOR_GENS 4

static char evo[256], tmp[64];

/* The median of v[0..n), sorted in place. */
static double median(double *v, int n)
{
	for (int i = 1; i < n; i++)
		for (int j = i; j > 0 && v[j - 1] > v[j]; j--) {
			double t = v[j];
			v[j] = v[j - 1];
			v[j - 1] = t;
		}
	return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

static int sh(const char *cmd)
{
	int rc = system(cmd);
	return rc == 0 ? 0 : -1;
}

/* Sum of the seconds column (the 8th) of run's log.csv, and of its
 * evaluations column (the 6th), over generations 1 on. */
static int log_times(const char *run, double *seconds, double *evals)
{
	char path[256], line[4096];
	snprintf(path, sizeof path, "%s/log.csv", run);
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	*seconds = *evals = 0;
	int rows = 0;
	while (fgets(line, sizeof line, f)) {
		long long gen;
		const char *end;
		if (evo_parse_whole(line, &end, 1, INT_MAX, &gen) ||
		    *end != ',')
			continue;
		char *col[10] = {0};
		int k = 0;
		for (char *p = strtok(line, ","); p && k < 10;
		     p = strtok(NULL, ","))
			col[k++] = p;
		if (k < 8)
			continue;
		*evals += atof(col[5]);
		*seconds += atof(col[7]);
		rows++;
	}
	fclose(f);
	return rows > 0 ? 0 : -1;
}

/* Train task `task` (a file in tmp) with np ranks of one thread; its
 * evaluation seconds and evaluations after generation 0. */
static int run(const char *mind, const char *task, int np, int threads,
	       int gens, double *seconds, double *evals)
{
	char cmd[2048], dir[160];
	snprintf(dir, sizeof dir, "%s/run-%s-%d-%d", tmp, task, np, threads);
	snprintf(
	    cmd, sizeof cmd,
	    "rm -rf %s && mpirun --oversubscribe --bind-to none -np %d %s run "
	    "%s/%s/Tasks/%s.simbatch --seed 3 --threads %d "
	    "--generations %d --run %s > %s.out 2>&1",
	    dir, np, evo, tmp, mind, task, threads, gens, dir, dir);
	if (sh(cmd)) {
		fprintf(stderr, "bench_cluster: failed: %s\n", cmd);
		return -1;
	}
	return log_times(dir, seconds, evals);
}

int main(int argc, char **argv)
{
	int rounds = 7;
	for (int i = 1; i < argc; i++) {
		long long n;
		if (strcmp(argv[i], "--rounds") == 0 && i + 1 < argc &&
		    evo_parse_whole(argv[i + 1], NULL, 1, 100, &n) == 0) {
			rounds = (int)n;
			i++;
		} else {
			fprintf(stderr, "usage: bench_cluster [--rounds N "
					"(1..100)]\n");
			return 2;
		}
	}
	const char *b = getenv("EVO_BUILD");
	snprintf(evo, sizeof evo, "%s/evo", b && b[0] ? b : "build");
	setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
	setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
	snprintf(tmp, sizeof tmp, "/tmp/evo-bench-cluster-XXXXXX");
	if (!mkdtemp(tmp)) {
		perror("bench_cluster: mkdtemp");
		return 1;
	}
	char cmd[1024];
	snprintf(
	    cmd, sizeof cmd,
	    "cp -r minds/Avoid minds/XOR %s/ && "
	    "printf 'TYPE:LEARNSIM\\nBOTMODEL:BotType8\\n"
	    "MASTERSKILL:Avoid\\nLEARNINGSKILL:Avoid\\nENV:EXP_Avoid\\n"
	    "LEARNINGMETHOD:NEAT\\nNUMGEN:%d\\nEVALREP:2\\nTICKLIM:%d\\n"
	    "NEAT_POPSIZE:%d\\n' > %s/Avoid/Tasks/Ten.simbatch && "
	    "printf "
	    "'TYPE:LEARNSIM\\nBOTMODEL:none\\nBOTNAME:XOR\\nMASTERSKILL:XOR\\n"
	    "LEARNINGSKILL:XOR\\nENV:XOR\\nLEARNINGMETHOD:NEAT\\n"
	    "NUMGEN:%d\\nNEAT_POPSIZE:%d\\n' > "
	    "%s/XOR/Tasks/Empty.simbatch",
	    tmp, GENS, TICKS, POP, tmp, XOR_GENS, XOR_POP, tmp);
	if (sh(cmd)) {
		fprintf(stderr, "bench_cluster: cannot set up %s\n", tmp);
		return 1;
	}
	printf("cluster runs over Open MPI, one thread a rank, %ld cores "
	       "online\n",
	       sysconf(_SC_NPROCESSORS_ONLN));
	/* Each round runs -np 1, -np 2 and one rank of two threads back to
	 * back, and gives their efficiencies; the figure is the median of
	 * the rounds'. On a shared virtual machine a rank's speed moves by
	 * a third from one minute to the next, so a best time of one
	 * configuration would be paired with a lucky minute of the other;
	 * runs close in time see the same machine. */
	double eff[64], efft[64], evals = 0, ms = 0;
	int rc = 0, done = 0;
	for (int r = 0; r < rounds && r < 64 && !rc; r++) {
		double s1, n1, s2, n2, st, nt;
		if (run("Avoid", "Ten", 1, 1, GENS, &s1, &n1) ||
		    run("Avoid", "Ten", 2, 1, GENS, &s2, &n2) ||
		    run("Avoid", "Ten", 1, 2, GENS, &st, &nt)) {
			rc = 1;
			break;
		}
		eff[done] = s1 / (2 * s2);
		efft[done] = s1 / (2 * st);
		evals = n1;
		ms += 1000 * s1 / n1;
		printf("  round %d: %.0f evaluations, -np 1 %.3f s, -np 2 "
		       "%.3f s (efficiency %.2f), one rank of two threads "
		       "%.3f s (%.2f)\n",
		       r + 1, n1, s1, s2, eff[done], st, efft[done]);
		done++;
	}
	if (!rc && done > 0) {
		double e = median(eff, done);
		printf("efficiency of -np 2 against -np 1, evaluations of "
		       "%.1f ms, %.0f a round: %.2f (median of %d rounds; bar "
		       "%.1f) %s\n"
		       "  beside it, one rank of two threads against one "
		       "thread: %.2f (what the machine's cores give, no "
		       "messages)\n",
		       ms / done, evals, e, done, BAR,
		       e >= BAR ? "ok" : "BELOW BAR", median(efft, done));
		if (e < BAR)
			rc = 1;
	}
	double s1, n1, s4, n4;
	if (run("XOR", "Empty", 1, 1, XOR_GENS, &s1, &n1) ||
	    run("XOR", "Empty", 4, 1, XOR_GENS, &s4, &n4)) {
		rc = 1;
	} else {
		printf("dispatch rate, XOR evaluations of %.1f us: -np 4 %.0f "
		       "evaluations/s (-np 1, no messages: %.0f "
		       "evaluations/s)\n",
		       1e6 * s1 / n1, n4 / s4, n1 / s1);
	}
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmp);
	if (sh(cmd))
		rc = 1;
	return rc;
}

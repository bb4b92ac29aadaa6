/* make bench: MAP-Elites in Kheperax's standard maze (issue 29,
 * acceptance 2 and 3), beside the QD libraries' figures measured on a
 * machine like this one (kheperax 0.2.0, qdax 0.4.1, ribs 0.12.0, CPU JAX;
 * the anchors).
 *
 * For each seed s = 1 .. N, each task trains a fresh copy of
 * minds/Kheperax with `evo run TASK --seed s --threads 2 --run DIR`,
 * exactly what a user gets:
 *
 *   100x100  Tasks/Kheperax-MAPELITES.simbatch as shipped: a 100 x 100
 *            grid over the final position, 375,000 evaluations. Printed:
 *            the coverage at 375,000 evaluations and the wall time to
 *            them, beside pyribs' novelty-search tutorial (46.0, 79.5,
 *            86.0 and 86.1 % in 226-246 s). Bar: >= 89 % in < 226 s.
 *   50x50    Tasks/Kheperax-MAPELITES-Ref.simbatch, Kheperax's reference
 *            configuration (50 x 50, batches of 2048, MLP 5-8-2, iso 0.2,
 *            line 0), with MAPELITES_TARGET_COVERAGE:0.89 added so it
 *            stops at 89 %. Printed: the evaluations and wall time to
 *            89 % and the QD-score there (offset -0.5, QDax's), beside
 *            QDax's 1,001,472 evaluations, 313 s and QD-score 975.5 (at
 *            89.0 %). Bar: fewer evaluations and less time than QDax.
 *   CMA-ME   the same reference task with MAPELITES_EMITTER:cmame, 16
 *            emitters of 128 (2,048 a batch, as the reference), sigma0
 *            0.2, printed beside it (no bar on it).
 *   NOVELTY  Tasks/Kheperax-NOVELTY.simbatch, for comparison in the
 *            100x100 table (no bar on it): novelty search over NEAT
 *            networks, 375,000 evaluations, its coverage that of the
 *            passive 100 x 100 result grid every evaluated robot marks
 *            (NOVELTY_COVERAGE_GRID:100), as pyribs' tutorial measures it.
 *
 * Wall time is the run's own `elapsed` column of log.csv at the row
 * that reaches the figure (start-up included, the final files not),
 * on whatever else the machine runs: run it on an idle machine. Beside
 * it, `evaluating` is the `seconds` column summed: the episodes alone.
 * `CPU/1k` is the CPU time (user + system, every thread) of the whole
 * evo run per 1,000 of its evaluations: what an evaluation costs, less
 * moved by the machine's other jobs than the times.
 * Exit 1 when a bar is not met (or a run does not reach 89 %).
 *
 * usage: bench_qd [--seeds N] [--only 100|50]
 *   --seeds N  seeds 1 .. N (default 1) */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "bench_proc.h"
#include "base/fileio.h"
#include "base/number.h"

#define BUDGET_100	375000L
#define TARGET		0.89
#define PYRIBS_SECONDS	226.0
#define QDAX_EVALS	1001472L
#define QDAX_SECONDS	313.0
#define QDAX_QD_SCORE	975.5

static char evo_bin[256];
/* CPU seconds of the last train(): its children's user + system time */
static double train_cpu;

/* The CPU seconds every finished child has used so far. */
static double children_cpu(void)
{
	struct rusage ru;
	if (getrusage(RUSAGE_CHILDREN, &ru) != 0)
		return 0;
	return (double)ru.ru_utime.tv_sec + ru.ru_utime.tv_usec / 1e6 +
	       (double)ru.ru_stime.tv_sec + ru.ru_stime.tv_usec / 1e6;
}
static char tmpdir[128];

/* One row of log.csv, the columns the bench reads. */
typedef struct row {
	long evals; /* evaluations so far (the column summed) */
	double elapsed, coverage, qd;
	double eval_secs; /* the seconds column summed: evaluation alone */
} row;

/* The index of column `name` in the header line, or -1. */
static int column(const char *header, const char *name)
{
	int k = 0;
	size_t n = strlen(name);
	for (const char *p = header; p && *p && *p != '\n'; k++) {
		if (strncmp(p, name, n) == 0 && (p[n] == ',' || p[n] == '\n'))
			return k;
		p = strchr(p, ',');
		if (p)
			p++;
	}
	return -1;
}

/* Field k of the line at p, as a number. */
static double field(const char *p, int k)
{
	for (int i = 0; i < k && p; i++) {
		p = strchr(p, ',');
		if (p)
			p++;
	}
	return p ? strtod(p, NULL) : 0;
}

/* The first row of DIR/run/log.csv whose evaluations reach `evals` (> 0)
 * or whose coverage reaches `coverage` (> 0); else the last row, with
 * *found 0. 0, or -1 after a message. */
static int read_log(long evals, double coverage, row *r, int *found)
{
	char path[512], *data;
	size_t len;
	evo_err err;
	snprintf(path, sizeof path, "%s/run/log.csv", tmpdir);
	if (evo_read_file(path, &data, &len, &err)) {
		fprintf(stderr, "bench_qd: %s\n", err.msg);
		return -1;
	}
	int ce = column(data, "evaluations"), ct = column(data, "elapsed"),
	    cs = column(data, "seconds"),
	    cc = column(data, "metric:coverage"),
	    cq = column(data, "metric:qd_score");
	if (ce < 0 || ct < 0 || cs < 0 || cc < 0) {
		fprintf(stderr, "bench_qd: %s: no coverage column (a MAPELITES "
				"log, or NOVELTY's with NOVELTY_COVERAGE_GRID)\n",
			path);
		free(data);
		return -1;
	}
	*found = 0;
	memset(r, 0, sizeof *r);
	long sum = 0;
	for (char *line = strchr(data, '\n'); line && line[1] && !*found;
	     line = strchr(line, '\n')) {
		line++;
		sum += (long)field(line, ce);
		r->evals = sum;
		r->eval_secs += field(line, cs);
		r->elapsed = field(line, ct);
		r->coverage = field(line, cc);
		r->qd = cq < 0 ? 0 : field(line, cq);
		*found = (evals > 0 && sum >= evals) ||
			 (coverage > 0 && r->coverage >= coverage);
	}
	free(data);
	return 0;
}

/* Trains a fresh copy of minds/Kheperax with task `task` (and `extra`, a
 * line added to it, or NULL) and seed s. 0, or -1 after a message. */
static int train(const char *task, const char *extra, int seed)
{
	char cmd[2048];
	snprintf(cmd, sizeof cmd,
		 "rm -rf %s/m %s/run && mkdir -p %s/m && cp -r "
		 "minds/Kheperax %s/m/",
		 tmpdir, tmpdir, tmpdir, tmpdir);
	if (bench_sh(cmd) != 0) {
		fprintf(stderr, "bench_qd: could not copy minds/Kheperax\n");
		return -1;
	}
	if (extra) {
		snprintf(cmd, sizeof cmd,
			 "printf '\\n%s\\n' >> %s/m/Kheperax/Tasks/%s.simbatch",
			 extra, tmpdir, task);
		if (bench_sh(cmd) != 0)
			return -1;
	}
	double cpu0 = children_cpu();
	snprintf(cmd, sizeof cmd,
		 "%s run %s/m/Kheperax/Tasks/%s.simbatch --seed %d --threads 2 "
		 "--run %s/run > %s/train.txt 2>&1",
		 evo_bin, tmpdir, task, seed, tmpdir, tmpdir);
	if (bench_sh(cmd) != 0) {
		fprintf(stderr, "bench_qd: %s seed %d: evo run failed; see "
				"%s/train.txt\n",
			task, seed, tmpdir);
		return -1;
	}
	train_cpu = children_cpu() - cpu0;
	return 0;
}

/* The last run's CPU seconds per 1,000 of its `evals` evaluations (the
 * whole run's CPU, whatever row the figures are read at: read from
 * log.csv's last row). */
static double cpu_per_1k(void)
{
	row r;
	int found;
	if (read_log(0, 0, &r, &found) || r.evals <= 0)
		return 0;
	return 1000.0 * train_cpu / (double)r.evals;
}

/* Seed s of task `task` to 375,000 evaluations, its row printed under
 * `method`: 1 when it met the bar, 0 when not, -1 on an error. */
static int run_100(const char *method, const char *task, int s)
{
	row r;
	int found;
	if (train(task, NULL, s) || read_log(BUDGET_100, 0, &r, &found))
		return -1;
	printf("%-10s %-5d %12ld %8.2f%% %8.1fs %10.1fs %7.3fs\n", method, s,
	       r.evals, 100 * r.coverage, r.elapsed, r.eval_secs, cpu_per_1k());
	fflush(stdout);
	return found && r.coverage >= TARGET && r.elapsed < PYRIBS_SECONDS;
}

/* Seeds 1 .. n of the 100 x 100 task, MAPELITES then NOVELTY: 1 when
 * MAPELITES meets the bar on every seed, 0 when not, -1 on an error. */
static int bench_100(int n)
{
	printf("Kheperax standard maze, 100 x 100 grid, 375,000 evaluations "
	       "(Tasks/Kheperax-MAPELITES.simbatch and, for comparison, "
	       "Tasks/Kheperax-NOVELTY.simbatch; 2 threads)\n");
	printf("%-10s %-5s %12s %9s %9s %11s %8s\n", "method", "seed",
	       "evaluations", "coverage", "time", "evaluating", "CPU/1k");
	int ok = 1;
	for (int s = 1; s <= n; s++) {
		int rc = run_100("MAPELITES", "Kheperax-MAPELITES", s);
		if (rc < 0)
			return -1;
		ok &= rc;
	}
	for (int s = 1; s <= n; s++)
		if (run_100("NOVELTY", "Kheperax-NOVELTY", s) < 0)
			return -1;
	printf("pyribs' novelty-search tutorial at 375,000 evaluations: "
	       "46.0, 79.5, 86.0, 86.1 %% in 226-246 s (published 88.93 %%)\n");
	printf("bar (MAPELITES): >= 89 %% within 375,000 evaluations in < "
	       "226 s: %s\n",
	       ok ? "met" : "NOT MET");
	return ok;
}

/* Seeds 1 .. n of the reference configuration, to 89 %. */
static int bench_50(int n)
{
	printf("Kheperax reference configuration, 50 x 50 grid, MAPELITES to "
	       "89 %% coverage (Tasks/Kheperax-MAPELITES-Ref.simbatch, 2 "
	       "threads)\n");
	printf("%-6s %12s %9s %9s %11s %9s %8s\n", "seed", "evaluations",
	       "coverage", "time", "evaluating", "QD-score", "CPU/1k");
	int ok = 1;
	for (int s = 1; s <= n; s++) {
		row r;
		int found;
		if (train("Kheperax-MAPELITES-Ref",
			  "MAPELITES_TARGET_COVERAGE:0.89", s) ||
		    read_log(0, TARGET, &r, &found))
			return -1;
		printf("%-6d %12ld %8.2f%% %8.1fs %10.1fs %9.1f %7.3fs%s\n", s,
		       r.evals, 100 * r.coverage, r.elapsed, r.eval_secs, r.qd,
		       cpu_per_1k(), found ? "" : "  (89 % not reached)");
		fflush(stdout);
		ok &= found && r.evals < QDAX_EVALS && r.elapsed < QDAX_SECONDS;
	}
	printf("the same with CMA-ME's improvement emitters (16 x 128, sigma0 "
	       "0.2), for comparison:\n");
	for (int s = 1; s <= n; s++) {
		row r;
		int found;
		if (train("Kheperax-MAPELITES-Ref",
			  "MAPELITES_TARGET_COVERAGE:0.89\\nMAPELITES_EMITTER:"
			  "cmame\\nMAPELITES_EMITTERS:16\\nMAPELITES_EMITTER_"
			  "BATCH:128\\nMAPELITES_EMITTER_SIGMA:0.2",
			  s) ||
		    read_log(0, TARGET, &r, &found))
			return -1;
		printf("%-6d %12ld %8.2f%% %8.1fs %10.1fs %9.1f %7.3fs%s\n", s,
		       r.evals, 100 * r.coverage, r.elapsed, r.eval_secs, r.qd,
		       cpu_per_1k(), found ? "" : "  (89 % not reached)");
		fflush(stdout);
	}
	printf("QDax MAP-Elites: 89.0 %% at %ld evaluations in %.0f s, "
	       "QD-score %.1f\n",
	       QDAX_EVALS, QDAX_SECONDS, QDAX_QD_SCORE);
	printf("bar: 89 %% in fewer evaluations and less time than QDax: "
	       "%s\n",
	       ok ? "met" : "NOT MET");
	return ok;
}

int main(int argc, char **argv)
{
	int seeds = 1, which = 0;
	for (int i = 1; i < argc; i++) {
		long long v;
		if (strcmp(argv[i], "--seeds") == 0 && i + 1 < argc &&
		    !evo_parse_whole(argv[i + 1], NULL, 1, 1000, &v)) {
			seeds = (int)v;
			i++;
		} else if (strcmp(argv[i], "--only") == 0 && i + 1 < argc &&
			   (strcmp(argv[i + 1], "100") == 0 ||
			    strcmp(argv[i + 1], "50") == 0)) {
			which = atoi(argv[++i]);
		} else {
			fprintf(stderr,
				"usage: bench_qd [--seeds N] [--only 100|50]\n");
			return 2;
		}
	}
	const char *b = getenv("EVO_BUILD");
	snprintf(evo_bin, sizeof evo_bin, "%s/evo", b && b[0] ? b : "build");
	snprintf(tmpdir, sizeof tmpdir, "/tmp/evo-bench-qd-XXXXXX");
	if (!mkdtemp(tmpdir)) {
		perror("bench_qd: mkdtemp");
		return 1;
	}
	int ok100 = which == 50 ? 1 : bench_100(seeds);
	int ok50 = which == 100 || ok100 < 0 ? 1 : bench_50(seeds);
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
	if (bench_sh(cmd) != 0)
		fprintf(stderr, "bench_qd: could not remove %s\n", tmpdir);
	return ok100 == 1 && ok50 == 1 ? 0 : 1;
}

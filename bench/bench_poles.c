/* make bench: double-pole balancing on the protocol of Gomez, Schmidhuber
 * & Miikkulainen, "Accelerated Neural Evolution through Cooperatively
 * Coevolved Synapses", JMLR 9 (2008), tables 3 and 4 (long pole started at
 * 4 degrees, cart friction; POLEPROTOCOL:GOMEZ, docs/learning.md), each
 * row beside the published figures it is compared with:
 *
 *   DPV   with velocities, evaluations to balance 100,000 steps: CMA-ES
 *         895, CoSyNE 954, NEAT 3,600 (Gomez 2008, table 3); an
 *         independent CMA-ES reproduction 637 (100 seeds);
 *   DPNV  without velocities, damping fitness, success = 100,000 steps
 *         and 200 of the 625 generalisation starts: CMA-ES 6,061, CoSyNE
 *         3,416, NEAT 6,929 with population 16 (table 4); the CMA-ES
 *         reproduction 3,043 with a lower bound on the step size.
 *
 * Each run is `evo run` on a fresh copy of the row's task (minds/...) with
 * --seed s for s = 1 .. N, exactly what a user gets. A run stops in the
 * generation where a candidate solves the task (log.csv's `solved`); its
 * evaluations are the sum of log.csv's `evaluations`, and a run that
 * reaches NUMGEN unsolved is a failure. The mean is over the solved runs.
 * For DPNV the generalisation of every run's saved champion is recomputed
 * here (sim/learn/literature.h) on the task's protocol, and printed as a
 * mean ± its standard error.
 *
 * The rows are data (table `rows` below): a row whose task file is not in
 * the tree is reported as not run. Bars (issue 28), exit 1 when one is not
 * met: CMA-ES DPV, at least 50 seeds, mean at most 895, no failure;
 * CMA-ES DPNV, at least 20 seeds, mean at most 3,416, no failure and every
 * champion's generalisation at least 200. The NEAT rows are printed beside
 * their anchors without a bar.
 *
 * usage: bench_poles [--seeds N] [--only NAME]
 *   --seeds N    N runs of each row (seeds 1 .. N); without it, each
 *                row's own count
 *   --only NAME  one row: neat-dpv, neat-dpnv, cmaes-dpv or cmaes-dpnv */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>

#include "bench_proc.h"
#include "base/fileio.h"
#include "base/number.h"
#include "learn/literature.h"

#define MAX_ANCHORS 4

typedef struct anchor {
	double evals;	    /* the published mean evaluations */
	const char *source; /* who, where, on which protocol */
} anchor;

typedef struct row {
	const char *only;   /* --only's word */
	const char *task;   /* label: DPV or DPNV */
	const char *method; /* the learning method, as printed */
	const char *mind;   /* folder under minds/ */
	const char *skill;  /* the learning skill */
	const char *file;   /* the task, under Tasks/ */
	int velocities;	    /* DPV: 1; DPNV: 0, generalisation recomputed */
	int seeds;	    /* runs without --seeds */
	/* the bar: at least bar_seeds runs, mean <= bar_mean, no failure,
	 * (DPNV) every champion generalising to EVO_LIT_GENERAL_NEEDED;
	 * bar_seeds 0: no bar */
	int bar_seeds;
	double bar_mean;
	anchor anchors[MAX_ANCHORS];
} row;

#define GOMEZ_DPV "Gomez et al. 2008, table 3, long pole at 4 deg"
#define GOMEZ_DPNV "Gomez et al. 2008, table 4, long pole at 4 deg"
#define REPRO "independent CMA-ES reproduction, 100 seeds"

static const row rows[] = {
    {"neat-dpv",
     "DPV",
     "NEAT",
     "DoublePole",
     "Balance",
     "DPV-Gomez-NEAT",
     1,
     50,
     0,
     0,
     {{3600, "NEAT, " GOMEZ_DPV " (the same as the NEAT paper's figure, "
	     "at 1 deg)"},
      {895, "CMA-ES, " GOMEZ_DPV},
      {954, "CoSyNE, " GOMEZ_DPV}}},
    {"neat-dpnv",
     "DPNV",
     "NEAT",
     "DoublePoleNV",
     "Balance",
     "DPNV-Gomez-NEAT",
     0,
     10, /* a failed run takes 5 to 12 minutes */
     0,
     0,
     {{6929, "NEAT, population 16, " GOMEZ_DPNV},
      {6061, "CMA-ES, " GOMEZ_DPNV},
      {3416, "CoSyNE, " GOMEZ_DPNV}}},
    {"cmaes-dpv",
     "DPV",
     "CMA-ES",
     "DoublePole",
     "BalanceLayered",
     "DPV-Gomez-CMAES",
     1,
     50,
     50,
     895,
     {{895, "CMA-ES, " GOMEZ_DPV},
      {954, "CoSyNE, " GOMEZ_DPV},
      {637, REPRO}}},
    {"cmaes-dpnv",
     "DPNV",
     "CMA-ES",
     "DoublePoleNV",
     "BalanceLayered",
     "DPNV-Gomez-CMAES",
     0,
     20,
     20,
     3416,
     {{6061, "CMA-ES, " GOMEZ_DPNV},
      {3416, "CoSyNE, " GOMEZ_DPNV},
      {3043, REPRO ", lower bound on the step size"}}},
};

static char evo_bin[256];
static char tmpdir[128];

/* The protocol the task file names with POLEPROTOCOL (NEAT without it),
 * or -1 with a message when the file cannot be read or names none. */
static int task_protocol(const char *path)
{
	char *data;
	size_t len;
	evo_err err;
	if (evo_read_file(path, &data, &len, &err)) {
		fprintf(stderr, "bench_poles: %s\n", err.msg);
		return -1;
	}
	int pr = EVO_LIT_PROTO_NEAT;
	for (char *line = data; line && *line;) {
		char *end = strchr(line, '\n');
		if (end)
			*end = '\0';
		if (strncmp(line, "POLEPROTOCOL:", 13) == 0) {
			char *v = line + 13;
			while (*v == ' ')
				v++;
			char *e = v + strlen(v);
			while (e > v && isspace((unsigned char)e[-1]))
				*--e = '\0';
			pr = evo_lit_protocol_named(v);
			if (pr < 0)
				fprintf(stderr,
					"bench_poles: %s: POLEPROTOCOL %s is "
					"not NEAT or GOMEZ\n",
					path, v);
		}
		line = end ? end + 1 : NULL;
	}
	free(data);
	return pr;
}

/* Column `name` of a log.csv header line, or -1. */
static int column(const char *header, const char *name)
{
	int k = 0;
	size_t n = strlen(name);
	for (const char *p = header; *p && *p != '\n'; k++) {
		if (strncmp(p, name, n) == 0 &&
		    (p[n] == ',' || p[n] == '\n' || p[n] == '\0'))
			return k;
		p += strcspn(p, ",\n");
		if (*p == ',')
			p++;
	}
	return -1;
}

/* Field k of a CSV line as a number. */
static double field(const char *line, int k)
{
	for (int i = 0; i < k && line; i++) {
		line = strchr(line, ',');
		if (line)
			line++;
	}
	return line ? strtod(line, NULL) : 0;
}

/* Evaluations and solved from a run's log.csv: 0, or -1. */
static int read_log(long *evals, int *solved)
{
	char path[512], *data;
	size_t len;
	evo_err err;
	snprintf(path, sizeof path, "%s/run/log.csv", tmpdir);
	if (evo_read_file(path, &data, &len, &err)) {
		fprintf(stderr, "bench_poles: %s\n", err.msg);
		return -1;
	}
	int ce = column(data, "evaluations"), cs = column(data, "solved");
	if (ce < 0 || cs < 0) {
		fprintf(stderr,
			"bench_poles: %s: no evaluations or solved column\n",
			path);
		free(data);
		return -1;
	}
	*evals = 0;
	*solved = 0;
	for (char *line = strchr(data, '\n'); line && line[1];
	     line = strchr(line, '\n')) {
		line++;
		*evals += (long)field(line, ce);
		*solved = field(line, cs) > 0;
	}
	free(data);
	return 0;
}

/* The saved champion's generalisation on protocol pr, or -1. */
static int champion_generalisation(const row *r, evo_lit_protocol pr)
{
	char path[512], *data;
	size_t len;
	evo_err err;
	snprintf(path, sizeof path, "%s/m/%s/Skills/%s/%s.net", tmpdir,
		 r->mind, r->skill, r->skill);
	if (evo_read_file(path, &data, &len, &err)) {
		fprintf(stderr, "bench_poles: %s\n", err.msg);
		return -1;
	}
	static evo_netdesc d;
	evo_diag diag;
	evo_status st = evo_netdesc_parse(data, len, path, &d, &diag);
	free(data);
	if (st != EVO_OK) {
		fprintf(stderr, "bench_poles: %s\n", diag.msg);
		return -1;
	}
	int g = evo_lit_generalisation_for(pr, &d, r->velocities, &err);
	if (g < 0)
		fprintf(stderr, "bench_poles: %s: %s\n", path, err.msg);
	return g;
}

/* One run: 0 with *evals, *solved, *general (-1 for DPV), or -1. */
static int run_once(const row *r, evo_lit_protocol pr, int seed, long *evals,
		    int *solved, int *general)
{
	char cmd[2048];
	snprintf(cmd, sizeof cmd,
		 "rm -rf %s/m %s/run && mkdir -p %s/m && cp -r minds/%s "
		 "%s/m/ && %s run %s/m/%s/Tasks/%s.simbatch --seed %d --run "
		 "%s/run > %s/out.txt 2>&1",
		 tmpdir, tmpdir, tmpdir, r->mind, tmpdir, evo_bin, tmpdir,
		 r->mind, r->file, seed, tmpdir, tmpdir);
	if (bench_sh(cmd) != 0) {
		fprintf(stderr,
			"bench_poles: %s seed %d: evo run failed; see "
			"%s/out.txt\n",
			r->only, seed, tmpdir);
		return -1;
	}
	if (read_log(evals, solved))
		return -1;
	*general = -1;
	if (!r->velocities) {
		*general = champion_generalisation(r, pr);
		if (*general < 0)
			return -1;
	}
	return 0;
}

static void print_anchors(const row *r)
{
	for (int k = 0; k < MAX_ANCHORS && r->anchors[k].source; k++)
		printf("    published %6.0f  %s\n", r->anchors[k].evals,
		       r->anchors[k].source);
}

/* Runs a row over seeds 1 .. n and prints it; 1 when its bar is met (or
 * it has none), 0 when not, -1 on an error. */
static int bench_row(const row *r, int n)
{
	char path[512];
	snprintf(path, sizeof path, "minds/%s/Tasks/%s.simbatch", r->mind,
		 r->file);
	struct stat sb;
	if (stat(path, &sb) != 0) {
		printf("%-5s %-8s %-6s  not run: no task file %s\n", r->task,
		       "-", r->method, path);
		print_anchors(r);
		if (r->bar_seeds)
			printf("    bar: NOT MET (not run)\n");
		return r->bar_seeds ? 0 : 1;
	}
	int pr = task_protocol(path);
	if (pr < 0)
		return -1;
	long sum = 0;
	int solved_runs = 0, failures = 0, gen_runs = 0, gen_min = 625;
	double gsum = 0, gsq = 0, t0 = bench_now();
	for (int s = 1; s <= n; s++) {
		long evals;
		int solved, general;
		double t1 = bench_now();
		if (run_once(r, (evo_lit_protocol)pr, s, &evals, &solved,
			     &general))
			return -1;
		/* progress, off the table: a long row shows where it is */
		fprintf(stderr,
			"bench_poles: %s seed %d: %ld evaluations, %s, "
			"generalisation %d, %.1f s\n",
			r->only, s, evals, solved ? "solved" : "FAILED",
			general, bench_now() - t1);
		if (solved) {
			solved_runs++;
			sum += evals;
		} else {
			failures++;
		}
		if (general >= 0) {
			gen_runs++;
			gsum += general;
			gsq += (double)general * general;
			gen_min = general < gen_min ? general : gen_min;
		}
	}
	double secs = bench_now() - t0;
	double mean = solved_runs ? (double)sum / solved_runs : 0;
	printf("%-5s %-8s %-6s %5d %10.0f %8d", r->task,
	       evo_lit_protocol_name((evo_lit_protocol)pr), r->method, n, mean,
	       failures);
	if (gen_runs) {
		double g = gsum / gen_runs, se = 0;
		if (gen_runs > 1) {
			double var = (gsq - gen_runs * g * g) / (gen_runs - 1);
			se = sqrt(var > 0 ? var : 0) / sqrt(gen_runs);
		}
		printf("   %5.1f/625 ±%4.1f (lowest %3d)", g, se, gen_min);
	} else {
		printf("   %-29s", "-");
	}
	printf("  %6.1f s a run\n", secs / n);
	print_anchors(r);
	if (!r->bar_seeds) {
		printf("    bar: none (printed beside)\n");
		fflush(stdout);
		return 1;
	}
	int ok = n >= r->bar_seeds && solved_runs > 0 &&
		 mean <= r->bar_mean && failures == 0 &&
		 (r->velocities || gen_min >= EVO_LIT_GENERAL_NEEDED);
	printf("    bar: at least %d seeds, mean <= %.0f, no failure%s: %s\n",
	       r->bar_seeds, r->bar_mean,
	       r->velocities ? "" : ", every champion generalising to 200",
	       ok ? "met" : "NOT MET");
	fflush(stdout);
	return ok;
}

int main(int argc, char **argv)
{
	int seeds = 0, seeds_given = 0;
	const char *only = NULL;
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--seeds") == 0 && i + 1 < argc) {
			long long v;
			seeds = evo_parse_whole(argv[++i], NULL, 1, 100000, &v)
				    ? 0
				    : (int)v;
			seeds_given = 1;
		} else if (strcmp(argv[i], "--only") == 0 && i + 1 < argc) {
			only = argv[++i];
		} else {
			fprintf(stderr, "usage: bench_poles [--seeds N] [--only "
					"neat-dpv|neat-dpnv|cmaes-dpv|"
					"cmaes-dpnv]\n");
			return 2;
		}
	}
	if (seeds_given && seeds < 1) {
		fprintf(stderr, "bench_poles: --seeds wants a whole number "
				"from 1 to 100000\n");
		return 2;
	}
	size_t n_rows = sizeof rows / sizeof rows[0], k;
	for (k = 0; only && k < n_rows; k++)
		if (strcmp(only, rows[k].only) == 0)
			break;
	if (only && k == n_rows) {
		fprintf(stderr,
			"bench_poles: --only %s: not a row (neat-dpv, "
			"neat-dpnv, cmaes-dpv or cmaes-dpnv)\n",
			only);
		return 2;
	}
	const char *b = getenv("EVO_BUILD");
	snprintf(evo_bin, sizeof evo_bin, "%s/evo", b && b[0] ? b : "build");
	snprintf(tmpdir, sizeof tmpdir, "/tmp/evo-bench-poles-XXXXXX");
	if (!mkdtemp(tmpdir)) {
		perror("bench_poles: mkdtemp");
		return 1;
	}
	printf("Double pole on the protocols of the published tables "
	       "(docs/learning.md, \"Literature tasks\")\n");
	printf("%-5s %-8s %-6s %5s %10s %8s   %-29s  %s\n", "task", "protocol",
	       "method", "seeds", "mean evals", "failures",
	       "generalisation ± s.e.", "time");
	int rc = 0;
	for (k = 0; k < n_rows; k++) {
		const row *r = &rows[k];
		if (only && strcmp(only, r->only) != 0)
			continue;
		if (bench_row(r, seeds_given ? seeds : r->seeds) != 1)
			rc = 1;
	}
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
	if (bench_sh(cmd) != 0)
		fprintf(stderr, "bench_poles: could not remove %s\n", tmpdir);
	return rc;
}

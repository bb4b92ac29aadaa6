/* make bench: OPENENDED on minds/OpenMaze (issue 30, acceptance 1 and 2),
 * with development and without it.
 *
 * For each seed s, two runs, each in its own fresh copy of the mind
 * folder, by `evo run TASK --seed s --generations B --threads T --no-save
 * --run DIR`, exactly what a user gets:
 *
 *   development     Tasks/OpenMaze.simbatch as shipped (OPEN_SKILL,
 *                   OPEN_DEVELOP 15, OPEN_PROGRESS largest)
 *   no development  the same task with OPEN_DEVELOP:0: the agents stay
 *                   one NEAT network from every sensor to the motors, a
 *                   flat NEAT agent (OpenMaze's seed hierarchy is that
 *                   one skill)
 *
 * Each row gives, from the run's log.csv, retention.csv and skills.csv:
 * ANNECS after a third, two thirds and all of the batches; the largest
 * solved maze's path at the same points (the seed maze's is 3); the
 * skills added; the admitted mazes no longer solved by any agent kept
 * after the last batch; the run's wall time.
 *
 * Bar (acceptance 1, for the development runs): ANNECS still rising over
 * the last third, the largest path at least 3 times the seed maze's, no
 * admitted maze lost at the end, and at least one skill added; exit 1
 * when a development run misses it. The runs without development are
 * printed beside, whatever they show (acceptance 2).
 *
 * Time: 100 batches take one to two minutes of CPU; the default is seed 1
 * and 100 batches. docs/openended.md says which budget is "about an hour
 * on this machine's two cores".
 *
 * usage: bench_openended [--seeds N] [--first S] [--batches B] [--threads T] */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_proc.h"
#include "base/fileio.h"
#include "base/number.h"

#define SEED_PATH 3 /* GEN_Maze's seed maze: 3 x 2 cells, no wall */

typedef struct variant {
	const char *name; /* as printed */
	const char *sed;  /* the change to the shipped task, or NULL */
} variant;

static const variant develop = {"development", NULL};
static const variant flat = {"no development",
			     "s/^OPEN_DEVELOP:.*/OPEN_DEVELOP:0/"};

typedef struct result {
	long annecs[3];	 /* after a third, two thirds, all of the batches */
	double largest[3];
	int batches;	 /* rows of log.csv */
	int skills;	 /* rows of skills.csv */
	int lost;	 /* mazes lost after the last batch */
	double secs;
} result;

static char evo_bin[256];
static char tmpdir[128];
static int threads = 2, first_seed = 1, batches = 100;

/* Field k (0 based) of a CSV row. */
static const char *field(const char *row, int k)
{
	for (int c = 0; c < k && row; c++) {
		row = strchr(row, ',');
		if (row)
			row++;
	}
	return row;
}

/* The file `name` of the run folder: its text, or NULL after a message
 * (a missing skills.csv is no error: *missing_ok). */
static char *run_file(const char *name, int missing_ok)
{
	char path[512], *data;
	size_t len;
	evo_err err;
	snprintf(path, sizeof path, "%s/run/%s", tmpdir, name);
	if (missing_ok && !evo_file_exists(path))
		return NULL;
	if (evo_read_file(path, &data, &len, &err)) {
		fprintf(stderr, "bench_openended: %s\n", err.msg);
		return NULL;
	}
	return data;
}

/* The rows of a CSV text after its header. */
static int rows(const char *csv)
{
	int n = 0;
	for (const char *p = strchr(csv, '\n'); p && p[1]; p = strchr(p + 1, '\n'))
		n++;
	return n;
}

/* Reads the run folder into r: 0, or -1 after a message. */
static int read_run(result *r)
{
	char *log = run_file("log.csv", 0);
	if (!log)
		return -1;
	const char *want = "generation,best,mean,best_ever,species,evaluations,"
			   "solved,seconds,elapsed,metric:annecs,metric:largest,";
	if (strncmp(log, want, strlen(want)) != 0) {
		fprintf(stderr, "bench_openended: log.csv: not the columns "
				"expected\n");
		free(log);
		return -1;
	}
	r->batches = rows(log);
	int at[3] = {r->batches / 3, 2 * r->batches / 3, r->batches};
	int row = 0;
	for (const char *line = strchr(log, '\n'); line && line[1];
	     line = strchr(line + 1, '\n')) {
		row++;
		for (int k = 0; k < 3; k++) {
			if (row != at[k])
				continue;
			const char *a = field(line + 1, 9), *l = field(line + 1, 10);
			r->annecs[k] = a ? strtol(a, NULL, 10) : -1;
			r->largest[k] = l ? strtod(l, NULL) : -1;
		}
	}
	free(log);
	char *ret = run_file("retention.csv", 0);
	if (!ret)
		return -1;
	const char *last = ret, *p = ret;
	while ((p = strchr(p, '\n')) && p[1])
		last = ++p;
	const char *ad = field(last, 1), *kept = field(last, 2);
	r->lost = ad && kept ? (int)(strtol(ad, NULL, 10) - strtol(kept, NULL, 10)) : -1;
	free(ret);
	char *sk = run_file("skills.csv", 1);
	r->skills = sk ? rows(sk) : 0;
	free(sk);
	return 0;
}

/* One run of variant v with seed s: 0 with *r, or -1 after a message. */
static int run_once(const variant *v, int seed, result *r)
{
	char cmd[2048];
	snprintf(cmd, sizeof cmd,
		 "rm -rf %s/m %s/run && mkdir -p %s/m && cp -r minds/OpenMaze "
		 "%s/m/ && rm -rf %s/m/OpenMaze/Runs",
		 tmpdir, tmpdir, tmpdir, tmpdir, tmpdir);
	if (bench_sh(cmd) != 0) {
		fprintf(stderr, "bench_openended: could not copy minds/OpenMaze "
				"to %s/m\n",
			tmpdir);
		return -1;
	}
	if (v->sed) {
		snprintf(cmd, sizeof cmd,
			 "sed -i '%s' %s/m/OpenMaze/Tasks/OpenMaze.simbatch",
			 v->sed, tmpdir);
		if (bench_sh(cmd) != 0)
			return -1;
	}
	snprintf(cmd, sizeof cmd,
		 "%s run %s/m/OpenMaze/Tasks/OpenMaze.simbatch --seed %d "
		 "--threads %d --generations %d --no-save --run %s/run > "
		 "%s/out.txt 2>&1",
		 evo_bin, tmpdir, seed, threads, batches, tmpdir, tmpdir);
	double t0 = bench_now();
	int rc = bench_sh(cmd);
	r->secs = bench_now() - t0;
	if (rc != 0) {
		fprintf(stderr, "bench_openended: %s seed %d: evo run failed; "
				"see %s/out.txt\n",
			v->name, seed, tmpdir);
		return -1;
	}
	return read_run(r);
}

/* Whether a development run meets acceptance 1. */
static int meets(const result *r)
{
	return r->annecs[2] > r->annecs[1] &&
	       r->largest[2] >= 3 * SEED_PATH && r->lost == 0 && r->skills > 0;
}

static void print_row(const variant *v, int seed, const result *r)
{
	printf("%-15s %4d  %6ld %6ld %6ld  %5g %5g %5g  %6d %5d  %7.0fs\n",
	       v->name, seed, r->annecs[0], r->annecs[1], r->annecs[2],
	       r->largest[0], r->largest[1], r->largest[2], r->skills,
	       r->lost, r->secs);
	fflush(stdout);
}

/* Prints the table: 1 when every development run meets the bar, 0 when
 * not, -1 on an error. */
static int bench(int n)
{
	printf("OPENENDED, minds/OpenMaze/Tasks/OpenMaze.simbatch, %d batches, "
	       "--threads %d; beside it the same task with OPEN_DEVELOP:0\n",
	       batches, threads);
	printf("%-15s %4s  %-20s  %-17s  %6s %5s  %8s\n", "", "seed",
	       "ANNECS at 1/3 2/3 end", "largest path", "skills", "lost",
	       "time");
	int met = 0;
	for (int s = first_seed; s < first_seed + n; s++) {
		result d, f;
		if (run_once(&develop, s, &d))
			return -1;
		print_row(&develop, s, &d);
		met += meets(&d);
		if (run_once(&flat, s, &f))
			return -1;
		print_row(&flat, s, &f);
	}
	int ok = met == n;
	printf("bar (development): ANNECS rising over the last third, the "
	       "largest path >= %d (3 x the seed maze's), no maze lost, a "
	       "skill added: %d of %d runs, %s\n",
	       3 * SEED_PATH, met, n, ok ? "met" : "NOT MET");
	return ok;
}

static int whole_arg(const char *opt, const char *text, int lo, int hi,
		     int *out)
{
	long long v;
	if (evo_parse_whole(text, NULL, lo, hi, &v)) {
		fprintf(stderr,
			"bench_openended: %s wants a whole number from %d to "
			"%d, found '%s'\n",
			opt, lo, hi, text);
		return -1;
	}
	*out = (int)v;
	return 0;
}

int main(int argc, char **argv)
{
	int seeds = 1;
	for (int i = 1; i < argc; i++) {
		int bad = i + 1 >= argc;
		if (!bad && strcmp(argv[i], "--seeds") == 0)
			bad = whole_arg(argv[i], argv[i + 1], 1, 1000, &seeds);
		else if (!bad && strcmp(argv[i], "--first") == 0)
			bad = whole_arg(argv[i], argv[i + 1], 1, 1000000,
					&first_seed);
		else if (!bad && strcmp(argv[i], "--batches") == 0)
			bad = whole_arg(argv[i], argv[i + 1], 3, 10000000,
					&batches);
		else if (!bad && strcmp(argv[i], "--threads") == 0)
			bad = whole_arg(argv[i], argv[i + 1], 1, 256, &threads);
		else
			bad = 1;
		if (bad) {
			fprintf(stderr, "usage: bench_openended [--seeds N] "
					"[--first S] [--batches B] "
					"[--threads T]\n");
			return 2;
		}
		i++;
	}
	const char *b = getenv("EVO_BUILD");
	snprintf(evo_bin, sizeof evo_bin, "%s/evo", b && b[0] ? b : "build");
	snprintf(tmpdir, sizeof tmpdir, "/tmp/evo-bench-openended-XXXXXX");
	if (!mkdtemp(tmpdir)) {
		perror("bench_openended: mkdtemp");
		return 1;
	}
	int ok = bench(seeds);
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
	if (bench_sh(cmd) != 0)
		fprintf(stderr, "bench_openended: could not remove %s\n",
			tmpdir);
	return ok == 1 ? 0 : 1;
}

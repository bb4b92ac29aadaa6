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
 * on this machine's two cores". Each row gives the run's wall time and
 * its CPU time (the run and its threads). --together runs a seed's two
 * runs at once, each with --threads T (the log is the same with any
 * number of threads), and --keep DIR keeps their run folders as
 * DIR/development-S and DIR/flat-S (S the seed) instead of a temporary
 * folder; a run kept there with all B batches is read, not run again.
 * --curve PREFIX draws PREFIX-annecs.png and PREFIX-largest.png, ANNECS
 * and the largest path per batch of the first seed's two runs, the
 * batches where the development run added a skill marked.
 *
 * usage: bench_openended [--seeds N] [--first S] [--batches B] [--threads T]
 *                        [--together] [--keep DIR] [--curve PREFIX] */
#define _DEFAULT_SOURCE /* wait4 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench_proc.h"
#include "base/fileio.h"
#include "base/number.h"
#include "learn/curve.h"

#define SEED_PATH 3 /* GEN_Maze's seed maze: 3 x 2 cells, no wall */

typedef struct variant {
	const char *name;   /* as printed */
	const char *folder; /* its folders' names: FOLDER-SEED */
	const char *sed;    /* the change to the shipped task, or NULL */
} variant;

static const variant develop = {"development", "development", NULL};
static const variant flat = {"no development", "flat",
			     "s/^OPEN_DEVELOP:.*/OPEN_DEVELOP:0/"};

typedef struct result {
	long annecs[3];	 /* after a third, two thirds, all of the batches */
	double largest[3];
	int batches;	 /* rows of log.csv */
	int skills;	 /* rows of skills.csv */
	int lost;	 /* mazes lost after the last batch */
	double secs;	 /* wall time */
	double cpu;	 /* CPU time of the run and its threads (NaN: not known) */
	double elapsed;	 /* log.csv's elapsed after the last batch */
} result;

static char evo_bin[256];
static char tmpdir[1024];
static const char *keep_dir, *curve_prefix;
static int threads = 2, first_seed = 1, batches = 100, together;

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
static char *run_file(const char *dir, const char *name, int missing_ok)
{
	char path[1400], *data;
	size_t len;
	evo_err err;
	snprintf(path, sizeof path, "%s/run/%s", dir, name);
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

/* Reads the run folder of dir into r: 0, or -1 after a message. */
static int read_run(const char *dir, result *r)
{
	char *log = run_file(dir, "log.csv", 0);
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
		if (row == r->batches) {
			const char *e = field(line + 1, 8);
			r->elapsed = e ? strtod(e, NULL) : NAN;
		}
		for (int k = 0; k < 3; k++) {
			if (row != at[k])
				continue;
			const char *a = field(line + 1, 9), *l = field(line + 1, 10);
			r->annecs[k] = a ? strtol(a, NULL, 10) : -1;
			r->largest[k] = l ? strtod(l, NULL) : -1;
		}
	}
	free(log);
	char *ret = run_file(dir, "retention.csv", 0);
	if (!ret)
		return -1;
	const char *last = ret, *p = ret;
	while ((p = strchr(p, '\n')) && p[1])
		last = ++p;
	const char *ad = field(last, 1), *kept = field(last, 2);
	r->lost = ad && kept ? (int)(strtol(ad, NULL, 10) - strtol(kept, NULL, 10)) : -1;
	free(ret);
	char *sk = run_file(dir, "skills.csv", 1);
	r->skills = sk ? rows(sk) : 0;
	free(sk);
	return 0;
}

/* A run of variant v with seed s, started or done. */
typedef struct job {
	const variant *v;
	int seed;
	char dir[1100]; /* its mind folder copy m/, run/ and out.txt */
	pid_t pid;	/* 0: a kept run of the whole budget, read again */
	double t0;
} job;

/* Copies minds/OpenMaze for job j and starts its evo run: 0, or -1
 * after a message. */
static int start(job *j)
{
	char cmd[8192];
	snprintf(j->dir, sizeof j->dir, "%s/%s-%d", tmpdir, j->v->folder,
		 j->seed);
	j->pid = 0;
	if (keep_dir) {
		char *log = run_file(j->dir, "log.csv", 1);
		int whole = log && rows(log) == batches;
		free(log);
		if (whole) {
			printf("(%s seed %d: the run kept in %s has all %d "
			       "batches; read, not run again)\n",
			       j->v->name, j->seed, j->dir, batches);
			return 0;
		}
	}
	snprintf(cmd, sizeof cmd,
		 "rm -rf %s && mkdir -p %s/m && cp -r minds/OpenMaze %s/m/ && "
		 "rm -rf %s/m/OpenMaze/Runs",
		 j->dir, j->dir, j->dir, j->dir);
	if (bench_sh(cmd) != 0) {
		fprintf(stderr, "bench_openended: could not copy minds/OpenMaze "
				"to %s/m\n",
			j->dir);
		return -1;
	}
	if (j->v->sed) {
		snprintf(cmd, sizeof cmd,
			 "sed -i '%s' %s/m/OpenMaze/Tasks/OpenMaze.simbatch",
			 j->v->sed, j->dir);
		if (bench_sh(cmd) != 0)
			return -1;
	}
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/m/OpenMaze/Tasks/OpenMaze.simbatch --seed %d "
		 "--threads %d --generations %d --no-save --run %s/run > "
		 "%s/out.txt 2>&1",
		 evo_bin, j->dir, j->seed, threads, batches, j->dir, j->dir);
	fflush(stdout);
	j->t0 = bench_now();
	j->pid = fork();
	if (j->pid < 0) {
		perror("bench_openended: fork");
		return -1;
	}
	if (j->pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	return 0;
}

/* Waits for job j's run and reads it into r: 0, or -1 after a message. */
static int finish(job *j, result *r)
{
	int st;
	struct rusage ru;
	if (j->pid == 0) { /* kept: its wall time is log.csv's elapsed */
		r->cpu = NAN;
		if (read_run(j->dir, r))
			return -1;
		r->secs = r->elapsed;
		return 0;
	}
	if (wait4(j->pid, &st, 0, &ru) != j->pid) {
		perror("bench_openended: wait4");
		return -1;
	}
	r->secs = bench_now() - j->t0;
	r->cpu = (double)ru.ru_utime.tv_sec + (double)ru.ru_utime.tv_usec * 1e-6 +
		 (double)ru.ru_stime.tv_sec + (double)ru.ru_stime.tv_usec * 1e-6;
	if (!WIFEXITED(st) || WEXITSTATUS(st) != 0) {
		fprintf(stderr, "bench_openended: %s seed %d: evo run failed; "
				"see %s/out.txt\n",
			j->v->name, j->seed, j->dir);
		return -1;
	}
	return read_run(j->dir, r);
}

/* Column col of each row of dir's log.csv after its header, in a new
 * array of *n values, or NULL after a message. */
static double *log_column(const char *dir, int col, int *n)
{
	char *log = run_file(dir, "log.csv", 0);
	if (!log)
		return NULL;
	*n = rows(log);
	double *v = malloc((size_t)(*n > 0 ? *n : 1) * sizeof *v);
	int i = 0;
	for (const char *line = strchr(log, '\n'); v && line && line[1] && i < *n;
	     line = strchr(line + 1, '\n')) {
		const char *f = field(line + 1, col);
		v[i++] = f ? strtod(f, NULL) : NAN;
	}
	free(log);
	return v;
}

/* The batches after which the first seed's development run added a
 * skill (its skills.csv's batch column), at most cap: how many. */
static int skill_batches(double *at, int cap)
{
	char dir[1100];
	snprintf(dir, sizeof dir, "%s/%s-%d", tmpdir, develop.folder,
		 first_seed);
	char *sk = run_file(dir, "skills.csv", 1);
	int n = 0;
	for (const char *line = sk ? strchr(sk, '\n') : NULL;
	     line && line[1] && n < cap; line = strchr(line + 1, '\n')) {
		const char *b = field(line + 1, 1);
		if (b)
			at[n++] = strtod(b, NULL);
	}
	free(sk);
	return n;
}

/* PREFIX-annecs.png and PREFIX-largest.png: ANNECS and the largest
 * solved maze's path per batch, with development and without, for the
 * first seed: 0, or -1 after a message. */
static int draw_curves(void)
{
	static const struct {
		const char *file, *title, *label;
		int col;
	} plots[2] = {{"annecs", "OpenMaze: ANNECS per batch", "ANNECS", 9},
		      {"largest", "OpenMaze: largest solved maze per batch",
		       "solution path (cells)", 10}};
	const variant *vs[2] = {&develop, &flat};
	const uint32_t rgb[2] = {EVO_CURVE_BEST, EVO_CURVE_MEAN};
	int rc = 0;
	for (int p = 0; p < 2 && rc == 0; p++) {
		evo_curve_series s[2];
		double *v[2] = {NULL, NULL};
		for (int k = 0; k < 2; k++) {
			char dir[1100];
			snprintf(dir, sizeof dir, "%s/%s-%d", tmpdir,
				 vs[k]->folder, first_seed);
			s[k] = (evo_curve_series){vs[k]->name, rgb[k], NULL, 0};
			v[k] = log_column(dir, plots[p].col, &s[k].n);
			s[k].v = v[k];
			rc = v[k] ? rc : -1;
		}
		char title[160], path[600];
		snprintf(title, sizeof title, "%s, seed %d", plots[p].title,
			 first_seed);
		snprintf(path, sizeof path, "%s-%s.png", curve_prefix,
			 plots[p].file);
		double marks[64];
		int n_marks = skill_batches(marks, 64);
		evo_curve_spec spec = {title, "batch", plots[p].label, s, 2,
				       marks, n_marks, "skill added"};
		evo_err err = {{0}};
		if (rc == 0 && evo_curve_plot(path, &spec, &err)) {
			fprintf(stderr, "bench_openended: %s\n", err.msg);
			rc = -1;
		} else if (rc == 0) {
			printf("curve: %s\n", path);
		}
		free(v[0]);
		free(v[1]);
	}
	return rc;
}

/* Whether a development run meets acceptance 1. */
static int meets(const result *r)
{
	return r->annecs[2] > r->annecs[1] &&
	       r->largest[2] >= 3 * SEED_PATH && r->lost == 0 && r->skills > 0;
}

static void print_row(const variant *v, int seed, const result *r)
{
	char cpu[32] = "       -";
	if (isfinite(r->cpu))
		snprintf(cpu, sizeof cpu, "%7.0fs", r->cpu);
	printf("%-15s %4d  %6ld %6ld %6ld  %5g %5g %5g  %6d %5d  %7.0fs "
	       "%s\n",
	       v->name, seed, r->annecs[0], r->annecs[1], r->annecs[2],
	       r->largest[0], r->largest[1], r->largest[2], r->skills,
	       r->lost, r->secs, cpu);
	fflush(stdout);
}

/* Prints the table: 1 when every development run meets the bar, 0 when
 * not, -1 on an error. */
static int bench(int n)
{
	printf("OPENENDED, minds/OpenMaze/Tasks/OpenMaze.simbatch, %d batches, "
	       "--threads %d%s; beside it the same task with OPEN_DEVELOP:0\n",
	       batches, threads, together ? ", the two at once" : "");
	printf("%-15s %4s  %-20s  %-17s  %6s %5s  %8s %8s\n", "", "seed",
	       "ANNECS by thirds", "largest by thirds", "skills", "lost",
	       "time", "CPU");
	int met = 0;
	for (int s = first_seed; s < first_seed + n; s++) {
		job d = {&develop, s, "", 0, 0}, f = {&flat, s, "", 0, 0};
		result rd, rf;
		if (start(&d))
			return -1;
		if (!together && finish(&d, &rd))
			return -1;
		if (start(&f))
			return -1;
		if ((together && finish(&d, &rd)) || finish(&f, &rf))
			return -1;
		print_row(&develop, s, &rd);
		print_row(&flat, s, &rf);
		met += meets(&rd);
	}
	if (curve_prefix && draw_curves())
		return -1;
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
	const char *keep = NULL;
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--together") == 0) {
			together = 1;
			continue;
		}
		int bad = i + 1 >= argc;
		if (!bad && strcmp(argv[i], "--keep") == 0)
			keep = argv[i + 1];
		else if (!bad && strcmp(argv[i], "--curve") == 0)
			curve_prefix = argv[i + 1];
		else if (!bad && strcmp(argv[i], "--seeds") == 0)
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
					"[--threads T] [--together] "
					"[--keep DIR] [--curve PREFIX]\n");
			return 2;
		}
		i++;
	}
	const char *b = getenv("EVO_BUILD");
	snprintf(evo_bin, sizeof evo_bin, "%s/evo", b && b[0] ? b : "build");
	if (keep) {
		struct stat st;
		if (strlen(keep) >= 512 || (mkdir(keep, 0777) &&
					    (stat(keep, &st) || !S_ISDIR(st.st_mode)))) {
			fprintf(stderr, "bench_openended: --keep %s: cannot make "
					"that folder\n",
				keep);
			return 2;
		}
		snprintf(tmpdir, sizeof tmpdir, "%s", keep);
		keep_dir = keep;
	} else {
		snprintf(tmpdir, sizeof tmpdir, "/tmp/evo-bench-openended-XXXXXX");
		if (!mkdtemp(tmpdir)) {
			perror("bench_openended: mkdtemp");
			return 1;
		}
	}
	int ok = bench(seeds);
	char cmd[1100];
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
	if (!keep && bench_sh(cmd) != 0)
		fprintf(stderr, "bench_openended: could not remove %s\n",
			tmpdir);
	return ok == 1 ? 0 : 1;
}

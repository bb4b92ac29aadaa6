/* make bench: novelty search on the hard maze (issue 29, acceptance 1),
 * beside objective NEAT on the same maze and budget.
 *
 * For each seed s, each method trains minds/Maze's skill in its own fresh
 * copy of the folder, with the task as shipped, by `evo run TASK --seed s
 * --run DIR`, exactly what a user gets:
 *
 *   NOVELTY  Tasks/HardMaze-NOVELTY.simbatch  up to 1,000 generations of 250
 *   NEAT     Tasks/HardMaze-NEAT.simbatch     the same, by --generations 1000
 *
 * (250,000 evaluations at most, one 400-step episode each, the paper's
 * budget). A run stops at the first generation in which a robot ends
 * within 5 units of the goal (env.solved); the evaluations to solve are
 * those of the generations up to and including that one, read from the
 * run's log.csv (its `solved` and `evaluations` columns).
 *
 * Printed beside: the paper (Lehman & Stanley 2011), novelty search solved
 * the hard maze in 39 of 40 runs within 250,000 evaluations; an
 * independent reproduction (the same robot and maze, NEAT population 250,
 * 400 steps), 10 of 10 runs with a mean of 29,531 evaluations, and
 * objective NEAT 0 of 10.
 *
 * Bar: NOVELTY solves at least 39/40 of its runs (with N seeds, at least
 * ceil(39 N / 40)) within 250,000 evaluations; exit 1 when not met.
 *
 * Time: a generation of 250 takes about half a second with one thread on
 * a shared two-core machine; a NOVELTY run solves in seconds, and an
 * objective NEAT run, which stays in the trap, uses all 1,000 generations
 * (about 8 minutes). The default is 5 NOVELTY seeds and 2 NEAT seeds,
 * under 20 minutes; --seeds 40 is the paper's figure, and --first lets
 * several benches share the cores.
 *
 * usage: bench_maze_ns [--seeds N] [--neat-seeds M] [--first S] [--threads T]
 *   --seeds N       NOVELTY on seeds S .. S + N - 1 (default 5; 0: none)
 *   --neat-seeds M  NEAT on seeds S .. S + M - 1 (default 2; 0: none)
 *   --first S       the first seed (default 1): several benches on
 *                   different seeds can share a machine's cores
 *   --threads T     worker threads of each run (default 2) */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_proc.h"
#include "base/fileio.h"
#include "base/number.h"

#define DEFAULT_SEEDS	   5
#define DEFAULT_NEAT_SEEDS 2
#define GENERATIONS	   1000
#define POPULATION	   250
#define BUDGET		   (GENERATIONS * POPULATION)
#define REPRODUCTION_MEAN  29531

typedef struct method {
	const char *name; /* as printed */
	const char *task; /* the training task under minds/Maze/Tasks/ */
} method;

static const method novelty = {"NOVELTY", "HardMaze-NOVELTY"};
static const method neat = {"NEAT", "HardMaze-NEAT"};

/* One run's result. */
typedef struct result {
	int solved;	    /* a robot reached the goal */
	int generation;	    /* the generation it did, or the last one run */
	long evaluations;   /* up to and including that generation */
	double secs;	    /* wall seconds of the run */
} result;

static char evo_bin[256];
static char tmpdir[128];
static int threads = 2;
static int first_seed = 1;

/* Field k (0 based) of a log.csv row. */
static const char *field(const char *row, int k)
{
	for (int c = 0; c < k && row; c++) {
		row = strchr(row, ',');
		if (row)
			row++;
	}
	return row;
}

/* Reads the run's log.csv into r: 0, or -1 after a message. */
static int read_log(result *r)
{
	char path[512], *data;
	size_t len;
	evo_err err;
	snprintf(path, sizeof path, "%s/run/log.csv", tmpdir);
	if (evo_read_file(path, &data, &len, &err)) {
		fprintf(stderr, "bench_maze_ns: %s\n", err.msg);
		return -1;
	}
	if (strncmp(data,
		    "generation,best,mean,best_ever,species,evaluations,"
		    "solved,",
		    58) != 0) {
		fprintf(stderr, "bench_maze_ns: %s: not the columns expected\n",
			path);
		free(data);
		return -1;
	}
	r->solved = 0;
	r->generation = -1;
	r->evaluations = 0;
	for (char *line = strchr(data, '\n'); line && line[1] && !r->solved;
	     line = strchr(line, '\n')) {
		line++;
		const char *ev = field(line, 5), *so = field(line, 6);
		if (!ev || !so)
			break;
		r->generation = (int)strtol(line, NULL, 10);
		r->evaluations += strtol(ev, NULL, 10);
		r->solved = strtol(so, NULL, 10) > 0;
	}
	free(data);
	return 0;
}

/* Trains a fresh copy of minds/Maze with m's task and seed: 0 with *r, or
 * -1 after a message. */
static int run_once(const method *m, int seed, result *r)
{
	char cmd[2048];
	snprintf(cmd, sizeof cmd,
		 "rm -rf %s/m %s/run && mkdir -p %s/m && cp -r minds/Maze "
		 "%s/m/",
		 tmpdir, tmpdir, tmpdir, tmpdir);
	if (bench_sh(cmd) != 0) {
		fprintf(stderr,
			"bench_maze_ns: could not copy minds/Maze to %s/m\n",
			tmpdir);
		return -1;
	}
	snprintf(cmd, sizeof cmd,
		 "%s run %s/m/Maze/Tasks/%s.simbatch --seed %d --threads %d "
		 "--generations %d --run %s/run > %s/train.txt 2>&1",
		 evo_bin, tmpdir, m->task, seed, threads, GENERATIONS, tmpdir,
		 tmpdir);
	double t0 = bench_now();
	int rc = bench_sh(cmd);
	r->secs = bench_now() - t0;
	if (rc != 0) {
		fprintf(stderr,
			"bench_maze_ns: %s seed %d: evo run failed; see "
			"%s/train.txt\n",
			m->name, seed, tmpdir);
		return -1;
	}
	if (read_log(r))
		return -1;
	/* progress, off the table: a run takes minutes */
	fprintf(stderr,
		"bench_maze_ns: %s seed %d: %s in generation %d, %ld "
		"evaluations, %.0f s\n",
		m->name, seed, r->solved ? "solved" : "not solved",
		r->generation, r->evaluations, r->secs);
	return 0;
}

/* What the runs of one method gave. */
typedef struct tally {
	int runs, solved;
	double evals_solved; /* summed over the runs that solved */
	double secs;
} tally;

/* n seeds of m from first_seed, a row each: 0 with *t, or -1 on an
 * error. */
static int run_method(const method *m, int n, tally *t)
{
	memset(t, 0, sizeof *t);
	for (int s = first_seed; s < first_seed + n; s++) {
		result r;
		if (run_once(m, s, &r))
			return -1;
		t->runs++;
		t->secs += r.secs;
		if (r.solved) {
			t->solved++;
			t->evals_solved += (double)r.evaluations;
		}
		printf("%-8s %4d  %-10s %10d %11ld %7.0fs\n", m->name, s,
		       r.solved ? "solved" : "not solved", r.generation,
		       r.evaluations, r.secs);
		fflush(stdout);
	}
	return 0;
}

static void print_tally(const method *m, const tally *t)
{
	printf("%s: solved %d of %d runs within %d evaluations", m->name,
	       t->solved, t->runs, BUDGET);
	if (t->solved > 0)
		printf(", mean %.0f evaluations to solve",
		       t->evals_solved / t->solved);
	printf(", mean %.0f s a run\n", t->runs ? t->secs / t->runs : 0);
}

/* Prints the table and the summary: 1 when the bar is met, 0 when not, -1
 * on an error. */
static int bench(int n, int n_neat)
{
	printf("Hard maze (Lehman & Stanley 2011): NOVELTY and objective NEAT, "
	       "%d networks a generation, at most %d evaluations\n",
	       POPULATION, BUDGET);
	printf("(minds/Maze/Tasks/HardMaze-NOVELTY and HardMaze-NEAT as "
	       "shipped, --generations %d --threads %d)\n",
	       GENERATIONS, threads);
	printf("%-8s %4s  %-10s %10s %11s %8s\n", "method", "seed", "result",
	       "generation", "evaluations", "time");
	tally nov, obj;
	if (run_method(&novelty, n, &nov) || run_method(&neat, n_neat, &obj))
		return -1;
	if (n > 0) {
		print_tally(&novelty, &nov);
		printf("  beside: the paper, 39 of 40 within 250,000; the "
		       "reproduction, 10 of 10, mean %d evaluations\n",
		       REPRODUCTION_MEAN);
	}
	if (n_neat > 0) {
		print_tally(&neat, &obj);
		printf("  beside: the reproduction's objective NEAT, 0 of 10 "
		       "on the hard maze\n");
	}
	if (n == 0) {
		printf("bar: not measured (no NOVELTY run)\n");
		return 0;
	}
	int need = (39 * n + 39) / 40;
	int ok = nov.solved >= need;
	printf("bar: NOVELTY solves at least 39/40 of its runs within %d "
	       "evaluations (%d of %d needed): %d of %d, %s\n",
	       BUDGET, need, n, nov.solved, n, ok ? "met" : "NOT MET");
	fflush(stdout);
	return ok;
}

/* A whole number from lo to hi for option opt: 0 with *out, or -1 after
 * a message. */
static int whole_arg(const char *opt, const char *text, int lo, int hi,
		     int *out)
{
	long long v;
	if (evo_parse_whole(text, NULL, lo, hi, &v)) {
		fprintf(stderr,
			"bench_maze_ns: %s wants a whole number from %d to %d, "
			"found '%s'\n",
			opt, lo, hi, text);
		return -1;
	}
	*out = (int)v;
	return 0;
}

int main(int argc, char **argv)
{
	int seeds = DEFAULT_SEEDS, neat_seeds = DEFAULT_NEAT_SEEDS;
	for (int i = 1; i < argc; i++) {
		int bad = i + 1 >= argc;
		if (!bad && strcmp(argv[i], "--seeds") == 0)
			bad = whole_arg(argv[i], argv[i + 1], 0, 1000, &seeds);
		else if (!bad && strcmp(argv[i], "--neat-seeds") == 0)
			bad = whole_arg(argv[i], argv[i + 1], 0, 1000,
					&neat_seeds);
		else if (!bad && strcmp(argv[i], "--first") == 0)
			bad = whole_arg(argv[i], argv[i + 1], 1, 1000000,
					&first_seed);
		else if (!bad && strcmp(argv[i], "--threads") == 0)
			bad = whole_arg(argv[i], argv[i + 1], 1, 256, &threads);
		else
			bad = 1;
		if (bad) {
			fprintf(stderr, "usage: bench_maze_ns [--seeds N] "
					"[--neat-seeds M] [--first S] "
					"[--threads T]\n");
			return 2;
		}
		i++;
	}
	const char *b = getenv("EVO_BUILD");
	snprintf(evo_bin, sizeof evo_bin, "%s/evo", b && b[0] ? b : "build");
	snprintf(tmpdir, sizeof tmpdir, "/tmp/evo-bench-maze-ns-XXXXXX");
	if (!mkdtemp(tmpdir)) {
		perror("bench_maze_ns: mkdtemp");
		return 1;
	}
	int ok = bench(seeds, neat_seeds);
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
	if (bench_sh(cmd) != 0)
		fprintf(stderr, "bench_maze_ns: could not remove %s\n",
			tmpdir);
	return ok == 1 ? 0 : 1;
}

/* make bench: how fast the LEARNSIM evaluator runs the mazes
 * (docs/world.md, "The mazes"), in episodes a second with two worker
 * threads, and what one robot step costs (sensing, the network, the
 * physics, the rewards) in processor time. On a machine others share, the
 * wall clock says what the others left; the processor time says what the
 * step costs, and 2 / (processor time per episode) is what two free cores
 * would run.
 *
 * Each maze's batch is 256 random layered networks (weights in [-4, 4):
 * robots that drive, turn and hit walls) for its skill, each evaluated on
 * one episode of the maze's length: Kheperax's standard maze (250 steps)
 * and the novelty-search paper's hard maze (400). A first batch is
 * untimed; then the best of three. The episodes a network ends early (the
 * target task's goal reached) count as whole ones; these tasks end none.
 * Bar (issue 29): Kheperax at 1,700 episodes a second on two threads, the
 * rate 375,000 episodes in 226 s need.
 *
 * usage: bench_maze */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "bench_proc.h"
#include "learn/evaluate.h"
#include "mind/net_build.h"

#define N_CAND 256
#define ROUNDS 3
#define BAR    1700.0

/* The processor time of the whole process, in seconds. */
static double cpu_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Episodes a second of task with 2 threads, over ticks-step episodes, and
 * in *cpu the least processor time of a batch; a negative value on
 * failure. */
static double rate(const char *task, long ticks, double *cpu)
{
	evo_err err = {{0}};
	evo_eval_def d = {
	    .task_path = task, .threads = 2, .seed = 1, .ticks = ticks};
	evo_evaluator *ev = evo_evaluator_create(&d, &err);
	if (!ev) {
		fprintf(stderr, "bench_maze: %s\n", err.msg);
		return -1;
	}
	const evo_eval_settings *set = evo_evaluator_settings(ev);
	unsigned n_in = set->n_in, n_out = set->n_out;
	size_t nw = evo_net_layered_weight_count(n_in, n_out, 0, 1);
	double *w = malloc(nw * sizeof *w);
	evo_netdesc *net = calloc(N_CAND, sizeof *net);
	const evo_netdesc **c = calloc(N_CAND, sizeof *c);
	evo_eval_result *res = calloc(N_CAND, sizeof *res);
	evo_rng r = evo_rng_seed(7);
	double best = -1;
	if (!w || !net || !c || !res)
		goto out;
	for (int i = 0; i < N_CAND; i++) {
		for (size_t k = 0; k < nw; k++)
			w[k] = evo_rng_range(&r, -4, 4);
		if (evo_net_build_layered(n_in, n_out, 0, 1, EVO_ACT_SIGMOID,
					  EVO_ACT_SIGMOID, w,
					  &net[i]) != EVO_OK)
			goto out;
		c[i] = &net[i];
	}
	best = 1e30;
	*cpu = 1e30;
	for (int k = 0; k <= ROUNDS; k++) {
		double c0 = cpu_now();
		double t0 = bench_now();
		if (evo_evaluate(ev, c, N_CAND, 0, res, &err)) {
			fprintf(stderr, "bench_maze: %s\n", err.msg);
			best = -1;
			goto out;
		}
		double t = bench_now() - t0;
		double used = cpu_now() - c0;
		if (k > 0) { /* the first: page faults, Lua's first calls */
			best = t < best ? t : best;
			*cpu = used < *cpu ? used : *cpu;
		}
	}
	best = N_CAND / best;
out:
	free(w);
	free(net);
	free(c);
	free(res);
	evo_evaluator_destroy(ev);
	return best;
}

int main(void)
{
	static const struct {
		const char *name, *task;
		long ticks;
	} mazes[] = {
	    {"Kheperax standard maze",
	     "minds/Kheperax/Tasks/Kheperax-NEAT.simbatch", 250},
	    {"novelty-search hard maze",
	     "minds/Maze/Tasks/HardMaze-NEAT.simbatch", 400},
	};
	double kheperax = 0;
	for (int m = 0; m < 2; m++) {
		double cpu;
		double eps = rate(mazes[m].task, mazes[m].ticks, &cpu);
		if (eps < 0) {
			fprintf(stderr, "bench_maze: could not run\n");
			return 2;
		}
		double steps = (double)N_CAND * (double)mazes[m].ticks;
		double free2 = 2 * N_CAND / cpu;
		printf("%s: %d episodes of %ld steps, 2 threads: %.0f "
		       "episodes/s by the clock; %.2f us of processor time a "
		       "robot step, %.0f episodes/s on two free cores (best "
		       "of %d)\n",
		       mazes[m].name, N_CAND, mazes[m].ticks, eps,
		       cpu / steps * 1e6, free2, ROUNDS);
		if (m == 0)
			kheperax = free2;
	}
	printf("Kheperax on two free cores: %.0f episodes/s, bar %.0f: %s\n",
	       kheperax, BAR, kheperax >= BAR ? "met" : "NOT MET");
	return kheperax >= BAR ? 0 : 1;
}

/* The LEARNSIM evaluator (sim/learn/evaluate.c) on EXP_Avoid (the Avoid example
 * in EvoAgents' environment, whose start is fixed and whose rewards pay
 * for standing still in the open): fitness does not
 * depend on the number of threads and repeats bit for bit; generations
 * change the grids; a candidate's index changes its episode seed but not
 * its grids; a network of the wrong shape is refused by name; a network
 * the mind image refuses fails its batch by name while the other workers
 * run theirs, and leaves the evaluator as good as new; a
 * zero-weight network (wheels neutral) earns a fitness we can reason
 * about. Episodes are kept short (300 ticks) so this runs in seconds, also
 * under ASan. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/alloc_fail.h"
#include "learn/evaluate.h"
#include "mind/net_build.h"
#include "support/rng.h"

#define AVOID  "minds/Avoid/Tasks/Avoid-EXP-NEAT.simbatch"
#define N_CAND 8

static evo_netdesc *cand[N_CAND];
static evo_netdesc *zero_net;

/* Avoid's skill shape: 11 inputs, 2 outputs, layers:0. Random weights in
 * [-4, 4): enough to make the bot drive and hit things. */
static evo_netdesc *random_net(rng *r, unsigned n_in, unsigned n_out,
			       double scale)
{
	evo_netdesc *d = calloc(1, sizeof *d);
	size_t nw = evo_net_layered_weight_count(n_in, n_out, 0, 1);
	double *w = calloc(nw, sizeof *w);
	for (size_t k = 0; k < nw; k++)
		w[k] = scale * rng_uniform(r, -4, 4);
	if (evo_net_build_layered(n_in, n_out, 0, 1, EVO_ACT_SIGMOID,
				  EVO_ACT_SIGMOID, w, d) != EVO_OK) {
		free(d);
		d = NULL;
	}
	free(w);
	return d;
}

static evo_evaluator *make(int threads, uint64_t seed, int reps, long ticks)
{
	evo_err err = {{0}};
	evo_eval_def def = {.task_path = AVOID,
			    .threads = threads,
			    .seed = seed,
			    .reps = reps,
			    .ticks = ticks};
	evo_evaluator *ev = evo_evaluator_create(&def, &err);
	if (!ev)
		printf("  evaluator: %s\n", err.msg);
	return ev;
}

/* The last batch's results, whose fitness run_batch copies to fit. */
static evo_eval_result last[N_CAND + 8];

static int run_batch(evo_evaluator *ev, const evo_netdesc *const *c, int n,
		     int gen, double *fit)
{
	evo_err err = {{0}};
	int rc = evo_evaluate(ev, c, n, gen, last, &err);
	if (rc)
		printf("  evaluate: %s\n", err.msg);
	for (int i = 0; i < n && rc == 0; i++)
		fit[i] = last[i].fitness;
	return rc;
}

static double fit1[N_CAND], fit2[N_CAND];
static long col1[N_CAND];

TEST(defaults_from_the_task)
{
	evo_evaluator *ev = make(0, 1, 0, 0);
	CHECK(ev != NULL);
	if (!ev)
		return;
	CHECK(evo_evaluator_settings(ev)->threads >= 1);
	const evo_eval_settings *set = evo_evaluator_settings(ev);
	CHECK_EQ_INT(set->reps, 2);	/* EVALREP:2 */
	CHECK_EQ_INT(set->ticks, 2000); /* TICKLIM:2000 */
	CHECK_EQ_INT(evo_evaluator_settings(ev)->n_in, 11);
	CHECK_EQ_INT(evo_evaluator_settings(ev)->n_out, 2);
	/* EXP_Avoid reports no metrics of its own */
	CHECK_EQ_INT(evo_evaluator_settings(ev)->n_metrics, 0);
	CHECK(evo_evaluator_metric_name(ev, 0) == NULL);
	evo_evaluator_destroy(ev);
}

/* One thread and two threads, same seed: the same bits. Repeating a batch
 * on the same evaluator (whose workers have run other candidates since)
 * gives the same bits again: no state leaks from one evaluation to the
 * next. */
TEST(threads_do_not_change_fitness)
{
	evo_evaluator *e1 = make(1, 42, 2, 300), *e2 = make(2, 42, 2, 300);
	CHECK(e1 && e2);
	if (!e1 || !e2)
		goto out;
	const evo_netdesc *const *c = (const evo_netdesc *const *)cand;
	CHECK_EQ_INT(run_batch(e1, c, N_CAND, 0, fit1), 0);
	for (int i = 0; i < N_CAND; i++)
		col1[i] = last[i].collisions;
	CHECK_EQ_INT(run_batch(e2, c, N_CAND, 0, fit2), 0);
	CHECK(memcmp(fit1, fit2, sizeof fit1) == 0);
	/* Not all alike: the candidates really differ. Random weights this
	 * large drive the bot into things: some candidate collides, and
	 * the collision counts too do not depend on the threads. */
	int differ = 0, collided = 0;
	for (int i = 0; i < N_CAND; i++) {
		printf("  candidate %d: %.6f, %ld collision ticks\n", i,
		       fit1[i], col1[i]);
		differ |= fit1[i] != fit1[0];
		collided |= col1[i] > 0;
		CHECK(last[i].collisions == col1[i]);
		CHECK(!last[i].solved);
	}
	CHECK(differ);
	CHECK(collided);

	double again[N_CAND];
	CHECK_EQ_INT(run_batch(e2, c, N_CAND, 0, again), 0);
	CHECK(memcmp(fit1, again, sizeof again) == 0);
	CHECK_EQ_INT(run_batch(e1, c, N_CAND, 0, again), 0);
	CHECK(memcmp(fit1, again, sizeof again) == 0);

	/* Generation 1 meets other grids: some candidate's fitness moves. */
	double gen1[N_CAND];
	CHECK_EQ_INT(run_batch(e2, c, N_CAND, 1, gen1), 0);
	int moved = 0;
	for (int i = 0; i < N_CAND; i++)
		moved |= gen1[i] != fit1[i];
	CHECK(moved);
out:
	evo_evaluator_destroy(e1);
	evo_evaluator_destroy(e2);
}

/* A part of a batch (evo_evaluate_part, what each MPI rank of a cluster
 * run evaluates) gives for its candidates the bits the whole batch gives
 * them, because they keep their index in the batch (their episode seeds).
 * A wrong candidate is named by its index in the whole batch. */
TEST(a_part_of_a_batch_gives_what_the_whole_batch_gives)
{
	evo_evaluator *ev = make(2, 42, 2, 300);
	CHECK(ev != NULL);
	if (!ev)
		return;
	const evo_netdesc *const *c = (const evo_netdesc *const *)cand;
	double whole[N_CAND];
	CHECK_EQ_INT(run_batch(ev, c, N_CAND, 3, whole), 0);
	evo_eval_result part[4];
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_evaluate_part(ev, c + 3, 3, 4, 3, part, &err), 0);
	for (int i = 0; i < 4; i++)
		CHECK(part[i].fitness == whole[3 + i]);
	const evo_netdesc *bad[2] = {cand[0], zero_net};
	evo_netdesc wrong = *zero_net;
	wrong.n_in = 3;
	bad[1] = &wrong;
	CHECK_EQ_INT(evo_evaluate_part(ev, bad, 5, 2, 3, part, &err), -1);
	CHECK_CONTAINS(err.msg, "candidate 6: the network has 3 inputs");
	evo_evaluator_destroy(ev);
}

/* Seeds: the grid seed depends on (seed, generation, rep) only, the
 * episode seed also on the candidate's index; the two streams differ. */
TEST(seed_derivation)
{
	CHECK(evo_eval_grid_seed(7, 3, 0) == evo_eval_grid_seed(7, 3, 0));
	CHECK(evo_eval_grid_seed(7, 3, 0) != evo_eval_grid_seed(7, 3, 1));
	CHECK(evo_eval_grid_seed(7, 3, 0) != evo_eval_grid_seed(7, 4, 0));
	CHECK(evo_eval_grid_seed(7, 3, 0) != evo_eval_grid_seed(8, 3, 0));
	CHECK(evo_eval_episode_seed(7, 3, 0, 0) !=
	      evo_eval_episode_seed(7, 3, 5, 0));
	CHECK(evo_eval_episode_seed(7, 3, 0, 0) !=
	      evo_eval_episode_seed(7, 3, 0, 1));
	CHECK(evo_eval_episode_seed(7, 3, 0, 0) !=
	      evo_eval_episode_seed(7, 4, 0, 0));
	CHECK(evo_eval_episode_seed(7, 3, 0, 0) != evo_eval_grid_seed(7, 3, 0));
}

/* The same network at indices 0 and 5 of one batch: different episode
 * seeds (seed_derivation) but the same grids. In EXP_Avoid the start is
 * fixed and no sensor is random, so nothing the episode seed drives
 * reaches a deterministic network: the two fitnesses are identical. (Were
 * the grids different, they would not be: gen 0 vs gen 1 above.) */
TEST(same_candidate_two_indices_same_grids)
{
	evo_evaluator *ev = make(2, 42, 2, 300);
	CHECK(ev != NULL);
	if (!ev)
		return;
	const evo_netdesc *c[6] = {cand[3], cand[1], cand[2],
				   cand[4], cand[5], cand[3]};
	double f[6];
	CHECK_EQ_INT(run_batch(ev, c, 6, 0, f), 0);
	CHECK(f[0] == f[5]);
	CHECK(f[0] == fit1[3]); /* and the same as at index 3 earlier */
	evo_evaluator_destroy(ev);
}

/* A network with 10 inputs for an 11-input skill: refused, naming the
 * candidate and both shapes; nothing is evaluated. The evaluator stays
 * usable. */
TEST(wrong_shape_is_refused)
{
	evo_evaluator *ev = make(2, 42, 1, 50);
	CHECK(ev != NULL);
	if (!ev)
		return;
	rng r = rng_seed(9);
	evo_netdesc *bad = random_net(&r, 10, 2, 1);
	const evo_netdesc *c[3] = {cand[0], cand[1], bad};
	double f[3];
	evo_eval_result res[3];
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_evaluate(ev, c, 3, 0, res, &err), -1);
	CHECK_CONTAINS(err.msg, "candidate 2");
	CHECK_CONTAINS(err.msg, "10 inputs");
	CHECK_CONTAINS(err.msg, "skill Avoid has 11 inputs");
	bad->n_in = 11;
	bad->n_out = 3;
	CHECK_EQ_INT(evo_evaluate(ev, c, 3, 0, res, &err), -1);
	CHECK_CONTAINS(err.msg, "candidate 2");
	CHECK_CONTAINS(err.msg, "3 outputs");
	c[2] = cand[2];
	CHECK_EQ_INT(run_batch(ev, c, 3, 0, f), 0);
	free(bad);
	evo_evaluator_destroy(ev);
}

/* A candidate of the right shape that the mind image refuses (its output
 * names a node it does not have) passes evo_evaluate's shape check and
 * fails on its worker only, while the other workers are mid-evaluation:
 * four threads, sixteen candidates of 2 x 300 ticks, the bad one at index
 * 6, which a worker takes only after the first four are under way. The
 * batch fails naming that candidate and its generation; the failing
 * worker's mind folder then holds the refused network and no image. A
 * second batch failing at its last index is named by its own index, not
 * the first's. A good batch afterwards gets the same fitness and
 * collisions, bit for bit, as a fresh evaluator gives it, and destroy
 * joins cleanly (ASan and TSan runs see it). */
TEST(failing_candidate_amid_a_batch)
{
	enum { THREADS = 4, N = 16, BAD = 6 };
	evo_evaluator *ev = make(THREADS, 42, 2, 300), *fresh = NULL;
	evo_netdesc *bad = malloc(sizeof *bad);
	CHECK(ev && bad);
	if (!ev || !bad)
		goto out;
	*bad = *cand[1];
	bad->out_id[0] = 999; /* no node 999: EVO_ERR_NAME */
	const evo_netdesc *c[N];
	for (int i = 0; i < N; i++)
		c[i] = cand[i % N_CAND];
	c[BAD] = bad;
	evo_eval_result res[N];
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_evaluate(ev, c, N, 3, res, &err), -1);
	CHECK_CONTAINS(err.msg, "generation 3, candidate 6: ");
	CHECK_CONTAINS(err.msg, "cannot build the mind image");
	printf("  failed as: %s\n", err.msg);

	c[BAD] = cand[BAD % N_CAND];
	c[N - 1] = bad;
	err.msg[0] = 0;
	CHECK_EQ_INT(evo_evaluate(ev, c, N, 3, res, &err), -1);
	CHECK_CONTAINS(err.msg, "generation 3, candidate 15: ");
	CHECK(!strstr(err.msg, "candidate 6:"));

	c[N - 1] = cand[(N - 1) % N_CAND];
	double after[N], want[N];
	long after_col[N];
	CHECK_EQ_INT(run_batch(ev, c, N, 3, after), 0);
	for (int i = 0; i < N; i++)
		after_col[i] = last[i].collisions;
	fresh = make(THREADS, 42, 2, 300);
	CHECK(fresh != NULL);
	if (!fresh)
		goto out;
	CHECK_EQ_INT(run_batch(fresh, c, N, 3, want), 0);
	CHECK(memcmp(after, want, sizeof want) == 0);
	for (int i = 0; i < N; i++)
		CHECK_EQ_INT(after_col[i], last[i].collisions);
out:
	free(bad);
	evo_evaluator_destroy(ev);
	evo_evaluator_destroy(fresh);
}

/* All weights zero: both wheels get 0.5, which is neutral, so the bot
 * stays where it starts (no obstacle within reach of the start: the grid
 * keeps clear of it). Its sensors then read the same every tick and every
 * tick earns the same reward: twice the ticks give twice the fitness, and
 * its fitness does not depend on its index. With no motion there is no
 * ForwardMotion, Speed or collision reward, so the per-tick reward is
 * what the proximity thresholds give: we print it. */
TEST(zero_network_stands_still)
{
	evo_evaluator *a = make(2, 5, 1, 200), *b = make(1, 5, 1, 400);
	CHECK(a && b);
	if (!a || !b)
		goto out;
	const evo_netdesc *c[3] = {zero_net, cand[0], zero_net};
	double fa[3], fb[3];
	CHECK_EQ_INT(run_batch(a, c, 3, 0, fa), 0);
	CHECK_EQ_INT(run_batch(b, c, 3, 0, fb), 0);
	printf("  zero network: %.6f over 200 ticks, %.6f over 400\n", fa[0],
	       fb[0]);
	CHECK(fa[0] == fa[2]);
	CHECK(fb[0] == fb[2]);
	CHECK(fabs(fb[0] - 2 * fa[0]) <= 1e-9 * (1 + fabs(fa[0])));
out:
	evo_evaluator_destroy(a);
	evo_evaluator_destroy(b);
}

/* Only DPNV leaves success to the learning loop, which picks the one
 * network a generation that gets the paper's test: the batch itself marks
 * no DPNV candidate solved, however well it does. XOR marks its solvers. */
TEST(dpnv_success_is_deferred)
{
	evo_err err = {{0}};
	evo_eval_def def = {.task_path =
				"minds/DoublePoleNV/Tasks/DPNV-NEAT.simbatch",
			    .threads = 2};
	evo_evaluator *ev = evo_evaluator_create(&def, &err);
	CHECK(ev != NULL);
	if (!ev) {
		printf("  evaluator: %s\n", err.msg);
		return;
	}
	CHECK_EQ_INT(evo_evaluator_deferred_success(ev), 1);
	evo_evaluator_destroy(ev);
	def.task_path = "minds/XOR/Tasks/XOR-NEAT.simbatch";
	ev = evo_evaluator_create(&def, &err);
	CHECK(ev != NULL);
	if (ev)
		CHECK_EQ_INT(evo_evaluator_deferred_success(ev), 0);
	evo_evaluator_destroy(ev);
	ev = make(1, 1, 1, 10);
	CHECK(ev != NULL);
	if (ev)
		CHECK_EQ_INT(evo_evaluator_deferred_success(ev), 0);
	evo_evaluator_destroy(ev);
}

TEST(bad_task_is_refused)
{
	evo_err err = {{0}};
	evo_eval_def def = {.task_path = "minds/Avoid/Tasks/none.simbatch"};
	evo_evaluator *ev = evo_evaluator_create(&def, &err);
	CHECK(ev == NULL);
	CHECK_CONTAINS(err.msg, "none.simbatch");
	evo_evaluator_destroy(ev);
}

/* The evaluator copies the task's path, and each worker loads its own
 * mind folder (two copies each); memory running out at any of these
 * strdups makes evo_evaluator_create fail with a message, and frees what
 * it had made (LeakSanitizer under make test-asan): no crash, no worker
 * left waiting. */
TEST(out_of_memory_while_starting_is_a_message)
{
	int nth = 1;
	for (; nth < 12; nth++) {
		evo_err err = {{0}};
		evo_eval_def def = {.task_path = AVOID, .threads = 2};
		alloc_fail_strdup(nth);
		evo_evaluator *ev = evo_evaluator_create(&def, &err);
		int calls = alloc_fail_strdup_calls();
		alloc_fail_strdup(0);
		if (calls < nth) {
			CHECK(ev != NULL);
			evo_evaluator_destroy(ev);
			break;
		}
		CHECK(ev == NULL);
		CHECK_CONTAINS(err.msg, "out of memory");
		if (!strstr(err.msg, "out of memory"))
			printf("    strdup %d failing: %s\n", nth, err.msg);
		evo_evaluator_destroy(ev);
	}
	CHECK(nth > 5); /* the path, then two per worker */
}

int main(void)
{
	rng r = rng_seed(2024);
	for (int i = 0; i < N_CAND; i++)
		cand[i] = random_net(&r, 11, 2, 1);
	zero_net = random_net(&r, 11, 2, 0);
	RUN(defaults_from_the_task);
	RUN(threads_do_not_change_fitness);
	RUN(a_part_of_a_batch_gives_what_the_whole_batch_gives);
	RUN(seed_derivation);
	RUN(same_candidate_two_indices_same_grids);
	RUN(wrong_shape_is_refused);
	RUN(failing_candidate_amid_a_batch);
	RUN(zero_network_stands_still);
	RUN(dpnv_success_is_deferred);
	RUN(bad_task_is_refused);
	RUN(out_of_memory_while_starting_is_a_message);
	for (int i = 0; i < N_CAND; i++)
		free(cand[i]);
	free(zero_net);
	return test_summary();
}

/* make bench: remote simulators over LCM on this machine's loopback
 * (docs/remote.md), each figure beside its baseline in the same run.
 *
 * 1. Lockstep ticks per second between evo and `evo serve` (a
 *    DEMOREMOTESIM episode of the Avoid mind: the mind here, the world
 *    there) beside a plain liblcm round trip of the same message sizes
 *    between two processes, with nothing else done, each on a port of its
 *    own (evo serve's episodes are on its own port). Bar (issue 17): evo
 *    reaches at least 0.8 of the plain round-trip rate.
 * 2. LEARNREMOTESIM evaluations per second with one `evo serve` and with
 *    two (each one environment). Bar (issue 17): two reach at least 1.7
 *    times one.
 *
 * The servers are `evo serve` itself, run in child processes from this
 * program (evo_serve_main). The two sides of a comparison are measured
 * in turns: the lockstep figures are the best of ROUNDS, the scaling's the
 * median of SCALE_ROUNDS rounds' ratios (below).
 *
 * usage: bench_remote [--ticks N] */
#define _POSIX_C_SOURCE 200809L
#include <lcm/lcm.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "bench_proc.h"
#include "bench_args.h"
#include "cmd/serve.h"
#include "learn/evaluate.h"
#include "mind/net_build.h"
#include "mind/task.h"
#include "remote/session.h"
#include "remote/wire.h"

#define DEMO_TASK "minds/Avoid/Tasks/Avoid-REMOTESIM.simbatch"
#define LEARN_TASK "minds/Avoid/Tasks/Avoid-REMOTE-NEAT.simbatch"
#define ROUNDS 3
/* The plain round trip's own port, as each evo serve's episodes have
 * theirs (docs/remote.md): no other process hears its traffic. */
#define PLAIN_URL "udpm://239.255.76.67:7666?ttl=0"
#define LOCKSTEP_BAR 0.8
#define SCALE_BAR 1.7
#define N_CAND 24
/* The scaling's rounds, each one server then two, and its figure the
 * median of the rounds' ratios: a round's two runs are measured minutes
 * apart at most, so a burst of other work on the machine moves both,
 * where the best of each alone would pair one lucky run with another. */
#define SCALE_ROUNDS 7

/* ---- the plain round trip ------------------------------------------------ */

typedef struct echo {
	lcm_t *lcm;
	size_t reply;
	int got;
} echo;

static void on_ping(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
	echo *e = user;
	(void)ch;
	static unsigned char buf[EVO_WIRE_MAX_BYTES];
	if (rb->data_size == 1) { /* the end */
		e->got = -1;
		return;
	}
	lcm_publish(e->lcm, "EVO_BENCH_PONG", buf, (unsigned)e->reply);
}

static void on_pong(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
	(void)rb;
	(void)ch;
	((echo *)user)->got = 1;
}

/* A child that answers each ping with `reply` bytes until told to end. */
static pid_t start_echo(size_t reply)
{
	pid_t pid = fork();
	if (pid != 0)
		return pid;
	echo e = {lcm_create(PLAIN_URL), reply, 0};
	if (!e.lcm)
		_exit(3);
	lcm_subscription_t *s =
	    lcm_subscribe(e.lcm, "EVO_BENCH_PING", on_ping, &e);
	lcm_subscription_set_queue_capacity(s, 10000);
	double limit = bench_now() + 120;
	while (e.got >= 0 && bench_now() < limit)
		lcm_handle_timeout(e.lcm, 100);
	lcm_destroy(e.lcm);
	_exit(0);
}

/* Round trips per second: `send` bytes out, `reply` bytes back. */
static double plain_rate(lcm_t *lcm, echo *e, size_t send, long n)
{
	static unsigned char buf[EVO_WIRE_MAX_BYTES];
	double t0 = bench_now();
	for (long i = 0; i < n; i++) {
		e->got = 0;
		lcm_publish(lcm, "EVO_BENCH_PING", buf, (unsigned)send);
		double limit = bench_now() + 5;
		while (!e->got && bench_now() < limit)
			lcm_handle_timeout(lcm, 100);
		if (!e->got)
			return -1;
	}
	return (double)n / (bench_now() - t0);
}

/* ---- evo serve in a child --------------------------------------------- */

static pid_t start_serve(const char *task, const char *name)
{
	fflush(stdout);
	pid_t pid = fork();
	if (pid != 0)
		return pid;
	/* its line "evo serve: NAME serves ..." is not the bench's */
	if (!freopen("/dev/null", "w", stdout))
		_exit(3);
	char *argv[] = {"evo", "serve", (char *)task, "--name", (char *)name,
			NULL};
	_exit(evo_serve_main(5, argv));
}

static void stop_serve(pid_t pid)
{
	if (pid <= 0)
		return;
	kill(pid, SIGTERM);
	waitpid(pid, NULL, 0);
}

/* Ticks per second of a DEMOREMOTESIM episode against the server. */
static double lockstep_rate(evo_remotes *r, const evo_task *task, long ticks,
			    int round)
{
	const evo_mind *m = &task->mind->mind;
	size_t need = (evo_state_size(m) + 7) & ~(size_t)7;
	void *mem = aligned_alloc(8, need);
	evo_state *state;
	evo_err err = {{0}};
	if (!mem || evo_state_init(m, mem, need, &state) != EVO_OK) {
		free(mem);
		return -1;
	}
	double in[EVO_MAX_SENSORS], out[EVO_MAX_ACTUATORS];
	evo_q16 qin[EVO_MAX_SENSORS], qout[EVO_MAX_ACTUATORS];
	double rate = -1;
	if (evo_remote_reset(r, 0, round + 1, 11, 12, &err) == 0) {
		double t0 = bench_now();
		long t;
		for (t = 0; t < ticks; t++) {
			evo_remote_sensors(r->r[0], 0, in);
			for (unsigned i = 0; i < m->n_sensors; i++)
				qin[i] = evo_q16_from_sensor(in[i]);
			evo_mind_step(m, state, qin, qout);
			for (unsigned i = 0; i < m->n_actuators; i++)
				out[i] = evo_q16_to_double(qout[i]);
			if (evo_remote_step(r, 0, out, &err) != 0)
				break;
		}
		rate = (double)t / (bench_now() - t0);
		if (t < ticks)
			fprintf(stderr, "bench_remote: episode ended at tick "
					"%ld: %s\n",
				t, err.msg);
	} else {
		fprintf(stderr, "bench_remote: %s\n", err.msg);
	}
	free(mem);
	return rate;
}

/* ---- 1: lockstep against the plain round trip --------------------------- */

static int bench_lockstep(long ticks)
{
	char name[64];
	snprintf(name, sizeof name, "bench-%ld", (long)getpid());
	evo_err err = {{0}};
	evo_task task;
	if (evo_task_load(DEMO_TASK, &task, &err)) {
		fprintf(stderr, "bench_remote: %s\n", err.msg);
		return 2;
	}
	/* the message sizes of this mind's ticks */
	evo_wire_sensors s = {.n = task.mind->botdesc->n_sensors};
	evo_wire_command c = {.n = task.mind->botdesc->n_actuators};
	snprintf(s.name, sizeof s.name, "%s", name);
	snprintf(c.name, sizeof c.name, "%s", name);
	static unsigned char buf[EVO_WIRE_MAX_BYTES];
	size_t s_len = (size_t)evo_wire_encode_sensors(&s, buf, sizeof buf);
	size_t c_len = (size_t)evo_wire_encode_command(&c, buf, sizeof buf);

	pid_t echo_pid = start_echo(s_len);
	pid_t serve_pid = start_serve(DEMO_TASK, name);
	lcm_t *lcm = lcm_create(PLAIN_URL);
	echo e = {lcm, 0, 0};
	int rc = 2;
	evo_remote_opts ro = {.name = name, .kind = EVO_REMOTE_SIMULATOR};
	evo_remotes *r = NULL;
	if (!lcm)
		goto out;
	lcm_subscription_t *sub =
	    lcm_subscribe(lcm, "EVO_BENCH_PONG", on_pong, &e);
	lcm_subscription_set_queue_capacity(sub, 10000);
	r = evo_remote_connect(task.mind, &ro, &err);
	if (!r) {
		fprintf(stderr, "bench_remote: %s\n", err.msg);
		goto out;
	}
	/* a first exchange of each, so both sides are up and warm */
	if (plain_rate(lcm, &e, c_len, 200) < 0 ||
	    lockstep_rate(r, &task, 200, 0) < 0) {
		fprintf(stderr, "bench_remote: no answer from the echo or the "
				"server\n");
		goto out;
	}
	double best_plain = 0, best_evo = 0;
	for (int k = 0; k < ROUNDS; k++) {
		double p = plain_rate(lcm, &e, c_len, ticks);
		double v = lockstep_rate(r, &task, ticks, k + 1);
		best_plain = p > best_plain ? p : best_plain;
		best_evo = v > best_evo ? v : best_evo;
	}
	double ratio = best_evo / best_plain;
	unsigned long lost = r->r[0]->resent;
	for (int k = 1; k < EVO_WIRE_N_REASONS; k++)
		lost += r->r[0]->dropped[k];
	printf("Lockstep over LCM on loopback, %zu-byte commands and %zu-byte "
	       "sensor messages, best of %d runs of %ld ticks:\n",
	       c_len, s_len, ROUNDS, ticks);
	printf("  plain liblcm round trip (publish, echo, receive)  %8.0f "
	       "round trips/s\n",
	       best_plain);
	printf("  evo run <-> evo serve (Avoid: mind, world, checks) %8.0f "
	       "ticks/s\n",
	       best_evo);
	printf("  ratio %.2f of the plain round trip (bar: at least %.1f): %s\n",
	       ratio, LOCKSTEP_BAR, ratio >= LOCKSTEP_BAR ? "met" : "NOT MET");
	printf("  messages lost (sent again) or dropped over %ld ticks: %lu\n",
	       200 + ROUNDS * ticks, lost);
	rc = ratio >= LOCKSTEP_BAR ? 0 : 1;
out:
	if (lcm) {
		unsigned char end = 0;
		lcm_publish(lcm, "EVO_BENCH_PING", &end, 1);
	}
	evo_remotes_close(r);
	if (lcm)
		lcm_destroy(lcm);
	waitpid(echo_pid, NULL, 0);
	stop_serve(serve_pid);
	evo_task_free(&task);
	return rc;
}

/* ---- 2: evaluations with one server and with two ----------------------- */

static double eval_rate(evo_evaluator *ev, const evo_netdesc *const *c,
			evo_eval_result *res)
{
	evo_err err = {{0}};
	double t0 = bench_now();
	if (evo_evaluate(ev, c, N_CAND, 0, res, &err)) {
		fprintf(stderr, "bench_remote: %s\n", err.msg);
		return -1;
	}
	return N_CAND / (bench_now() - t0);
}

/* An evaluator that finds `want` servers, one batch timed, destroyed: two
 * evaluators alive at once would each hear the other's traffic. */
static double one_rate(const evo_eval_def *d, int want,
		       const evo_netdesc *const *c, int *reps)
{
	evo_err err = {{0}};
	evo_eval_result res[N_CAND];
	evo_evaluator *ev = evo_evaluator_create(d, &err);
	double rate = -1;
	if (!ev)
		fprintf(stderr, "bench_remote: %s\n", err.msg);
	else if (evo_evaluator_remotes(ev) != want)
		fprintf(stderr, "bench_remote: found %d servers, not %d\n",
			evo_evaluator_remotes(ev), want);
	else
		rate = eval_rate(ev, c, res);
	if (ev)
		*reps = evo_evaluator_settings(ev)->reps;
	evo_evaluator_destroy(ev);
	return rate;
}

static int by_value(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* One line: the median of SCALE_ROUNDS figures, their lowest and
 * highest; returns the median. */
static double print_spread(const char *what, const double *v,
			   const char *unit)
{
	double s[SCALE_ROUNDS];
	memcpy(s, v, sizeof s);
	qsort(s, SCALE_ROUNDS, sizeof *s, by_value);
	double med = s[SCALE_ROUNDS / 2];
	printf("  %s %7.2f  (%.2f-%.2f) %s\n", what, med, s[0],
	       s[SCALE_ROUNDS - 1], unit);
	return med;
}

static int bench_scaling(long ticks)
{
	/* the names the task's REMOTENAME gives (sim1,sim2): a learning
	 * run takes only the simulators its task names */
	const char *n1 = "sim1", *n2 = "sim2";
	evo_eval_def d1 = {.task_path = LEARN_TASK, .seed = 1, .ticks = ticks};
	evo_eval_def d2 = d1;
	int rc = 2, reps = 0;
	evo_netdesc *net = calloc(N_CAND, sizeof *net);
	const evo_netdesc *c[N_CAND];
	double r1[SCALE_ROUNDS], r2[SCALE_ROUNDS], q[SCALE_ROUNDS];
	evo_err err = {{0}};
	evo_task t;
	if (!net || evo_task_load(LEARN_TASK, &t, &err)) {
		fprintf(stderr, "bench_remote: %s\n", err.msg);
		free(net);
		return 2;
	}
	const evo_ades *a = &t.mind->skill[evo_mindfolder_skill(
	    t.mind, evo_simbatch_get(t.sb, "LEARNINGSKILL"))];
	unsigned n_in = a->n_in, n_out = a->n_out;
	evo_task_free(&t);
	size_t nw = evo_net_layered_weight_count(n_in, n_out, 0, 1);
	double *w = malloc(nw * sizeof *w);
	evo_rng r = evo_rng_seed(7);
	for (int i = 0; w && i < N_CAND; i++) {
		for (size_t k = 0; k < nw; k++)
			w[k] = evo_rng_range(&r, -4, 4);
		evo_net_build_layered(n_in, n_out, 0, 1, EVO_ACT_SIGMOID,
				      EVO_ACT_SIGMOID, w, &net[i]);
		c[i] = &net[i];
	}
	free(w);
	/* in turns: the first server alone, then with a second one started
	 * beside it, stopped again before the next turn */
	pid_t pa = start_serve(LEARN_TASK, n1), pb = -1;
	for (int k = 0; k < SCALE_ROUNDS; k++) {
		r1[k] = one_rate(&d1, 1, c, &reps);
		pb = start_serve(LEARN_TASK, n2);
		r2[k] = one_rate(&d2, 2, c, &reps);
		stop_serve(pb);
		pb = -1;
		if (r1[k] < 0 || r2[k] < 0)
			goto out;
		q[k] = r2[k] / r1[k];
	}
	printf("LEARNREMOTESIM on Avoid, %d random networks x %d episodes of at "
	       "most %ld ticks, %d rounds (median, lowest-highest):\n",
	       N_CAND, reps, ticks, SCALE_ROUNDS);
	print_spread("one evo serve   ", r1, "evaluations/s");
	print_spread("two evo serves  ", r2, "evaluations/s");
	double ratio = print_spread("ratio of a round", q, "");
	printf("  median ratio %.2f (bar: at least %.1f): %s\n", ratio,
	       SCALE_BAR, ratio >= SCALE_BAR ? "met" : "NOT MET");
	rc = ratio >= SCALE_BAR ? 0 : 1;
out:
	stop_serve(pa);
	stop_serve(pb);
	free(net);
	return rc;
}

int main(int argc, char **argv)
{
	long ticks = 3000;
	for (int i = 1; i < argc; i++)
		if (strcmp(argv[i], "--ticks") == 0 && i + 1 < argc) {
			long long n;
			if (bench_ticks_arg("bench_remote", argv[++i], &n))
				return 2;
			ticks = (long)n;
		}
	int a = bench_lockstep(ticks);
	int b = bench_scaling(ticks / 10 < 100 ? 100 : ticks / 10);
	return a > b ? a : b;
}

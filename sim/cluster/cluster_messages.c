/* The checks rank 0 makes of what a rank sends (cluster_messages.h). */
#include "cluster/cluster_messages.h"

#include <stdio.h>
#include <string.h>

/* s[0 .. cap-1] ended and made printable: a message from another process
 * goes to the user's terminal, where control bytes would be commands. */
static void printable(char *s, size_t cap)
{
	s[cap - 1] = 0;
	for (; *s; s++)
		if ((unsigned char)*s < 0x20 || *s == 0x7f)
			*s = '?';
}

int evo_cluster_check_hello(const void *msg, size_t len, int rank,
			    const evo_cluster_task *t, evo_cluster_hello *h,
			    evo_err *err)
{
	memset(h, 0, sizeof *h);
	if (len != sizeof *h)
		return evo_fail(err,
				"rank %d: a hello of %zu bytes, where evo's "
				"has %zu: start every rank with the same evo",
				rank, len, sizeof *h);
	memcpy(h, msg, sizeof *h);
	printable(h->host, sizeof h->host);
	printable(h->msg, sizeof h->msg);
	if (h->ok == 0)
		return evo_fail(err, "rank %d (on %s): %s", rank, h->host,
				h->msg);
	if (h->ok != 1)
		return evo_fail(err,
				"rank %d (on %s): a hello whose status is %d "
				"(evo's are 0 and 1): start every rank with "
				"the same evo",
				rank, h->host, (int)h->ok);
	/* rank 0 deals chunks by threads, and divides by their sum */
	if (h->threads < 1 || h->threads > EVO_EVAL_MAX_THREADS)
		return evo_fail(err,
				"rank %d (on %s): a hello with %d threads "
				"(a rank has 1 to %d): start every rank with "
				"the same evo",
				rank, h->host, (int)h->threads,
				EVO_EVAL_MAX_THREADS);
	if (h->seed != t->seed || h->reps != t->reps || h->ticks != t->ticks ||
	    h->n_in != t->n_in || h->n_out != t->n_out)
		return evo_fail(
		    err,
		    "rank %d (on %s) runs the task with seed %llu, %d "
		    "repetitions of %lld ticks, a skill of %u inputs and %u "
		    "outputs; rank 0 with seed %llu, %d of %ld, %u and %u: "
		    "start every rank with the same command and files",
		    rank, h->host, (unsigned long long)h->seed, (int)h->reps,
		    (long long)h->ticks, (unsigned)h->n_in, (unsigned)h->n_out,
		    (unsigned long long)t->seed, t->reps, t->ticks, t->n_in,
		    t->n_out);
	return 0;
}

/* -1 when r's behaviour is none an evaluation gives: more values than
 * evo keeps, or one not in [0, 1] (a NaN included). */
static int behaviour_check(const evo_eval_result *r)
{
	if (r->n_behaviour < 0 || r->n_behaviour > EVO_SIM_MAX_BEHAVIOUR)
		return -1;
	for (int k = 0; k < r->n_behaviour; k++)
		if (!(r->behaviour[k] >= 0 && r->behaviour[k] <= 1))
			return -1;
	return 0;
}

int evo_cluster_check_result(const void *msg, size_t len, int rank,
			     const char *host, int first, int count,
			     evo_eval_result *res, evo_err *err)
{
	int32_t head[3];
	if (len < sizeof head)
		return evo_fail(err, "rank %d (on %s): a result of %zu bytes",
				rank, host, len);
	memcpy(head, msg, sizeof head);
	const char *body = (const char *)msg + sizeof head;
	size_t n = len - sizeof head;
	if (head[2] == 1) {
		/* the rank's own failure: its message, at most what fits */
		char why[900];
		size_t k = n < sizeof why - 1 ? n : sizeof why - 1;
		memcpy(why, body, k);
		why[k] = 0;
		printable(why, sizeof why);
		return evo_fail(err, "rank %d (on %s): %s", rank, host, why);
	}
	if (head[2] != 0)
		return evo_fail(err,
				"rank %d (on %s): a result whose status is %d "
				"(evo's are 0 and 1)",
				rank, host, (int)head[2]);
	if (head[0] != first || head[1] != count ||
	    n != (size_t)count * sizeof *res)
		return evo_fail(err,
				"rank %d (on %s): results of candidates %d.. "
				"(%d, in %zu bytes) for %d.. (%d)",
				rank, host, (int)head[0], (int)head[1], n, first,
				count);
	for (int i = 0; i < count; i++) {
		evo_eval_result r;
		memcpy(&r, body + (size_t)i * sizeof r, sizeof r);
		/* what an evaluation can give: a flag, a count of ticks;
		 * a cluster runs one-agent tasks only (docs/cluster.md), so
		 * no team and no won repetitions */
		if ((r.solved != 0 && r.solved != 1) || r.collisions < 0 ||
		    r.wins != 0 || r.group != 0)
			return evo_fail(err,
					"rank %d (on %s): candidate %d: a "
					"result no evaluation gives (solved "
					"%d, collisions %ld, team %d, wins "
					"%d)",
					rank, host, first + i, r.solved,
					r.collisions, r.group, r.wins);
		if (behaviour_check(&r))
			return evo_fail(err,
					"rank %d (on %s): candidate %d: a "
					"behaviour of %d values, or one not in "
					"[0, 1]",
					rank, host, first + i, r.n_behaviour);
		res[i] = r;
	}
	return 0;
}

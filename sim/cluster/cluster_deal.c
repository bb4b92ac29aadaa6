/* Rank 0's side of a cluster run (sim/cluster/cluster.h): each batch dealt
 * out in chunks to every rank and its own share, the results collected,
 * the ranks greeted, and an OPENENDED batch's environment genome and
 * grown hierarchy sent to them (evo_cluster_spread; the scheme at the top
 * of cluster.c). */
#define _GNU_SOURCE /* sched_getaffinity */
#include "cluster/cluster.h"

#include <mpi.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cluster/cluster_internal.h"

/* Rank 0's batch, shared by its main thread and the thread that runs
 * its own share. */
typedef struct batch {
	evo_evaluator *ev;
	const evo_netdesc *const *cand;
	evo_eval_result *res;
	int n, gen;
	pthread_mutex_t mu; /* guards next, failed, err */
	int next;
	int failed;
	evo_err err;
	int threads; /* of every rank together */
} batch;

/* ---- rank 0 -------------------------------------------------------------- */

static void fail_batch(batch *b, const evo_err *e)
{
	pthread_mutex_lock(&b->mu);
	if (!b->failed) {
		b->failed = 1;
		b->err = *e;
	}
	pthread_mutex_unlock(&b->mu);
}

/* Take a chunk for a rank of `threads` threads from the batch (the top
 * of this file): its count (0 when none is left or the batch failed), the
 * first in *first. */
static int take(batch *b, int threads, int *first)
{
	pthread_mutex_lock(&b->mu);
	int k = 0;
	if (!b->failed && b->next < b->n) {
		int left = b->n - b->next;
		int each = left / (2 * b->threads);
		int most = b->n / (8 * b->threads);
		each = each < most ? each : most;
		k = threads * (each > 1 ? each : 1);
		if (k > left)
			k = left;
		*first = b->next;
		b->next += k;
	}
	pthread_mutex_unlock(&b->mu);
	return k;
}

static int left(batch *b)
{
	pthread_mutex_lock(&b->mu);
	int k = b->failed ? 0 : b->n - b->next;
	pthread_mutex_unlock(&b->mu);
	return k;
}

/* Rank 0's share: chunks on its own workers until the batch is dealt. */
static void *own_share(void *arg)
{
	batch *b = arg;
	int first, k;
	int threads = evo_evaluator_settings(b->ev)->threads;
	while ((k = take(b, threads, &first)) > 0) {
		evo_err e = {{0}};
		if (evo_evaluate_part(b->ev, b->cand + first, first, k, b->gen,
				      b->res + first, &e))
			fail_batch(b, &e);
	}
	return NULL;
}

/* Rank r's next hello, received whatever its size (a larger one would
 * end the job in MPI_Recv) into c->buf; its length. */
static int recv_hello(evo_cluster *c, int r)
{
	MPI_Status st;
	cluster_wait_message(r, TAG_HELLO, &st);
	int len = 0;
	MPI_Get_count(&st, MPI_BYTE, &len);
	if (!cluster_room(c, len > 0 ? (size_t)len : 1))
		cluster_out_of_memory(c->rank);
	MPI_Recv(c->buf, len, MPI_BYTE, r, TAG_HELLO, MPI_COMM_WORLD,
		 MPI_STATUS_IGNORE);
	return len > 0 ? len : 0;
}

/* Wait for every rank's hello and check it runs the task as rank 0 does. */
static int greet(evo_cluster *c, const evo_evaluator *ev, evo_err *err)
{
	if (c->greeted > 0)
		return 0;
	if (c->greeted < 0) {
		*err = c->greet_err;
		return -1;
	}
	c->peer[0].threads = evo_evaluator_settings(ev)->threads;
	evo_cluster_task t = {
	    .seed = c->seed,
	    .reps = evo_evaluator_settings(ev)->reps,
	    .ticks = evo_evaluator_settings(ev)->ticks,
	    .n_in = evo_evaluator_settings(ev)->n_in,
	    .n_out = evo_evaluator_settings(ev)->n_out,
	};
	int rc = 0;
	for (int r = 1; r < c->size; r++) {
		int len = recv_hello(c, r);
		if (rc)
			continue; /* the first failure is the one told */
		evo_cluster_hello h;
		rc = evo_cluster_check_hello(c->buf, (size_t)len, r, &t, &h,
					     err);
		if (rc == 0) {
			c->peer[r].threads = h.threads;
			snprintf(c->peer[r].host, sizeof c->peer[r].host, "%s",
				 h.host);
		}
	}
	if (rc) {
		c->greeted = -1;
		c->greet_err = *err;
		return -1;
	}
	c->greeted = 1;
	int total = 0;
	for (int r = 0; r < c->size; r++)
		total += c->peer[r].threads;
	if (!c->told++) {
		printf("cluster: %d ranks, %d threads in all\n", c->size,
		       total);
		fflush(stdout);
	}
	return 0;
}

/* Send rank r a chunk; 0 when none is left. */
static int deal(evo_cluster *c, batch *b, int r)
{
	int first, k = take(b, c->peer[r].threads, &first);
	if (k == 0)
		return 0;
	size_t n = 12;
	for (int i = 0; i < k; i++)
		n += cluster_net_bytes(b->cand[first + i]);
	unsigned char *buf = malloc(n), *p = buf;
	if (!buf) {
		evo_err e;
		evo_fail(&e, "out of memory");
		fail_batch(b, &e);
		return 0;
	}
	int32_t head[3] = {b->gen, first, k};
	p = cluster_put(p, head, sizeof head);
	for (int i = 0; i < k; i++)
		p = cluster_pack_net(p, b->cand[first + i]);
	sent *s = &c->peer[r].held[c->peer[r].n_held++];
	s->buf = buf;
	s->first = first;
	s->count = k;
	MPI_Isend(buf, (int)n, MPI_BYTE, r, TAG_CHUNK, MPI_COMM_WORLD, &s->req);
	return k;
}

/* A RESULT from rank r: its chunk's results into the batch. */
static void collect(evo_cluster *c, batch *b, int r, MPI_Status *st)
{
	int len;
	MPI_Get_count(st, MPI_BYTE, &len);
	unsigned char *buf = cluster_room(c, len > 0 ? (size_t)len : 1);
	if (!buf)
		cluster_out_of_memory(c->rank);
	MPI_Recv(buf, len, MPI_BYTE, r, TAG_RESULT, MPI_COMM_WORLD,
		 MPI_STATUS_IGNORE);
	peer *pr = &c->peer[r];
	evo_err e = {{0}};
	if (pr->n_held == 0) {
		evo_fail(&e, "rank %d: a result it was not asked for", r);
		fail_batch(b, &e);
		return;
	}
	sent s = pr->held[0];
	memmove(&pr->held[0], &pr->held[1], sizeof pr->held[0] * (HELD - 1));
	pr->n_held--;
	MPI_Wait(&s.req, MPI_STATUS_IGNORE);
	free(s.buf);
	if (evo_cluster_check_result(buf, len > 0 ? (size_t)len : 0, r,
				     pr->host, s.first, s.count,
				     b->res + s.first, &e))
		fail_batch(b, &e);
}

/* 1 when a and b are the same text, or both none. */
static int same_text(const char *a, const char *b)
{
	return a == b || (a && b && strcmp(a, b) == 0);
}

/* Send every other rank the environment genome of ev when it is not the
 * one they hold (OPENENDED): before the batch's chunks, which it thus
 * reaches ahead of. Any size a message can hold; a larger one fails the
 * batch with its size said. */
static int share_genome(evo_cluster *c, const evo_evaluator *ev,
			evo_err *err)
{
	const char *g = evo_evaluator_genome(ev);
	if (same_text(g, c->genome))
		return 0;
	size_t n = g ? strlen(g) + 1 : 0;
	if (n > (size_t)INT_MAX)
		return evo_fail(err,
				"cluster: an environment genome of %zu bytes, "
				"where a message between ranks holds at most "
				"%d",
				n - 1, INT_MAX - 1);
	char *copy = NULL;
	if (g) {
		copy = malloc(n);
		if (!copy)
			return evo_fail(err,
					"cluster: no memory for an environment "
					"genome of %zu bytes",
					n - 1);
		memcpy(copy, g, n);
	}
	for (int r = 1; r < c->size; r++)
		MPI_Send(g, (int)n, MPI_BYTE, r, TAG_GENOME, MPI_COMM_WORLD);
	free(c->genome);
	c->genome = copy;
	return 0;
}

static int spread_evaluate(void *ctx, evo_evaluator *ev,
			   const evo_netdesc *const *cand, int n, int gen,
			   evo_eval_result *res, evo_err *err)
{
	evo_cluster *c = ctx;
	if (greet(c, ev, err) || share_genome(c, ev, err))
		return -1;
	int total = 0;
	for (int r = 0; r < c->size; r++)
		total += c->peer[r].threads;
	batch b = {
	    .ev = ev,
	    .cand = cand,
	    .res = res,
	    .n = n,
	    .gen = gen,
	    .threads = total,
	};
	pthread_mutex_init(&b.mu, NULL);
	for (int r = 1; r < c->size; r++)
		deal(c, &b, r);
	pthread_t own;
	int own_started = pthread_create(&own, NULL, own_share, &b) == 0;
	if (!own_started)
		own_share(&b);
	long pause = 20000; /* at most 1 ms: every rank holds a chunk ahead */
	for (;;) {
		int held = 0;
		for (int r = 1; r < c->size; r++) {
			peer *pr = &c->peer[r];
			if (pr->n_held == 0 ||
			    (pr->n_held < HELD && left(&b) >= total))
				deal(c, &b, r);
			held += pr->n_held;
		}
		if (held == 0)
			break;
		int flag = 0;
		MPI_Status st;
		MPI_Iprobe(MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &flag,
			   &st);
		if (flag) {
			collect(c, &b, st.MPI_SOURCE, &st);
			pause = 20000;
			continue;
		}
		struct timespec ts = {0, pause};
		nanosleep(&ts, NULL);
		pause = pause < 1000000 ? pause * 2 : 1000000;
	}
	if (own_started)
		pthread_join(own, NULL);
	pthread_mutex_destroy(&b.mu);
	if (b.failed) {
		*err = b.err;
		return -1;
	}
	return 0;
}

/* def as GROW's text (cluster_messages.h) in *out (malloc'd, *len
 * bytes); 0, or -1 with err set. */
static int grow_text(const evo_eval_def *def, char **out, size_t *len,
		     evo_err *err)
{
	const char *skill = def->learning_skill ? def->learning_skill : "";
	size_t n = strlen(def->task_path) + strlen(skill) + 2;
	for (unsigned k = 0; k < def->n_nets; k++)
		n += strlen(def->nets[k].skill) + strlen(def->nets[k].source) +
		     2;
	if (n > (size_t)INT_MAX)
		return evo_fail(err,
				"cluster: a grown task of %zu bytes to send, "
				"where a message between ranks holds at most "
				"%d",
				n, INT_MAX);
	char *t = malloc(n), *p = t;
	if (!t)
		return evo_fail(err, "cluster: out of memory");
	p = stpcpy(p, def->task_path) + 1;
	p = stpcpy(p, skill) + 1;
	for (unsigned k = 0; k < def->n_nets; k++) {
		p = stpcpy(p, def->nets[k].skill) + 1;
		p = stpcpy(p, def->nets[k].source) + 1;
	}
	*out = t;
	*len = n;
	return 0;
}

/* Rank 0's evaluator was made anew as def says (evo.grow): every other
 * rank makes its own anew so (GROW) and says hello again, checked as its
 * first was, against ev, before this returns: a rank that cannot load
 * the grown task stops the run here, with its reason. Their new
 * evaluators, as ev, hold no environment genome. */
static int spread_remake(void *ctx, evo_evaluator *ev, const evo_eval_def *def,
			 evo_err *err)
{
	evo_cluster *c = ctx;
	if (c->greeted < 0) {
		*err = c->greet_err;
		return -1;
	}
	char *text = NULL;
	size_t n = 0;
	if (grow_text(def, &text, &n, err))
		return -1;
	for (int r = 1; r < c->size; r++)
		MPI_Send(text, (int)n, MPI_BYTE, r, TAG_GROW, MPI_COMM_WORLD);
	free(text);
	/* before the first batch (a run resumed with its skills), the
	 * hellos of the ranks' first evaluators are still to be read: the
	 * grown ones' come after them */
	if (c->greeted == 0)
		for (int r = 1; r < c->size; r++)
			recv_hello(c, r);
	c->greeted = 0;
	free(c->genome);
	c->genome = NULL;
	return greet(c, ev, err);
}

const evo_eval_spread *evo_cluster_spread(evo_cluster *c, uint64_t seed)
{
	c->seed = seed;
	c->spread.evaluate = spread_evaluate;
	c->spread.remake = spread_remake;
	c->spread.ctx = c;
	return &c->spread;
}

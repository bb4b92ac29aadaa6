/* Cluster runs over Open MPI (cluster.h, docs/cluster.md).
 *
 * Rank 0 deals a batch out in chunks of consecutive candidates: every
 * rank takes a chunk as soon as it has one fewer than it can hold, from
 * one counter, so a fast rank takes more and the batch ends with every
 * rank busy to its last chunk or so. Rank 0's own share runs on a thread
 * of its own (evo_evaluate_part on rank 0's workers) while rank 0's main
 * thread, the only one that calls MPI, deals and collects.
 *
 * A chunk's size shrinks as the batch goes (guided self-scheduling): the
 * rank's threads times half the candidates left for each thread of the
 * job, at least one each, and at most an eighth of a thread's share of
 * the batch (so that no rank holds much of it at the start). A big batch
 * of short evaluations thus costs few messages, and its last chunks are
 * one candidate a thread, so the ranks finish together. A rank holds two
 * chunks while the batch has a candidate left for every thread, so it has
 * its next at hand when it sends one back.
 *
 * The messages, and the checks of what a rank sends, are in
 * cluster_messages.h. Waiting for a message polls with a pause that
 * grows to a millisecond, so an idle rank does not hold a core that
 * another rank on it could use (mpirun --oversubscribe on a small
 * machine). */
#define _GNU_SOURCE /* sched_getaffinity */
#include "cluster/cluster.h"
#include "cluster/cluster_messages.h"

#include <mpi.h>
#include <limits.h>
#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Under AddressSanitizer (make test-asan), Open MPI's own leaks are not
 * evo's, and no suppression can name them: its components have no frame
 * pointers and are unloaded before the check at exit, so their frames
 * have no library. So what MPI_Init allocates on this thread is ignored,
 * and the leak check runs just before MPI_Finalize (when everything of
 * the run is freed, and Open MPI's threads still hold what they use)
 * instead of at exit. */
#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#define MPI_OWN_BEGIN()	 __lsan_disable()
#define MPI_OWN_END()	 __lsan_enable()
#define LEAK_CHECK_NOW() __lsan_do_leak_check()
#else
#define MPI_OWN_BEGIN()	 ((void)0)
#define MPI_OWN_END()	 ((void)0)
#define LEAK_CHECK_NOW() ((void)0)
#endif

#define TAG_HELLO  EVO_CLUSTER_TAG_HELLO
#define TAG_CHUNK  EVO_CLUSTER_TAG_CHUNK
#define TAG_RESULT EVO_CLUSTER_TAG_RESULT
#define TAG_STOP   EVO_CLUSTER_TAG_STOP
#define TAG_GENOME EVO_CLUSTER_TAG_GENOME
#define TAG_GROW   EVO_CLUSTER_TAG_GROW

/* Chunks a rank holds at most. */
#define HELD 2

/* A chunk sent and not yet answered. */
typedef struct sent {
	MPI_Request req;
	unsigned char *buf;
	int first, count;
} sent;

typedef struct peer {
	int threads;
	char host[64];
	sent held[HELD]; /* in the order sent */
	int n_held;
} peer;

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

struct evo_cluster {
	int rank, size;
	uint64_t seed;
	evo_eval_spread spread;
	int greeted; /* 1: every rank said hello; -1: one failed (greet_err) */
	int told;    /* the ranks and threads were printed */
	evo_err greet_err;
	peer *peer; /* [size], peer[0] unused but for its threads */
	unsigned char *buf;
	size_t cap;
	evo_netdesc *nets;
	const evo_netdesc **ptr;
	evo_eval_result *res;
	int n_nets;
	/* rank 0: the environment genome the other ranks hold (NULL: none,
	 * as they start); the others: why the last one they were sent
	 * could not be set, which their next chunk answers */
	char *genome;
	int genome_failed;
	evo_err genome_err;
};

int evo_cluster_launched(void)
{
	const char *n = getenv("OMPI_COMM_WORLD_SIZE");
	return n && *n;
}

/* Wait until a message from source with tag is there (MPI_ANY_* allowed),
 * pausing longer and longer between looks, up to a millisecond. */
static void wait_message(int source, int tag, MPI_Status *st)
{
	long pause = 20000;
	for (;;) {
		int flag = 0;
		MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, st);
		if (flag)
			return;
		struct timespec ts = {0, pause};
		nanosleep(&ts, NULL);
		pause = pause < 1000000 ? pause * 2 : 1000000;
	}
}

/* A message that cannot be received for want of memory would stay at
 * the head of the queue and be found again and again: the job ends
 * instead, as when a rank dies (every finished generation is on disk). */
static void out_of_memory(int rank)
{
	fprintf(stderr, "evo: rank %d: out of memory for a message\n", rank);
	MPI_Abort(MPI_COMM_WORLD, 1);
}

/* The buffer of c grown to at least n bytes; NULL when memory is out. */
static unsigned char *room(evo_cluster *c, size_t n)
{
	if (n > c->cap) {
		unsigned char *b = realloc(c->buf, n);
		if (!b)
			return NULL;
		c->buf = b;
		c->cap = n;
	}
	return c->buf;
}

evo_cluster *evo_cluster_join(evo_err *err)
{
	int provided = 0;
	MPI_OWN_BEGIN();
	int rc = MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided);
	MPI_OWN_END();
	if (rc != MPI_SUCCESS) {
		evo_fail(err, "cluster: MPI does not start");
		return NULL;
	}
	evo_cluster *c = calloc(1, sizeof *c);
	if (!c) {
		MPI_Finalize();
		evo_fail(err, "out of memory");
		return NULL;
	}
	MPI_Comm_rank(MPI_COMM_WORLD, &c->rank);
	MPI_Comm_size(MPI_COMM_WORLD, &c->size);
	c->peer = calloc((size_t)c->size, sizeof *c->peer);
	if (!c->peer) {
		free(c);
		MPI_Finalize();
		evo_fail(err, "out of memory");
		return NULL;
	}
	return c;
}

int evo_cluster_cores(void)
{
	cpu_set_t set;
	CPU_ZERO(&set);
	if (sched_getaffinity(0, sizeof set, &set) != 0)
		return 1;
	int n = CPU_COUNT(&set);
	return n < 1 ? 1 : n > EVO_EVAL_MAX_THREADS ? EVO_EVAL_MAX_THREADS : n;
}

int evo_cluster_rank(const evo_cluster *c)
{
	return c->rank;
}

int evo_cluster_size(const evo_cluster *c)
{
	return c->size;
}

/* ---- networks as bytes ------------------------------------------------- */

static size_t net_bytes(const evo_netdesc *d)
{
	return 8 + 2 * (size_t)d->n_out + 7 * (size_t)d->n_nodes +
	       8 * (size_t)d->n_links;
}

static unsigned char *put(unsigned char *p, const void *v, size_t n)
{
	memcpy(p, v, n);
	return p + n;
}

static unsigned char *pack_net(unsigned char *p, const evo_netdesc *d)
{
	p = put(p, &d->n_in, 2);
	p = put(p, &d->n_out, 2);
	p = put(p, &d->n_nodes, 2);
	p = put(p, &d->n_links, 2);
	p = put(p, d->out_id, 2 * (size_t)d->n_out);
	for (int i = 0; i < d->n_nodes; i++) {
		p = put(p, &d->node[i].id, 2);
		p = put(p, &d->node[i].act, 1);
		p = put(p, &d->node[i].bias, 4);
	}
	for (int i = 0; i < d->n_links; i++) {
		p = put(p, &d->link[i].from, 2);
		p = put(p, &d->link[i].to, 2);
		p = put(p, &d->link[i].weight, 4);
	}
	return p;
}

/* Read a network from [*p, end) into d; -1 when the bytes do not hold
 * one (a message that is not evo's). */
static int unpack_net(const unsigned char **p, const unsigned char *end,
		      evo_netdesc *d)
{
	memset(d, 0, sizeof *d);
	if (end - *p < 8)
		return -1;
	memcpy(&d->n_in, *p, 2);
	memcpy(&d->n_out, *p + 2, 2);
	memcpy(&d->n_nodes, *p + 4, 2);
	memcpy(&d->n_links, *p + 6, 2);
	*p += 8;
	if (d->n_out > EVO_MAX_SKILL_IO || d->n_nodes > EVO_NET_MAX_NODES ||
	    d->n_links > EVO_NET_MAX_LINKS ||
	    (size_t)(end - *p) < net_bytes(d) - 8)
		return -1;
	memcpy(d->out_id, *p, 2 * (size_t)d->n_out);
	*p += 2 * (size_t)d->n_out;
	for (int i = 0; i < d->n_nodes; i++, *p += 7) {
		memcpy(&d->node[i].id, *p, 2);
		memcpy(&d->node[i].act, *p + 2, 1);
		memcpy(&d->node[i].bias, *p + 3, 4);
	}
	for (int i = 0; i < d->n_links; i++, *p += 8) {
		memcpy(&d->link[i].from, *p, 2);
		memcpy(&d->link[i].to, *p + 2, 2);
		memcpy(&d->link[i].weight, *p + 4, 4);
	}
	return 0;
}

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
	int threads = evo_evaluator_threads(b->ev);
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
	wait_message(r, TAG_HELLO, &st);
	int len = 0;
	MPI_Get_count(&st, MPI_BYTE, &len);
	if (!room(c, len > 0 ? (size_t)len : 1))
		out_of_memory(c->rank);
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
	c->peer[0].threads = evo_evaluator_threads(ev);
	evo_cluster_task t = {
	    .seed = c->seed,
	    .reps = evo_evaluator_reps(ev),
	    .ticks = evo_evaluator_ticks(ev),
	    .n_in = evo_evaluator_n_in(ev),
	    .n_out = evo_evaluator_n_out(ev),
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
		n += net_bytes(b->cand[first + i]);
	unsigned char *buf = malloc(n), *p = buf;
	if (!buf) {
		evo_err e;
		evo_fail(&e, "out of memory");
		fail_batch(b, &e);
		return 0;
	}
	int32_t head[3] = {b->gen, first, k};
	p = put(p, head, sizeof head);
	for (int i = 0; i < k; i++)
		p = pack_net(p, b->cand[first + i]);
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
	unsigned char *buf = room(c, len > 0 ? (size_t)len : 1);
	if (!buf)
		out_of_memory(c->rank);
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

/* ---- the other ranks ----------------------------------------------------- */

/* Room for k networks and their results; -1 when memory is out. */
static int nets_room(evo_cluster *c, int k)
{
	if (k <= c->n_nets)
		return 0;
	free(c->nets);
	free(c->ptr);
	free(c->res);
	c->nets = malloc((size_t)k * sizeof *c->nets);
	c->ptr = malloc((size_t)k * sizeof *c->ptr);
	c->res = malloc((size_t)k * sizeof *c->res);
	c->n_nets = c->nets && c->ptr && c->res ? k : 0;
	return c->n_nets ? 0 : -1;
}

/* Evaluate a CHUNK of st's length; send its RESULT. */
static void answer_chunk(evo_cluster *c, evo_evaluator *ev, MPI_Status *st)
{
	int len;
	MPI_Get_count(st, MPI_BYTE, &len);
	unsigned char *buf = room(c, len > 0 ? (size_t)len : 1);
	evo_err e = {{0}};
	int32_t head[3] = {0, 0, 0};
	int rc = 0;
	if (!buf)
		out_of_memory(c->rank);
	MPI_Recv(buf, len, MPI_BYTE, 0, TAG_CHUNK, MPI_COMM_WORLD,
		 MPI_STATUS_IGNORE);
	if (len < (int)sizeof head)
		rc = evo_fail(&e, "a chunk of %d bytes", len);
	if (!rc) {
		memcpy(head, buf, sizeof head);
		/* a network takes 8 bytes at least: a count the chunk cannot
		 * hold asks for memory it has no use for */
		if (head[0] < 0 || head[1] < 0 || head[2] < 1 ||
		    head[2] > (len - (int)sizeof head) / 8 ||
		    head[1] > INT32_MAX - head[2] || nets_room(c, head[2]))
			rc = evo_fail(&e,
				      "a chunk of %d networks from candidate "
				      "%d of generation %d, in %d bytes",
				      head[2], head[1], head[0], len);
	}
	if (!rc && !ev)
		rc = evo_fail(&e, "no evaluator");
	if (!rc && c->genome_failed) {
		e = c->genome_err;
		rc = -1;
	}
	const unsigned char *p = buf + sizeof head, *end = buf + len;
	for (int i = 0; !rc && i < head[2]; i++) {
		if (unpack_net(&p, end, &c->nets[i]))
			rc = evo_fail(&e,
				      "candidate %d: a network evo cannot "
				      "read",
				      head[1] + i);
		c->ptr[i] = &c->nets[i];
	}
	if (!rc)
		rc = evo_evaluate_part(ev, c->ptr, head[1], head[2], head[0],
				       c->res, &e);
	int32_t out[3] = {head[1], head[2], rc ? 1 : 0};
	size_t body =
	    rc ? strlen(e.msg) + 1 : (size_t)head[2] * sizeof(evo_eval_result);
	unsigned char *msg = malloc(sizeof out + body);
	if (!msg) {
		out[2] = 1;
		MPI_Send(out, (int)sizeof out, MPI_BYTE, 0, TAG_RESULT,
			 MPI_COMM_WORLD);
		return;
	}
	memcpy(msg, out, sizeof out);
	memcpy(msg + sizeof out,
	       rc ? (const void *)e.msg : (const void *)c->res, body);
	MPI_Send(msg, (int)(sizeof out + body), MPI_BYTE, 0, TAG_RESULT,
		 MPI_COMM_WORLD);
	free(msg);
}

/* A GENOME of st's length: the environment genome of the chunks to
 * come. One that cannot be set fails them, with the reason. */
static void take_genome(evo_cluster *c, evo_evaluator *ev, MPI_Status *st)
{
	int len;
	MPI_Get_count(st, MPI_BYTE, &len);
	unsigned char *buf = room(c, len > 0 ? (size_t)len : 1);
	if (!buf)
		out_of_memory(c->rank);
	MPI_Recv(buf, len, MPI_BYTE, 0, TAG_GENOME, MPI_COMM_WORLD,
		 MPI_STATUS_IGNORE);
	c->genome_failed = 0;
	if (len > 0 && buf[len - 1] != 0)
		c->genome_failed = evo_fail(&c->genome_err,
					    "an environment genome of %d "
					    "bytes with no end",
					    len) != 0;
	else if (ev && evo_evaluator_set_genome(ev,
						len > 0 ? (const char *)buf
							: NULL,
						&c->genome_err))
		c->genome_failed = 1;
}

/* Tell rank 0 the settings of ev, made as def says, or (ev NULL) why
 * there is none: err. */
static void say_hello(const evo_evaluator *ev, const evo_eval_def *def,
		      const evo_err *err)
{
	evo_cluster_hello h;
	memset(&h, 0, sizeof h);
	/* the name may be longer than the hello holds */
	char host[MPI_MAX_PROCESSOR_NAME + 1] = "";
	int len = 0;
	MPI_Get_processor_name(host, &len);
	snprintf(h.host, sizeof h.host, "%.63s", host);
	if (ev) {
		h.ok = 1;
		h.threads = evo_evaluator_threads(ev);
		h.reps = evo_evaluator_reps(ev);
		h.ticks = evo_evaluator_ticks(ev);
		h.seed = def->seed;
		h.n_in = evo_evaluator_n_in(ev);
		h.n_out = evo_evaluator_n_out(ev);
	} else {
		snprintf(h.msg, sizeof h.msg, "%s", err->msg);
	}
	MPI_Send(&h, (int)sizeof h, MPI_BYTE, 0, TAG_HELLO, MPI_COMM_WORLD);
}

/* The texts ended by a 0 byte in msg[0 .. len-1], which must end with
 * one: their number (0 when msg does not end so). */
static size_t count_texts(const unsigned char *msg, int len)
{
	if (len < 1 || msg[len - 1] != 0)
		return 0;
	size_t n = 0;
	for (int i = 0; i < len; i++)
		n += msg[i] == 0;
	return n;
}

/* A GROW of st's length: ev (destroyed) made anew as it says, with def's
 * threads, seed and ticks; hello again. The new evaluator, or NULL with
 * err set when it could not be made (the hello said why). */
static evo_evaluator *take_grow(evo_cluster *c, evo_evaluator *ev,
				const evo_eval_def *def, MPI_Status *st,
				evo_err *err)
{
	int len;
	MPI_Get_count(st, MPI_BYTE, &len);
	if (!room(c, len > 0 ? (size_t)len : 1))
		out_of_memory(c->rank);
	MPI_Recv(c->buf, len, MPI_BYTE, 0, TAG_GROW, MPI_COMM_WORLD,
		 MPI_STATUS_IGNORE);
	evo_evaluator_destroy(ev);
	ev = NULL;
	c->genome_failed = 0;
	evo_err e = {{0}};
	size_t n = count_texts(c->buf, len);
	evo_net_choice *nets =
	    n >= 2 && n % 2 == 0 ? malloc((n / 2) * sizeof *nets) : NULL;
	if (n < 2 || n % 2) {
		evo_fail(&e, "a grown task of %d bytes that is not evo's", len);
	} else if (!nets) {
		evo_fail(&e, "out of memory");
	} else {
		evo_eval_def g = *def;
		const char *p = (const char *)c->buf;
		g.task_path = p;
		p += strlen(p) + 1;
		g.learning_skill = *p ? p : NULL;
		p += strlen(p) + 1;
		g.n_nets = (unsigned)(n / 2 - 1);
		for (unsigned k = 0; k < g.n_nets; k++) {
			nets[k].skill = p;
			p += strlen(p) + 1;
			nets[k].source = p;
			p += strlen(p) + 1;
		}
		g.nets = nets;
		evo_err why = {{0}};
		ev = evo_evaluator_create(&g, &why);
		if (!ev)
			evo_fail(&e,
				 "the hierarchy rank 0 grew does not load "
				 "here (%s); every rank reads it where rank 0 "
				 "wrote it, in the run folder: give --run a "
				 "folder all the machines share",
				 why.msg);
	}
	free(nets);
	say_hello(ev, def, &e);
	if (!ev)
		*err = e;
	return ev;
}

int evo_cluster_serve(evo_cluster *c, const evo_eval_def *def, evo_err *err)
{
	evo_evaluator *ev = evo_evaluator_create(def, err);
	say_hello(ev, def, err);
	for (;;) {
		MPI_Status st;
		wait_message(0, MPI_ANY_TAG, &st);
		if (st.MPI_TAG == TAG_STOP) {
			MPI_Recv(NULL, 0, MPI_BYTE, 0, TAG_STOP, MPI_COMM_WORLD,
				 MPI_STATUS_IGNORE);
			break;
		}
		if (st.MPI_TAG == TAG_CHUNK) {
			answer_chunk(c, ev, &st);
		} else if (st.MPI_TAG == TAG_GENOME) {
			take_genome(c, ev, &st);
		} else if (st.MPI_TAG == TAG_GROW) {
			ev = take_grow(c, ev, def, &st, err);
		} else { /* not evo's: take it off the queue */
			int n;
			MPI_Get_count(&st, MPI_BYTE, &n);
			unsigned char *buf = room(c, n > 0 ? (size_t)n : 1);
			if (!buf)
				out_of_memory(c->rank);
			MPI_Recv(buf, n, MPI_BYTE, 0, st.MPI_TAG,
				 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
		}
	}
	int rc = ev ? 0 : -1;
	evo_evaluator_destroy(ev);
	return rc;
}

void evo_cluster_leave(evo_cluster *c)
{
	if (!c)
		return;
	if (c->rank == 0)
		for (int r = 1; r < c->size; r++)
			MPI_Send(NULL, 0, MPI_BYTE, r, TAG_STOP,
				 MPI_COMM_WORLD);
	free(c->peer);
	free(c->buf);
	free(c->nets);
	free(c->ptr);
	free(c->res);
	free(c->genome);
	free(c);
	LEAK_CHECK_NOW();
	MPI_Finalize();
}

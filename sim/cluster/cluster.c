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
 * machine).
 *
 * This file joins and leaves the job and holds what both sides use;
 * rank 0's dealing is cluster_deal.c's, the other ranks' loop
 * cluster_serve.c's, sharing cluster_internal.h. */
#define _GNU_SOURCE /* sched_getaffinity */
#include "cluster/cluster.h"
#include "cluster/cluster_internal.h"
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

int evo_cluster_launched(void)
{
	const char *n = getenv("OMPI_COMM_WORLD_SIZE");
	return n && *n;
}

/* Wait until a message from source with tag is there (MPI_ANY_* allowed),
 * pausing longer and longer between looks, up to a millisecond. */
void cluster_wait_message(int source, int tag, MPI_Status *st)
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
void cluster_out_of_memory(int rank)
{
	fprintf(stderr, "evo: rank %d: out of memory for a message\n", rank);
	MPI_Abort(MPI_COMM_WORLD, 1);
}

/* The buffer of c grown to at least n bytes; NULL when memory is out. */
unsigned char *cluster_room(evo_cluster *c, size_t n)
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

size_t cluster_net_bytes(const evo_netdesc *d)
{
	return 8 + 2 * (size_t)d->n_out + 7 * (size_t)d->n_nodes +
	       8 * (size_t)d->n_links;
}

unsigned char *cluster_put(unsigned char *p, const void *v, size_t n)
{
	memcpy(p, v, n);
	return p + n;
}

unsigned char *cluster_pack_net(unsigned char *p, const evo_netdesc *d)
{
	p = cluster_put(p, &d->n_in, 2);
	p = cluster_put(p, &d->n_out, 2);
	p = cluster_put(p, &d->n_nodes, 2);
	p = cluster_put(p, &d->n_links, 2);
	p = cluster_put(p, d->out_id, 2 * (size_t)d->n_out);
	for (int i = 0; i < d->n_nodes; i++) {
		p = cluster_put(p, &d->node[i].id, 2);
		p = cluster_put(p, &d->node[i].act, 1);
		p = cluster_put(p, &d->node[i].bias, 4);
	}
	for (int i = 0; i < d->n_links; i++) {
		p = cluster_put(p, &d->link[i].from, 2);
		p = cluster_put(p, &d->link[i].to, 2);
		p = cluster_put(p, &d->link[i].weight, 4);
	}
	return p;
}

/* Read a network from [*p, end) into d; -1 when the bytes do not hold
 * one (a message that is not evo's). */
int cluster_unpack_net(const unsigned char **p, const unsigned char *end,
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
	    (size_t)(end - *p) < cluster_net_bytes(d) - 8)
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

/* evo — private to the cluster's files (sim/cluster/cluster.c,
 * cluster_deal.c, cluster_serve.c): the run's state on every rank, the
 * message tags, and the waiting, buffers and network packing rank 0 and
 * the other ranks share. No other file may use it. */
#ifndef EVO_CLUSTER_PRIVATE_H
#define EVO_CLUSTER_PRIVATE_H

#include <mpi.h>
#include <stddef.h>

#include "cluster/cluster.h"
#include "cluster/cluster_messages.h"

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

/* shared by rank 0 and the others (cluster.c) */
void cluster_wait_message(int source, int tag, MPI_Status *st);
void cluster_out_of_memory(int rank);
unsigned char *cluster_room(evo_cluster *c, size_t n);
size_t cluster_net_bytes(const evo_netdesc *d);
unsigned char *cluster_put(unsigned char *p, const void *v, size_t n);
unsigned char *cluster_pack_net(unsigned char *p, const evo_netdesc *d);
int cluster_unpack_net(const unsigned char **p, const unsigned char *end,
		      evo_netdesc *d);

#endif

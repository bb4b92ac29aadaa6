/* The messages between the ranks of a cluster run (cluster_deal.c,
 * cluster_serve.c), and the checks rank 0 makes of every message a rank
 * sends (cluster_messages.c; its tests and its fuzz target use them
 * too).
 *
 * Messages (MPI_BYTE, in this machine's byte order: a cluster of one
 * architecture, as Open MPI's own homogeneous default):
 *     HELLO  rank -> 0   evo_cluster_hello: the rank's settings, or why it
 *                        has none
 *     CHUNK  0 -> rank   int32 generation, first index, count; the
 *                        networks
 *     RESULT rank -> 0   int32 first index, count, status (0 or 1); the
 *                        count results, or (status 1) why not as text
 *     STOP   0 -> rank   the run is over
 *     GENOME 0 -> rank   the environment genome of the batches to come
 *                        (OPENENDED, evo_evaluator_set_genome): its text
 *                        and a 0 byte, or no byte for none; sent before
 *                        a batch's first chunk when it changed, so it
 *                        reaches the rank ahead of them (MPI keeps the
 *                        order of one sender's messages)
 *     GROW   0 -> rank   rank 0 made its evaluator anew (OPENENDED's
 *                        development, evo.grow): the task, the skill the
 *                        candidates run as ("" for LEARNINGSKILL), then
 *                        each chosen network's skill and file, every
 *                        one a text ended by a 0 byte; the rank makes
 *                        its evaluator anew so and says HELLO again
 * A rank is another evo process, but what it sends is checked as any
 * input is (a damaged build, another version, a stray program under the
 * same mpirun): every field is in range before rank 0 uses it, and a
 * message that is not evo's stops the run with the rank named. */
#ifndef EVO_CLUSTER_INTERNAL_H
#define EVO_CLUSTER_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"
#include "learn/evaluate.h"

enum {
	EVO_CLUSTER_TAG_HELLO = 1,
	EVO_CLUSTER_TAG_CHUNK,
	EVO_CLUSTER_TAG_RESULT,
	EVO_CLUSTER_TAG_STOP,
	EVO_CLUSTER_TAG_GENOME,
	EVO_CLUSTER_TAG_GROW
};

/* What a rank tells rank 0 once its evaluator is up, or why not. */
typedef struct evo_cluster_hello {
	int32_t ok; /* 1: up; 0: not, msg says why */
	int32_t threads, reps;
	int64_t ticks;
	uint64_t seed;
	uint32_t n_in, n_out;
	char host[64];
	char msg[1024]; /* ok == 0: why */
} evo_cluster_hello;

/* Rank 0's settings of the task, which every rank must share. */
typedef struct evo_cluster_task {
	uint64_t seed;
	int reps;
	long ticks;
	unsigned n_in, n_out;
} evo_cluster_task;

/* Check the HELLO of len bytes at msg from rank; fill *h with it (host
 * and msg ended and made printable). 0 when the rank is up with rank 0's
 * settings and 1..EVO_EVAL_MAX_THREADS threads; else -1 with err naming
 * the rank (and its host, once that is known to be a string). */
int evo_cluster_check_hello(const void *msg, size_t len, int rank,
			    const evo_cluster_task *t, evo_cluster_hello *h,
			    evo_err *err);

/* Check the RESULT of len bytes at msg from rank (on host) for the chunk
 * of count candidates from first; copy its results into res[0 ..
 * count-1]. 0, or -1 with err naming the rank: a rank's own failure (its
 * message, made printable), or a message not evo's (its size, status,
 * candidates, or a result out of range). */
int evo_cluster_check_result(const void *msg, size_t len, int rank,
			     const char *host, int first, int count,
			     evo_eval_result *res, evo_err *err);

#endif

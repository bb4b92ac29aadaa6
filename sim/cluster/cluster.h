/* evo — cluster runs over Open MPI (docs/cluster.md).
 *
 * `mpirun -np N evo run TASK.simbatch` starts N evo processes, the ranks.
 * Rank 0 runs the learning loop (sim/learn/learn.h) as a plain run does;
 * its evaluator hands each batch to evo_cluster_spread, which deals the
 * candidates out in chunks to every rank, rank 0 included, each of which
 * evaluates its chunks on its own worker threads (evo_evaluate_part) and
 * sends back what they gave. Messages carry genomes (the candidates'
 * networks, and an OPENENDED batch's environment genome) and their
 * results, and where to load the task anew when OPENENDED's development
 * grew rank 0's hierarchy (the grown mind folder, which rank 0 wrote in
 * the run folder: every rank reads it there).
 *
 * A candidate's evaluation depends on its network and its seeds, which
 * follow from (run seed, generation, index in the batch) and not from
 * who runs it (sim/learn/evaluate.h): the same seed gives the same log
 * and champion for any number of ranks and threads.
 *
 * Faults: a rank that dies ends the job (mpirun signals the others, and
 * rank 0 stops as on SIGTERM); every finished generation is already in
 * the run folder, which --resume continues with any number of ranks. */
#ifndef EVO_CLUSTER_H
#define EVO_CLUSTER_H

#include <stdint.h>

#include "base/err.h"
#include "learn/evaluate.h"

typedef struct evo_cluster evo_cluster;

/* 1 when this process was started by Open MPI's mpirun (its environment
 * says so), without touching MPI: a plain `evo run` never starts it. */
int evo_cluster_launched(void);

/* Join the MPI job of this process. NULL with err set when MPI does not
 * start. */
evo_cluster *evo_cluster_join(evo_err *err);

/* The cores this process may run on: those mpirun bound it to (one core
 * a rank by default for two ranks or fewer), else all. A rank's worker
 * threads when --threads does not say. */
int evo_cluster_cores(void);

/* This process's rank (0 runs the learning loop) and the job's size. */
int evo_cluster_rank(const evo_cluster *c);
int evo_cluster_size(const evo_cluster *c);

/* Rank 0: the spread its evaluator is to use (evo_eval_def.spread).
 * seed: the run's, which every rank must share. Its first batch waits for
 * every other rank's evaluator and checks that it runs the same task
 * settings. Valid until evo_cluster_leave. */
const evo_eval_spread *evo_cluster_spread(evo_cluster *c, uint64_t seed);

/* Ranks above 0: load the task as def says (on this rank's own threads),
 * tell rank 0 the settings, then evaluate the chunks rank 0 sends until
 * it says the run is over; load the task anew, and tell again, when rank
 * 0 made its evaluator anew (OPENENDED's development, evo.grow). Returns 0, or -1 with err set (rank 0 has been
 * told, and the run has stopped with the message). */
int evo_cluster_serve(evo_cluster *c, const evo_eval_def *def, evo_err *err);

/* Rank 0: tell the other ranks the run is over. Every rank: leave MPI
 * and free c. NULL is allowed. */
void evo_cluster_leave(evo_cluster *c);

#endif

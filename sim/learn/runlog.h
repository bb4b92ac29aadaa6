/* evo — what a learning run leaves behind, and the line it prints each
 * generation.
 *
 * A run folder holds log.csv (one row per generation), the best network
 * of each generation (best/gen-NNNN.net), the checkpoint, the champion
 * and .lock, locked by the run that holds the folder. Every file is
 * written whole to a temporary name and renamed, so a run killed at any
 * moment leaves each file either as it was or complete. docs/learning.md. */
#ifndef EVO_RUNLOG_H
#define EVO_RUNLOG_H

#include <stddef.h>

#include "base/err.h"

typedef struct evo_gen_stats {
	int generation;	   /* 0 based */
	int generations;   /* planned, for the ETA; 0 when open-ended */
	double best, mean; /* fitness of this generation */
	double best_ever;
	int species;	   /* 0 when the method has none */
	long evaluations;  /* this generation's */
	int solved;	   /* candidates that met the task's success
			    * criterion (literature tasks), else 0 */
	double seconds;	   /* this generation's wall time */
	double elapsed;	   /* since this process started the run */
	int first;	   /* the first generation this process ran (after
			    * --resume, the one after the checkpoint): the
			    * ETA extrapolates from the generations since */
} evo_gen_stats;

typedef struct evo_runlog {
	char dir[1024];
	char *csv; /* the whole log, rewritten each generation */
	size_t len, cap;
	/* resumed: the elapsed time of the last row kept, which the rows
	 * of this process add to, so log.csv's elapsed column counts the
	 * whole run's time, not this process's */
	double elapsed_before;
} evo_runlog;

/* Create (or reuse) the run folder dir and its best/ folder; start the log
 * with its header, or, when resuming, keep the rows of generations before
 * `from_generation` of the existing log. Returns 0 or -1 with err. */
int evo_runlog_open(evo_runlog *log, const char *dir, int from_generation,
		    evo_err *err);
void evo_runlog_close(evo_runlog *log);

/* Claim the run folder dir for this process: create it and lock its
 * .lock file, so that a second evo run into the same folder is refused
 * while this one lives (the lock goes with the process, however it ends).
 * Returns the lock's descriptor, to close when the run is over, or -1
 * with err. */
int evo_runlog_claim(const char *dir, evo_err *err);

/* A fresh run into a folder that holds an earlier run (log.csv or
 * checkpoint.lua): move the earlier run's files, all but the lock, to the
 * first free dir.N and say so on stdout. Returns 0 or -1 with err. */
int evo_runlog_set_aside(const char *dir, evo_err *err);

/* Add a generation's row and save log.csv atomically. */
int evo_runlog_add(evo_runlog *log, const evo_gen_stats *s, evo_err *err);

/* Save text as <dir>/<name> atomically (a network, a checkpoint). */
int evo_runlog_save(const evo_runlog *log, const char *name, const char *text,
		    size_t len, evo_err *err);

/* The progress line of a generation: with tty, a bar and no newline (the
 * caller rewrites it in place with '\r'); without, a plain line. */
void evo_progress_format(char *buf, size_t cap, const evo_gen_stats *s,
			 int tty);

#endif

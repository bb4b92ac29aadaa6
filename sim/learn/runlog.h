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
	/* the environment's metrics for this row, one value for each name
	 * given to evo_runlog_open, in its order; NULL when there are none */
	const double *metrics;
	/* a team task (docs/teams.md): the learning team, and the share of
	 * the generation's episodes it won; NULL team: not a team task */
	const char *team;
	double win_rate;
	/* the method's own figures for the progress line ("coverage 0.5234
	 * qd_score 257.1"), or NULL */
	const char *note;
} evo_gen_stats;

/* Metric columns a log can hold: the environment's, and on --resume an
 * earlier run's that it no longer reports. */
#define EVO_RUNLOG_MAX_COLUMNS 64
#define EVO_RUNLOG_COLUMN_MAX 64 /* a column's name, with its NUL */

typedef struct evo_runlog {
	char dir[1024];
	char *csv; /* the whole log */
	size_t len, cap;
	/* the bytes of csv that log.csv holds: after the first row, each
	 * row is appended to the file (0: the next row rewrites it whole) */
	size_t saved;
	/* resumed: the elapsed time of the last row kept, which the rows
	 * of this process add to, so log.csv's elapsed column counts the
	 * whole run's time, not this process's */
	double elapsed_before;
	/* The columns after elapsed, "metric:NAME" each: on --resume the
	 * earlier rows' first, then the environment's metrics they lack.
	 * column_metric[c] is the index of column c's metric among the ones
	 * given to evo_runlog_open, or -1 (a metric no longer reported: its
	 * cells in new rows are empty). */
	int n_metrics;
	int n_columns;
	char column[EVO_RUNLOG_MAX_COLUMNS][EVO_RUNLOG_COLUMN_MAX];
	int column_metric[EVO_RUNLOG_MAX_COLUMNS];
} evo_runlog;

/* Create (or reuse) the run folder dir and its best/ folder; start the log
 * with its header, or, when resuming, keep the rows of generations before
 * `from_generation` of the existing log. The header ends with a column
 * "metric:NAME" for each of the n_metrics names (the environment's,
 * evo_evaluator_metric_name). Resuming a log whose columns name other
 * metrics keeps every earlier column: a metric the earlier rows lack is a
 * new column, empty in those rows, and one no longer reported stays,
 * empty in the new rows; a warning on stderr says which. Returns 0 or -1
 * with err. */
int evo_runlog_open(evo_runlog *log, const char *dir, int from_generation,
		    const char *const *metrics, int n_metrics, evo_err *err);
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

/* Add a generation's row to log.csv. The first row of a process rewrites
 * the file whole and atomically (the header, and on --resume the rows
 * kept); each later row is appended with one write, so the file is never
 * recreated per generation (on some file systems creating a file cost
 * more than a generation of XOR). A killed run leaves whole rows, or at
 * worst a last row without its newline, which --resume drops; log.csv is
 * synced to disk with the next checkpoint (evo_runlog_save). */
int evo_runlog_add(evo_runlog *log, const evo_gen_stats *s, evo_err *err);

/* Save text as <dir>/<name> atomically (a network, a checkpoint). A file
 * under best/ (one a generation) is not synced to disk on its own; any
 * other (the checkpoint) is, and log.csv with it first, so that after a
 * power cut the checkpoint on disk never has a log behind it. */
int evo_runlog_save(const evo_runlog *log, const char *name, const char *text,
		    size_t len, evo_err *err);

/* The progress line of a generation: with tty, a bar and no newline (the
 * caller rewrites it in place with '\r'); without, a plain line. */
void evo_progress_format(char *buf, size_t cap, const evo_gen_stats *s,
			 int tty);

#endif

/* A learning run's folder, log and progress line (sim/learn/runlog.h). */
#define _POSIX_C_SOURCE 200809L
#include "learn/runlog.h"

#include <dirent.h>
#include <math.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/fileio.h"
#include "base/number.h"

static int make_dirs(const char *path, evo_err *err)
{
	char p[1024];
	if (snprintf(p, sizeof p, "%s", path) >= (int)sizeof p)
		return evo_fail(err, "%s: path too long", path);
	for (char *s = p + 1;; s++) {
		int end = *s == 0;
		if (*s == '/' || end) {
			*s = 0;
			if (mkdir(p, 0755) != 0 && errno != EEXIST)
				return evo_fail(err, "%s: cannot create: %s",
						p, strerror(errno));
			if (end)
				break;
			*s = '/';
		}
	}
	return 0;
}

int evo_runlog_set_aside(const char *dir, evo_err *err)
{
	char log[1100], checkpoint[1100];
	if (evo_path_fmt(log, sizeof log, err, "%s/log.csv", dir) ||
	    evo_path_fmt(checkpoint, sizeof checkpoint, err,
			 "%s/checkpoint.lua", dir))
		return -1;
	if (!evo_file_exists(log) && !evo_file_exists(checkpoint))
		return 0;
	char base[1024], aside[1100];
	snprintf(base, sizeof base, "%s", dir);
	for (size_t n = strlen(base); n > 1 && base[n - 1] == '/'; n--)
		base[n - 1] = 0;
	int k = 1;
	for (; k < 1000; k++) {
		snprintf(aside, sizeof aside, "%s.%d", base, k);
		if (mkdir(aside, 0755) == 0)
			break;
		if (errno != EEXIST)
			return evo_fail(err, "%s: cannot create: %s", aside,
					strerror(errno));
	}
	if (k == 1000)
		return evo_fail(err,
				"%s holds an earlier run, and %s.1 to %s.999 "
				"are all taken: remove some, or name another "
				"run folder with --run",
				dir, base, base);
	/* The names first, then the moves: a directory read while it
	 * changes may skip or repeat entries. */
	DIR *d = opendir(base);
	if (!d)
		return evo_fail(err, "%s: cannot read: %s", base,
				strerror(errno));
	char **names = NULL;
	size_t n = 0, cap = 0;
	int rc = 0;
	struct dirent *e;
	while (rc == 0 && (e = readdir(d)) != NULL) {
		if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..") ||
		    !strcmp(e->d_name, ".lock"))
			continue;
		if (n == cap) {
			cap = cap ? cap * 2 : 16;
			char **more = realloc(names, cap * sizeof *names);
			if (!more) {
				rc = evo_fail(err, "out of memory");
				break;
			}
			names = more;
		}
		if (!(names[n] = strdup(e->d_name)))
			rc = evo_fail(err, "out of memory");
		else
			n++;
	}
	closedir(d);
	for (size_t i = 0; i < n; i++) {
		char from[1400], to[1400];
		snprintf(from, sizeof from, "%s/%s", base, names[i]);
		snprintf(to, sizeof to, "%s/%s", aside, names[i]);
		if (rc == 0 && rename(from, to) != 0)
			rc = evo_fail(err,
				      "%s holds an earlier run, and %s cannot "
				      "be moved to %s: %s",
				      dir, from, to, strerror(errno));
		free(names[i]);
	}
	free(names);
	if (rc == 0) {
		printf("the earlier run in %s is now in %s\n", base, aside);
		fflush(stdout);
	}
	return rc;
}

int evo_runlog_claim(const char *dir, evo_err *err)
{
	char path[1100];
	if (snprintf(path, sizeof path, "%s/.lock", dir) >= (int)sizeof path)
		return evo_fail(err, "%s: path too long", dir);
	if (make_dirs(dir, err))
		return -1;
	/* O_NOFOLLOW: a .lock a mind folder ships as a link would have evo
	 * create the file it names; the link is removed, and .lock made. */
	int fd = open(path, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
	if (fd < 0 && errno == ELOOP && unlink(path) == 0)
		fd = open(path, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC,
			  0644);
	if (fd < 0)
		return evo_fail(err, "%s: cannot create: %s", path,
				strerror(errno));
	struct flock fl = {.l_type = F_WRLCK, .l_whence = SEEK_SET};
	if (fcntl(fd, F_SETLK, &fl) != 0) {
		int busy = errno == EACCES || errno == EAGAIN;
		const char *why = strerror(errno);
		struct flock who = {.l_type = F_WRLCK, .l_whence = SEEK_SET};
		long pid = busy && fcntl(fd, F_GETLK, &who) == 0 &&
				   who.l_type != F_UNLCK
			       ? (long)who.l_pid
			       : 0;
		close(fd);
		if (!busy)
			return evo_fail(err, "%s: cannot lock: %s", path, why);
		if (pid > 0)
			return evo_fail(err,
					"%s is in use by another evo run "
					"(process %ld): wait for it to end, or "
					"name another run folder with --run",
					dir, pid);
		return evo_fail(err,
				"%s is in use by another evo run: wait for it "
				"to end, or name another run folder with --run",
				dir);
	}
	return fd;
}

static int append(evo_runlog *log, const char *s, size_t n, evo_err *err)
{
	if (log->len + n + 1 > log->cap) {
		size_t cap = (log->len + n + 1) * 2;
		char *p = realloc(log->csv, cap);
		if (!p)
			return evo_fail(err, "out of memory");
		log->csv = p;
		log->cap = cap;
	}
	memcpy(log->csv + log->len, s, n);
	log->len += n;
	log->csv[log->len] = 0;
	return 0;
}

/* The columns every log has, in this order; the metrics follow. */
static const char HEADER[] =
	"generation,best,mean,best_ever,species,evaluations,solved,seconds,"
	"elapsed";
enum { BASE_COLUMNS = 9, ELAPSED_COLUMN = 8 };

/* The start of field k (0 based) of the line at p, or NULL. */
static const char *field(const char *p, const char *end, int k)
{
	for (; k > 0 && p < end; p++)
		if (*p == ',')
			k--;
	return k == 0 ? p : NULL;
}

/* Add column name[0 .. n-1] after the others; 0 or -1 with err. */
static int add_column(evo_runlog *log, const char *name, size_t n,
		      const char *path, evo_err *err)
{
	if (log->n_columns == EVO_RUNLOG_MAX_COLUMNS)
		return evo_fail(err, "%s: more than %d metric columns", path,
				EVO_RUNLOG_MAX_COLUMNS);
	if (n >= EVO_RUNLOG_COLUMN_MAX)
		return evo_fail(err, "%s: a column name of %zu characters "
				     "(at most %d): '%.40s...'",
				path, n, EVO_RUNLOG_COLUMN_MAX - 1, name);
	char *c = log->column[log->n_columns];
	memcpy(c, name, n);
	c[n] = 0;
	log->column_metric[log->n_columns++] = -1;
	return 0;
}

/* The columns after the base ones: the earlier header's (old, of length
 * n; NULL for a fresh log), then each metric's that is not among them,
 * and the header line that names them all. A metric new to an earlier
 * log, or gone from it, gets a warning. *added counts the new columns. */
static int set_columns(evo_runlog *log, const char *old, size_t n,
		       const char *const *metrics, int n_metrics, int *added,
		       const char *path, evo_err *err)
{
	log->n_metrics = n_metrics;
	*added = 0;
	const char *p = old ? field(old, old + n, BASE_COLUMNS) : NULL;
	while (p && p < old + n) {
		const char *e = memchr(p, ',', (size_t)(old + n - p));
		if (!e)
			e = old + n;
		if (add_column(log, p, (size_t)(e - p), path, err))
			return -1;
		p = e + 1;
	}
	int earlier = log->n_columns;
	for (int k = 0; k < n_metrics; k++) {
		char name[EVO_RUNLOG_COLUMN_MAX];
		int len = snprintf(name, sizeof name, "metric:%s", metrics[k]);
		int c = 0;
		while (c < log->n_columns && strcmp(log->column[c], name))
			c++;
		if (c == log->n_columns) {
			if (add_column(log, name, (size_t)len, path, err))
				return -1;
			if (old)
				fprintf(stderr,
					"%s: warning: the environment now "
					"reports %s, which the earlier rows "
					"lack: their cells are left empty\n",
					path, name);
			++*added;
		}
		log->column_metric[c] = k;
	}
	for (int c = 0; c < earlier; c++)
		if (log->column_metric[c] < 0)
			fprintf(stderr,
				"%s: warning: the environment no longer "
				"reports %s: its cells in the new rows are "
				"left empty\n",
				path, log->column[c]);
	if (append(log, HEADER, strlen(HEADER), err))
		return -1;
	for (int c = 0; c < log->n_columns; c++)
		if (append(log, ",", 1, err) ||
		    append(log, log->column[c], strlen(log->column[c]), err))
			return -1;
	return append(log, "\n", 1, err);
}

int evo_runlog_open(evo_runlog *log, const char *dir, int from_generation,
		    const char *const *metrics, int n_metrics, evo_err *err)
{
	memset(log, 0, sizeof *log);
	if (snprintf(log->dir, sizeof log->dir, "%s", dir) >=
	    (int)sizeof log->dir)
		return evo_fail(err, "%s: path too long", dir);
	if (n_metrics < 0 || n_metrics > EVO_RUNLOG_MAX_COLUMNS)
		return evo_fail(err, "%s: %d metrics (at most %d)", dir,
				n_metrics, EVO_RUNLOG_MAX_COLUMNS);
	char best[1100], path[1100];
	snprintf(best, sizeof best, "%s/best", dir);
	snprintf(path, sizeof path, "%s/log.csv", dir);
	int added;
	if (evo_folder_check_links(dir, "best", err) || make_dirs(best, err))
		return -1;
	if (from_generation <= 0)
		return set_columns(log, NULL, 0, metrics, n_metrics, &added,
				   path, err);
	/* Resuming: keep the rows before from_generation, drop any later
	 * one (written after the checkpoint the run resumes from). The
	 * header keeps the earlier run's columns; a metric it lacks is a
	 * column more, empty in the rows kept. */
	char *old;
	size_t len;
	if (evo_read_file_max(path, EVO_RUN_FILE_MAX, &old, &len, err))
		return -1;
	const char *line = strchr(old, '\n');
	size_t head = line ? (size_t)(line - old) : len;
	if (set_columns(log, old, head, metrics, n_metrics, &added, path,
			err)) {
		free(old);
		return -1;
	}
	unsigned lineno = 1;
	while (line && line[1]) {
		line++;
		lineno++;
		const char *end = strchr(line, '\n');
		if (!end)
			break;
		/* a row starts with its generation, as evo wrote it: a row
		 * that does not was not written by evo */
		long long gen;
		const char *after;
		if (evo_parse_whole(line, &after, 0, INT_MAX, &gen) ||
		    *after != ',') {
			evo_fail(err,
				 "%s:%u: expected a row that starts with its "
				 "generation (a whole number, then ','), found "
				 "'%.*s'",
				 path, lineno,
				 (int)(end - line > 40 ? 40 : end - line), line);
			free(old);
			return -1;
		}
		if (gen < from_generation) {
			int bad = append(log, line, (size_t)(end - line), err);
			for (int k = 0; !bad && k < added; k++)
				bad = append(log, ",", 1, err);
			if (bad || append(log, "\n", 1, err)) {
				free(old);
				return -1;
			}
			const char *e = field(line, end, ELAPSED_COLUMN);
			double v = e ? strtod(e, NULL) : 0;
			if (isfinite(v) && v > log->elapsed_before)
				log->elapsed_before = v;
		}
		line = end;
	}
	free(old);
	return 0;
}

void evo_runlog_close(evo_runlog *log)
{
	free(log->csv);
	memset(log, 0, sizeof *log);
}

/* Append n bytes to the file at path (no symbolic link) in one write. */
static int append_row(const char *path, const char *row, size_t n,
		      evo_err *err)
{
	int fd = open(path, O_WRONLY | O_APPEND | O_NOFOLLOW);
	if (fd < 0)
		return evo_fail(err, "%s: cannot open it to add a row: %s",
				path, strerror(errno));
	ssize_t w;
	do
		w = write(fd, row, n);
	while (w < 0 && errno == EINTR);
	int e = errno;
	close(fd);
	if (w != (ssize_t)n)
		return evo_fail(err, "%s: cannot add a row: %s", path,
				w < 0 ? strerror(e) : "short write");
	return 0;
}

int evo_runlog_add(evo_runlog *log, const evo_gen_stats *s, evo_err *err)
{
	if (log->n_metrics > 0 && !s->metrics)
		return evo_fail(err, "a log row without its %d metrics",
				log->n_metrics);
	/* %.17g: the log holds the exact doubles, so two runs compare equal
	 * only when their fitness values are bit for bit the same. The
	 * times are the two columns before the metrics, and are left out of
	 * such comparisons. */
	char row[512 + EVO_RUNLOG_MAX_COLUMNS * 32];
	int n = snprintf(row, sizeof row, "%d,%.17g,%.17g,%.17g,%d,%ld,%d,%.3f,%.3f",
			 s->generation, s->best, s->mean, s->best_ever,
			 s->species, s->evaluations, s->solved, s->seconds,
			 log->elapsed_before + s->elapsed);
	for (int c = 0; c < log->n_columns; c++) {
		int k = log->column_metric[c];
		n += k < 0 ? snprintf(row + n, sizeof row - (size_t)n, ",")
			   : snprintf(row + n, sizeof row - (size_t)n, ",%.17g",
				      s->metrics[k]);
	}
	n += snprintf(row + n, sizeof row - (size_t)n, "\n");
	if (append(log, row, (size_t)n, err))
		return -1;
	char path[1200];
	if (evo_path_fmt(path, sizeof path, err, "%s/log.csv", log->dir))
		return -1;
	if (log->saved == 0) {
		if (evo_write_file_replace(path, log->csv, log->len, err))
			return -1;
	} else if (append_row(path, log->csv + log->saved,
			      log->len - log->saved, err)) {
		return -1;
	}
	log->saved = log->len;
	return 0;
}

int evo_runlog_save(const evo_runlog *log, const char *name, const char *text,
		    size_t len, evo_err *err)
{
	char path[1200];
	if (evo_path_fmt(path, sizeof path, err, "%s/%s", log->dir, name))
		return -1;
	/* a sync costs more than a generation of a fast task (XOR): the
	 * generation's files wait for the checkpoint's */
	if (strncmp(name, "best/", 5) == 0)
		return evo_write_file_replace(path, text, len, err);
	char csv[1200];
	if (evo_path_fmt(csv, sizeof csv, err, "%s/log.csv", log->dir) ||
	    (evo_file_exists(csv) && evo_file_sync(csv, err)))
		return -1;
	return evo_write_file_atomic(path, text, len, err);
}

static void clock_text(char *buf, size_t cap, double seconds)
{
	long s = seconds > 0 && seconds < 1e9 ? (long)(seconds + 0.5) : 0;
	if (s >= 3600)
		snprintf(buf, cap, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60,
			 s % 60);
	else
		snprintf(buf, cap, "%ld:%02ld", s / 60, s % 60);
}

/* A NaN (a generation whose every fitness is one) prints as "nan", not
 * printf's "-nan" of a NaN with its sign bit set. */
static double unsigned_nan(double v)
{
	return isnan(v) ? fabs(v) : v;
}

void evo_progress_format(char *buf, size_t cap, const evo_gen_stats *s,
			 int tty)
{
	char elapsed[32], eta[32] = "?";
	clock_text(elapsed, sizeof elapsed, s->elapsed);
	int done = s->generation + 1, ran = done - s->first;
	if (s->generations > 0 && ran > 0)
		clock_text(eta, sizeof eta,
			   s->elapsed / ran * (s->generations - done));
	double rate = s->seconds > 0 ? (double)s->evaluations / s->seconds : 0;
	char bar[32] = "";
	if (tty && s->generations > 0) {
		int fill = (int)(20.0 * done / s->generations);
		fill = fill < 0 ? 0 : fill > 20 ? 20 : fill;
		bar[0] = '[';
		for (int i = 0; i < 20; i++)
			bar[1 + i] = i < fill ? '#' : '.';
		bar[21] = ']';
		bar[22] = ' ';
		bar[23] = 0;
	}
	char species[256] = "";
	if (s->species > 0)
		snprintf(species, sizeof species, "  species %d", s->species);
	if (s->solved > 0)
		snprintf(species + strlen(species),
			 sizeof species - strlen(species), "  solved %d",
			 s->solved);
	if (s->team)
		snprintf(species + strlen(species),
			 sizeof species - strlen(species), "  %s won %.1f%%",
			 s->team, 100 * s->win_rate);
	if (s->note && s->note[0])
		snprintf(species + strlen(species),
			 sizeof species - strlen(species), "  %s", s->note);
	char total[32] = "";
	if (s->generations > 0)
		snprintf(total, sizeof total, "/%d", s->generations);
	snprintf(buf, cap,
		 "%sgen %d%s  best %.6g  mean %.6g%s  %.0f eval/s  "
		 "elapsed %s  ETA %s",
		 bar, s->generation, total, unsigned_nan(s->best),
		 unsigned_nan(s->mean), species, rate,
		 elapsed, s->generations > 0 ? eta : "-");
}

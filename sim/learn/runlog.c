/* A learning run's folder, log and progress line (sim/learn/runlog.h). */
#define _POSIX_C_SOURCE 200809L
#include "learn/runlog.h"

#include <dirent.h>
#include <math.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/fileio.h"

static const char HEADER[] =
	"generation,best,mean,best_ever,species,evaluations,solved,seconds,"
	"elapsed\n";

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
	int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
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

int evo_runlog_open(evo_runlog *log, const char *dir, int from_generation,
		    evo_err *err)
{
	memset(log, 0, sizeof *log);
	if (snprintf(log->dir, sizeof log->dir, "%s", dir) >=
	    (int)sizeof log->dir)
		return evo_fail(err, "%s: path too long", dir);
	char best[1100];
	snprintf(best, sizeof best, "%s/best", dir);
	if (make_dirs(best, err) || append(log, HEADER, strlen(HEADER), err))
		return -1;
	if (from_generation <= 0)
		return 0;
	/* Resuming: keep the rows before from_generation, drop any later
	 * one (written after the checkpoint the run resumes from). */
	char path[1100], *old;
	size_t len;
	snprintf(path, sizeof path, "%s/log.csv", dir);
	if (evo_read_file(path, &old, &len, err))
		return -1;
	const char *line = strchr(old, '\n');
	while (line && line[1]) {
		line++;
		const char *end = strchr(line, '\n');
		if (!end)
			break;
		if (atoi(line) < from_generation) {
			if (append(log, line, (size_t)(end - line + 1), err)) {
				free(old);
				return -1;
			}
			/* elapsed is the last column */
			const char *comma = end;
			while (comma > line && comma[-1] != ',')
				comma--;
			double e = strtod(comma, NULL);
			if (isfinite(e) && e > log->elapsed_before)
				log->elapsed_before = e;
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

int evo_runlog_add(evo_runlog *log, const evo_gen_stats *s, evo_err *err)
{
	/* %.17g: the log holds the exact doubles, so two runs compare equal
	 * only when their fitness values are bit for bit the same. The
	 * times come last and are left out of such comparisons. */
	char row[512];
	int n = snprintf(row, sizeof row, "%d,%.17g,%.17g,%.17g,%d,%ld,%d,%.3f,%.3f\n",
			 s->generation, s->best, s->mean, s->best_ever,
			 s->species, s->evaluations, s->solved, s->seconds,
			 log->elapsed_before + s->elapsed);
	if (append(log, row, (size_t)n, err))
		return -1;
	return evo_runlog_save(log, "log.csv", log->csv, log->len, err);
}

int evo_runlog_save(const evo_runlog *log, const char *name, const char *text,
		    size_t len, evo_err *err)
{
	char path[1200];
	if (evo_path_fmt(path, sizeof path, err, "%s/%s", log->dir, name))
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
	char species[64] = "";
	if (s->species > 0)
		snprintf(species, sizeof species, "  species %d", s->species);
	if (s->solved > 0)
		snprintf(species + strlen(species),
			 sizeof species - strlen(species), "  solved %d",
			 s->solved);
	char total[32] = "";
	if (s->generations > 0)
		snprintf(total, sizeof total, "/%d", s->generations);
	snprintf(buf, cap,
		 "%sgen %d%s  best %.6g  mean %.6g%s  %.0f eval/s  "
		 "elapsed %s  ETA %s",
		 bar, s->generation, total, s->best, s->mean, species, rate,
		 elapsed, s->generations > 0 ? eta : "-");
}

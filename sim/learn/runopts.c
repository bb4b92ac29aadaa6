/* What a learning run's folder remembers of its options (runopts.h). */
#define _POSIX_C_SOURCE 200809L
#include "learn/runopts.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/fileio.h"

int evo_learn_run_dir(const char *task_path, const evo_task *task,
		      const evo_learn_opts *o, char *dir, size_t cap,
		      evo_err *err)
{
	if (o->run_dir)
		return evo_path_fmt(dir, cap, err, "%s", o->run_dir);
	const char *base = strrchr(task_path, '/');
	base = base ? base + 1 : task_path;
	int n = (int)strcspn(base, ".");
	return evo_path_fmt(dir, cap, err, "%s/Runs/%.*s-seed%llu",
			    task->mind->root, n, base,
			    (unsigned long long)o->seed);
}

static const char header[] =
    "# the options this learning run was started with: evo run --resume\n"
    "# restores them (docs/learning.md); 0 is the task's TICKLIM or NUMGEN\n";

int evo_run_record_write(const char *dir, const evo_learn_opts *o,
			 evo_err *err)
{
	char path[1100], text[512];
	if (evo_path_fmt(path, sizeof path, err, "%s/options.txt", dir))
		return -1;
	int n = snprintf(text, sizeof text,
			 "%sseed %" PRIu64 "\nticks %ld\ngenerations %d\n"
			 "no-save %d\n",
			 header, o->seed, o->ticks, o->generations,
			 o->no_save ? 1 : 0);
	return evo_write_file_atomic(path, text, (size_t)n, err);
}

/* One "KEY VALUE" line of the record into r. 0, or -1 when the line is
 * none of them. */
static int record_line(const char *key, size_t klen, const char *v,
		       evo_run_record *r)
{
	char *end;
	errno = 0;
	unsigned long long x = strtoull(v, &end, 10);
	if (end == v || (*end && *end != '\n') || errno || v[0] == '-')
		return -1;
	if (klen == 4 && strncmp(key, "seed", 4) == 0)
		r->seed = (uint64_t)x;
	else if (klen == 5 && strncmp(key, "ticks", 5) == 0 && x <= 1000000000)
		r->ticks = (long)x;
	else if (klen == 11 && strncmp(key, "generations", 11) == 0 &&
		 x <= 1000000000)
		r->generations = (int)x;
	else if (klen == 7 && strncmp(key, "no-save", 7) == 0 && x <= 1)
		r->no_save = (int)x;
	else
		return -1;
	return 0;
}

int evo_run_record_read(const char *dir, evo_run_record *r, evo_err *err)
{
	memset(r, 0, sizeof *r);
	char path[1100];
	if (evo_path_fmt(path, sizeof path, err, "%s/options.txt", dir))
		return -1;
	if (!evo_file_exists(path))
		return 0;
	char *text;
	size_t len;
	if (evo_read_file(path, &text, &len, err))
		return -1;
	unsigned line = 1;
	int rc = 0;
	for (char *p = text; *p && rc == 0; line++) {
		char *nl = strchr(p, '\n');
		size_t n = nl ? (size_t)(nl - p) : strlen(p);
		if (n > 0 && p[0] != '#') {
			size_t k = strcspn(p, " \n");
			if (k >= n || record_line(p, k, p + k + 1, r))
				rc = evo_fail(err,
					      "%s:%u: expected 'seed N', "
					      "'ticks N', 'generations N' or "
					      "'no-save 0|1', found '%.*s'",
					      path, line, (int)(n > 60 ? 60 : n),
					      p);
		}
		p += n + (nl ? 1 : 0);
	}
	free(text);
	r->found = rc == 0;
	return rc;
}

/* The run's value of an option given again otherwise: refused. */
static int conflict(const char *dir, const char *flag, long given, long kept,
		    const char *none, evo_err *err)
{
	char was[64];
	if (kept)
		snprintf(was, sizeof was, "with %s %ld", flag, kept);
	else
		snprintf(was, sizeof was, "without %s (%s)", flag, none);
	return evo_fail(err,
			"evo run: %s %ld conflicts with the run in %s, which "
			"was started %s (%s/options.txt): --resume goes on with "
			"the options the run was started with, so leave out %s, "
			"or start a new run with another --run folder",
			flag, given, dir, was, dir, flag);
}

int evo_run_record_restore(const char *dir, evo_learn_opts *o, int seed_given,
			   evo_err *err)
{
	evo_run_record r;
	if (evo_run_record_read(dir, &r, err))
		return -1;
	if (!r.found)
		return 0;
	if (seed_given && o->seed != r.seed)
		return evo_fail(err,
				"evo run: --seed %" PRIu64 " conflicts with the "
				"run in %s, which was started with --seed %" PRIu64
				" (%s/options.txt): leave out --seed to resume "
				"it, or start a new run with another --run "
				"folder",
				o->seed, dir, r.seed, dir);
	o->seed = r.seed;
	if (o->ticks && o->ticks != r.ticks)
		return conflict(dir, "--ticks", o->ticks, r.ticks,
				"the task's TICKLIM", err);
	/* --generations may change: the generations to come are scored as
	 * they would be, the run just ends elsewhere (as with NUMGEN) */
	o->ticks = r.ticks;
	if (!o->generations)
		o->generations = r.generations;
	o->no_save = o->no_save || r.no_save;
	return 0;
}

void evo_run_record_args(const evo_learn_opts *o, char *buf, size_t cap)
{
	size_t at = 0;
	at += (size_t)snprintf(buf, cap, " --seed %" PRIu64, o->seed);
	if (o->ticks && at < cap)
		at += (size_t)snprintf(buf + at, cap - at, " --ticks %ld",
				       o->ticks);
	if (o->generations && at < cap)
		at += (size_t)snprintf(buf + at, cap - at, " --generations %d",
				       o->generations);
	if (o->no_save && at < cap)
		snprintf(buf + at, cap - at, " --no-save");
}

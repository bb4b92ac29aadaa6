/* Reading a trace (firmware/host/trace_file.h). */
#define _POSIX_C_SOURCE 200809L
#include "trace_file.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail(char *err, size_t cap, const char *path, size_t line,
		const char *what)
{
	snprintf(err, cap, "%s:%zu: %s", path, line, what);
	return -1;
}

/* The next line into *line; -1 at the end. */
static int next_line(FILE *f, char **line, size_t *cap, size_t *lineno)
{
	if (getline(line, cap, f) < 0)
		return -1;
	++*lineno;
	return 0;
}

/* A whole number in [lo, hi] at p, as strtol reads it, ended by a space,
 * '|' or the line's end; end after it. 0, or -1 when there is none
 * (end == p), more follows ("1e9") or it is out of range. */
static int field(const char *p, char **end, long lo, long hi, int32_t *v)
{
	errno = 0;
	long x = strtol(p, end, 10);
	if (*end == p || !strchr(" |\n", **end) || errno == ERANGE ||
	    x < lo || x > hi)
		return -1;
	*v = (int32_t)x;
	return 0;
}

int trace_load(const char *path, trace_file *t, char *err, size_t cap)
{
	memset(t, 0, sizeof *t);
	FILE *f = fopen(path, "r");
	if (!f) {
		snprintf(err, cap, "%s: %s", path, strerror(errno));
		return -1;
	}
	char *line = NULL;
	size_t linecap = 0, lineno = 0, alloc = 0;
	int rc = -1;
	unsigned long hash;
	int version = 0;
	if (next_line(f, &line, &linecap, &lineno) ||
	    sscanf(line, "evo-trace %d", &version) != 1 || version < 1 ||
	    version > 2) {
		fail(err, cap, path, 1, "expected 'evo-trace 1' or 'evo-trace 2'");
		goto out;
	}
	if (next_line(f, &line, &linecap, &lineno) ||
	    sscanf(line, "mind %63s names %lx", t->mind, &hash) != 2) {
		fail(err, cap, path, 2, "expected 'mind NAME names HASH'");
		goto out;
	}
	t->names_hash = (uint32_t)hash;
	if (next_line(f, &line, &linecap, &lineno) ||
	    sscanf(line, "sensors %u", &t->n_sensors) != 1 ||
	    next_line(f, &line, &linecap, &lineno) ||
	    sscanf(line, "actuators %u", &t->n_actuators) != 1 ||
	    t->n_sensors == 0 || t->n_actuators == 0 || t->n_sensors > 128 ||
	    t->n_actuators > 64) {
		fail(err, cap, path, lineno,
		     "expected 'sensors N ...' then 'actuators M ...'");
		goto out;
	}
	if (version >= 2 &&
	    (next_line(f, &line, &linecap, &lineno) ||
	     sscanf(line, "skills %u", &t->n_skills) != 1 || t->n_skills == 0 ||
	     t->n_skills > 256)) {
		fail(err, cap, path, lineno, "expected 'skills K ...'");
		goto out;
	}
	while (next_line(f, &line, &linecap, &lineno) == 0) {
		if (t->n_ticks == alloc) {
			alloc = alloc ? 2 * alloc : 1024;
			t->tick = realloc(t->tick, alloc * sizeof *t->tick);
			t->sensor = realloc(t->sensor, alloc * t->n_sensors *
							       sizeof *t->sensor);
			t->actuator =
				realloc(t->actuator, alloc * t->n_actuators *
							     sizeof *t->actuator);
			if (t->n_skills)
				t->influence = realloc(
				    t->influence,
				    alloc * t->n_skills * sizeof *t->influence);
			if (!t->tick || !t->sensor || !t->actuator ||
			    (t->n_skills && !t->influence)) {
				fail(err, cap, path, lineno, "out of memory");
				goto out;
			}
		}
		char *p = line, *end;
		size_t i = t->n_ticks;
		t->tick[i] = (uint32_t)strtoul(p, &end, 10);
		if (end == p)
			goto bad;
		p = end;
		/* A sensor value is what the tick read, after docs/mind.md's
		 * rule: Q16 in [0, 1]. Anything else (nan, inf, 1e9, past an
		 * int32) is a damaged trace, not something to send a robot. */
		for (unsigned s = 0; s < t->n_sensors; s++, p = end) {
			if (field(p, &end, 0, 65536,
				  &t->sensor[i * t->n_sensors + s])) {
				char what[96];
				snprintf(what, sizeof what,
					 "sensor %u: expected a Q16 value in "
					 "0..65536 ([0, 1])",
					 s + 1);
				fail(err, cap, path, lineno, what);
				goto out;
			}
		}
		while (*p == ' ')
			p++;
		if (*p++ != '|')
			goto bad;
		for (unsigned a = 0; a < t->n_actuators; a++, p = end)
			if (field(p, &end, INT32_MIN, INT32_MAX,
				  &t->actuator[i * t->n_actuators + a]))
				goto bad;
		if (t->n_skills) {
			while (*p == ' ')
				p++;
			if (*p++ != '|')
				goto bad;
			for (unsigned k = 0; k < t->n_skills; k++, p = end)
				if (field(p, &end, INT32_MIN, INT32_MAX,
					  &t->influence[i * t->n_skills + k]))
					goto bad;
		}
		if (*p != '\n' && *p != 0)
			goto bad;
		t->n_ticks++;
	}
	rc = 0;
	goto out;
bad:
	fail(err, cap, path, lineno,
	     "expected 'TICK sensors... | actuators... [| influences...]' "
	     "with the counts of the header");
out:
	free(line);
	fclose(f);
	if (rc != 0)
		trace_free(t);
	return rc;
}

void trace_free(trace_file *t)
{
	free(t->tick);
	free(t->sensor);
	free(t->actuator);
	free(t->influence);
	t->tick = NULL;
	t->sensor = t->actuator = t->influence = NULL;
}

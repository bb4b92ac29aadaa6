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
		for (unsigned s = 0; s < t->n_sensors; s++, p = end) {
			t->sensor[i * t->n_sensors + s] =
				(int32_t)strtol(p, &end, 10);
			if (end == p)
				goto bad;
		}
		while (*p == ' ')
			p++;
		if (*p++ != '|')
			goto bad;
		for (unsigned a = 0; a < t->n_actuators; a++, p = end) {
			t->actuator[i * t->n_actuators + a] =
				(int32_t)strtol(p, &end, 10);
			if (end == p)
				goto bad;
		}
		if (t->n_skills) {
			while (*p == ' ')
				p++;
			if (*p++ != '|')
				goto bad;
			for (unsigned k = 0; k < t->n_skills; k++, p = end) {
				t->influence[i * t->n_skills + k] =
					(int32_t)strtol(p, &end, 10);
				if (end == p)
					goto bad;
			}
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

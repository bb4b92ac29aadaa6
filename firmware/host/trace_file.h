/* A trace recorded by `evo run --trace` (docs/running.md): per tick the
 * sensor values the mind read, the actuator values it wrote and (from
 * version 2 on) each skill's influence, Q16. Versions 1 and 2 are read. */
#ifndef EVO_FW_TRACE_FILE_H
#define EVO_FW_TRACE_FILE_H

#include <stddef.h>
#include <stdint.h>

typedef struct trace_file {
	char mind[64];
	uint32_t names_hash;
	unsigned n_sensors, n_actuators;
	unsigned n_skills;  /* 0 in a version-1 trace */
	size_t n_ticks;
	uint32_t *tick;	    /* n_ticks tick numbers */
	int32_t *sensor;    /* n_ticks * n_sensors */
	int32_t *actuator;  /* n_ticks * n_actuators */
	int32_t *influence; /* n_ticks * n_skills; NULL when n_skills is 0 */
} trace_file;

/* The largest trace read: a million ticks of a large mind. A larger file,
 * or one that is no regular file, is refused before it is read. */
#define TRACE_FILE_MAX (1ull << 30)

/* Read a trace. 0, or -1 with "path:line: what" in err. */
int trace_load(const char *path, trace_file *t, char *err, size_t cap);

void trace_free(trace_file *t);

#endif

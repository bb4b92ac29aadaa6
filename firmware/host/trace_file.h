/* A trace recorded by `evo run --trace` (docs/running.md): per tick the
 * sensor values the mind read and the actuator values it wrote, Q16. */
#ifndef EVO_FW_TRACE_FILE_H
#define EVO_FW_TRACE_FILE_H

#include <stddef.h>
#include <stdint.h>

typedef struct trace_file {
	char mind[64];
	uint32_t names_hash;
	unsigned n_sensors, n_actuators;
	size_t n_ticks;
	uint32_t *tick;	    /* n_ticks tick numbers */
	int32_t *sensor;    /* n_ticks * n_sensors */
	int32_t *actuator;  /* n_ticks * n_actuators */
} trace_file;

/* Read a trace. 0, or -1 with "path:line: what" in err. */
int trace_load(const char *path, trace_file *t, char *err, size_t cap);

void trace_free(trace_file *t);

#endif

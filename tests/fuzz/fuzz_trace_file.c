/* libFuzzer target for the trace reader (firmware/host/trace_file.c),
 * which feeds a recorded trace to a firmware under QEMU: the input is
 * written to a file and read. Besides crashes, sanitizer reports and
 * leaks it checks its promises: a trace taken has counts in their ranges
 * and sensor values that are Q16 in [0, 1]; a refusal says where. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "host/trace_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char path[64];

static void remove_file(void)
{
	unlink(path);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	/* in memory where the machine has /dev/shm: a file on disk a run
	 * costs a journal write */
	if (!path[0]) {
		snprintf(path, sizeof path, "%s/evo-fuzz-trace-%ld",
			 access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp",
			 (long)getpid());
		atexit(remove_file);
	}
	FILE *f = fopen(path, "wb");
	if (!f)
		return 0;
	fwrite(data, 1, size, f);
	fclose(f);
	trace_file t;
	char err[512] = "";
	if (trace_load(path, &t, err, sizeof err) != 0) {
		if (!strstr(err, path))
			abort();
		return 0;
	}
	if (t.n_sensors < 1 || t.n_sensors > 128 || t.n_actuators < 1 ||
	    t.n_actuators > 64 || t.n_skills > 256)
		abort();
	for (size_t i = 0; i < t.n_ticks * t.n_sensors; i++)
		if (t.sensor[i] < 0 || t.sensor[i] > 65536)
			abort();
	trace_free(&t);
	return 0;
}

/* Reading a trace (firmware/host/trace_file.h). */
#define _POSIX_C_SOURCE 200809L
#include "trace_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int fail(char *err, size_t cap, const char *path, size_t line,
		const char *what)
{
	snprintf(err, cap, "%s:%zu: %s", path, line, what);
	return -1;
}

/* The longest line read: a tick of 128 sensors, 64 actuators and 256
 * skills, each at most 11 characters and a space, is under 6 KB. */
#define LINE_MAX_BYTES 65536

/* The next line into line (LINE_MAX_BYTES), its '\n' (and a '\r' before
 * it) removed; 0, 1 at the end of the file, -1 with err for a line too
 * long or a read error. */
static int next_line(FILE *f, char *line, size_t *lineno, const char *path,
		     char *err, size_t cap)
{
	if (!fgets(line, LINE_MAX_BYTES, f))
		return ferror(f) ? fail(err, cap, path, *lineno + 1,
					"cannot read")
				 : 1;
	++*lineno;
	size_t n = strlen(line);
	if (n == LINE_MAX_BYTES - 1 && line[n - 1] != '\n' && !feof(f)) {
		char what[64];
		snprintf(what, sizeof what, "a line longer than %d bytes",
			 LINE_MAX_BYTES - 1);
		return fail(err, cap, path, *lineno, what);
	}
	if (n && line[n - 1] == '\n')
		line[--n] = 0;
	if (n && line[n - 1] == '\r')
		line[--n] = 0;
	return 0;
}

/* A whole number in [lo, hi] at p: decimal digits, '-' first only when
 * lo < 0; no '+', no space, no wrap-round past the range (strtoul took
 * "-5" for 4294967291 and saturated 99999999999999999999). *end after
 * it. 0, or -1 when there is none or it is out of range. */
static int whole(const char *p, const char **end, long long lo, long long hi,
		 long long *v)
{
	int neg = *p == '-' && lo < 0;
	const char *q = p + neg;
	if (*q < '0' || *q > '9')
		return -1;
	unsigned long long cap = neg ? 0ull - (unsigned long long)lo
				     : (unsigned long long)hi;
	unsigned long long m = 0;
	for (; *q >= '0' && *q <= '9'; q++) {
		unsigned d = (unsigned)(*q - '0');
		if (d > cap || m > (cap - d) / 10)
			return -1;
		m = m * 10 + d;
	}
	long long x = neg ? (long long)(0ull - m) : (long long)m;
	if (x < lo || x > hi)
		return -1;
	*end = q;
	*v = x;
	return 0;
}

/* A field of a tick line: spaces, a whole number in [lo, hi], then a
 * space, '|' or the line's end ("1e9", "5x" are no numbers). */
static int field(const char *p, const char **end, long long lo, long long hi,
		 int32_t *v)
{
	while (*p == ' ')
		p++;
	long long x;
	if (whole(p, end, lo, hi, &x) || !strchr(" |", **end))
		return -1;
	*v = (int32_t)x;
	return 0;
}

/* A header line: word, a space, a whole number in [lo, hi], then the
 * line's end or a space (after which the names follow). */
static int header_count(const char *line, const char *word, long long lo,
			long long hi, unsigned *v)
{
	size_t n = strlen(word);
	const char *end;
	long long x;
	if (strncmp(line, word, n) != 0 || line[n] != ' ' ||
	    whole(line + n + 1, &end, lo, hi, &x) || (*end && *end != ' '))
		return -1;
	*v = (unsigned)x;
	return 0;
}

/* "mind NAME names HASH", HASH up to 8 hex digits. */
static int mind_line(const char *line, trace_file *t)
{
	if (strncmp(line, "mind ", 5) != 0)
		return -1;
	const char *name = line + 5;
	size_t n = strcspn(name, " ");
	if (n == 0 || n >= sizeof t->mind || strncmp(name + n, " names ", 7))
		return -1;
	const char *h = name + n + 7;
	uint32_t hash = 0;
	size_t k = 0;
	for (; h[k]; k++) {
		char c = h[k];
		int d = c >= '0' && c <= '9'   ? c - '0'
			: c >= 'a' && c <= 'f' ? c - 'a' + 10
			: c >= 'A' && c <= 'F' ? c - 'A' + 10
					       : -1;
		if (d < 0 || k == 8)
			return -1;
		hash = hash << 4 | (uint32_t)d;
	}
	if (k == 0)
		return -1;
	memcpy(t->mind, name, n);
	t->mind[n] = 0;
	t->names_hash = hash;
	return 0;
}

int trace_load(const char *path, trace_file *t, char *err, size_t cap)
{
	memset(t, 0, sizeof *t);
	/* O_NONBLOCK: a FIFO would wait for a writer before fstat could
	 * refuse it */
	int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
	FILE *f = fd >= 0 ? fdopen(fd, "r") : NULL;
	if (!f) {
		snprintf(err, cap, "%s: %s", path, strerror(errno));
		if (fd >= 0)
			close(fd);
		return -1;
	}
	struct stat st;
	if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
		snprintf(err, cap, "%s: not a regular file", path);
		fclose(f);
		return -1;
	}
	if ((unsigned long long)st.st_size > TRACE_FILE_MAX) {
		snprintf(err, cap,
			 "%s: %llu bytes, larger than a trace evo reads (at "
			 "most %llu MiB)",
			 path, (unsigned long long)st.st_size,
			 (unsigned long long)TRACE_FILE_MAX >> 20);
		fclose(f);
		return -1;
	}
	char *line = malloc(LINE_MAX_BYTES);
	size_t lineno = 0, alloc = 0;
	int rc = -1, r;
	unsigned version = 0;
	if (!line) {
		snprintf(err, cap, "%s: out of memory", path);
		fclose(f);
		return -1;
	}
	if ((r = next_line(f, line, &lineno, path, err, cap)) < 0)
		goto out;
	if (r || header_count(line, "evo-trace", 1, 2, &version)) {
		fail(err, cap, path, 1, "expected 'evo-trace 1' or 'evo-trace 2'");
		goto out;
	}
	if ((r = next_line(f, line, &lineno, path, err, cap)) < 0)
		goto out;
	if (r || mind_line(line, t)) {
		fail(err, cap, path, 2, "expected 'mind NAME names HASH'");
		goto out;
	}
	if ((r = next_line(f, line, &lineno, path, err, cap)) < 0)
		goto out;
	if (r || header_count(line, "sensors", 1, 128, &t->n_sensors)) {
		fail(err, cap, path, lineno,
		     "expected 'sensors N ...' (N in 1..128)");
		goto out;
	}
	if ((r = next_line(f, line, &lineno, path, err, cap)) < 0)
		goto out;
	if (r || header_count(line, "actuators", 1, 64, &t->n_actuators)) {
		fail(err, cap, path, lineno,
		     "expected 'actuators M ...' (M in 1..64)");
		goto out;
	}
	if (version >= 2) {
		if ((r = next_line(f, line, &lineno, path, err, cap)) < 0)
			goto out;
		if (r || header_count(line, "skills", 1, 256, &t->n_skills)) {
			fail(err, cap, path, lineno,
			     "expected 'skills K ...' (K in 1..256)");
			goto out;
		}
	}
	while ((r = next_line(f, line, &lineno, path, err, cap)) == 0) {
		if (t->n_ticks == alloc) {
			alloc = alloc ? 2 * alloc : 64;
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
		const char *p = line, *end;
		size_t i = t->n_ticks;
		long long tick;
		/* A tick number is what evo's counter wrote: 0 to 2^32 - 1,
		 * digits only ("-5" is not 4294967291, 2^64 not 2^32 - 1). */
		if (whole(p, &end, 0, UINT32_MAX, &tick) || *end != ' ') {
			char what[96];
			snprintf(what, sizeof what,
				 "expected a tick number in 0..%lu first, "
				 "found '%.24s'",
				 (unsigned long)UINT32_MAX, line);
			fail(err, cap, path, lineno, what);
			goto out;
		}
		t->tick[i] = (uint32_t)tick;
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
		while (*p == ' ')
			p++;
		if (*p != 0)
			goto bad;
		t->n_ticks++;
	}
	if (r == 1)
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

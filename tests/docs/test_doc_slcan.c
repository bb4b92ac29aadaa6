/* The slcan lines the docs show are lines evo's decoder takes, and hold
 * what the docs say they hold.
 *
 * Every line of the .md files of docs/ and of README.md whose first word is an slcan frame line
 * (`t` and hex digits, with or without a written `\r`) is decoded by
 * core's evo_slcan_decode, the decoder the firmware and the host use: it
 * must give a frame. Where the rest of the line says what the frame
 * carries (docs/wire.md's examples), that is checked too: each number in
 * parentheses is one of the frame's Q16 values (sensor and actuator
 * frames), "tick N" is the tick number a TICK or TICKED carries, and a
 * value written as "1.0" is 65536.
 *
 * Run from the repository root (make test does). Ends with "N passed, N
 * failed" and exits non-zero on a failure. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "evo/wire.h"
#include "harness.h"

static int lines_seen;

/* The frame's 32-bit little-endian values (sensor and actuator frames). */
static int frame_has_value(const evo_can_frame *f, long v)
{
	for (unsigned i = 0; i + 4 <= f->len; i += 4) {
		long w = (long)((uint32_t)f->data[i] | (uint32_t)f->data[i + 1] << 8 |
				(uint32_t)f->data[i + 2] << 16 |
				(uint32_t)f->data[i + 3] << 24);
		if (w == v)
			return 1;
	}
	return 0;
}

static int is_values_frame(const evo_can_frame *f)
{
	return (f->id >= EVO_WIRE_SENSOR && f->id < EVO_WIRE_SENSOR + EVO_WIRE_SENSOR_FRAMES) ||
	       (f->id >= EVO_WIRE_ACTUATOR &&
		f->id < EVO_WIRE_ACTUATOR + EVO_WIRE_ACTUATOR_FRAMES);
}

/* What the words after the line say, against the frame. */
static void check_note(const char *where, const evo_can_frame *f, const char *note)
{
	static char what[600];
	for (const char *p = strchr(note, '('); p; p = strchr(p + 1, '(')) {
		char *end;
		long v = strtol(p + 1, &end, 10);
		if (end == p + 1 || *end != ')')
			continue;
		snprintf(what, sizeof what, "%s: the frame carries %ld", where, v);
		test_current_name = what;
		CHECK(is_values_frame(f) && frame_has_value(f, v));
	}
	if (strstr(note, " 1.0") && is_values_frame(f)) {
		snprintf(what, sizeof what, "%s: the frame carries 1.0 (65536)", where);
		test_current_name = what;
		CHECK(frame_has_value(f, 65536));
	}
	const char *t = strstr(note, "tick ");
	if (t && (f->id == EVO_WIRE_TICK || f->id == EVO_WIRE_TICKED)) {
		long v = strtol(t + 5, NULL, 10);
		snprintf(what, sizeof what, "%s: the frame's tick is %ld", where, v);
		test_current_name = what;
		CHECK(f->len >= 4 && frame_has_value(f, v));
	}
}

static void check_line(const char *path, int lineno, const char *line)
{
	while (*line == ' ' || *line == '\t' || *line == '`')
		line++;
	if (line[0] != 't' || !isxdigit((unsigned char)line[1]))
		return;
	size_t n = 1;
	while (isxdigit((unsigned char)line[n]))
		n++;
	const char *rest = line + n;
	if (strncmp(rest, "\\r", 2) == 0)
		rest += 2;
	if (*rest && *rest != ' ' && *rest != '`' && *rest != '\n')
		return; /* a word that only starts like a line */
	if (n < 5)
		return;
	char where[512];
	snprintf(where, sizeof where, "%s:%d: %.*s decodes as an slcan line", path, lineno,
		 (int)n, line);
	evo_can_frame f;
	evo_wire_bad bad;
	test_current_name = where;
	test_current_failed = 0;
	lines_seen++;
	int ok = evo_slcan_decode(line, n, &f, &bad) == EVO_SLCAN_FRAME;
	CHECK_EQ_INT(ok, 1);
	if (ok)
		check_note(where, &f, rest);
	if (test_current_failed)
		test_failed_count++;
	else
		test_passed_count++;
}

static void check_file(const char *path)
{
	FILE *fp = fopen(path, "r");
	if (!fp) {
		test_current_name = path;
		CHECK(fp != NULL);
		test_failed_count++;
		return;
	}
	char line[4096];
	int lineno = 0;
	while (fgets(line, sizeof line, fp))
		check_line(path, ++lineno, line);
	fclose(fp);
}

int main(void)
{
	DIR *d = opendir("docs");
	if (!d) {
		fprintf(stderr, "test_doc_slcan: run from the repository root\n");
		return 2;
	}
	struct dirent *e;
	while ((e = readdir(d))) {
		size_t len = strlen(e->d_name);
		if (len > 3 && strcmp(e->d_name + len - 3, ".md") == 0) {
			char path[300];
			snprintf(path, sizeof path, "docs/%s", e->d_name);
			check_file(path);
		}
	}
	closedir(d);
	check_file("README.md");
	/* docs/wire.md's five examples and firmware.md's HELLO at least */
	test_current_name = "the docs show slcan lines";
	test_current_failed = 0;
	CHECK(lines_seen >= 6);
	if (test_current_failed)
		test_failed_count++;
	else
		test_passed_count++;
	return test_summary();
}

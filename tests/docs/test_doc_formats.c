/* The example files the docs show are files evo reads.
 *
 * A fenced block of any .md file of docs/ (or README.md) whose line before
 * says `<!-- format: KIND -->` is an example file of that kind: `botdesc`,
 * `vardesc`, `ades`, `simbatch` or `net`. It is parsed by core's own
 * parser of that format (the one evo loads mind folders with), which must
 * take it without an error, and for a .simbatch without a warning (an
 * unknown key). A mark of another kind fails, and so does a docs tree with
 * fewer marked examples than formats.md's own (so the marks cannot all go
 * missing unnoticed).
 *
 * Run from the repository root (make test does). Ends with "N passed, N
 * failed" and exits non-zero on a failure. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "evo/formats.h"
#include "harness.h"

static int examples_seen;

/* Parse buf as KIND; 1 when it is taken. err gets the parser's message. */
static int parse_as(const char *kind, const char *buf, size_t len, const char *where,
		    evo_diag *err)
{
	static evo_botdesc bd;
	static evo_vardesc vd;
	static evo_ades ad;
	static evo_simbatch sb;
	static evo_netdesc nd;
	err->msg[0] = 0;
	if (strcmp(kind, "botdesc") == 0)
		return evo_botdesc_parse(buf, len, where, &bd, err) == EVO_OK;
	if (strcmp(kind, "vardesc") == 0)
		return evo_vardesc_parse(buf, len, where, &vd, err) == EVO_OK;
	if (strcmp(kind, "ades") == 0)
		return evo_ades_parse(buf, len, where, &ad, err) == EVO_OK;
	if (strcmp(kind, "net") == 0)
		return evo_netdesc_parse(buf, len, where, &nd, err) == EVO_OK;
	if (strcmp(kind, "simbatch") == 0) {
		if (evo_simbatch_parse(buf, len, where, &sb, err) != EVO_OK)
			return 0;
		if (sb.n_warnings) {
			snprintf(err->msg, sizeof err->msg, "%s", sb.warning[0].msg);
			return 0;
		}
		return 1;
	}
	snprintf(err->msg, sizeof err->msg, "unknown format '%s'", kind);
	return 0;
}

static void check_example(const char *path, int line, const char *kind, const char *buf,
			  size_t len)
{
	char where[600];
	evo_diag err;
	snprintf(where, sizeof where, "%s:%d (a %s example)", path, line, kind);
	test_current_name = where;
	test_current_failed = 0;
	examples_seen++;
	int ok = parse_as(kind, buf, len, where, &err);
	CHECK_EQ_INT(ok, 1);
	if (!ok)
		printf("    %s\n", err.msg);
	if (test_current_failed)
		test_failed_count++;
	else
		test_passed_count++;
}

static void check_file(const char *path)
{
	FILE *fp = fopen(path, "r");
	if (!fp)
		return;
	static char block[65536];
	char line[4096], kind[32] = "";
	size_t len = 0;
	int lineno = 0, start = 0, in = 0;
	while (fgets(line, sizeof line, fp)) {
		lineno++;
		if (strncmp(line, "```", 3) == 0) {
			if (in && kind[0])
				check_example(path, start, kind, block, len);
			if (in)
				kind[0] = 0;
			in = !in;
			start = lineno;
			len = 0;
			continue;
		}
		if (in) {
			size_t n = strlen(line);
			if (len + n < sizeof block) {
				memcpy(block + len, line, n);
				len += n;
			}
			continue;
		}
		if (sscanf(line, "<!-- format: %31[a-z] -->", kind) != 1 && line[0] != '\n')
			kind[0] = 0;
	}
	fclose(fp);
}

int main(void)
{
	DIR *d = opendir("docs");
	if (!d) {
		fprintf(stderr, "test_doc_formats: run from the repository root\n");
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
	/* formats.md's own: a botdesc, a vardesc, two .ades, a .simbatch, a .net */
	test_current_name = "the docs mark their example files";
	test_current_failed = 0;
	CHECK(examples_seen >= 6);
	if (test_current_failed)
		test_failed_count++;
	else
		test_passed_count++;
	return test_summary();
}

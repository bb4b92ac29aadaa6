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
 * formats.md's examples of error messages are checked the other way: each
 * is what core's parser says of an input this test holds, exactly, and
 * every line of that block is one of them.
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

/* The inputs behind formats.md's error messages ("for example"), in the
 * block's order. */
static const struct {
	const char *kind, *file, *text;
} error_inputs[] = {
    {"ades", "Avoid.ades",
     "Avoid\ninput:16\nSE:S1\nSE:S2\nSE:S3\nSE:S4\nSE:S5\nSE:S6\nSE:S7\nSE:S8\n"
     "SE:S9\nSE:S10\nSE:S11\nSE:S12\nSE:S13\nSE:S14\nSE:S15\noutput:4\n"},
    {"botdesc", "b.botdesc", "SENSORS\nS1:proxSensor\nS2:proxSensor\nS1:proxSensor\n"},
    {"vardesc", "v.vardesc", "A:VariableModule\nB:VariableModule\nC:Countervariable\n"},
    {"net", "x.net", "inputs:2\noutputs:1\nnode:2:tanh:0\noutput:2\nlink:0:2:-200.5\n"},
};

/* The lines of formats.md's block of error messages, the one after
 * `<!-- checked by tests/docs/test_doc_formats.c -->`. */
static int read_error_block(char lines[][512], int max)
{
	FILE *fp = fopen("docs/formats.md", "r");
	char line[4096];
	int n = 0, state = 0; /* 0 looking, 1 after the mark, 2 in the block */
	if (!fp)
		return 0;
	while (fgets(line, sizeof line, fp)) {
		line[strcspn(line, "\n")] = 0;
		if (state == 0 &&
		    strcmp(line, "<!-- checked by tests/docs/test_doc_formats.c -->") == 0)
			state = 1;
		else if (state == 1 && strcmp(line, "```") == 0)
			state = 2;
		else if (state == 2 && strcmp(line, "```") == 0)
			break;
		else if (state == 2 && n < max) {
			size_t k = strlen(line) < 511 ? strlen(line) : 511;
			memcpy(lines[n], line, k);
			lines[n++][k] = 0;
		}
	}
	fclose(fp);
	return n;
}

static void check_error_examples(void)
{
	static char lines[16][512];
	int n = read_error_block(lines, 16);
	test_current_name = "formats.md's error messages are what the parsers say";
	test_current_failed = 0;
	CHECK_EQ_INT(n, (int)(sizeof error_inputs / sizeof error_inputs[0]));
	for (int i = 0; i < n && i < (int)(sizeof error_inputs / sizeof error_inputs[0]); i++) {
		evo_diag err;
		const char *t = error_inputs[i].text;
		int ok = parse_as(error_inputs[i].kind, t, strlen(t), error_inputs[i].file, &err);
		CHECK_EQ_INT(ok, 0);
		CHECK_EQ_STR(err.msg, lines[i]);
	}
	if (test_current_failed)
		test_failed_count++;
	else
		test_passed_count++;
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
	check_error_examples();
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

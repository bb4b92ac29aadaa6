/* Networks compiled at -O0 and at -O2 give bit-identical outputs: runs
 * $EVO_BUILD/tests/net_dump_O0 and net_dump_O2 (built by the Makefile from
 * tests/support/net_dump_main.c and core/src) and compares what they
 * print. EVO_BUILD defaults to "build". */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>

#include "harness.h"

#define MIN_LINES 2000 /* 300 nets x 8 evaluations, and the sweeps */

typedef struct dump {
	char *text;
	size_t len;
	long lines;
	int status;
} dump;

static dump run_dump(const char *name)
{
	const char *build = getenv("EVO_BUILD");
	char cmd[1024];
	dump d = {NULL, 0, 0, -1};
	size_t cap = 0;
	FILE *p;
	int c;

	snprintf(cmd, sizeof cmd, "'%s/tests/%s'", build ? build : "build",
		 name);
	p = popen(cmd, "r");
	if (!p)
		return d;
	while ((c = getc(p)) != EOF) {
		if (d.len + 1 >= cap) {
			char *t = realloc(d.text, cap = cap ? 2 * cap : 65536);
			if (!t)
				break;
			d.text = t;
		}
		d.text[d.len++] = (char)c;
		d.lines += c == '\n';
	}
	if (d.text)
		d.text[d.len] = 0;
	d.status = pclose(p);
	return d;
}

TEST(net_outputs_identical_at_O0_and_O2)
{
	dump a = run_dump("net_dump_O0"), b = run_dump("net_dump_O2");
	size_t i;

	CHECK_EQ_INT(a.status, 0);
	CHECK_EQ_INT(b.status, 0);
	CHECK(a.lines >= MIN_LINES);
	CHECK_EQ_INT(a.lines, b.lines);
	CHECK_EQ_INT(a.len, b.len);
	for (i = 0; i < a.len && i < b.len; i++)
		if (a.text[i] != b.text[i])
			break;
	if (i < a.len || i < b.len) {
		size_t line = 1, k;
		for (k = 0; k < i; k++)
			line += a.text[k] == '\n';
		printf("  first difference on line %lu\n", (unsigned long)line);
		CHECK(!"net_dump_O0 and net_dump_O2 differ");
	} else {
		printf("  %ld lines, %lu bytes, identical\n", a.lines,
		       (unsigned long)a.len);
	}
	free(a.text);
	free(b.text);
}

int main(void)
{
	RUN(net_outputs_identical_at_O0_and_O2);
	return test_summary();
}

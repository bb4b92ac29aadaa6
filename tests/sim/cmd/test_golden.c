/* Golden outputs (tests/data/golden/, its README.md): the DEMOSIM traces
 * and rewards of the four shipped 2D examples, and the logs, champions and
 * reports of short learning runs (XOR, DPV and DPNV with NEAT; Avoid in
 * the 2D world with NEAT, GENETIC and ANNEALING), recorded with the code
 * as it was before the sim/ and tests/ layout move. This test runs the
 * same commands with the evo under test and finds every figure equal,
 * line by line. It guards that the layout refactor, and every later
 * change, changes no figure. A change that means to change figures
 * re-records these files (tests/data/golden/record.sh) in a commit that
 * says why; the commands here and in record.sh must stay the same.
 *
 * On a difference it prints the golden file, the first differing line's
 * number and both lines (for a trace also the episode, tick and column),
 * and how many lines differ.
 *
 * Beside the golden files, a few values that do not come from them: each
 * trace's header lists the sensors and actuators of the mind's .botdesc in
 * order and holds 2 episodes of 1000 ticks; each learning log has the
 * task's population in its evaluations column and, with its champion's
 * first line, agrees on the generations and the best fitness. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "harness.h"
#include "support/cli.h"

#define GOLDEN "tests/data/golden"

/* ---- reading and comparing ---------------------------------------------- */

/* A whole file's text, gzip-compressed or not (gzread reads a plain file
 * as it is); free it. NULL when it cannot be read. */
static char *read_gz(const char *path)
{
	gzFile f = gzopen(path, "rb");
	if (!f)
		return NULL;
	size_t cap = 1 << 16, len = 0;
	char *buf = malloc(cap);
	for (;;) {
		if (!buf)
			break;
		if (cap - len < 2) {
			char *more = realloc(buf, cap * 2);
			if (!more) {
				free(buf);
				buf = NULL;
				break;
			}
			buf = more;
			cap *= 2;
		}
		int n = gzread(f, buf + len, (unsigned)(cap - len - 1));
		if (n < 0) {
			free(buf);
			buf = NULL;
			break;
		}
		if (n == 0)
			break;
		len += (size_t)n;
	}
	gzclose(f);
	if (buf)
		buf[len] = 0;
	return buf;
}

/* The line at *p (its length in *len); *p moves to the next line. NULL at
 * the end of the text. */
static const char *next_line(const char **p, size_t *len)
{
	if (!**p)
		return NULL;
	const char *line = *p, *end = strchr(line, '\n');
	*len = end ? (size_t)(end - line) : strlen(line);
	*p = line + *len + (end ? 1 : 0);
	return line;
}

static int blank(char c)
{
	return c == ' ' || c == '\t' || c == '\r';
}

/* The n-th (from 0) blank-separated word of line[0..len) into out; 0, or
 * -1 when the line has fewer words. */
static int word(const char *line, size_t len, int n, char *out, size_t cap)
{
	size_t i = 0;
	for (int k = 0;; k++) {
		while (i < len && blank(line[i]))
			i++;
		if (i >= len)
			return -1;
		size_t start = i;
		while (i < len && !blank(line[i]))
			i++;
		if (k == n) {
			size_t w = i - start < cap - 1 ? i - start : cap - 1;
			memcpy(out, line + start, w);
			out[w] = 0;
			return 0;
		}
	}
}

/* In a trace: the name of data column `col` (0 the tick, then the sensors,
 * "|", the actuators, "|", the skills' influences), from the header of
 * `text`. */
static void trace_column(const char *text, int col, char *out, size_t cap)
{
	const char *p = text, *line;
	size_t len;
	int ns = -1, na = -1;
	char w[64];
	snprintf(out, cap, "column %d", col);
	if (col == 0) {
		snprintf(out, cap, "tick");
		return;
	}
	while ((line = next_line(&p, &len))) {
		if (len > 8 && strncmp(line, "sensors ", 8) == 0) {
			ns = atoi(line + 8);
			if (col <= ns &&
			    word(line, len, col + 1, w, sizeof w) == 0)
				snprintf(out, cap, "sensor %s", w);
		} else if (len > 10 && strncmp(line, "actuators ", 10) == 0) {
			na = atoi(line + 10);
			if (ns >= 0 && col == ns + 1)
				snprintf(out, cap, "the '|'");
			else if (ns >= 0 && col > ns + 1 && col <= ns + 1 + na &&
				 word(line, len, col - ns, w, sizeof w) == 0)
				snprintf(out, cap, "actuator %s", w);
		} else if (len > 7 && strncmp(line, "skills ", 7) == 0) {
			int k0 = ns + 1 + na + 1; /* the second '|' */
			if (ns >= 0 && na >= 0 && col == k0)
				snprintf(out, cap, "the second '|'");
			else if (ns >= 0 && na >= 0 && col > k0 &&
				 word(line, len, col - k0 + 1, w, sizeof w) == 0)
				snprintf(out, cap, "influence of %s", w);
			return;
		}
	}
}

/* Where a trace's line `lineno` (from 1) is: its episode (from 1, counting
 * the tick-0 lines up to it), tick and the first column where `a` and `b`
 * differ. */
static void trace_where(const char *text, int lineno, const char *a,
			size_t alen, const char *b, size_t blen)
{
	const char *p = text, *line;
	size_t len;
	int n = 0, episode = 0;
	while ((line = next_line(&p, &len)) && ++n <= lineno)
		episode += len > 2 && line[0] == '0' && line[1] == ' ';
	char wa[64], wb[64], tick[64], col[96];
	if (word(a, alen, 0, tick, sizeof tick) != 0 || tick[0] < '0' ||
	    tick[0] > '9')
		return;
	int c = 0;
	for (;; c++) {
		int ra = word(a, alen, c, wa, sizeof wa);
		int rb = word(b, blen, c, wb, sizeof wb);
		if (ra != 0 && rb != 0)
			return;
		if (ra != rb || strcmp(wa, wb) != 0)
			break;
	}
	trace_column(text, c, col, sizeof col);
	printf("    episode %d, tick %s, first in %s\n", episode, tick, col);
}

/* Compares `got` with the golden text `want` of `file`, line by line. On a
 * difference, prints the file, the first differing line's number, both
 * lines and how many lines differ; 0 then, 1 when they are equal. */
static int same_lines(const char *file, const char *want, const char *got,
		      int is_trace)
{
	const char *pw = want, *pg = got, *lw, *lg;
	const char *first_w = NULL, *first_g = NULL;
	size_t nw = 0, ng = 0, first_nw = 0, first_ng = 0;
	int lineno = 0, first = 0, differ = 0;
	for (;;) {
		lw = next_line(&pw, &nw);
		lg = next_line(&pg, &ng);
		if (!lw && !lg)
			break;
		lineno++;
		if (lw && lg && nw == ng && memcmp(lw, lg, nw) == 0)
			continue;
		if (!differ++) {
			first = lineno;
			first_w = lw;
			first_nw = nw;
			first_g = lg;
			first_ng = ng;
		}
	}
	if (!differ)
		return 1;
	printf("  %s: first difference at line %d; %d of %d lines differ\n",
	       file, first, differ, lineno);
	if (first_w)
		printf("    want: %.*s\n", (int)first_nw, first_w);
	else
		printf("    want: (end of file)\n");
	if (first_g)
		printf("    got:  %.*s\n", (int)first_ng, first_g);
	else
		printf("    got:  (end of file)\n");
	if (is_trace && first_w && first_g)
		trace_where(want, first, first_w, first_nw, first_g, first_ng);
	return 0;
}

/* Compares the text `got` with the golden file GOLDEN/name. */
static void check_golden(const char *name, const char *got, int is_trace)
{
	char path[512];
	snprintf(path, sizeof path, "%s/%s", GOLDEN, name);
	char *want = read_gz(path);
	if (!want)
		printf("  cannot read the golden file %s\n", path);
	CHECK(want != NULL);
	CHECK(got != NULL);
	if (want && got)
		CHECK(same_lines(path, want, got, is_trace));
	free(want);
}

/* ---- DEMOSIM ------------------------------------------------------------- */

/* "sensors N a b ..." and "actuators N x y ..." as a trace's header would
 * list the entries of the .botdesc at `path` (docs/formats.md): the
 * names before the first ':' of its entries, in order. 0, or -1. */
static int botdesc_header(const char *path, char *sens, char *acts, size_t cap)
{
	char *text = cli_read("%s", path);
	if (!text)
		return -1;
	char names[2][2048] = {"", ""}, w[256];
	int count[2] = {0, 0}, section = -1;
	const char *p = text, *line;
	size_t len;
	while ((line = next_line(&p, &len))) {
		for (int k = 0; word(line, len, k, w, sizeof w) == 0; k++) {
			if (w[0] == '#')
				break; /* a comment: the rest of the line */
			if (strcmp(w, "SENSORS") == 0 ||
			    strcmp(w, "ACTUATORS") == 0) {
				section = w[0] == 'A';
				continue;
			}
			char *colon = strchr(w, ':');
			if (section < 0 || !colon)
				continue;
			*colon = 0;
			size_t used = strlen(names[section]);
			snprintf(names[section] + used,
				 sizeof names[section] - used, " %s", w);
			count[section]++;
		}
	}
	free(text);
	snprintf(sens, cap, "sensors %d%s", count[0], names[0]);
	snprintf(acts, cap, "actuators %d%s", count[1], names[1]);
	return 0;
}

/* The trace's header names the .botdesc's sensors and actuators in order,
 * then the skills, and its data lines are `episodes` episodes of `ticks`
 * ticks, each line the tick, the sensor values, "|", the actuator values,
 * "|" and the skills' influences. */
static void check_trace_shape(const char *trace, const char *botdesc,
			      int episodes, int ticks)
{
	char sens[4096], acts[4096];
	int rc = botdesc_header(botdesc, sens, acts, sizeof sens);
	CHECK_EQ_INT(rc, 0);
	if (rc != 0)
		return;
	const char *p = trace, *line;
	size_t len;
	char buf[4096];
	line = next_line(&p, &len);
	CHECK(line && len == 11 && strncmp(line, "evo-trace 2", 11) == 0);
	line = next_line(&p, &len); /* mind NAME names HASH */
	CHECK(line && strncmp(line, "mind ", 5) == 0);
	line = next_line(&p, &len);
	snprintf(buf, sizeof buf, "%.*s", line ? (int)len : 0,
		 line ? line : "");
	CHECK_EQ_STR(buf, sens);
	line = next_line(&p, &len);
	snprintf(buf, sizeof buf, "%.*s", line ? (int)len : 0,
		 line ? line : "");
	CHECK_EQ_STR(buf, acts);
	line = next_line(&p, &len); /* skills K master ... */
	CHECK(line && strncmp(line, "skills ", 7) == 0);
	int nk = line ? atoi(line + 7) : 0;
	CHECK(nk >= 1);
	int ns = atoi(sens + 8), na = atoi(acts + 10), rows = 0, bad = 0;
	while ((line = next_line(&p, &len))) {
		char w[64];
		int words = 0;
		while (word(line, len, words, w, sizeof w) == 0)
			words++;
		word(line, len, 0, w, sizeof w);
		int ok = atoi(w) == rows % ticks &&
			 words == 1 + ns + 1 + na + 1 + nk &&
			 word(line, len, 1 + ns, w, sizeof w) == 0 &&
			 strcmp(w, "|") == 0 &&
			 word(line, len, 1 + ns + 1 + na, w, sizeof w) == 0 &&
			 strcmp(w, "|") == 0;
		if (!ok && !bad++)
			printf("  trace line %d: %.*s\n", rows + 6, (int)len,
			       line);
		rows++;
	}
	CHECK_EQ_INT(bad, 0);
	CHECK_EQ_INT(rows, episodes * ticks);
}

/* `evo run TASK --headless --seed 3 --episodes 2 --ticks 1000 --trace`:
 * its output and trace equal the golden NAME.out and NAME.trace.gz. */
static void demo(const char *name, const char *task, const char *botdesc)
{
	int rc =
	    cli_sh("%s run %s --headless --seed 3 --episodes 2 "
		   "--ticks 1000 --trace %s/%s.trace > %s/%s.out "
		   "2> %s/%s.err",
		   cli_evo, task, cli_tmp, name, cli_tmp, name, cli_tmp, name);
	CHECK_EQ_INT(rc, 0);
	if (rc != 0) {
		char *err = cli_read("%s/%s.err", cli_tmp, name);
		printf("  %s said: %s\n", task, err ? err : "(nothing)");
		free(err);
	}
	char gold[128], path[512];
	char *out = cli_read("%s/%s.out", cli_tmp, name);
	snprintf(gold, sizeof gold, "%s.out", name);
	check_golden(gold, out, 0);
	free(out);
	snprintf(path, sizeof path, "%s/%s.trace", cli_tmp, name);
	char *trace = read_gz(path);
	snprintf(gold, sizeof gold, "%s.trace.gz", name);
	check_golden(gold, trace, 1);
	if (trace)
		check_trace_shape(trace, botdesc, 2, 1000);
	free(trace);
}

TEST(avoid_demo_trace_is_golden)
{
	demo("avoid-demo", "minds/Avoid/Tasks/Avoid-DEMO.simbatch",
	     "minds/Avoid/Avoid.botdesc");
}

TEST(gto_demo_trace_is_golden)
{
	demo("gto-demo", "minds/GTO/Tasks/GTO-DEMO.simbatch",
	     "minds/GTO/GTO.botdesc");
}

TEST(gtoa_demo_trace_is_golden)
{
	demo("gtoa-demo", "minds/GTO/Tasks/GTOA-DEMO.simbatch",
	     "minds/GTO/GTO.botdesc");
}

TEST(collect_demo_trace_is_golden)
{
	demo("collect-demo", "minds/Collect/Tasks/Collect-DEMO.simbatch",
	     "minds/Collect/Collect.botdesc");
}

/* ---- LEARNSIM ------------------------------------------------------------ */

typedef struct learn_run {
	const char *name;   /* the golden files' prefix */
	const char *mind;   /* the folder under minds/ that is copied */
	const char *task;   /* the task, under the copy's Tasks/ */
	int own_task;	    /* the task comes from tests/data/golden/tasks/ */
	const char *sed;    /* a sed script applied to the copy's `file` */
	const char *file;   /* (relative to the copy), or NULL */
	const char *method; /* as the champion's first line names it */
	int evaluations;    /* the log's evaluations column, every row */
	int generations;    /* the log's rows; 0: until solved */
} learn_run;

/* The n-th (from 0) comma-separated field of a log row into out. */
static void field(const char *row, int n, char *out, size_t cap)
{
	for (int k = 0; k < n && row; k++) {
		row = strchr(row, ',');
		if (row)
			row++;
	}
	size_t len = row ? strcspn(row, ",\n") : 0;
	if (len >= cap)
		len = cap - 1;
	memcpy(out, row ? row : "", len);
	out[len] = 0;
}

/* The log's rows agree with the task's population and length, and with
 * the champion's first line: "# trained by evo: METHOD, seed 1, R
 * generations, fitness F", R the rows and F the last row's best_ever. A
 * run that stops when solved has `solved` 0 in every row but its last. */
static void check_log_shape(const learn_run *r, const char *log,
			    const char *champion)
{
	const char *p = strchr(log, '\n'), *last = NULL;
	int rows = 0, unsolved_before_last = 1;
	char f[64], want[64];
	snprintf(want, sizeof want, "%d", r->evaluations);
	while (p && p[1]) {
		const char *row = p + 1;
		if (last) {
			field(last, 6, f, sizeof f);
			unsolved_before_last &= strcmp(f, "0") == 0;
		}
		field(row, 5, f, sizeof f);
		CHECK_EQ_STR(f, want);
		field(row, 0, f, sizeof f);
		CHECK_EQ_INT(atoi(f), rows);
		last = row;
		rows++;
		p = strchr(row, '\n');
	}
	CHECK(last != NULL);
	if (!last)
		return;
	if (r->generations) {
		CHECK_EQ_INT(rows, r->generations);
	} else {
		field(last, 6, f, sizeof f);
		CHECK(atoi(f) >= 1);
		CHECK(unsolved_before_last);
	}
	char best[64], line[256];
	field(last, 3, best, sizeof best);
	snprintf(line, sizeof line,
		 "# trained by evo: %s, seed 1, %d generations, fitness %s",
		 r->method, rows, best);
	size_t n = champion ? strcspn(champion, "\n") : 0;
	char got[256];
	snprintf(got, sizeof got, "%.*s", (int)n, champion ? champion : "");
	CHECK_EQ_STR(got, line);
}

/* The lines of a learning run's output that carry figures and neither
 * time nor path (record.sh's grep); free it. */
static char *report_of(const char *out)
{
	static const char *const keep[] = {"solved in generation ",
					   "replay on unseen ",
					   "  champion: ", "  untrained "};
	char *rep = malloc(strlen(out) + 1), *w = rep;
	if (!rep)
		return NULL;
	const char *p = out, *line;
	size_t len;
	while ((line = next_line(&p, &len))) {
		for (size_t k = 0; k < sizeof keep / sizeof keep[0]; k++)
			if (strncmp(line, keep[k], strlen(keep[k])) == 0) {
				memcpy(w, line, len);
				w += len;
				*w++ = '\n';
				break;
			}
	}
	*w = 0;
	return rep;
}

/* A copy of minds/MIND in cli_tmp/NAME, prepared, trained with seed 1 on 2
 * threads into cli_tmp/NAME/run: its log without the time columns, its
 * champion and its report equal the golden NAME.log.csv,
 * NAME.champion.net and NAME.report.txt. */
static void learn(const learn_run *r)
{
	int rc = cli_sh("mkdir -p %s/%s && cp -r minds/%s %s/%s/", cli_tmp,
			r->name, r->mind, cli_tmp, r->name);
	CHECK_EQ_INT(rc, 0);
	if (r->own_task)
		CHECK_EQ_INT(cli_sh("cp %s/tasks/%s %s/%s/%s/Tasks/", GOLDEN,
				    r->task, cli_tmp, r->name, r->mind),
			     0);
	if (r->sed)
		CHECK_EQ_INT(cli_sh("sed -i '%s' %s/%s/%s/%s", r->sed, cli_tmp,
				    r->name, r->mind, r->file),
			     0);
	rc = cli_sh("%s run %s/%s/%s/Tasks/%s --seed 1 --threads 2 --run "
		    "%s/%s/run > %s/%s/out.txt 2>&1",
		    cli_evo, cli_tmp, r->name, r->mind, r->task, cli_tmp,
		    r->name, cli_tmp, r->name);
	CHECK_EQ_INT(rc, 0);
	char *out = cli_read("%s/%s/out.txt", cli_tmp, r->name);
	if (rc != 0)
		printf("  %s said: %s\n", r->name, out ? out : "(nothing)");
	char run[512], gold[128];
	snprintf(run, sizeof run, "%s/%s/run", cli_tmp, r->name);
	char *log = cli_fitness_log(run);
	char *champion = cli_read("%s/champion.net", run);
	char *report = out ? report_of(out) : NULL;
	snprintf(gold, sizeof gold, "%s.log.csv", r->name);
	check_golden(gold, log, 0);
	snprintf(gold, sizeof gold, "%s.champion.net", r->name);
	check_golden(gold, champion, 0);
	snprintf(gold, sizeof gold, "%s.report.txt", r->name);
	check_golden(gold, report, 0);
	if (log)
		check_log_shape(r, log, champion);
	free(out);
	free(log);
	free(champion);
	free(report);
}

/* The literature tasks as shipped (XOR and DPV stop when solved, seed 1
 * solving both in a few seconds); DPNV cut to 3 generations. */
TEST(xor_neat_log_is_golden)
{
	static const learn_run r = {.name = "xor-neat",
				    .mind = "XOR",
				    .task = "XOR-NEAT.simbatch",
				    .method = "NEAT",
				    .evaluations = 150};
	learn(&r);
}

TEST(dpv_neat_log_is_golden)
{
	static const learn_run r = {.name = "dpv-neat",
				    .mind = "DoublePole",
				    .task = "DPV-NEAT.simbatch",
				    .method = "NEAT",
				    .evaluations = 150};
	learn(&r);
}

TEST(dpnv_neat_log_is_golden)
{
	static const learn_run r = {.name = "dpnv-neat",
				    .mind = "DoublePoleNV",
				    .task = "DPNV-NEAT.simbatch",
				    .sed = "s/^NUMGEN:.*/NUMGEN:3/",
				    .file = "Tasks/DPNV-NEAT.simbatch",
				    .method = "NEAT",
				    .evaluations = 1000,
				    .generations = 3};
	learn(&r);
}

/* Avoid in the 2D world with the golden folder's small tasks: NEAT in the
 * mind folder's own Envs/Roam.lua; GENETIC and ANNEALING, on a layered
 * network (layers:1), in the built-in EXP_Avoid. */
TEST(avoid_neat_log_is_golden)
{
	static const learn_run r = {.name = "avoid-neat",
				    .mind = "Avoid",
				    .task = "Avoid-NEAT-golden.simbatch",
				    .own_task = 1,
				    .method = "NEAT",
				    .evaluations = 24,
				    .generations = 4};
	learn(&r);
}

TEST(avoid_genetic_log_is_golden)
{
	static const learn_run r = {.name = "avoid-genetic",
				    .mind = "Avoid",
				    .task = "Avoid-GENETIC-golden.simbatch",
				    .own_task = 1,
				    .sed = "s/^layers:0$/layers:1/",
				    .file = "Skills/Avoid/Avoid.ades",
				    .method = "GENETIC",
				    .evaluations = 12,
				    .generations = 4};
	learn(&r);
}

TEST(avoid_annealing_log_is_golden)
{
	static const learn_run r = {.name = "avoid-annealing",
				    .mind = "Avoid",
				    .task = "Avoid-ANNEALING-golden.simbatch",
				    .own_task = 1,
				    .sed = "s/^layers:0$/layers:1/",
				    .file = "Skills/Avoid/Avoid.ades",
				    .method = "ANNEALING",
				    .evaluations = 4,
				    .generations = 4};
	learn(&r);
}

int main(void)
{
	if (cli_setup("golden"))
		return 1;
	RUN(avoid_demo_trace_is_golden);
	RUN(gto_demo_trace_is_golden);
	RUN(gtoa_demo_trace_is_golden);
	RUN(collect_demo_trace_is_golden);
	RUN(xor_neat_log_is_golden);
	RUN(dpv_neat_log_is_golden);
	RUN(dpnv_neat_log_is_golden);
	RUN(avoid_neat_log_is_golden);
	RUN(avoid_genetic_log_is_golden);
	RUN(avoid_annealing_log_is_golden);
	cli_cleanup();
	return test_summary();
}

/* LEARNSIM with GENETIC and ANNEALING end to end (sim/learn.c,
 * lua/learn/learnsim.lua over lua/learn/genetic.lua and annealing.lua): a
 * copy of the Avoid example, its skill given `layers:1`, trains for three
 * small generations; the run ends well, logs three rows, and its champion
 * is a layered network that evo loads (evo check of the copy's DEMO task).
 * GENETIC gives the same log with one thread and with two. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "fileio.h"
#include "harness.h"

static char evo_bin[256];
static char tmpdir[128];

static int sh(const char *cmd)
{
	int st = system(cmd);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* A copy of Avoid with a three-generation task for `method`; `extra` is
 * more simbatch lines (each ending in \\n). POPSIZE, not GA_POPSIZE: the
 * .simbatch parser keeps only the keys it reserves. */
static void make_mind(const char *name, const char *method, const char *extra)
{
	char cmd[1536];
	snprintf(cmd, sizeof cmd,
		 "mkdir -p %s/%s && cp -r minds/Avoid %s/%s/ && "
		 "sed -i 's/^layers:0$/layers:1/' "
		 "%s/%s/Avoid/Skills/Avoid/Avoid.ades && "
		 "printf 'TYPE:LEARNSIM\\nBOTMODEL:BotType8\\nMASTERSKILL:Avoid\\n"
		 "LEARNINGSKILL:Avoid\\nENV:EXP_Avoid\\nLEARNINGMETHOD:%s\\n"
		 "NUMGEN:3\\nEVALREP:2\\nTICKLIM:120\\n%s' "
		 "> %s/%s/Avoid/Tasks/Small.simbatch",
		 tmpdir, name, tmpdir, name, tmpdir, name, method, extra,
		 tmpdir, name);
	CHECK_EQ_INT(sh(cmd), 0);
}

static int train(const char *name, const char *extra)
{
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "%s run %s/%s/Avoid/Tasks/Small.simbatch --seed 5 --run "
		 "%s/%s/run %s > %s/%s/out.txt 2>&1",
		 evo_bin, tmpdir, name, tmpdir, name, extra, tmpdir, name);
	return sh(cmd);
}

static char *read_text(const char *path)
{
	char *data;
	size_t len;
	evo_err err;
	return evo_read_file(path, &data, &len, &err) ? NULL : data;
}

/* log.csv without its two time columns (seconds, elapsed). */
static char *fitness_log(const char *name)
{
	char path[512];
	snprintf(path, sizeof path, "%s/%s/run/log.csv", tmpdir, name);
	char *data = read_text(path);
	if (!data)
		return NULL;
	char *w = data;
	for (char *line = data; *line;) {
		char *end = strchr(line, '\n');
		size_t n = end ? (size_t)(end - line) : strlen(line);
		size_t keep = 0;
		int commas = 0;
		while (keep < n && commas < 6)
			commas += line[keep++] == ',';
		memmove(w, line, keep);
		w += keep;
		*w++ = '\n';
		line += n + (end ? 1 : 0);
	}
	*w = 0;
	return data;
}

static int rows(const char *log)
{
	int n = -1; /* the header */
	for (const char *p = log; p && *p; p++)
		n += *p == '\n';
	return n;
}

/* The champion is where DEMOSIM finds it, and the copy's DEMO task (which
 * loads every skill's network) passes evo check. */
static void check_champion(const char *name, const char *method)
{
	char path[512];
	snprintf(path, sizeof path, "%s/%s/Avoid/Skills/Avoid/Avoid.net",
		 tmpdir, name);
	char *net = read_text(path);
	CHECK(net != NULL);
	if (net) {
		char want[64];
		snprintf(want, sizeof want, "trained by evo: %s, seed 5",
			 method);
		CHECK_CONTAINS(net, want);
		/* layers:1 over 11 inputs and 2 outputs: 11 hidden nodes,
		 * ids 13..23, 11*11 + 2*11 links. */
		CHECK_CONTAINS(net, "node:23:sigmoid:");
		CHECK_CONTAINS(net, "link:10:23:");
		CHECK_CONTAINS(net, "link:23:12:");
		int links = 0;
		for (const char *p = strstr(net, "link:"); p;
		     p = strstr(p + 1, "\nlink:"))
			links++;
		CHECK_EQ_INT(links, 143);
	}
	free(net);
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "%s check %s/%s/Avoid/Tasks/Avoid-DEMO.simbatch > "
		 "%s/%s/check.txt 2>&1",
		 evo_bin, tmpdir, name, tmpdir, name);
	CHECK_EQ_INT(sh(cmd), 0);
}

TEST(genetic_trains_and_threads_do_not_change_the_log)
{
	make_mind("g1", "GENETIC", "POPSIZE:10\\nGA_ELITISM:1\\n");
	make_mind("g2", "GENETIC", "POPSIZE:10\\nGA_ELITISM:1\\n");
	CHECK_EQ_INT(train("g1", "--threads 1"), 0);
	CHECK_EQ_INT(train("g2", "--threads 2"), 0);
	char *a = fitness_log("g1"), *b = fitness_log("g2");
	CHECK(a && b);
	if (a && b) {
		CHECK_EQ_INT(rows(a), 3);
		/* 10 evaluations a generation, no species */
		CHECK_CONTAINS(a, "\n2,");
		CHECK_CONTAINS(a, ",0,10,\n");
		CHECK_EQ_STR(a, b);
	}
	free(a);
	free(b);
	check_champion("g1", "GENETIC");
}

TEST(annealing_trains)
{
	make_mind("a", "ANNEALING", "SA_T0:5\\n");
	CHECK_EQ_INT(train("a", "--threads 2"), 0);
	char *a = fitness_log("a");
	CHECK(a != NULL);
	if (a) {
		CHECK_EQ_INT(rows(a), 3);
		/* SA_STEPS_PER_GENERATION's default: 10 candidates */
		CHECK_CONTAINS(a, ",0,10,\n");
	}
	free(a);
	check_champion("a", "ANNEALING");
}

int main(void)
{
	const char *b = getenv("EVO_BUILD");
	snprintf(evo_bin, sizeof evo_bin, "%s/evo", b && b[0] ? b : "build");
	snprintf(tmpdir, sizeof tmpdir, "/tmp/evo-test-methods-XXXXXX");
	if (!mkdtemp(tmpdir))
		return 1;
	RUN(genetic_trains_and_threads_do_not_change_the_log);
	RUN(annealing_trains);
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
	if (sh(cmd) != 0)
		printf("could not remove %s\n", tmpdir);
	return test_summary();
}

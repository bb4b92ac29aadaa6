/* The mind loader (sim/mind/mindfolder.c): the tutorial's files load; every
 * way a mind folder can be wrong is refused with file:line and a message
 * that says what is wrong; a file past the size limit, or a FIFO, is
 * refused by name before it is read. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <string.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "harness.h"
#include "support/cli.h"
#include "mind/mindfolder.h"
#include "mind/task.h"
#include "support/alloc_fail.h"

#define TUTORIAL "tests/data/minds/T6-NEAT"

TEST(tutorial_task_loads)
{
	evo_task t;
	evo_err err = {{0}};
	int rc = evo_task_load(TUTORIAL "/Tasks/T6-NEAT.simbatch", &t, &err);
	CHECK_EQ_STR(err.msg, "");
	CHECK_EQ_INT(rc, 0);
	if (rc != 0)
		return;
	CHECK_EQ_STR(t.type, "LEARNSIM");
	CHECK_EQ_STR(evo_simbatch_get(t.sb, "ENV"), "EXP_Avoid");
	CHECK_EQ_STR(evo_simbatch_get(t.sb, "LEARNINGMETHOD"), "NEAT");
	CHECK_EQ_STR(evo_simbatch_get(t.sb, "TICKLIM"), "100000");
	/* Avoid and the four movement skills it names, master first. */
	CHECK_EQ_INT(t.mind->n_skills, 5);
	CHECK_EQ_STR(t.mind->skill[0].name, "Avoid");
	CHECK_EQ_STR(t.mind->skill[1].name, "moveForward");
	CHECK_EQ_STR(t.mind->skill[4].name, "moveBackwards");
	CHECK_EQ_INT(t.mind->mind.n_skills, 5);
	CHECK_EQ_INT(t.mind->mind.n_vars, 3);
	evo_task_free(&t);
}

TEST(tutorial_collect_hierarchy_loads_top_down)
{
	evo_err err = {{0}};
	evo_mindfolder_opts o = {.master = "Collect"};
	evo_mindfolder *l = evo_mindfolder_load(TUTORIAL, &o, &err);
	CHECK_EQ_STR(err.msg, "");
	CHECK(l != NULL);
	if (!l)
		return;
	static const char *const order[] = {
		"Collect",  "GTO+Avoid", "GTDZ+Avoid", "moveForward",
		"turnLeft", "turnRight", "ClawControl"};
	CHECK_EQ_INT(l->n_skills, 7);
	for (unsigned i = 0; i < 7 && i < l->n_skills; i++) {
		CHECK_EQ_STR(l->skill[i].name, order[i]);
		CHECK_EQ_STR(evo_mind_skill_name(&l->mind, i), order[i]);
	}
	CHECK_EQ_STR(evo_mind_sensor_name(&l->mind, 0), "US_1");
	CHECK_EQ_STR(evo_mind_actuator_name(&l->mind, 2), "EMAG");
	CHECK_EQ_STR(evo_mind_var_name(&l->mind, 2), "VAR_COUNT");
	evo_mindfolder_free(l);
}

/* The loader copies the folder's path and the bot's name with strdup;
 * when memory runs out there, loading fails with a message (it once went
 * on with a NULL path and crashed). Every strdup of a load is made to
 * fail in turn, until one load makes no more calls than that. */
TEST(out_of_memory_is_a_message_not_a_crash)
{
	int nth = 1;
	for (; nth < 10; nth++) {
		evo_err err = {{0}};
		evo_mindfolder_opts o = {.master = "Collect"};
		alloc_fail_strdup(nth);
		evo_mindfolder *l = evo_mindfolder_load(TUTORIAL, &o, &err);
		int calls = alloc_fail_strdup_calls();
		alloc_fail_strdup(0);
		if (calls < nth) { /* nothing failed: the load went through */
			CHECK(l != NULL);
			evo_mindfolder_free(l);
			break;
		}
		CHECK(l == NULL);
		CHECK_EQ_STR(err.msg, "out of memory");
		evo_mindfolder_free(l);
	}
	CHECK(nth > 2); /* the folder's path and the bot's name */
}

/* A copy of minds/Avoid under top whose mind folder's path (ending in
 * /Avoid) is len bytes, through folders of at most 200 'x'; its task's
 * path in task. */
static void long_copy(const char *top, size_t len, char *task, size_t cap)
{
	char mind[1400], x[201];
	memset(x, 'x', 200);
	x[200] = 0;
	size_t n = (size_t)snprintf(mind, sizeof mind, "%s", top);
	const size_t want = len - (sizeof "/Avoid" - 1);
	while (n < want && n < sizeof mind - 202) {
		size_t r = want - n, chunk = r <= 201 ? r - 1 : 200;
		if (r > 201 && r - 201 < 2)
			chunk = 150;
		n += (size_t)snprintf(mind + n, sizeof mind - n, "/%.*s",
				      (int)chunk, x);
	}
	char cmd[4400];
	snprintf(cmd, sizeof cmd, "mkdir -p %s && cp -r minds/Avoid %s/", mind,
		 mind);
	CHECK_EQ_INT(system(cmd), 0);
	snprintf(task, cap, "%s/Avoid/Tasks/Avoid-DEMO.simbatch", mind);
	CHECK_EQ_INT(strlen(task), len + sizeof "/Tasks/Avoid-DEMO.simbatch" - 1);
}

/* A mind folder so deep that its files' paths would not fit evo's path
 * buffers is refused with 'path too long' and the path's start, whether
 * the task's own path is too long (over 1023 bytes) or only the mind
 * folder's files would be (a root over 883 bytes: its
 * Skills/NAME/NAME.ades, with names of 63 bytes, would pass 1023). Both
 * were cut before, and evo reported a file missing at a cut path, or cut
 * its message in the middle of the path. */
TEST(too_deep_a_mind_folder_is_refused_with_its_path)
{
	char top[512], task[1500];
	snprintf(top, sizeof top, "%s/evo-test-load-%ld-deep",
		 cli_tmp_root(), (long)getpid());
	static const size_t lens[] = {900, 1100};
	for (int k = 0; k < 2; k++) {
		long_copy(top, lens[k], task, sizeof task);
		evo_task t;
		evo_err err = {{0}};
		CHECK_EQ_INT(evo_task_load(task, &t, &err), -1);
		CHECK_CONTAINS(err.msg, "...: path too long (");
		CHECK_CONTAINS(err.msg, k == 0 ? "at most 883)" : "at most 1023)");
		CHECK(strncmp(err.msg, top, strlen(top)) == 0);
		CHECK(strlen(err.msg) < 200);
		char cmd[600];
		snprintf(cmd, sizeof cmd, "rm -rf %s", top);
		CHECK_EQ_INT(system(cmd), 0);
	}
	/* a mind folder a little shallower loads */
	long_copy(top, 860, task, sizeof task);
	evo_task t;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_task_load(task, &t, &err), 0);
	CHECK_EQ_STR(err.msg, "");
	evo_task_free(&t);
	char cmd[600];
	snprintf(cmd, sizeof cmd, "rm -rf %s", top);
	CHECK_EQ_INT(system(cmd), 0);
}

/* ---- broken mind folders ------------------------------------------------ */

static char dir[256];

static void put(const char *rel, const char *text)
{
	char path[512];
	snprintf(path, sizeof path, "%s/%s", dir, rel);
	for (char *p = path + strlen(dir) + 1; *p; p++)
		if (*p == '/') {
			*p = 0;
			mkdir(path, 0755);
			*p = '/';
		}
	FILE *f = fopen(path, "w");
	if (!f) {
		perror(path);
		exit(2);
	}
	fputs(text, f);
	fclose(f);
}

/* A fresh mind folder "Bot": sensors A B, actuators L R, variable V, a
 * master M over a hard-coded Fwd. */
static void fresh(void)
{
	static int n;
	snprintf(dir, sizeof dir, "%s/evo-test-load-%ld-%d/Bot",
		 cli_tmp_root(), (long)getpid(), n++);
	char parent[256];
	snprintf(parent, sizeof parent, "%.*s", (int)(strlen(dir) - 4), dir);
	mkdir(parent, 0755);
	mkdir(dir, 0755);
	put("Bot.botdesc", "SENSORS\nA:prox\nB:prox\nACTUATORS\nL:wheel\n"
			   "R:wheel\n");
	put("Bot.vardesc", "V:VariableModule\n");
	put("Skills/Fwd/Fwd.ades",
	    "Fwd\ninput:0\noutput:2\nMO:L\nMO:R\nhardCoded\n"
	    "class:MoveForward\n");
	put("Skills/M/M.ades", "M\ninput:1\nSE:A\noutput:1\nSK:Fwd\n"
			       "neural\nlayers:0\n");
	put("Skills/M/M.net", "inputs:1\noutputs:1\nnode:1:sigmoid:0\n"
			      "output:1\nlink:0:1:1\n");
}

static char *load_error(const char *master)
{
	static evo_err err;
	memset(&err, 0, sizeof err);
	evo_mindfolder_opts o = {.master = master};
	evo_mindfolder *l = evo_mindfolder_load(dir, &o, &err);
	if (l) {
		evo_mindfolder_free(l);
		return NULL;
	}
	/* Messages name files under the folder; strip it for comparison. */
	char *p;
	while ((p = strstr(err.msg, dir)) != NULL)
		memmove(p, p + strlen(dir) + 1, strlen(p + strlen(dir) + 1) + 1);
	return err.msg;
}

TEST(fresh_folder_loads)
{
	fresh();
	CHECK(load_error("M") == NULL);
	CHECK(load_error(NULL) == NULL); /* M is the only root */
}

TEST(unknown_sensor)
{
	fresh();
	put("Skills/M/M.ades", "M\ninput:1\nSE:Bx\noutput:1\nSK:Fwd\n"
			       "neural\nlayers:0\n");
	CHECK_EQ_STR(load_error("M"),
		     "Skills/M/M.ades:3: unknown sensor 'Bx': Bot.botdesc has "
		     "no such sensor; did you mean B?");
}

TEST(unknown_sensor_in_derivative)
{
	fresh();
	put("Skills/M/M.ades", "M\ninput:1\nSD:Z\noutput:1\nSK:Fwd\n"
			       "neural\nlayers:0\n");
	CHECK_CONTAINS(load_error("M"),
		       "Skills/M/M.ades:3: unknown sensor 'Z'");
}

TEST(unknown_actuator)
{
	fresh();
	put("Skills/Fwd/Fwd.ades", "Fwd\ninput:0\noutput:2\nMO:L\nMO:Right\n"
				   "hardCoded\nclass:MoveForward\n");
	CHECK_EQ_STR(load_error("M"),
		     "Skills/Fwd/Fwd.ades:5: unknown actuator 'Right': "
		     "Bot.botdesc has no such actuator");
}

TEST(unknown_variable)
{
	fresh();
	put("Skills/M/M.ades", "M\ninput:1\nVA:W\noutput:1\nSK:Fwd\n"
			       "neural\nlayers:0\n");
	CHECK_EQ_STR(load_error("M"),
		     "Skills/M/M.ades:3: unknown variable 'W': Bot.vardesc "
		     "has no such variable; did you mean V?");
}

TEST(unknown_output_variable)
{
	fresh();
	put("Skills/M/M.ades", "M\ninput:1\nSE:A\noutput:2\nSK:Fwd\nVA:Q\n"
			       "neural\nlayers:0\n");
	CHECK_CONTAINS(load_error("M"),
		       "Skills/M/M.ades:6: unknown variable 'Q'");
}

TEST(sk_names_a_missing_skill)
{
	fresh();
	put("Skills/M/M.ades", "M\ninput:1\nSE:A\noutput:1\nSK:Back\n"
			       "neural\nlayers:0\n");
	CHECK_EQ_STR(load_error("M"),
		     "Skills/M/M.ades:5: SK:Back names a skill that does not "
		     "exist: no file Skills/Back/Back.ades");
}

TEST(cycle_among_skills)
{
	fresh();
	put("Skills/M/M.ades", "M\ninput:1\nSE:A\noutput:1\nSK:P\n"
			       "neural\nlayers:0\n");
	put("Skills/P/P.ades", "P\ninput:0\noutput:1\nSK:Q\nhardCoded\n"
			       "class:Stop\n");
	put("Skills/Q/Q.ades", "Q\ninput:0\noutput:1\nSK:P\nhardCoded\n"
			       "class:Stop\n");
	/* Stop writes two outputs; the cycle is found first, while walking. */
	CHECK_EQ_STR(load_error("M"),
		     "Skills/Q/Q.ades:4: SK:P makes a cycle among skills: "
		     "P -> Q -> P");
}

/* Twenty skills of the longest names a skill can have, each naming the
 * next and the last the first: the message cannot hold the whole cycle,
 * so it must cut it short ("... -> ") rather than write past its buffer
 * (ASan catches that in make test-asan), and still name the cycle. */
TEST(long_cycle_of_long_names)
{
	enum { N = 20 };
	char name[N][EVO_NAME_MAX];
	for (int i = 0; i < N; i++) {
		memset(name[i], 'a' + i, EVO_NAME_MAX - 1);
		name[i][EVO_NAME_MAX - 1] = 0;
	}
	fresh();
	/* %.*s with the longest name, so the compiler sees the bound. */
	const int w = EVO_NAME_MAX - 1;
	char rel[256], text[512];
	snprintf(text, sizeof text,
		 "M\ninput:1\nSE:A\noutput:1\nSK:%.*s\nneural\nlayers:0\n", w,
		 name[0]);
	put("Skills/M/M.ades", text);
	for (int i = 0; i < N; i++) {
		snprintf(rel, sizeof rel, "Skills/%.*s/%.*s.ades", w, name[i],
			 w, name[i]);
		snprintf(text, sizeof text,
			 "%.*s\ninput:0\noutput:1\nSK:%.*s\nhardCoded\n"
			 "class:Stop\n",
			 w, name[i], w, name[(i + 1) % N]);
		put(rel, text);
	}
	const char *msg = load_error("M");
	char want[256];
	snprintf(want, sizeof want,
		 "SK:%.*s makes a cycle among skills: %.*s -> ", w, name[0], w,
		 name[0]);
	CHECK_CONTAINS(msg, want);
	CHECK_CONTAINS(msg, "... -> ");
	snprintf(want, sizeof want, " -> %.*s", w, name[0]);
	size_t ml = msg ? strlen(msg) : 0, wl = strlen(want);
	CHECK(ml >= wl && strcmp(msg + ml - wl, want) == 0);
}

TEST(skill_that_names_itself)
{
	fresh();
	put("Skills/M/M.ades", "M\ninput:1\nSE:A\noutput:2\nSK:Fwd\nSK:M\n"
			       "neural\nlayers:0\n");
	CHECK_CONTAINS(load_error("M"),
		       "Skills/M/M.ades:6: SK:M makes a cycle among skills: "
		       "M -> M");
}

TEST(count_that_does_not_match_its_lines)
{
	fresh();
	put("Skills/M/M.ades", "M\ninput:2\nSE:A\noutput:1\nSK:Fwd\n"
			       "neural\nlayers:0\n");
	CHECK_CONTAINS(load_error("M"), "Skills/M/M.ades:4: ");
	CHECK_CONTAINS(load_error("M"), "output:1");
}

TEST(unknown_internal_function_type)
{
	fresh();
	put("Skills/M/M.ades", "M\ninput:1\nSE:A\noutput:1\nSK:Fwd\n"
			       "fuzzy\n");
	CHECK_CONTAINS(load_error("M"), "Skills/M/M.ades:6: ");
	CHECK_CONTAINS(load_error("M"), "fuzzy");
}

TEST(unknown_hardcoded_class)
{
	fresh();
	put("Skills/Fwd/Fwd.ades", "Fwd\ninput:0\noutput:2\nMO:L\nMO:R\n"
				   "hardCoded\nclass:MoveForwards\n");
	CHECK_CONTAINS(load_error("M"),
		       "Skills/Fwd/Fwd.ades:6: unknown hard-coded class "
		       "'MoveForwards'; did you mean MoveForward? (known "
		       "classes: MoveForward, MoveBackwards, TurnLeft, "
		       "TurnRight, Stop");
}

TEST(hardcoded_class_with_wrong_outputs)
{
	fresh();
	put("Skills/Fwd/Fwd.ades", "Fwd\ninput:0\noutput:1\nMO:L\n"
				   "hardCoded\nclass:MoveForward\n");
	CHECK_EQ_STR(load_error("M"),
		     "Skills/Fwd/Fwd.ades:5: hard-coded class MoveForward "
		     "writes 2 outputs, but the skill declares 1");
}

TEST(neural_skill_without_network)
{
	fresh();
	char path[512];
	snprintf(path, sizeof path, "%s/Skills/M/M.net", dir);
	unlink(path);
	CHECK_EQ_STR(load_error("M"),
		     "Skills/M/M.ades:6: neural skill M has no trained "
		     "network: expected Skills/M/M.net (train it with a "
		     "LEARNSIM task, or run it with --net M=random)");
	/* ...unless it is the skill being trained. */
	evo_err err;
	evo_mindfolder_opts o = {.master = "M", .learning_skill = "M"};
	evo_mindfolder *l = evo_mindfolder_load(dir, &o, &err);
	CHECK(l != NULL);
	evo_mindfolder_free(l);
}

TEST(network_of_the_wrong_shape)
{
	fresh();
	put("Skills/M/M.net", "inputs:2\noutputs:1\nnode:2:sigmoid:0\n"
			      "output:2\nlink:0:2:1\n");
	CHECK_EQ_STR(load_error("M"),
		     "Skills/M/M.net:1: the network has 2 inputs and 1 "
		     "outputs, but skill M declares 1 and 1");
	/* ...but a skill being trained starts afresh from a placeholder of
	 * its new shape (its inputs changed since it was saved), with a
	 * warning, instead of being blocked until the file is deleted */
	evo_err err = {{0}};
	evo_mindfolder_opts o = {.master = "M", .learning_skill = "M"};
	evo_mindfolder *l = evo_mindfolder_load(dir, &o, &err);
	CHECK(l != NULL);
	if (l) {
		int k = evo_mindfolder_skill(l, "M");
		CHECK(k >= 0 && l->net[k]->n_in == 1 && l->net[k]->n_out == 1);
		evo_mindfolder_free(l);
	}
}

TEST(malformed_network_file)
{
	fresh();
	put("Skills/M/M.net", "inputs:1\noutputs:1\nnode:1:sigmoid:zero\n");
	CHECK_CONTAINS(load_error("M"), "Skills/M/M.net:3: ");
}

TEST(skill_file_for_another_skill)
{
	fresh();
	put("Skills/Fwd/Fwd.ades", "Forward\ninput:0\noutput:2\nMO:L\nMO:R\n"
				   "hardCoded\nclass:MoveForward\n");
	CHECK_EQ_STR(load_error("M"),
		     "Skills/Fwd/Fwd.ades:1: the skill is named 'Forward' but "
		     "its file is for 'Fwd' (Skills/Fwd/Fwd.ades)");
}

TEST(missing_master)
{
	fresh();
	CHECK_CONTAINS(load_error("Nope"), "master skill Nope: no file ");
}

TEST(not_a_mind_folder)
{
	fresh();
	char path[512];
	snprintf(path, sizeof path, "%s/Bot.botdesc", dir);
	unlink(path);
	CHECK_CONTAINS(load_error("M"), "not a mind folder: no Bot.botdesc");
}

TEST(malformed_botdesc)
{
	fresh();
	put("Bot.botdesc", "A:prox\nSENSORS\n");
	CHECK_CONTAINS(load_error("M"), "Bot.botdesc:1: ");
}

TEST(vardesc_is_optional)
{
	fresh();
	char path[512];
	snprintf(path, sizeof path, "%s/Bot.vardesc", dir);
	unlink(path);
	CHECK(load_error("M") == NULL);
}

TEST(task_with_unknown_method)
{
	fresh();
	put("Tasks/T.simbatch",
	    "TYPE:LEARNSIM BOTMODEL:BotType8 ENV:EXP_Avoid\nMASTERSKILL:M\n"
	    "LEARNINGSKILL:M\nLEARNINGMETHOD:HILLCLIMB\nNUMGEN:3\n");
	char path[512];
	snprintf(path, sizeof path, "%s/Tasks/T.simbatch", dir);
	evo_task t;
	evo_err err;
	CHECK_EQ_INT(evo_task_load(path, &t, &err), -1);
	CHECK_CONTAINS(err.msg, "T.simbatch:4: LEARNINGMETHOD: expected NEAT, "
				"GENETIC, ANNEALING, CMAES, NOVELTY or MAPELITES, "
				"found 'HILLCLIMB'");
}

TEST(task_missing_a_key)
{
	fresh();
	put("Tasks/T.simbatch", "TYPE:DEMOSIM\nBOTMODEL:BotType8\nENV:X\n");
	char path[512];
	snprintf(path, sizeof path, "%s/Tasks/T.simbatch", dir);
	evo_task t;
	evo_err err;
	CHECK_EQ_INT(evo_task_load(path, &t, &err), -1);
	CHECK_CONTAINS(err.msg, "a DEMOSIM task needs the key MASTERSKILL");
}

/* evo run Tasks/T.simbatch from inside the mind folder: the folder is "."
 * and its name is the directory's own, not "."; evo run T.simbatch from
 * inside Tasks/ finds the mind folder above. */
TEST(task_run_from_inside_its_mind_folder)
{
	char here[1024];
	CHECK(getcwd(here, sizeof here) != NULL);
	CHECK_EQ_INT(chdir(TUTORIAL), 0);
	evo_task t;
	evo_err err = {{0}};
	int rc = evo_task_load("Tasks/T6-NEAT.simbatch", &t, &err);
	CHECK_EQ_STR(err.msg, "");
	CHECK_EQ_INT(rc, 0);
	if (rc == 0) {
		CHECK_EQ_STR(t.mind->bot_name, "T6-NEAT");
		CHECK_EQ_STR(t.mind->skill[0].name, "Avoid");
		evo_task_free(&t);
	}
	/* and from inside its Tasks/ folder: the mind folder is ".." */
	CHECK_EQ_INT(chdir("Tasks"), 0);
	rc = evo_task_load("T6-NEAT.simbatch", &t, &err);
	CHECK_EQ_STR(err.msg, "");
	CHECK_EQ_INT(rc, 0);
	if (rc == 0) {
		CHECK_EQ_STR(t.mind->root, "..");
		CHECK_EQ_STR(t.mind->bot_name, "T6-NEAT");
		evo_task_free(&t);
	}
	CHECK_EQ_INT(chdir("../Skills"), 0);
	evo_mindfolder_opts o = {.master = "Collect"};
	evo_mindfolder *l = evo_mindfolder_load("..", &o, &err);
	CHECK_EQ_STR(err.msg, "");
	if (l)
		CHECK_EQ_STR(l->bot_name, "T6-NEAT");
	evo_mindfolder_free(l);
	CHECK_EQ_INT(chdir(here), 0);
}

static long max_rss_kb(void)
{
	struct rusage ru;
	getrusage(RUSAGE_SELF, &ru);
	return ru.ru_maxrss;
}

/* A shared mind folder's 1.5 GB sparse .net cost 1.58 GB of memory before
 * "not a text file": it is refused by name, at once, and memory stays as
 * it was. An .ades that is a FIFO is no file of the skill. */
TEST(a_huge_or_fifo_file_is_refused_before_it_is_read)
{
	fresh();
	char path[600];
	snprintf(path, sizeof path, "%s/Skills/M/M.net", dir);
	int fd = open(path, O_WRONLY | O_TRUNC);
	CHECK(fd >= 0);
	CHECK_EQ_INT(ftruncate(fd, (off_t)1500000000), 0);
	close(fd);
	long before = max_rss_kb();
	CHECK_EQ_STR(load_error("M"), "Skills/M/M.net: 1500000000 bytes, "
				      "larger than evo reads (at most 16 MiB)");
	CHECK(max_rss_kb() - before < 4096);
	unlink(path);
	fresh();
	snprintf(path, sizeof path, "%s/Skills/Fwd/Fwd.ades", dir);
	unlink(path);
	CHECK_EQ_INT(mkfifo(path, 0644), 0);
	CHECK_CONTAINS(load_error("M"), "no file Skills/Fwd/Fwd.ades");
	unlink(path);
}

/* A skill's name is the name of its folder: SK:../Fwd read
 * Skills/../Fwd/../Fwd.ades (Bot/Fwd.ades, given a folder Bot/Fwd), and a
 * champion trained for it would be saved beside that, outside Skills/. */
TEST(a_skill_name_that_is_no_folder_name_is_refused)
{
	fresh();
	put("Fwd/README", "a folder\n");
	put("Fwd.ades", "../Fwd\ninput:0\noutput:2\nMO:L\nMO:R\n"
			    "hardCoded\nclass:MoveForward\n");
	put("Skills/M/M.ades", "M\ninput:1\nSE:A\noutput:1\nSK:../Fwd\n"
			       "neural\nlayers:0\n");
	CHECK_EQ_STR(load_error("M"),
		     "Skills/M/M.ades:5: SK:../Fwd: a skill's name is the name "
		     "of its folder, which holds no '/' and is not '.' or '..'");
	CHECK_CONTAINS(load_error(".."), "master skill ..: a skill's name is");
}

int main(void)
{
	RUN(tutorial_task_loads);
	RUN(tutorial_collect_hierarchy_loads_top_down);
	RUN(out_of_memory_is_a_message_not_a_crash);
	RUN(too_deep_a_mind_folder_is_refused_with_its_path);
	RUN(fresh_folder_loads);
	RUN(unknown_sensor);
	RUN(unknown_sensor_in_derivative);
	RUN(unknown_actuator);
	RUN(unknown_variable);
	RUN(unknown_output_variable);
	RUN(sk_names_a_missing_skill);
	RUN(cycle_among_skills);
	RUN(long_cycle_of_long_names);
	RUN(skill_that_names_itself);
	RUN(count_that_does_not_match_its_lines);
	RUN(unknown_internal_function_type);
	RUN(unknown_hardcoded_class);
	RUN(hardcoded_class_with_wrong_outputs);
	RUN(neural_skill_without_network);
	RUN(network_of_the_wrong_shape);
	RUN(malformed_network_file);
	RUN(a_huge_or_fifo_file_is_refused_before_it_is_read);
	RUN(skill_file_for_another_skill);
	RUN(a_skill_name_that_is_no_folder_name_is_refused);
	RUN(missing_master);
	RUN(not_a_mind_folder);
	RUN(malformed_botdesc);
	RUN(vardesc_is_optional);
	RUN(task_with_unknown_method);
	RUN(task_missing_a_key);
	RUN(task_run_from_inside_its_mind_folder);
	/* The folders fresh() made: one per test, under this process's id. */
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf /tmp/evo-test-load-%ld-*",
		 (long)getpid());
	if (system(cmd) != 0)
		printf("could not remove /tmp/evo-test-load-%ld-*\n",
		       (long)getpid());
	return test_summary();
}

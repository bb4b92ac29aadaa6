/* LEARNSIMCONTINUOUS end to end (lua/learn/continuous.lua over
 * sim/learn/learn.c), on a copy of the Collect hierarchy in EXP_Collect:
 * two rounds train every neural skill in turn, bottom-up; a skill's
 * network is replaced only when its turn's champion beats it on the
 * validation episodes, and summary.csv, the run folder's current networks
 * and the Skills/ folder agree on which were; a run killed with SIGKILL
 * in the middle of a round and resumed with another number of threads
 * ends as the uninterrupted run; SKILLORDER sets the order, and one that
 * names no neural skill is refused at its line. The validation episodes
 * an evaluator runs give the same figures in a fresh worker as in one
 * that has run episodes before (tests/data/collect-worker). */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "base/fileio.h"
#include "harness.h"
#include "learn/evaluate.h"
#include "support/cli.h"

/* A copy of minds/Collect named `name` with a small continuous task:
 * popsize 10, 3 generations a turn, 2 rounds, episodes of 400 ticks.
 * `extra` is more simbatch lines. */
static void make_mind(const char *name, const char *extra)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/%s && cp -r minds/Collect %s/%s/ && "
			    "rm -rf %s/%s/Collect/Runs && "
			    "printf 'TYPE:LEARNSIMCONTINUOUS\\n"
			    "BOTMODEL:BotType8\\nMASTERSKILL:Collect\\n"
			    "ENV:EXP_Collect\\nLEARNINGMETHOD:NEAT\\n"
			    "POPSIZE:10\\nNUMGEN:3\\nEVALREP:1\\nTICKLIM:400\\n"
			    "ROUNDS:2\\nVALIDATION:3\\n%s' "
			    "> %s/%s/Collect/Tasks/Small.simbatch",
			    cli_tmp, name, cli_tmp, name, cli_tmp, name, extra,
			    cli_tmp, name),
		     0);
}

static int train(const char *name, const char *extra)
{
	return cli_sh("%s run %s/%s/Collect/Tasks/Small.simbatch --seed 7 "
		      "--run %s/%s/run %s > %s/%s/out.txt 2>&1",
		      cli_evo, cli_tmp, name, cli_tmp, name, extra, cli_tmp,
		      name);
}

static const char *const SKILLS[4] = {"ClawControl", "GTDZ+Avoid", "GTO+Avoid",
				      "Collect"};

/* One row of summary.csv. */
typedef struct row {
	int round;
	char skill[64];
	int first, last;
	double current, champion;
	char replaced[8];
} row;

/* The rows of summary.csv after its header; their number, or -1. */
static int read_summary(const char *text, row *rows, int cap)
{
	static const char header[] = "round,skill,first_generation,"
				     "last_generation,current,champion,"
				     "replaced\n";
	if (!text || strncmp(text, header, sizeof header - 1) != 0)
		return -1;
	int n = 0;
	const char *p = strchr(text, '\n') + 1;
	while (*p && n < cap) {
		row *r = &rows[n];
		if (sscanf(p, "%d,%63[^,],%d,%d,%lf,%lf,%7[a-z]", &r->round,
			   r->skill, &r->first, &r->last, &r->current,
			   &r->champion, r->replaced) != 7)
			return -1;
		n++;
		p = strchr(p, '\n');
		if (!p)
			return -1;
		p++;
	}
	return n;
}

/* Two rounds, every skill in turn, bottom-up, NUMGEN generations each;
 * only a champion that scores more than the current network on the
 * validation episodes replaces it; the hierarchy's current score at each
 * turn is the one the turn before left (the champion's when it replaced,
 * else the unchanged score), so the validation episodes are the same
 * for every skill and round; the shipped networks are the last replacing
 * champions, and the others are as they were. */
TEST(two_rounds_replace_only_improving_skills)
{
	make_mind("c", "");
	CHECK_EQ_INT(train("c", "--threads 2"), 0);
	char *text = cli_read("%s/c/run/summary.csv", cli_tmp);
	row rows[16];
	int n = read_summary(text, rows, 16);
	CHECK_EQ_INT(n, 8);
	int yes = 0, no = 0, last_replaced[4] = {0, 0, 0, 0};
	for (int i = 0; i < n && i < 8; i++) {
		const row *r = &rows[i];
		CHECK_EQ_INT(r->round, 1 + i / 4);
		CHECK_EQ_STR(r->skill, SKILLS[i % 4]);
		CHECK_EQ_INT(r->first, 3 * i);
		CHECK_EQ_INT(r->last, 3 * i + 2);
		int better = r->champion > r->current;
		CHECK_EQ_STR(r->replaced, better ? "yes" : "no");
		if (better) {
			yes++;
			last_replaced[i % 4] = r->round;
		} else {
			no++;
		}
		if (i > 0) {
			const row *q = &rows[i - 1];
			double left =
			    q->champion > q->current ? q->champion : q->current;
			CHECK(r->current == left);
		}
	}
	/* the seed gives both cases, so each branch is tested */
	CHECK(yes > 0 && no > 0);
	for (int k = 0; k < 4; k++) {
		char *net = cli_read("%s/c/Collect/Skills/%s/%s.net", cli_tmp,
				     SKILLS[k], SKILLS[k]);
		char *cur =
		    cli_read("%s/c/run/current-%s.net", cli_tmp, SKILLS[k]);
		CHECK(net && cur && strcmp(net, cur) == 0);
		if (last_replaced[k]) {
			char mark[128];
			snprintf(mark, sizeof mark,
				 "# trained by evo: LEARNSIMCONTINUOUS NEAT, "
				 "seed 7, round %d,",
				 last_replaced[k]);
			CHECK(net && strncmp(net, mark, strlen(mark)) == 0);
		} else {
			CHECK_EQ_INT(cli_sh("cmp -s minds/Collect/Skills/%s/"
					    "%s.net %s/c/Collect/Skills/%s/"
					    "%s.net",
					    SKILLS[k], SKILLS[k], cli_tmp,
					    SKILLS[k], SKILLS[k]),
				     0);
		}
		free(net);
		free(cur);
	}
	char *log = cli_read("%s/c/run/log.csv", cli_tmp);
	CHECK(log && strstr(log, ",metric:round,metric:turn\n"));
	CHECK_EQ_INT(cli_count_lines(log, ""), 1 + 24);
	CHECK(log && strstr(log, "\n23,"));
	free(log);
	free(text);
	char *out = cli_read("%s/c/out.txt", cli_tmp);
	CHECK(out && strstr(out, "round 2, skill Collect (4 of 4)"));
	free(out);
}

/* Killed with SIGKILL in the middle of round 1 (GTO+Avoid's turn) and
 * resumed with one thread instead of two: the same log, summary, current
 * networks and shipped networks as the run above. */
TEST(a_killed_and_resumed_run_ends_as_an_uninterrupted_one)
{
	make_mind("k", "");
	char cmd[1024], out[256];
	snprintf(out, sizeof out, "%s/k/out1.txt", cli_tmp);
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/k/Collect/Tasks/Small.simbatch --seed 7 "
		 "--threads 2 --run %s/k/run > %s 2>&1",
		 cli_evo, cli_tmp, cli_tmp, out);
	int st;
	double s;
	CHECK_EQ_INT(cli_stop(cmd, out, "round 1, skill GTO+Avoid (3 of 4)",
			      0.02, SIGKILL, &st, &s),
		     0);
	CHECK(WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL);
	char *early = cli_read("%s/k/run/summary.csv", cli_tmp);
	row rows[16];
	CHECK_EQ_INT(read_summary(early, rows, 16), 2);
	free(early);
	CHECK_EQ_INT(train("k", "--threads 1 --resume"), 0);
	char *said = cli_read("%s/k/out.txt", cli_tmp);
	CHECK(said && strstr(said, "resuming in round 1, skill GTO+Avoid"));
	free(said);
	char dir[256];
	snprintf(dir, sizeof dir, "%s/c/run", cli_tmp);
	char *a = cli_fitness_log(dir);
	snprintf(dir, sizeof dir, "%s/k/run", cli_tmp);
	char *b = cli_fitness_log(dir);
	CHECK(a && b && strcmp(a, b) == 0);
	free(a);
	free(b);
	const char *same[] = {"summary.csv", "checkpoint.lua"};
	for (int i = 0; i < 2; i++)
		CHECK_EQ_INT(cli_sh("cmp -s %s/c/run/%s %s/k/run/%s", cli_tmp,
				    same[i], cli_tmp, same[i]),
			     0);
	for (int k = 0; k < 4; k++)
		CHECK_EQ_INT(cli_sh("cmp -s %s/c/Collect/Skills/%s/%s.net "
				    "%s/k/Collect/Skills/%s/%s.net",
				    cli_tmp, SKILLS[k], SKILLS[k], cli_tmp,
				    SKILLS[k], SKILLS[k]),
			     0);
}

/* SKILLORDER sets the turns; a name that is no neural skill of the
 * hierarchy stops the run, and evo check, at its line, naming the ones
 * there are. */
TEST(skillorder_sets_the_turns_and_is_checked)
{
	make_mind("o", "SKILLORDER:Collect,ClawControl\\n");
	CHECK_EQ_INT(cli_sh("sed -i 's/^ROUNDS:2$/ROUNDS:1/' "
			    "%s/o/Collect/Tasks/Small.simbatch",
			    cli_tmp),
		     0);
	CHECK_EQ_INT(train("o", ""), 0);
	char *text = cli_read("%s/o/run/summary.csv", cli_tmp);
	row rows[4];
	CHECK_EQ_INT(read_summary(text, rows, 4), 2);
	CHECK_EQ_STR(rows[0].skill, "Collect");
	CHECK_EQ_STR(rows[1].skill, "ClawControl");
	free(text);

	make_mind("b", "SKILLORDER:Collect,TurnLeft\\n");
	char out[4096];
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/b/Collect/Tasks/Small.simbatch "
				 "--run %s/b/run",
				 cli_evo, cli_tmp, cli_tmp),
		     1);
	CHECK_CONTAINS(out, "Small.simbatch:12: SKILLORDER names TurnLeft, "
			    "which is not a neural skill of the hierarchy "
			    "under Collect (its neural skills: Collect, ");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/b/Collect/Tasks/Small.simbatch",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out, "SKILLORDER names TurnLeft");
}

/* The validation episodes (generation 2147483647) of a Collect hierarchy
 * that used to score otherwise in a fresh worker than later in the same
 * worker (tests/data/collect-worker/README.md): one worker, the same four
 * evaluations three times, the same figures each time. */
TEST(an_evaluation_does_not_depend_on_the_workers_past)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/w && cp -r minds/Collect %s/w/ && "
			    "cp tests/data/collect-worker/Collect.net "
			    "%s/w/Collect/Skills/Collect/",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	char task[256], net[256];
	snprintf(task, sizeof task,
		 "%s/w/Collect/Tasks/Collect-CONTINUOUS.simbatch", cli_tmp);
	snprintf(net, sizeof net,
		 "%s/w/Collect/Skills/GTDZ+Avoid/GTDZ+Avoid.net", cli_tmp);
	evo_eval_def def = {.task_path = task,
			    .threads = 1,
			    .seed = 1,
			    .learning_skill = "GTDZ+Avoid"};
	evo_err err = {{0}};
	evo_evaluator *ev = evo_evaluator_create(&def, &err);
	CHECK(ev != NULL);
	static evo_netdesc d;
	char *text = NULL;
	size_t len;
	evo_diag diag;
	CHECK_EQ_INT(evo_read_file(net, &text, &len, &err), 0);
	CHECK(text && evo_netdesc_parse(text, len, net, &d, &diag) == EVO_OK);
	free(text);
	if (!ev)
		return;
	const evo_netdesc *four[4] = {&d, &d, &d, &d};
	evo_eval_result first[4], again[4];
	CHECK_EQ_INT(evo_evaluate(ev, four, 4, 2147483647, first, &err), 0);
	for (int round = 0; round < 2; round++) {
		CHECK_EQ_INT(evo_evaluate(ev, four, 4, 2147483647, again, &err),
			     0);
		for (int k = 0; k < 4; k++)
			CHECK(again[k].fitness == first[k].fitness);
	}
	/* the evaluations differ from one another (their episodes do), so
	 * equal figures are not a constant */
	CHECK(first[0].fitness != first[3].fitness);
	evo_evaluator_destroy(ev);
}

int main(void)
{
	if (cli_setup("continuous"))
		return 1;
	RUN(two_rounds_replace_only_improving_skills);
	RUN(a_killed_and_resumed_run_ends_as_an_uninterrupted_one);
	RUN(skillorder_sets_the_turns_and_is_checked);
	RUN(an_evaluation_does_not_depend_on_the_workers_past);
	cli_cleanup();
	return test_summary();
}

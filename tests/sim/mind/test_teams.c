/* A team task's keys (sim/mind/task.c, docs/teams.md): the TEAM lines
 * become teams with their own mind folders; every mistake in them is one
 * message with the task file's line, before anything runs. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "mind/task.h"
#include "support/cli.h"

static char path[512];
static evo_err err;

/* Write Minds/Forager/Tasks/T.simbatch (a copy of minds/Forager) and load
 * it: 0 or -1 with err. */
static int load(const char *text, evo_task *t)
{
	snprintf(path, sizeof path, "%s/Minds/Forager/Tasks/T.simbatch",
		 cli_tmp);
	if (cli_write(text, "%s", path))
		return -2;
	memset(&err, 0, sizeof err);
	return evo_task_load(path, t, &err);
}

/* The message of a task that must not load. */
static const char *refused(const char *text)
{
	evo_task t;
	if (load(text, &t) == 0) {
		evo_task_free(&t);
		return "(it loaded)";
	}
	return err.msg;
}

static char want[1024];

/* "PATH:LINE: rest" for the task file. */
static const char *at(int line, const char *rest)
{
	snprintf(want, sizeof want, "%s:%d: %s", path, line, rest);
	return want;
}

TEST(a_team_task_loads_every_team)
{
	evo_task t;
	int rc = load("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
		      "TEAM:Red:Forager:BotType8:4:Forage\n"
		      "TEAM:Blue:Other:BotType8:2:Forage\n",
		      &t);
	CHECK_EQ_INT(rc, 0);
	if (rc)
		printf("  %s\n", err.msg);
	if (rc)
		return;
	CHECK_EQ_INT(t.n_teams, 2);
	CHECK_EQ_STR(t.team[0].name, "Red");
	CHECK_EQ_INT(t.team[0].size, 4);
	CHECK_EQ_INT(t.team[0].line, 3);
	CHECK_EQ_STR(t.team[0].botmodel, "BotType8");
	CHECK_EQ_STR(t.team[1].name, "Blue");
	CHECK_EQ_STR(t.team[1].mind->bot_name, "Other");
	CHECK_EQ_INT(t.team[1].size, 2);
	/* the task's mind is the first team's, owned by it */
	CHECK(t.mind == t.team[0].mind);
	CHECK_EQ_INT(t.heterogeneous, 0);
	CHECK_EQ_INT(t.own_fitness, 0);
	CHECK_EQ_INT(t.alternate, 5);
	evo_task_free(&t);
}

TEST(learning_options_are_read)
{
	evo_task t;
	int rc = load("TYPE:LEARN2DSIMMULTI\nENV:EXP_Forage\n"
		      "TEAM:Red:Forager:BotType8:4:Forage\n"
		      "TEAM:Blue:Other:BotType8:2:Forage:Forage\n"
		      "LEARNINGTEAM:Blue,Red LEARNINGSKILL:Forage\n"
		      "LEARNINGMETHOD:NEAT NUMGEN:3\n"
		      "TEAMGENOME:heterogeneous TEAMFITNESS:Own ALTERNATE:2\n",
		      &t);
	CHECK_EQ_INT(rc, 0);
	if (rc) {
		printf("  %s\n", err.msg);
		return;
	}
	CHECK_EQ_INT(t.n_learning, 2);
	CHECK_EQ_INT(t.learning[0], 1);
	CHECK_EQ_INT(t.learning[1], 0);
	CHECK(t.team[0].learns && t.team[1].learns);
	CHECK_EQ_STR(t.team[0].learning_skill, "Forage");
	CHECK_EQ_INT(t.heterogeneous, 1);
	CHECK_EQ_INT(t.own_fitness, 1);
	CHECK_EQ_INT(t.alternate, 2);
	/* the first learning team's mind */
	CHECK(t.mind == t.team[1].mind);
	evo_task_free(&t);
}

TEST(a_malformed_team_line_is_refused_at_its_line)
{
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:4\n"),
		       at(3, "TEAM: expected NAME:MIND:BOTMODEL:SIZE:"
			     "MASTERSKILL[:LEARNINGSKILL], found "
			     "'Red:Forager:4'"));
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:4:Forage:F:x\n"),
		       at(3, "TEAM: expected NAME:MIND"));
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red::BotType8:4:Forage\n"),
		       at(3, "TEAM: expected NAME:MIND"));
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:2nd:Forager:BotType8:4:Forage\n"),
		       at(3, "TEAM: expected a team name of letters, digits "
			     "and _, not starting with a digit, at most 31 "
			     "characters, found '2nd'"));
}

TEST(a_duplicate_team_name_is_refused)
{
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:4:Forage\n"
			       "TEAM:Red:Forager:BotType8:2:Forage\n"),
		       at(4, "TEAM: a second team named Red (first on line "
			     "3)"));
}

TEST(a_team_of_size_0_is_refused)
{
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:0:Forage\n"),
		       at(3, "TEAM Red: expected a size of 1..4096 bots, "
			     "found '0'"));
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:4097:Forage\n"),
		       at(3, "TEAM Red: expected a size of 1..4096 bots, "
			     "found '4097'"));
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:-1:Forage\n"),
		       "found '-1'");
}

TEST(a_learning_team_that_does_not_exist_is_refused)
{
	CHECK_CONTAINS(refused("TYPE:LEARN2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:4:Forage\n"
			       "TEAM:Blue:Forager:BotType8:4:Forage\n"
			       "LEARNINGMETHOD:NEAT NUMGEN:3\n"
			       "LEARNINGSKILL:Forage\n"
			       "LEARNINGTEAM:Blu\n"),
		       at(7, "LEARNINGTEAM: no team named Blu; the teams are "
			     "Red and Blue (did you mean Blue?)"));
	/* several teams, none named */
	CHECK_CONTAINS(refused("TYPE:LEARN2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:4:Forage\n"
			       "TEAM:Blue:Forager:BotType8:4:Forage\n"
			       "LEARNINGMETHOD:NEAT NUMGEN:3\n"
			       "LEARNINGSKILL:Forage\n"),
		       "names the one that learns: LEARNINGTEAM:NAME (the "
		       "teams are Red and Blue)");
	/* a learning team without a skill to train */
	CHECK_CONTAINS(refused("TYPE:LEARN2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:4:Forage\n"
			       "LEARNINGMETHOD:NEAT NUMGEN:3\n"),
		       at(3, "TEAM Red learns, but names no skill to train"));
}

TEST(a_team_whose_mind_folder_is_missing_or_broken_is_refused)
{
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forage:BotType8:4:Forage\n"),
		       at(3, "TEAM Red: "));
	CHECK_CONTAINS(err.msg, "Minds/Forage");
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:4:Foraging\n"),
		       at(3, "TEAM Red: "));
	CHECK_CONTAINS(err.msg, "Foraging");
}

TEST(team_options_take_their_words_only)
{
	CHECK_CONTAINS(refused("TYPE:LEARN2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:4:Forage:Forage\n"
			       "LEARNINGMETHOD:NEAT NUMGEN:3\n"
			       "TEAMGENOME:MIXED\n"),
		       at(5, "TEAMGENOME: expected HOMOGENEOUS or "
			     "HETEROGENEOUS, found 'MIXED'"));
	CHECK_CONTAINS(refused("TYPE:LEARN2DSIMMULTI\nENV:EXP_Forage\n"
			       "TEAM:Red:Forager:BotType8:4:Forage:Forage\n"
			       "LEARNINGMETHOD:NEAT NUMGEN:3\n"
			       "TEAMFITNESS:BOTH\n"),
		       at(5, "TEAMFITNESS: expected TEAM or OWN, found 'BOTH'"));
}

TEST(a_team_task_needs_a_team)
{
	CHECK_CONTAINS(refused("TYPE:DEMO2DSIMMULTI\nENV:EXP_Forage\n"),
		       "a DEMO2DSIMMULTI task needs the key TEAM");
}

int main(void)
{
	if (cli_setup("teams"))
		return 1;
	/* Minds/Forager and Minds/Other, two copies of minds/Forager */
	if (cli_sh("mkdir -p %s/Minds && cp -r minds/Forager %s/Minds/ && "
		   "cp -r minds/Forager %s/Minds/Other && "
		   "mv %s/Minds/Other/Forager.botdesc "
		   "%s/Minds/Other/Other.botdesc",
		   cli_tmp, cli_tmp, cli_tmp, cli_tmp, cli_tmp) != 0)
		return 1;
	RUN(a_team_task_loads_every_team);
	RUN(learning_options_are_read);
	RUN(a_malformed_team_line_is_refused_at_its_line);
	RUN(a_duplicate_team_name_is_refused);
	RUN(a_team_of_size_0_is_refused);
	RUN(a_learning_team_that_does_not_exist_is_refused);
	RUN(a_team_whose_mind_folder_is_missing_or_broken_is_refused);
	RUN(team_options_take_their_words_only);
	RUN(a_team_task_needs_a_team);
	cli_cleanup();
	return test_summary();
}

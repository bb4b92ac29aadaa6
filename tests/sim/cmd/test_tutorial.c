/* The tutorial's own T6-NEAT mind folder (tests/data/minds/T6-NEAT: its
 * botdesc, vardesc, skills, and the .simbatch exactly as the tutorial
 * prints it, BOTMODEL BotType6, sensors US_1..US_10 and DOF, ENV
 * EXP_Avoid) trains with no edit, for two generations of short episodes
 * (`--generations 2 --ticks 200`, so the test is quick), and the trained
 * skill then runs under DEMOSIM, headless; the tutorial's environment
 * example, EXP_GTDZA, is built in. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/cli.h"

static char out[1 << 16];

TEST(t6_neat_trains_as_written)
{
	CHECK_EQ_INT(cli_sh("cp -r tests/data/minds/T6-NEAT %s/", cli_tmp), 0);
	/* the task as printed, untouched */
	char *task = cli_read("%s/T6-NEAT/Tasks/T6-NEAT.simbatch", cli_tmp);
	CHECK(task != NULL);
	CHECK_CONTAINS(task, "BOTMODEL:BotType6\n");
	CHECK_CONTAINS(task, "LEARNINGMETHOD: NEAT ROOTFOLDER: Minds/T6-NEAT");
	CHECK_CONTAINS(task, "NUMGEN:50 EVALREP:3 TICKLIM:100000");
	free(task);
	int rc = cli_capture(out, sizeof out,
			     "%s check %s/T6-NEAT/Tasks/T6-NEAT.simbatch",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	rc = cli_capture(out, sizeof out,
			 "%s run %s/T6-NEAT/Tasks/T6-NEAT.simbatch "
			 "--generations 2 --ticks 200 --run %s/run",
			 cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	if (rc != 0)
		printf("  said: %s\n", out);
	CHECK_CONTAINS(out, "NEAT of skill Avoid");
	CHECK_CONTAINS(out, "replay on unseen episodes (3 x 200 ticks each)");
	/* two generations logged, of 150 candidates (NEAT's default) */
	char *log = cli_read("%s/run/log.csv", cli_tmp);
	CHECK(log != NULL);
	CHECK_EQ_INT(cli_count_lines(log, "0,") + cli_count_lines(log, "1,"), 2);
	CHECK_EQ_INT(cli_count_lines(log, "2,"), 0);
	free(log);
	/* the champion is the skill's network now: 15 inputs (ten US_,
	 * three derivatives, VAR_SIN, DOF), 4 outputs */
	char *net = cli_read("%s/T6-NEAT/Skills/Avoid/Avoid.net", cli_tmp);
	CHECK(net != NULL);
	CHECK_CONTAINS(net, "inputs:15\noutputs:4\n");
	free(net);
}

TEST(t6_neat_then_runs_under_demosim)
{
	/* a DEMOSIM task a user writes beside the tutorial's */
	char path[512];
	snprintf(path, sizeof path, "%s/T6-NEAT/Tasks/T6-DEMO.simbatch",
		 cli_tmp);
	CHECK_EQ_INT(cli_write("TYPE:DEMOSIM\nBOTMODEL:BotType6\nBOTNAME:T6-NEAT\n"
			       "MASTERSKILL:Avoid\nENV:EXP_Avoid\nTICKLIM:300\n",
			       "%s", path),
		     0);
	int rc = cli_capture(out, sizeof out, "%s -nog %s --episodes 2",
			     cli_evo, path);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward ");
	CHECK_CONTAINS(out, "episode 2: reward ");
	CHECK_EQ_INT(cli_count_lines(out, "episode "), 2);
	CHECK(!strstr(out, "warning"));
	if (rc != 0)
		printf("  said: %s\n", out);
}

TEST(the_tutorials_environment_example_is_built_in)
{
	/* EXP_GTDZA, the tutorial's section 6.2, with its GTDZ+Avoid skill
	 * as the master, on BotType6 */
	char path[512];
	snprintf(path, sizeof path, "%s/T6-NEAT/Tasks/GTDZA-DEMO.simbatch",
		 cli_tmp);
	CHECK_EQ_INT(cli_write("TYPE:DEMOSIM\nBOTMODEL:BotType6\nBOTNAME:T6-NEAT\n"
			       "MASTERSKILL:GTDZ+Avoid\nENV:EXP_GTDZA\nTICKLIM:500\n",
			       "%s", path),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out, "%s check %s", cli_evo, path),
		     0);
	int rc = cli_capture(out, sizeof out,
			     "%s -nog %s --episodes 2 --seed 4", cli_evo, path);
	CHECK_EQ_INT(rc, 0);
	CHECK_EQ_INT(cli_count_lines(out, "episode "), 2);
	CHECK_CONTAINS(out, "over 500 ticks");
	if (rc != 0)
		printf("  said: %s\n", out);
}

int main(void)
{
	if (cli_setup("tutorial"))
		return 1;
	RUN(t6_neat_trains_as_written);
	RUN(t6_neat_then_runs_under_demosim);
	RUN(the_tutorials_environment_example_is_built_in);
	cli_cleanup();
	return test_summary();
}

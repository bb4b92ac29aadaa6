/* Looking at a mind before it is finished or after it is exported
 * (sim/cmd/evo_main.c, sim/cmd/mindinfo.c, sim/mind/mindfolder.c): evo
 * info and evo check of a hierarchy whose sub-skills have no network yet
 * show the hierarchy, name those skills and the bottom-up order to train
 * them in, with the task that trains each; evo info takes --net; evo info
 * and evo tick take an exported .bin and say what evo info and evo tick of
 * its mind folder say; a mind folder copied under a new name loads with
 * its old NAME.botdesc, and two botdescs are refused, naming both. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/cli.h"

static char out[32768];

/* A copy of Collect (a two-level hierarchy over hard-coded skills) with
 * the networks of its sub-skills GTO+Avoid and ClawControl removed. */
static void make_untrained(const char *name)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/%s && cp -r minds/Collect %s/%s/ && "
			    "rm %s/%s/Collect/Skills/GTO+Avoid/GTO+Avoid.net "
			    "%s/%s/Collect/Skills/ClawControl/ClawControl.net",
			    cli_tmp, name, cli_tmp, name, cli_tmp, name, cli_tmp,
			    name),
		     0);
}

TEST(info_of_a_hierarchy_with_untrained_sub_skills_shows_it)
{
	make_untrained("u");
	int rc = cli_capture(out, sizeof out, "%s info %s/u/Collect 2>&1",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK(strstr(out, "has no trained network") == NULL);
	CHECK_CONTAINS(out, " 0 Collect          neural");
	CHECK_CONTAINS(out, "GTO+Avoid        neural    in 4  out 3  network: "
			    "none yet -> MoveForward");
	CHECK_CONTAINS(out, "not trained yet (no Skills/S/S.net): GTO+Avoid, "
			    "ClawControl\n");
	/* bottom-up: the sub-skills first, the master last */
	const char *claw = strstr(out, ". ClawControl      no network yet");
	const char *gto = strstr(out, ". GTO+Avoid        no network yet: evo "
				      "run ");
	const char *top = strstr(out, ". Collect          has its network");
	CHECK(claw && gto && top && claw < gto && gto < top);
	CHECK_CONTAINS(out, "Collect/Tasks/GTO+Avoid-NEAT.simbatch\n");
	/* --net gives an untrained skill a network to look at */
	rc = cli_capture(out, sizeof out,
			 "%s info %s/u/Collect --net GTO+Avoid=random "
			 "--net ClawControl=zero 2>&1",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK(strstr(out, "not trained yet") == NULL);
	CHECK(strstr(out, "none yet") == NULL);
	/* evo tick still needs every network */
	CHECK(cli_capture(out, sizeof out, "%s tick %s/u/Collect 2>&1",
			  cli_evo, cli_tmp) != 0);
	CHECK_CONTAINS(out, "has no trained network");
}

TEST(check_of_a_task_whose_sub_skills_are_untrained_says_what_to_train)
{
	make_untrained("c");
	int rc = cli_capture(out, sizeof out,
			     "%s check %s/c/Collect/Tasks/Collect-NEAT.simbatch "
			     "2>&1",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK(strstr(out, "has no trained network") == NULL);
	CHECK_CONTAINS(out, "Collect-NEAT.simbatch: task LEARNSIM, mind folder ");
	CHECK_CONTAINS(out, "not ready to run until the skills below are "
			    "trained");
	CHECK_CONTAINS(out, "GTDZ+Avoid       neural");
	CHECK_CONTAINS(out, "not trained yet (no Skills/S/S.net): GTO+Avoid, "
			    "ClawControl\n");
	/* --net gives the untrained skills networks, as evo run --net */
	rc = cli_capture(out, sizeof out,
			 "%s check %s/c/Collect/Tasks/Collect-DEMO.simbatch "
			 "--net GTO+Avoid=random --net ClawControl=zero 2>&1",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "Collect-DEMO.simbatch: task DEMOSIM, mind folder ");
	/* evo run of the demo names every skill with no network, and the
	 * order to train them in, not only the first */
	rc = cli_capture(out, sizeof out,
			 "%s run %s/c/Collect/Tasks/Collect-DEMO.simbatch "
			 "--headless --ticks 5 2>&1",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "neural skill GTO+Avoid has no trained network");
	CHECK_CONTAINS(out, "not trained yet (no Skills/S/S.net): GTO+Avoid, "
			    "ClawControl\n");
	CHECK_CONTAINS(out, "train the hierarchy bottom-up");
	/* the task that trains a sub-skill itself is fine */
	rc = cli_capture(out, sizeof out,
			 "%s check %s/c/Collect/Tasks/GTO+Avoid-NEAT.simbatch "
			 "2>&1",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, ": ok\n");
}

/* An exported image: evo info names its skills as the folder's info does,
 * and evo tick prints the same lines as evo tick of the folder. */
TEST(info_and_tick_take_an_exported_image)
{
	CHECK_EQ_INT(cli_sh("%s export minds/Collect -o %s/c.bin > /dev/null",
			    cli_evo, cli_tmp),
		     0);
	int rc = cli_capture(out, sizeof out, "%s info %s/c.bin 2>&1", cli_evo,
			     cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "20 sensors, 3 actuators, 1 variables, 7 skills");
	CHECK_CONTAINS(out, " 3 MoveForward      hardCoded in 0  out 2  "
			    "class:MoveForward");
	CHECK_CONTAINS(out, " 0 Collect          neural    in 3  out 3  "
			    "network: ");
	char folder[8192];
	CHECK_EQ_INT(cli_capture(folder, sizeof folder,
				 "%s info minds/Collect 2>&1", cli_evo),
		     0);
	/* the same skill lines, and the same image and state sizes */
	const char *a = strstr(out, "   0 Collect"), *b = strstr(folder, "   0 Collect");
	CHECK(a && b);
	if (a && b)
		CHECK_EQ_STR(a, b);
	CHECK_EQ_INT(cli_capture(folder, sizeof folder,
				 "%s tick minds/Collect --ticks 5 --sensor "
				 "S2=0.1 2>&1",
				 cli_evo),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s tick %s/c.bin --ticks 5 --sensor S2=0.1 "
				 "2>&1",
				 cli_evo, cli_tmp),
		     0);
	CHECK_EQ_STR(out, folder);
	CHECK(cli_capture(out, sizeof out, "%s tick %s/c.bin --sensor X=1 2>&1",
			  cli_evo, cli_tmp) != 0);
	CHECK_CONTAINS(out, "c.bin has no sensor 'X'");
	/* a file that is no image says so, with its name */
	CHECK_EQ_INT(cli_sh("echo hello > %s/no.bin", cli_tmp), 0);
	CHECK(cli_capture(out, sizeof out, "%s info %s/no.bin 2>&1", cli_evo,
			  cli_tmp) != 0);
	CHECK_CONTAINS(out, "no.bin: not a mind image evo can run: ");
}

/* A mind folder copied under a new name runs with its old NAME.botdesc
 * and NAME.vardesc; two botdescs and none named after the folder are
 * refused, naming both. */
TEST(a_mind_folder_copied_under_a_new_name_loads)
{
	CHECK_EQ_INT(cli_sh("cp -r minds/Avoid %s/MyBot", cli_tmp), 0);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/MyBot/Tasks/Avoid-DEMO.simbatch "
			     "--headless --ticks 50 2>&1",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward ");
	rc = cli_capture(out, sizeof out, "%s info %s/MyBot 2>&1", cli_evo,
			 cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "mind Avoid: ");
	CHECK_EQ_INT(cli_sh("cp minds/Avoid/Avoid.botdesc %s/MyBot/Other.botdesc",
			    cli_tmp),
		     0);
	CHECK(cli_capture(out, sizeof out, "%s info %s/MyBot 2>&1", cli_evo,
			  cli_tmp) != 0);
	CHECK_CONTAINS(out, "MyBot: no MyBot.botdesc, and 2 .botdesc files");
	CHECK_CONTAINS(out, "Avoid.botdesc");
	CHECK_CONTAINS(out, "Other.botdesc");
}

/* Broken copies of a task in Tasks/ (ENV misspelt) are passed over for
 * the hint: the task named is one that passes evo check, SKILL-NEAT
 * before another good one; with none good, the hint says so and why. */
TEST(the_task_a_hint_names_passes_evo_check)
{
	make_untrained("t");
	char tasks[600];
	snprintf(tasks, sizeof tasks, "%s/t/Collect/Tasks", cli_tmp);
	CHECK_EQ_INT(cli_sh("cd %s && for n in A Typo Steer Z; do sed "
			    "'s/^ENV:GoToObject$/ENV:GoToObjecx/' "
			    "GTO+Avoid-NEAT.simbatch > $n.simbatch; done && "
			    "cp GTO+Avoid-NEAT.simbatch Good.simbatch",
			    tasks),
		     0);
	int rc = cli_capture(out, sizeof out, "%s info %s/t/Collect 2>&1",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, ". GTO+Avoid        no network yet: evo run ");
	CHECK_CONTAINS(out, "Collect/Tasks/GTO+Avoid-NEAT.simbatch\n");
	/* trying the tasks prints none of their messages */
	CHECK(strstr(out, "GoToObjecx") == NULL);
	CHECK_EQ_INT(cli_sh("rm %s/GTO+Avoid-NEAT.simbatch", tasks), 0);
	rc = cli_capture(out, sizeof out, "%s info %s/t/Collect 2>&1", cli_evo,
			 cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "Collect/Tasks/Good.simbatch\n");
	CHECK_EQ_INT(cli_sh("rm %s/Good.simbatch", tasks), 0);
	rc = cli_capture(out, sizeof out,
			 "%s check %s/Collect-NEAT.simbatch 2>&1", cli_evo,
			 tasks);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, ". GTO+Avoid        no network yet: no task of ");
	CHECK_CONTAINS(out, "Collect/Tasks that trains it passes evo check (");
	CHECK_CONTAINS(out, "Tasks/A.simbatch:6: ENV: environment "
			    "'GoToObjecx' not found");
}

int main(void)
{
	if (cli_setup("mind-inspect"))
		return 1;
	RUN(info_of_a_hierarchy_with_untrained_sub_skills_shows_it);
	RUN(check_of_a_task_whose_sub_skills_are_untrained_says_what_to_train);
	RUN(the_task_a_hint_names_passes_evo_check);
	RUN(info_and_tick_take_an_exported_image);
	RUN(a_mind_folder_copied_under_a_new_name_loads);
	cli_cleanup();
	return test_summary();
}

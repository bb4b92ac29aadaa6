/* `evo run --net SKILL=NET` (sim/cmd/run.c, sim/mind/mindfolder.c): a
 * DEMOSIM run shows a neural skill with a network of the user's choice (a
 * .net file such as a run folder's best/gen-NNNN.net or champion.net, a
 * random one, or one of zero weights) and leaves Skills/ as it is; a mind
 * whose skill has no network yet runs that way. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/cli.h"

#define DEMO "minds/Avoid/Tasks/Avoid-DEMO.simbatch"

static char out[1 << 16], out2[1 << 16];

/* The two actuator values of a trace's first tick line (Avoid: MotL MotR),
 * as fractions of 1.0. 0, or -1 when the trace has no tick line. */
static int first_actuators(const char *path, double *l, double *r)
{
	char *t = cli_read("%s", path);
	int rc = -1;
	const char *line = t;
	for (int skip = 0; line && skip < 5; skip++) {
		line = strchr(line, '\n');
		line = line ? line + 1 : NULL;
	}
	const char *bar = line ? strchr(line, '|') : NULL;
	long a, b;
	if (bar && sscanf(bar + 1, "%ld %ld", &a, &b) == 2) {
		*l = (double)a / 65536.0;
		*r = (double)b / 65536.0;
		rc = 0;
	}
	free(t);
	return rc;
}

/* A copy of the Avoid mind folder in the test's folder. */
static void copy_avoid(void)
{
	cli_sh("rm -rf %s/Avoid && cp -r minds/Avoid %s/Avoid && "
	       "rm -rf %s/Avoid/Runs",
	       cli_tmp, cli_tmp, cli_tmp);
}

/* A network with no links: each output is the sigmoid of its bias, so
 * what the motors get is known without running the network. */
TEST(a_net_file_drives_the_skill)
{
	CHECK_EQ_INT(cli_write("inputs:11\noutputs:2\n"
			       "node:11:sigmoid:2\nnode:12:sigmoid:-1\n"
			       "output:11\noutput:12\n",
			       "%s/bias.net", cli_tmp),
		     0);
	int rc = cli_capture(out, sizeof out,
			     "%s run " DEMO " -nog --ticks 3 --net "
			     "Avoid=%s/bias.net --trace %s/bias.trace",
			     cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	double l = -1, r = -1;
	char path[256];
	snprintf(path, sizeof path, "%s/bias.trace", cli_tmp);
	CHECK_EQ_INT(first_actuators(path, &l, &r), 0);
	CHECK(fabs(l - 1.0 / (1.0 + exp(-2.0))) < 1e-3);
	CHECK(fabs(r - 1.0 / (1.0 + exp(1.0))) < 1e-3);
}

/* The skill's own network, given as a file, runs exactly as without
 * --net. */
TEST(its_own_network_as_a_file_runs_the_same)
{
	int a = cli_capture(out, sizeof out, "%s run " DEMO " -nog --ticks 600",
			    cli_evo);
	int b = cli_capture(out2, sizeof out2,
			    "%s run " DEMO " -nog --ticks 600 --net "
			    "Avoid=minds/Avoid/Skills/Avoid/Avoid.net",
			    cli_evo);
	CHECK_EQ_INT(a, 0);
	CHECK_EQ_INT(b, 0);
	CHECK_CONTAINS(out, "episode 1: reward ");
	CHECK_EQ_STR(out, out2);
}

/* A mind whose neural skill has never been trained: the run says how to
 * run it anyway, and runs it with a zero or a random network. */
TEST(a_skill_without_a_network_runs_with_random_or_zero)
{
	copy_avoid();
	cli_sh("rm %s/Avoid/Skills/Avoid/Avoid.net", cli_tmp);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/Avoid-DEMO.simbatch -nog "
			     "--ticks 100",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "Avoid.ades:");
	CHECK_CONTAINS(out, "has no trained network");
	CHECK_CONTAINS(out, "--net Avoid=random");

	/* zero weights: every output 0.5, which stops both wheels: the bot
	 * never moves, so it never collides and earns nothing */
	rc = cli_capture(out, sizeof out,
			 "%s run %s/Avoid/Tasks/Avoid-DEMO.simbatch -nog "
			 "--ticks 100 --net Avoid=zero --trace %s/zero.trace",
			 cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward 0.000000 over 100 ticks, 0 "
			    "collision ticks");
	double l = -1, r = -1;
	char path[256];
	snprintf(path, sizeof path, "%s/zero.trace", cli_tmp);
	CHECK_EQ_INT(first_actuators(path, &l, &r), 0);
	CHECK(l == 0.5 && r == 0.5);

	/* random: drawn from the run's seed, so a seed gives one network and
	 * another seed another */
	double l1 = -1, r1 = -1, l2 = -1, r2 = -1, l3 = -1, r3 = -1;
	for (int s = 1; s <= 3; s++) {
		rc = cli_sh("%s run %s/Avoid/Tasks/Avoid-DEMO.simbatch -nog "
			    "--ticks 2 --net Avoid=random --seed %d "
			    "--trace %s/random%d.trace >/dev/null",
			    cli_evo, cli_tmp, s == 3 ? 1 : s, cli_tmp, s);
		CHECK_EQ_INT(rc, 0);
	}
	snprintf(path, sizeof path, "%s/random1.trace", cli_tmp);
	CHECK_EQ_INT(first_actuators(path, &l1, &r1), 0);
	snprintf(path, sizeof path, "%s/random2.trace", cli_tmp);
	CHECK_EQ_INT(first_actuators(path, &l2, &r2), 0);
	snprintf(path, sizeof path, "%s/random3.trace", cli_tmp);
	CHECK_EQ_INT(first_actuators(path, &l3, &r3), 0);
	CHECK(l1 == l3 && r1 == r3);
	CHECK(l1 != l2 || r1 != r2);
	CHECK(l1 != 0.5 || r1 != 0.5);
	/* the skill's folder is left as it was: still no network */
	CHECK_EQ_INT(cli_sh("test -e %s/Avoid/Skills/Avoid/Avoid.net", cli_tmp),
		     1);
}

/* A learning run's networks replayed one by one: best/gen-NNNN.net and
 * champion.net, with Skills/ untouched. */
TEST(a_run_folder_s_networks_replay_without_touching_skills)
{
	copy_avoid();
	int rc = cli_sh("%s run %s/Avoid/Tasks/Avoid-NEAT.simbatch "
			"--generations 2 --ticks 50 --threads 2 --run %s/run "
			">/dev/null 2>&1",
			cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	/* the run saved its champion as the skill's network: replace that
	 * with the shipped one, so that Skills/ and the run differ */
	cli_sh("cp minds/Avoid/Skills/Avoid/Avoid.net "
	       "%s/Avoid/Skills/Avoid/Avoid.net",
	       cli_tmp);
	char *before = cli_read("%s/Avoid/Skills/Avoid/Avoid.net", cli_tmp);
	const char *nets[] = {"run/best/gen-0000.net", "run/best/gen-0001.net",
			      "run/champion.net"};
	for (int i = 0; i < 3; i++) {
		rc = cli_capture(out2, sizeof out2,
				 "%s run %s/Avoid/Tasks/Avoid-DEMO.simbatch "
				 "-nog --ticks 300 --net Avoid=%s/%s",
				 cli_evo, cli_tmp, cli_tmp, nets[i]);
		CHECK_EQ_INT(rc, 0);
		CHECK_CONTAINS(out2, "episode 1: reward ");
	}
	rc = cli_capture(out, sizeof out,
			 "%s run %s/Avoid/Tasks/Avoid-DEMO.simbatch -nog "
			 "--ticks 300",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	/* the champion (out2) is not the skill's network now, so it runs
	 * differently */
	CHECK(strcmp(out2, out) != 0);
	char *after = cli_read("%s/Avoid/Skills/Avoid/Avoid.net", cli_tmp);
	CHECK(before && after && strcmp(before, after) == 0);
	free(before);
	free(after);
}

TEST(wrong_choices_are_refused_with_what_was_wrong)
{
	int rc = cli_capture(out, sizeof out,
			     "%s run " DEMO " -nog --net avoid=zero", cli_evo);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "--net avoid: no such skill in the hierarchy; did "
			    "you mean Avoid?");

	rc = cli_capture(out, sizeof out,
			 "%s run minds/GTO/Tasks/GTO-DEMO.simbatch -nog --net "
			 "MoveForward=zero",
			 cli_evo);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "--net MoveForward: a hard-coded skill has no "
			    "network");
	CHECK_CONTAINS(out, "neural skills under the master skill: GTO");

	rc = cli_capture(out, sizeof out,
			 "%s run " DEMO " -nog --net "
			 "Avoid=minds/GTO/Skills/GTO/GTO.net",
			 cli_evo);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "GTO.net:1: the network has 4 inputs and 3 "
			    "outputs, but skill Avoid declares 11 and 2");

	rc = cli_capture(out, sizeof out,
			 "%s run " DEMO " -nog --net Avoid=%s/none.net",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "none.net: no such network file");

	rc = cli_capture(out, sizeof out,
			 "%s run " DEMO " -nog --net Avoid=zero --net "
			 "Avoid=random",
			 cli_evo);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "chosen twice for skill Avoid");

	rc = cli_capture(out, sizeof out, "%s run " DEMO " -nog --net Avoid",
			 cli_evo);
	CHECK_EQ_INT(rc, 2);
	CHECK_CONTAINS(out, "--net expects SKILL=NET");

	/* a learning task trains over Skills/: --net would be silently
	 * ignored by its workers, so it is refused */
	rc = cli_capture(out, sizeof out,
			 "%s run minds/Avoid/Tasks/Avoid-NEAT.simbatch --net "
			 "Avoid=zero",
			 cli_evo);
	CHECK_EQ_INT(rc, 2);
	CHECK_CONTAINS(out, "--net chooses the networks a DEMOSIM run shows");
}

int main(void)
{
	if (cli_setup("run-net"))
		return 1;
	RUN(a_net_file_drives_the_skill);
	RUN(its_own_network_as_a_file_runs_the_same);
	RUN(a_skill_without_a_network_runs_with_random_or_zero);
	RUN(a_run_folder_s_networks_replay_without_touching_skills);
	RUN(wrong_choices_are_refused_with_what_was_wrong);
	cli_cleanup();
	return test_summary();
}

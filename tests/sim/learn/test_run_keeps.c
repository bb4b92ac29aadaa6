/* What a learning run keeps (sim/learn/learn.c, sim/learn/runopts.c): a
 * champion that replaces a network it did not make keeps that network in
 * the run folder, named, and says so; --no-save leaves Skills/ as it is;
 * a team run of the same skill keeps it too. The run folder remembers the
 * options that shape the run: --resume restores --ticks and --generations
 * (the run goes on as it was started, not with TICKLIM and NUMGEN),
 * refuses a --ticks or --seed given otherwise and takes another
 * --generations; the interrupt's hint names evo as it was
 * run and those options. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "base/fileio.h"
#include "harness.h"
#include "support/doc_block.h"
#include "support/cli.h"

/* A copy of Avoid with a small NEAT task: 4 generations of 16 networks,
 * 150 ticks an episode (TICKLIM, which --ticks overrides). */
static void make_mind(const char *name)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/%s && cp -r minds/Avoid %s/%s/ && "
			    "printf 'TYPE:LEARNSIM\\nBOTMODEL:BotType8\\n"
			    "MASTERSKILL:Avoid\\nLEARNINGSKILL:Avoid\\n"
			    "ENV:EXP_Avoid\\nLEARNINGMETHOD:NEAT\\nNUMGEN:4\\n"
			    "EVALREP:1\\nTICKLIM:150\\nNEAT_POPSIZE:16\\n' "
			    "> %s/%s/Avoid/Tasks/Small.simbatch",
			    cli_tmp, name, cli_tmp, name, cli_tmp, name),
		     0);
}

static int train(const char *name, const char *extra, char *out, size_t cap)
{
	return cli_capture(out, cap,
			   "%s run %s/%s/Avoid/Tasks/Small.simbatch --seed 7 "
			   "--threads 2 --run %s/%s/run %s 2>&1",
			   cli_evo, cli_tmp, name, cli_tmp, name, extra);
}

static char *skill_net(const char *name)
{
	return cli_read("%s/%s/Avoid/Skills/Avoid/Avoid.net", cli_tmp, name);
}

/* The shipped Avoid.net is replaced by the champion and kept in the run
 * folder as replaced-Avoid.net, which the output names. */
TEST(the_network_a_champion_replaces_is_kept_in_the_run_folder)
{
	char out[16384];
	make_mind("k");
	char *shipped = skill_net("k");
	CHECK(shipped != NULL);
	CHECK_EQ_INT(train("k", "--generations 1", out, sizeof out), 0);
	char *now = skill_net("k");
	char *kept = cli_read("%s/k/run/replaced-Avoid.net", cli_tmp);
	char *champ = cli_read("%s/k/run/champion.net", cli_tmp);
	CHECK(now && kept && champ && shipped);
	if (now && kept && champ && shipped) {
		CHECK_EQ_STR(kept, shipped);
		CHECK_EQ_STR(now, champ);
		CHECK(strcmp(now, shipped) != 0);
	}
	CHECK_CONTAINS(out, "the network it replaced is kept in ");
	CHECK_CONTAINS(out, "/k/run/replaced-Avoid.net");
	/* docs/learning.md quotes these lines for minds/Avoid's own run
	 * folder */
	char doc[1024], mind[400], run[400];
	snprintf(mind, sizeof mind, "%s/k/Avoid/", cli_tmp);
	snprintf(run, sizeof run, "%s/k/run/", cli_tmp);
	const char *sub[] = {"minds/Avoid/Runs/Avoid-NEAT-seed1/", run,
			     "minds/Avoid/", mind, NULL};
	CHECK_EQ_INT(doc_block("docs/learning.md", "tests/sim/learn/test_run_keeps.c",
			       0, doc, sizeof doc),
		     0);
	CHECK_EQ_INT(doc_lines_missing(doc, out, sub, 0), 0);
	/* a second run into a new folder keeps the first run's champion */
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/k/Avoid/Tasks/Small.simbatch "
				 "--seed 8 --generations 1 --run %s/k/run2 2>&1",
				 cli_evo, cli_tmp, cli_tmp),
		     0);
	char *kept2 = cli_read("%s/k/run2/replaced-Avoid.net", cli_tmp);
	CHECK(kept2 && champ);
	if (kept2 && champ)
		CHECK_EQ_STR(kept2, champ);
	free(kept2);
	free(shipped);
	free(now);
	free(kept);
	free(champ);
}

/* --no-save: the champion is in the run folder, Skills/ untouched, and
 * the output says where each is. */
TEST(no_save_leaves_the_skills_folder_as_it_is)
{
	char out[16384];
	make_mind("n");
	char *shipped = skill_net("n");
	CHECK_EQ_INT(train("n", "--generations 1 --no-save", out, sizeof out),
		     0);
	char *now = skill_net("n");
	CHECK(shipped && now);
	if (shipped && now)
		CHECK_EQ_STR(now, shipped);
	char path[512];
	snprintf(path, sizeof path, "%s/n/run/champion.net", cli_tmp);
	CHECK(evo_file_exists(path));
	snprintf(path, sizeof path, "%s/n/run/replaced-Avoid.net", cli_tmp);
	CHECK(!evo_file_exists(path));
	CHECK_CONTAINS(out, "left as it was (--no-save)");
	CHECK(strstr(out, "champion saved in") == NULL);
	free(shipped);
	free(now);
}

/* A team run of the skill keeps the network it replaces as well. */
TEST(a_team_run_keeps_the_network_it_replaces)
{
	char out[16384];
	CHECK_EQ_INT(cli_sh("mkdir -p %s/t && cp -r minds/Forager %s/t/ && "
			    "printf 'TYPE:LEARN2DSIMMULTI\\nENV:EXP_Forage\\n"
			    "TEAM:Foragers:Forager:BotType8:2:Forage\\n"
			    "LEARNINGSKILL:Forage\\nLEARNINGMETHOD:NEAT\\n"
			    "NUMGEN:1\\nEVALREP:1\\nTICKLIM:100\\n"
			    "POPSIZE:8\\n' > %s/t/Forager/Tasks/T.simbatch",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	char *shipped =
	    cli_read("%s/t/Forager/Skills/Forage/Forage.net", cli_tmp);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/t/Forager/Tasks/T.simbatch --seed 3 "
			     "--run %s/t/team 2>&1",
			     cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	if (rc)
		printf("%s\n", out);
	char *kept = cli_read("%s/t/team/replaced-Forage.net", cli_tmp);
	CHECK(kept && shipped);
	if (kept && shipped)
		CHECK_EQ_STR(kept, shipped);
	CHECK_CONTAINS(out, "the network it replaced is kept in ");
	free(kept);
	free(shipped);
}

/* The resume restores --ticks and --generations: the resumed run does 2
 * generations of 60 ticks as it was started, where the task says 4 of
 * 150. A conflicting --ticks is refused, naming the run's value. */
TEST(resume_goes_on_with_the_options_the_run_was_started_with)
{
	char out[16384];
	make_mind("r");
	CHECK_EQ_INT(train("r", "--generations 2 --ticks 60", out, sizeof out),
		     0);
	char run[512];
	snprintf(run, sizeof run, "%s/r/run", cli_tmp);
	char *log1 = cli_fitness_log(run);
	char *net1 = skill_net("r");
	/* the run had finished its 2 generations, not the task's 4: the
	 * resume says so and leaves the log and the skill's network alone */
	CHECK_EQ_INT(train("r", "--resume", out, sizeof out), 0);
	CHECK_CONTAINS(out, "with the options it was started with: --seed 7 "
			    "--ticks 60 --generations 2");
	CHECK_CONTAINS(out, "/r/run is complete: its last generation, 1, was "
			    "the last of its 2 (");
	CHECK(strstr(out, "resuming after generation") == NULL);
	CHECK(strstr(out, "replay on unseen episodes") == NULL);
	char *net2 = skill_net("r");
	CHECK(net1 && net2);
	if (net1 && net2)
		CHECK_EQ_STR(net2, net1);
	free(net1);
	free(net2);
	char *log2 = cli_fitness_log(run);
	CHECK(log1 && log2);
	if (log1 && log2)
		CHECK_EQ_STR(log2, log1); /* 2 rows, not 4 */
	CHECK_EQ_INT(cli_count_lines(log2, "2,"), 0);
	char *opts = cli_read("%s/options.txt", run);
	CHECK_CONTAINS(opts, "\nticks 60\n");
	CHECK_CONTAINS(opts, "\ngenerations 2\n");
	free(opts);
	CHECK(train("r", "--resume --ticks 150", out, sizeof out) != 0);
	CHECK_CONTAINS(out, "--ticks 150 conflicts with the run in ");
	CHECK_CONTAINS(out, "started with --ticks 60");
	/* the same values again are no conflict */
	CHECK_EQ_INT(train("r", "--resume --ticks 60", out, sizeof out), 0);
	/* --generations may change: the run goes on to 3, of 60 ticks */
	CHECK_EQ_INT(train("r", "--resume --generations 3", out, sizeof out),
		     0);
	CHECK_CONTAINS(out, "the run was started with --generations 2; it now "
			    "runs 3 generations");
	CHECK_CONTAINS(out, "x 60 ticks each");
	char *log3 = cli_fitness_log(run);
	CHECK_EQ_INT(cli_count_lines(log3, "2,"), 1);
	free(log3);
	free(log1);
	free(log2);
}

/* --episodes does not shape a learning run: refused, not ignored. */
TEST(episodes_is_refused_for_a_learning_task)
{
	char out[4096];
	make_mind("e");
	CHECK_EQ_INT(train("e", "--episodes 3", out, sizeof out), 2);
	CHECK_CONTAINS(out, "--episodes is for DEMO tasks; ");
	CHECK_CONTAINS(out, "whose networks each play EVALREP episodes");
}

/* --run DIR --resume without --seed: the seed the run was started with,
 * not the task's; another --seed is refused. */
TEST(resume_with_a_run_folder_takes_its_seed)
{
	char out[16384];
	make_mind("s");
	CHECK_EQ_INT(train("s", "--generations 1 --ticks 50", out, sizeof out),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/s/Avoid/Tasks/Small.simbatch "
				 "--run %s/s/run --resume 2>&1",
				 cli_evo, cli_tmp, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "seed 7");
	CHECK(cli_capture(out, sizeof out,
			  "%s run %s/s/Avoid/Tasks/Small.simbatch --seed 2 "
			  "--run %s/s/run --resume 2>&1",
			  cli_evo, cli_tmp, cli_tmp) != 0);
	CHECK_CONTAINS(out, "--seed 2 conflicts with the run in ");
}

/* Interrupted: the hint names the program as it was run (a path, here)
 * and the options that shape the run. */
TEST(the_interrupt_hint_names_the_binary_and_the_options)
{
	make_mind("i");
	/* 1000 generations: the run is still going when it is stopped */
	char cmd[2048], ready[512], said_path[512];
	snprintf(ready, sizeof ready, "%s/i/said.txt", cli_tmp);
	snprintf(said_path, sizeof said_path, "%s/i/said.txt", cli_tmp);
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/i/Avoid/Tasks/Small.simbatch --seed 7 "
		 "--ticks 2000 --generations 1000 --threads 1 --run %s/i/run "
		 "> %s 2>&1",
		 cli_evo, cli_tmp, cli_tmp, said_path);
	int status = 0;
	double secs = 0;
	CHECK_EQ_INT(cli_stop(cmd, ready, "gen 2/", 0, SIGINT, &status, &secs),
		     0);
	char *said = cli_read("%s", said_path);
	CHECK_CONTAINS(said, "interrupted: ");
	char want[1200];
	snprintf(want, sizeof want,
		 "; %s run %s/i/Avoid/Tasks/Small.simbatch --seed 7 --ticks "
		 "2000 --generations 1000 --resume --run %s/i/run goes on",
		 cli_evo, cli_tmp, cli_tmp);
	CHECK_CONTAINS(said, want);
	/* docs/learning.md quotes it for minds/Avoid's Avoid-NEAT task run
	 * with --seed 2 --ticks 500 into its default run folder: its line is
	 * this run's but for those numbers, the paths, and the options this
	 * run adds */
	char doc[2048], task[400], run[400], tail[600];
	snprintf(task, sizeof task, "%s/i/Avoid/Tasks/Small.simbatch", cli_tmp);
	snprintf(run, sizeof run, "%s/i/run", cli_tmp);
	snprintf(tail, sizeof tail, " --generations 1000 --resume --run %s goes on", run);
	const char *sub[] = {"minds/Avoid/Runs/Avoid-NEAT-seed2", run,
			     "minds/Avoid/Tasks/Avoid-NEAT.simbatch", task,
			     "build/evo", cli_evo,
			     " --resume goes on", tail,
			     NULL};
	CHECK_EQ_INT(doc_block("docs/learning.md", "tests/sim/learn/test_run_keeps.c",
			       1, doc, sizeof doc),
		     0);
	CHECK_EQ_INT(doc_lines_missing(doc, said ? said : "", sub, 1), 0);
	free(said);
}

int main(void)
{
	if (cli_setup("run-keeps"))
		return 1;
	RUN(the_network_a_champion_replaces_is_kept_in_the_run_folder);
	RUN(no_save_leaves_the_skills_folder_as_it_is);
	RUN(a_team_run_keeps_the_network_it_replaces);
	RUN(resume_goes_on_with_the_options_the_run_was_started_with);
	RUN(resume_with_a_run_folder_takes_its_seed);
	RUN(episodes_is_refused_for_a_learning_task);
	RUN(the_interrupt_hint_names_the_binary_and_the_options);
	cli_cleanup();
	return test_summary();
}

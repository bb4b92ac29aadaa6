/* LEARNREMOTESIM against `evo serve` (docs/remote.md): the log and the
 * champion are those of LEARNSIM of the same task in one process with the
 * same seed, with one simulator and with two; a simulator killed with
 * SIGKILL in the middle of a run costs nothing but its episodes, which
 * start over on the other; with none left, the run stops, and --resume
 * with a simulator back ends as an uninterrupted run. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "harness.h"
#include "support/doc_block.h"
#include "support/cli.h"
#include "support/serve.h"
#include "support/serve.h"

static char out[1 << 16];

static double mono(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* A copy of minds/Avoid in DIR with two tasks of the same training: T
 * (LEARNSIM, in one process) and R (LEARNREMOTESIM, which `evo serve` of R
 * serves); a small population so a generation is quick. */
static void make_avoid(const char *dir)
{
	cli_sh("rm -rf %s/%s && mkdir -p %s/%s && cp -r minds/Avoid %s/%s/ && "
	       "rm -rf %s/%s/Avoid/Runs",
	       cli_tmp, dir, cli_tmp, dir, cli_tmp, dir, cli_tmp, dir);
	/* LCM on a port of this run's own, so no other run's simulators
	 * answer (the simulators' episodes take ports above it) */
	char common[512];
	snprintf(common, sizeof common,
		 "BOTMODEL:BotType8\nMASTERSKILL:Avoid\n"
		 "LEARNINGSKILL:Avoid\nENV:Roam\n"
		 "LEARNINGMETHOD:NEAT\nNUMGEN:3\nEVALREP:2\n"
		 "TICKLIM:120\nNEAT_POPSIZE:16\nREMOTETIMEOUT:1\n"
		 "LCMURL:udpm://239.255.76.67:%ld?ttl=0\n",
		 30000 + (long)getpid() % 20000);
	char text[640];
	snprintf(text, sizeof text, "TYPE:LEARNSIM\n%s", common);
	cli_write(text, "%s/%s/Avoid/Tasks/T.simbatch", cli_tmp, dir);
	snprintf(text, sizeof text,
		 "TYPE:LEARNREMOTESIM\nREMOTENAME:%s-a-%ld,%s-b-%ld\n%s", dir,
		 (long)getpid(), dir, (long)getpid(), common);
	cli_write(text, "%s/%s/Avoid/Tasks/R.simbatch", cli_tmp, dir);
}

static pid_t start_serve(const char *dir, const char *name)
{
	char task[512], opts[128], log[512];
	snprintf(task, sizeof task, "%s/%s/Avoid/Tasks/R.simbatch", cli_tmp,
		 dir);
	snprintf(opts, sizeof opts, "--name %s", name);
	snprintf(log, sizeof log, "%s/%s/%s.log", cli_tmp, dir, name);
	return cli_serve_start(task, opts, log);
}

static void stop_serve(pid_t pid, int sig)
{
	kill(pid, sig);
	waitpid(pid, NULL, 0);
}

/* Start `evo run` of dir's R into dir/run (its output in dir/run.out) and
 * return once generation 0 is logged, inside generation 1. */
static pid_t start_run_past_generation_0(const char *dir)
{
	char cmd[2048];
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/%s/Avoid/Tasks/R.simbatch --seed 9 --run "
		 "%s/%s/run >%s/%s/run.out 2>&1",
		 cli_evo, cli_tmp, dir, cli_tmp, dir, cli_tmp, dir);
	pid_t run = fork();
	if (run == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	double limit = mono() + 120;
	for (;;) {
		char *t = cli_read("%s/%s/run/log.csv", cli_tmp, dir);
		int rows = cli_count_lines(t, "");
		free(t);
		if (rows >= 2 || mono() > limit)
			break;
		struct timespec ms = {0, 2000000};
		nanosleep(&ms, NULL);
	}
	return run;
}

/* The in-process run of dir's T: its fitness log and champion. */
static void local_run(const char *dir, char **log, char **champion)
{
	int rc = cli_sh("%s run %s/%s/Avoid/Tasks/T.simbatch --seed 9 "
			"--threads 2 --run %s/%s/local >/dev/null 2>&1",
			cli_evo, cli_tmp, dir, cli_tmp, dir);
	CHECK_EQ_INT(rc, 0);
	char path[512];
	snprintf(path, sizeof path, "%s/%s/local", cli_tmp, dir);
	*log = cli_fitness_log(path);
	*champion = cli_read("%s/%s/local/champion.net", cli_tmp, dir);
	CHECK(*log && *champion);
	CHECK_EQ_INT(cli_count_lines(*log, ""), 1 + 3);
}

static void same_as_local(const char *dir, const char *run, const char *log,
			  const char *champion)
{
	char path[512];
	snprintf(path, sizeof path, "%s/%s/%s", cli_tmp, dir, run);
	char *rlog = cli_fitness_log(path);
	char *rchamp = cli_read("%s/champion.net", path);
	CHECK(rlog && log && strcmp(rlog, log) == 0);
	CHECK(rchamp && champion && strcmp(rchamp, champion) == 0);
	if (rlog && log && strcmp(rlog, log) != 0)
		printf("  remote:\n%s  local:\n%s", rlog, log);
	free(rlog);
	free(rchamp);
}

TEST(one_and_two_simulators_give_the_log_and_champion_of_one_process)
{
	char *log, *champion;
	make_avoid("eq");
	local_run("eq", &log, &champion);
	char n1[64], n2[64];
	snprintf(n1, sizeof n1, "eq-a-%ld", (long)getpid());
	snprintf(n2, sizeof n2, "eq-b-%ld", (long)getpid());
	pid_t a = start_serve("eq", n1);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/eq/Avoid/Tasks/R.simbatch --seed 9 "
			     "--run %s/eq/one",
			     cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "1 environment on 1 remote simulator");
	same_as_local("eq", "one", log, champion);
	pid_t b = start_serve("eq", n2);
	rc = cli_capture(out, sizeof out,
			 "%s run %s/eq/Avoid/Tasks/R.simbatch --seed 9 --run "
			 "%s/eq/two",
			 cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "2 environments on 2 remote simulators");
	/* docs/remote.md quotes this line for its own task and seed */
	static char doc[1024];
	char task[512];
	snprintf(task, sizeof task, "%s/eq/Avoid/Tasks/R.simbatch", cli_tmp);
	const char *sub[] = {"minds/Avoid/Tasks/Avoid-REMOTE-NEAT.simbatch", task, NULL};
	CHECK_EQ_INT(doc_block("docs/remote.md", "tests/sim/remote/test_learn_remote.c",
			       0, doc, sizeof doc),
		     0);
	CHECK_EQ_INT(doc_lines_missing(doc, out, sub, 1), 0);
	same_as_local("eq", "two", log, champion);
	stop_serve(a, SIGTERM);
	stop_serve(b, SIGTERM);
	free(log);
	free(champion);
}

/* One of two simulators killed once the run is under way: its episodes
 * go to the other, and the run ends as it would have. */
TEST(a_simulator_killed_mid_run_loses_nothing)
{
	char *log, *champion;
	make_avoid("kill");
	local_run("kill", &log, &champion);
	char n1[64], n2[64];
	snprintf(n1, sizeof n1, "kill-a-%ld", (long)getpid());
	snprintf(n2, sizeof n2, "kill-b-%ld", (long)getpid());
	pid_t a = start_serve("kill", n1), b = start_serve("kill", n2);
	pid_t run = start_run_past_generation_0("kill");
	stop_serve(b, SIGKILL);
	int st = 0;
	waitpid(run, &st, 0);
	CHECK(WIFEXITED(st) && WEXITSTATUS(st) == 0);
	char *said = cli_read("%s/kill/run.out", cli_tmp);
	CHECK(said && strstr(said, "taken as lost; its evaluations go to the "
				   "others"));
	free(said);
	same_as_local("kill", "run", log, champion);
	stop_serve(a, SIGTERM);
	free(log);
	free(champion);
}

/* The only simulator killed: the run stops at its last generation; a
 * simulator back and --resume end as the uninterrupted run. */
TEST(with_no_simulator_left_the_run_stops_and_resumes)
{
	char *log, *champion;
	make_avoid("none");
	local_run("none", &log, &champion);
	char n1[64], n2[64];
	snprintf(n1, sizeof n1, "none-a-%ld", (long)getpid());
	snprintf(n2, sizeof n2, "none-b-%ld", (long)getpid());
	pid_t a = start_serve("none", n1);
	pid_t run = start_run_past_generation_0("none");
	stop_serve(a, SIGKILL);
	int st = 0;
	waitpid(run, &st, 0);
	CHECK(WIFEXITED(st) && WEXITSTATUS(st) == 1);
	char *said = cli_read("%s/none/run.out", cli_tmp);
	CHECK(said && strstr(said, "every remote simulator is lost"));
	free(said);
	pid_t b = start_serve("none", n2);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/none/Avoid/Tasks/R.simbatch --seed 9 "
			     "--run %s/none/run --resume",
			     cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	same_as_local("none", "run", log, champion);
	stop_serve(b, SIGTERM);
	free(log);
	free(champion);
}

/* A task's simulators are the ones it names, or, with a key, the ones
 * that present it: a stranger's simulator answering on the same URL is
 * not adopted (before, every simulator that answered took a share of the
 * episodes). */
TEST(a_strangers_simulator_on_the_url_is_not_adopted)
{
	make_avoid("strange");
	char mine[64], stranger[64], keyed[64];
	snprintf(mine, sizeof mine, "strange-a-%ld", (long)getpid());
	snprintf(stranger, sizeof stranger, "stranger-%ld", (long)getpid());
	snprintf(keyed, sizeof keyed, "strange-k-%ld", (long)getpid());
	/* the stranger serves the same world, with no key */
	pid_t x = start_serve("strange", stranger);
	pid_t a = start_serve("strange", mine);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/strange/Avoid/Tasks/R.simbatch --seed 9 "
			     "--run %s/strange/named",
			     cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "1 environment on 1 remote simulator");
	char want[128];
	snprintf(want, sizeof want, "remote %s: simulator", stranger);
	CHECK(strstr(out, want) == NULL);
	stop_serve(a, SIGTERM);
	/* with a key and no names: the simulator with the key only */
	cli_write("the-key-of-strange-runs\n",
		  "%s/strange/Avoid/Tasks/lcm.key", cli_tmp);
	cli_sh("sed '/^REMOTENAME:/d' %s/strange/Avoid/Tasks/R.simbatch "
	       ">%s/strange/Avoid/Tasks/K.simbatch && echo LCMKEYFILE:lcm.key "
	       ">>%s/strange/Avoid/Tasks/K.simbatch",
	       cli_tmp, cli_tmp, cli_tmp);
	char log[512], cmd[1024];
	snprintf(log, sizeof log, "%s/strange/%s.log", cli_tmp, keyed);
	snprintf(cmd, sizeof cmd,
		 "exec %s serve %s/strange/Avoid/Tasks/K.simbatch --name %s "
		 ">%s 2>&1",
		 cli_evo, cli_tmp, keyed, log);
	pid_t k = fork();
	if (k == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	double limit = mono() + 30;
	for (;;) {
		char *t = cli_read("%s", log);
		int ready = t && strstr(t, " serves ");
		free(t);
		if (ready || mono() > limit)
			break;
		struct timespec ms = {0, 5000000};
		nanosleep(&ms, NULL);
	}
	rc = cli_capture(out, sizeof out,
			 "%s run %s/strange/Avoid/Tasks/K.simbatch --seed 9 "
			 "--run %s/strange/keyed",
			 cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "1 environment on 1 remote simulator");
	CHECK_CONTAINS(out, "dropped a message on EVO_HELLO whose MAC fails "
			    "the key");
	CHECK(strstr(out, want) == NULL);
	CHECK(strstr(out, "the-key-of") == NULL);
	stop_serve(k, SIGTERM);
	stop_serve(x, SIGTERM);
}

int main(void)
{
	if (cli_setup("learn-remote"))
		return 1;
	RUN(one_and_two_simulators_give_the_log_and_champion_of_one_process);
	RUN(a_simulator_killed_mid_run_loses_nothing);
	RUN(with_no_simulator_left_the_run_stops_and_resumes);
	RUN(a_strangers_simulator_on_the_url_is_not_adopted);
	cli_cleanup();
	return test_summary();
}

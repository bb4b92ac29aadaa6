/* Cluster runs (sim/cluster/, docs/cluster.md) under Open MPI's mpirun:
 * one, two and three ranks, each with one and with two threads, give the
 * same log (but for its times), checkpoint and champion as a plain run
 * with threads; a rank killed with SIGKILL in the middle of a generation
 * ends the run within seconds with every finished generation kept, and
 * --resume with another number of ranks ends as the uninterrupted run; a
 * rank started with other settings than rank 0 is named, a rank whose
 * hello is not evo's (-1 threads, a huge count, the wrong size) stops the
 * run with the rank named instead of rank 0 dividing by zero, and a team
 * task is refused on more than one rank; an OPENENDED run on two ranks
 * is the plain one's with one and two threads, and resumes to it when
 * mpirun and its ranks are killed with SIGKILL, and an environment genome
 * of 300,000 bytes gets to the other rank whole; with development too
 * (the skills added reach the other rank), killed after its first skill,
 * and with a rank that cannot read the grown hierarchy named.
 *
 * Runs as root too (the OMPI_ALLOW_RUN_AS_ROOT variables) and on a
 * machine with fewer cores than ranks (--oversubscribe), as
 * docs/cluster.md says. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <mpi.h>

#include "cluster/cluster_messages.h"
#include "harness.h"
#include "support/cli.h"

/* main sets OMPI_ALLOW_RUN_AS_ROOT and its confirmation */
#define MPIRUN "mpirun --oversubscribe"

/* A copy of the Avoid example with a small NEAT task: `gens`
 * generations of `pop` candidates, 2 repetitions of `ticks` ticks. */
static void make_mind_pop(const char *name, int gens, int ticks, int pop)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/%s && cp -r minds/Avoid %s/%s/ && "
			    "printf 'TYPE:LEARNSIM\\nBOTMODEL:BotType8\\n"
			    "MASTERSKILL:Avoid\\nLEARNINGSKILL:Avoid\\n"
			    "ENV:EXP_Avoid\\nLEARNINGMETHOD:NEAT\\nNUMGEN:%d\\n"
			    "EVALREP:2\\nTICKLIM:%d\\nNEAT_POPSIZE:%d\\n' "
			    "> %s/%s/Avoid/Tasks/Small.simbatch",
			    cli_tmp, name, cli_tmp, name, gens, ticks, pop,
			    cli_tmp, name),
		     0);
}

static void make_mind(const char *name, int gens, int ticks)
{
	make_mind_pop(name, gens, ticks, 24);
}

/* Train `name` with `launch` before evo ("" or an mpirun line) and
 * `extra` after it; its output in out.txt. */
static int train(const char *name, const char *launch, const char *extra)
{
	return cli_sh("%s %s run %s/%s/Avoid/Tasks/Small.simbatch --seed 11 "
		      "--run %s/%s/run %s > %s/%s/out.txt 2>&1",
		      launch, cli_evo, cli_tmp, name, cli_tmp, name, extra,
		      cli_tmp, name);
}

static char *log_of(const char *name)
{
	char run[256];
	snprintf(run, sizeof run, "%s/%s/run", cli_tmp, name);
	return cli_fitness_log(run);
}

static char *champion_of(const char *name)
{
	return cli_read("%s/%s/Avoid/Skills/Avoid/Avoid.net", cli_tmp, name);
}

/* name's log, checkpoint and champion are reference's. */
static void same_run(const char *name, const char *reference)
{
	char *a = log_of(reference), *b = log_of(name);
	CHECK(a && b);
	if (a && b)
		CHECK_EQ_STR(b, a);
	char *ka = cli_read("%s/%s/run/checkpoint.lua", cli_tmp, reference);
	char *kb = cli_read("%s/%s/run/checkpoint.lua", cli_tmp, name);
	CHECK(ka && kb);
	if (ka && kb)
		CHECK(strcmp(ka, kb) == 0);
	char *ca = champion_of(reference), *cb = champion_of(name);
	CHECK(ca && cb);
	if (ca && cb)
		CHECK_EQ_STR(cb, ca);
	free(a);
	free(b);
	free(ka);
	free(kb);
	free(ca);
	free(cb);
}

TEST(any_number_of_ranks_and_threads_gives_the_plain_runs_result)
{
	make_mind_pop("plain", 3, 60, 16);
	CHECK_EQ_INT(train("plain", "", "--threads 2"), 0);
	/* worked out apart from the cluster: three generations of 24
	 * evaluations, and a champion that NEAT trained */
	char *ref = log_of("plain");
	CHECK(ref && cli_count_lines(ref, "2,") == 1 &&
	      cli_count_lines(ref, "3,") == 0);
	CHECK(ref && strstr(ref, ",1,16,0"));
	char *champ = champion_of("plain");
	CHECK_CONTAINS(champ, "trained by evo: NEAT, seed 11");
	free(ref);
	free(champ);
	for (int np = 1; np <= 3; np++)
		for (int th = 1; th <= 2; th++) {
			char name[32], launch[160], extra[32], want[64];
			snprintf(name, sizeof name, "np%d-t%d", np, th);
			snprintf(launch, sizeof launch, MPIRUN " -np %d", np);
			snprintf(extra, sizeof extra, "--threads %d", th);
			make_mind_pop(name, 3, 60, 16);
			CHECK_EQ_INT(train(name, launch, extra), 0);
			same_run(name, "plain");
			/* more than one rank says how many work */
			char *out = cli_read("%s/%s/out.txt", cli_tmp, name);
			snprintf(want, sizeof want,
				 "cluster: %d ranks, %d threads in all", np,
				 np * th);
			if (np > 1)
				CHECK_CONTAINS(out, want);
			else
				CHECK(out && !strstr(out, "cluster:"));
			free(out);
		}
}

/* CMAES (layers:1, 19 networks a generation) on two ranks of one
 * thread ends with the log, checkpoint and champion of a plain run. */
TEST(a_cmaes_run_on_two_ranks_is_the_plain_runs)
{
	const char *names[] = {"cm-plain", "cm-np2"};
	for (int i = 0; i < 2; i++) {
		CHECK_EQ_INT(cli_sh("mkdir -p %s/%s && cp -r minds/Avoid %s/%s/ && "
				    "sed -i 's/^layers:0$/layers:1/' "
				    "%s/%s/Avoid/Skills/Avoid/Avoid.ades && "
				    "printf 'TYPE:LEARNSIM\\nBOTMODEL:BotType8\\n"
				    "MASTERSKILL:Avoid\\nLEARNINGSKILL:Avoid\\n"
				    "ENV:EXP_Avoid\\nLEARNINGMETHOD:CMAES\\n"
				    "NUMGEN:3\\nEVALREP:2\\nTICKLIM:60\\n' "
				    "> %s/%s/Avoid/Tasks/Small.simbatch",
				    cli_tmp, names[i], cli_tmp, names[i], cli_tmp,
				    names[i], cli_tmp, names[i]),
			     0);
	}
	CHECK_EQ_INT(train("cm-plain", "", "--threads 1"), 0);
	CHECK_EQ_INT(train("cm-np2", MPIRUN " -np 2", "--threads 1"), 0);
	char *ref = log_of("cm-plain");
	CHECK(ref && strstr(ref, ",0,19,0"));
	free(ref);
	char *champ = champion_of("cm-plain");
	CHECK_CONTAINS(champ, "trained by evo: CMAES, seed 11");
	free(champ);
	same_run("cm-np2", "cm-plain");
}

/* NOVELTY (16 networks, the bot's final position as behaviour) on two
 * ranks of one thread ends with the plain run's log, checkpoint (the
 * archive in it) and champion: the descriptors come back from the ranks
 * in candidate order, as the fitnesses do. */
TEST(a_novelty_run_on_two_ranks_is_the_plain_runs)
{
	const char *names[] = {"nv-plain", "nv-np2"};
	for (int i = 0; i < 2; i++) {
		make_mind_pop(names[i], 4, 60, 16);
		CHECK_EQ_INT(cli_sh("sed -i 's/LEARNINGMETHOD:NEAT/"
				    "LEARNINGMETHOD:NOVELTY/' "
				    "%s/%s/Avoid/Tasks/Small.simbatch",
				    cli_tmp, names[i]),
			     0);
	}
	CHECK_EQ_INT(train("nv-plain", "", "--threads 1"), 0);
	CHECK_EQ_INT(train("nv-np2", MPIRUN " -np 2", "--threads 1"), 0);
	char *ref = log_of("nv-plain");
	CHECK_CONTAINS(ref, ",metric:archive,metric:threshold,"
			    "metric:best_novelty\n");
	free(ref);
	char *ckpt = cli_read("%s/nv-plain/run/checkpoint.lua", cli_tmp);
	CHECK_CONTAINS(ckpt, "[\"archive_meta\"]={");
	CHECK(ckpt && !strstr(ckpt, "[\"archive_meta\"]={}"));
	free(ckpt);
	char *champ = champion_of("nv-plain");
	CHECK_CONTAINS(champ, "trained by evo: NOVELTY, seed 11");
	free(champ);
	same_run("nv-np2", "nv-plain");
}

/* A LEARN3DSIM task spreads as a LEARNSIM task does: the blimp's
 * go-to-target, two generations of 20, on two ranks of one thread, ends
 * with the plain run's log and champion. */
TEST(a_3d_task_spreads_over_ranks_as_a_2d_one)
{
	const char *task = "Blimp3D/Tasks/GoToTarget-NEAT.simbatch";
	int rc = 0;
	for (int k = 0; k < 2; k++) {
		const char *name = k ? "blimp-np2" : "blimp-plain";
		rc |= cli_sh("mkdir -p %s/%s && cp -r minds/Blimp3D %s/%s/ && "
			     "sed -i -e 's/^NUMGEN:.*/NUMGEN:2/' -e "
			     "'s/^EVALREP:.*/EVALREP:1/' -e "
			     "'s/^TICKLIM:.*/TICKLIM:150/' %s/%s/%s && echo "
			     "POPSIZE:20 >> %s/%s/%s",
			     cli_tmp, name, cli_tmp, name, cli_tmp, name, task,
			     cli_tmp, name, task);
		rc |= cli_sh("%s %s run %s/%s/%s --seed 4 %s --run %s/%s/run "
			     "> %s/%s/out.txt 2>&1",
			     k ? MPIRUN " -np 2" : "", cli_evo, cli_tmp, name,
			     task, k ? "--threads 1" : "--threads 2", cli_tmp,
			     name, cli_tmp, name);
	}
	CHECK_EQ_INT(rc, 0);
	char run[256];
	snprintf(run, sizeof run, "%s/blimp-plain/run", cli_tmp);
	char *a = cli_fitness_log(run);
	snprintf(run, sizeof run, "%s/blimp-np2/run", cli_tmp);
	char *b = cli_fitness_log(run);
	/* two generations of 20 evaluations, and the same two */
	CHECK(a && cli_count_lines(a, "1,") == 1 && strstr(a, ",20,"));
	CHECK(a && b);
	if (a && b)
		CHECK_EQ_STR(b, a);
	char *out = cli_read("%s/blimp-np2/out.txt", cli_tmp);
	CHECK_CONTAINS(out, "cluster: 2 ranks, 2 threads in all");
	char *ca = cli_read("%s/blimp-plain/run/champion.net", cli_tmp);
	char *cb = cli_read("%s/blimp-np2/run/champion.net", cli_tmp);
	CHECK(ca && cb);
	if (ca && cb)
		CHECK_EQ_STR(cb, ca);
	free(a);
	free(b);
	free(out);
	free(ca);
	free(cb);
}

/* The pid of rank `rank` among the children of mpirun `parent`, from its
 * environment (OMPI_COMM_WORLD_RANK); -1 when there is none. */
static pid_t rank_pid(pid_t parent, int rank)
{
	char want[48];
	snprintf(want, sizeof want, "OMPI_COMM_WORLD_RANK=%d", rank);
	DIR *d = opendir("/proc");
	pid_t found = -1;
	struct dirent *e;
	while (d && found < 0 && (e = readdir(d))) {
		pid_t pid = (pid_t)atoi(e->d_name);
		if (pid <= 0)
			continue;
		char path[64], buf[8192];
		snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
		FILE *f = fopen(path, "r");
		if (!f)
			continue;
		int ppid = -1;
		size_t n = fread(buf, 1, sizeof buf - 1, f);
		fclose(f);
		buf[n] = 0;
		const char *close_paren = strrchr(buf, ')');
		if (!close_paren ||
		    sscanf(close_paren + 1, " %*c %d", &ppid) != 1 ||
		    ppid != parent)
			continue;
		snprintf(path, sizeof path, "/proc/%d/environ", (int)pid);
		f = fopen(path, "r");
		if (!f)
			continue;
		n = fread(buf, 1, sizeof buf - 1, f);
		fclose(f);
		for (size_t i = 0; i < n; i += strlen(buf + i) + 1)
			if (strcmp(buf + i, want) == 0)
				found = pid;
	}
	if (d)
		closedir(d);
	return found;
}

static int rows(const char *name)
{
	char *t = cli_read("%s/%s/run/log.csv", cli_tmp, name);
	int n = -1;
	for (const char *p = t; p && *p; p++)
		n += *p == '\n';
	free(t);
	return n;
}

static double mono(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

TEST(a_killed_rank_stops_the_run_and_resume_with_other_ranks_finishes_it)
{
	/* 1,000 ticks a repetition: a generation lasts long enough that
	 * the kill lands inside one */
	make_mind("ref", 5, 1000);
	CHECK_EQ_INT(train("ref", "", "--threads 2"), 0);
	make_mind("k", 5, 1000);
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "exec " MPIRUN " -np 3 %s run %s/k/Avoid/Tasks/Small.simbatch "
		 "--seed 11 --threads 1 --run %s/k/run > %s/k/out1.txt 2>&1",
		 cli_evo, cli_tmp, cli_tmp, cli_tmp);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	struct timespec ms = {0, 2000000};
	for (int i = 0; i < 30000 && rows("k") < 3; i++)
		nanosleep(&ms, NULL);
	CHECK(rows("k") >= 3);
	pid_t victim = rank_pid(pid, 1);
	CHECK(victim > 0);
	double t0 = mono();
	if (victim > 0)
		kill(victim, SIGKILL);
	int st = 0, ended = 0;
	/* within seconds: give it ten before calling it a hang */
	while (mono() - t0 < 10 && !(ended = waitpid(pid, &st, WNOHANG) > 0))
		nanosleep(&ms, NULL);
	if (!ended) {
		kill(pid, SIGKILL);
		waitpid(pid, &st, 0);
	}
	double took = mono() - t0;
	CHECK(ended);
	CHECK(took < 5);
	CHECK(!(WIFEXITED(st) && WEXITSTATUS(st) == 0));
	int kept = rows("k");
	CHECK(kept >= 2 && kept < 5); /* it really was stopped */
	/* rank 0 stopped as on SIGTERM: every finished generation's row
	 * and a checkpoint at most a second old are on disk, and it says
	 * how to go on */
	char *said = cli_read("%s/k/out1.txt", cli_tmp);
	char how[300]; /* evo as mpirun ran it */
	snprintf(how, sizeof how, "second of work back; mpirun -np N %s run ",
		 cli_evo);
	CHECK(said && strstr(said, " as of its last checkpoint, at most a ") &&
	      strstr(said, how));
	CHECK(said && strstr(said, " goes on, with any number of ranks N, "
				   "or without mpirun\n"));
	free(said);
	/* resumed from the checkpoint with two ranks, the run does the
	 * generations after it again and ends as the uninterrupted one */
	CHECK_EQ_INT(train("k", MPIRUN " -np 2", "--threads 1 --resume"), 0);
	char *out = cli_read("%s/k/out.txt", cli_tmp);
	CHECK(out && strstr(out, "resuming after generation"));
	free(out);
	same_run("k", "ref");
}

/* ---- OPENENDED ----------------------------------------------------------- */

/* A copy of minds/OpenMaze (docs/openended.md) with no run in it, and
 * no development (the tests of development are further on). */
static void make_open(const char *name)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/%s && cp -r minds/OpenMaze %s/%s/ && "
			    "rm -rf %s/%s/OpenMaze/Runs && "
			    "sed -i 's/^OPEN_DEVELOP:.*/OPEN_DEVELOP:0/' "
			    "%s/%s/OpenMaze/Tasks/OpenMaze.simbatch",
			    cli_tmp, name, cli_tmp, name, cli_tmp, name, cli_tmp,
			    name),
		     0);
}

/* name's OPENENDED task for 6 batches, seed 3, with `launch` before evo
 * and `extra` after it; its output in out.txt. */
static int open_run(const char *name, const char *launch, const char *extra)
{
	return cli_sh("%s %s run %s/%s/OpenMaze/Tasks/OpenMaze.simbatch "
		      "--seed 3 --generations 6 --no-save --run %s/%s/run %s "
		      "> %s/%s/out.txt 2>&1",
		      launch, cli_evo, cli_tmp, name, cli_tmp, name, extra,
		      cli_tmp, name);
}

/* name's log (but for its times), envs.csv, retention.csv and checkpoint
 * are reference's. */
static void same_open_run(const char *name, const char *reference)
{
	char *a = log_of(reference), *b = log_of(name);
	CHECK(a && b);
	if (a && b)
		CHECK_EQ_STR(b, a);
	free(a);
	free(b);
	static const char *files[] = {"envs.csv", "retention.csv",
				      "checkpoint.lua"};
	for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
		char *fa = cli_read("%s/%s/run/%s", cli_tmp, reference,
				    files[k]);
		char *fb = cli_read("%s/%s/run/%s", cli_tmp, name, files[k]);
		CHECK(fa && fb);
		if (fa && fb && strcmp(fa, fb) != 0)
			printf("  %s of %s differs from %s's\n", files[k], name,
			       reference);
		CHECK(fa && fb && strcmp(fa, fb) == 0);
		free(fa);
		free(fb);
	}
}

/* An OPENENDED batch on two ranks: every rank's workers build the maze
 * rank 0 chose (its genome sent with the batch), so the run is the plain
 * one's with one thread and with two. */
TEST(an_openended_run_on_two_ranks_is_the_plain_runs)
{
	make_open("op-t1");
	CHECK_EQ_INT(open_run("op-t1", "", "--threads 1"), 0);
	/* worked out apart from the cluster: batch 0 admits the seed maze
	 * of 3 x 2 cells and no wall, whose path is 3 (docs/openended.md),
	 * and the run logs its 6 batches */
	char *ref = log_of("op-t1");
	CHECK(ref && cli_count_lines(ref, "5,") == 1 &&
	      cli_count_lines(ref, "6,") == 0);
	CHECK(ref && strstr(ref, "\n0,") && strstr(strstr(ref, "\n0,"), ",1,3,"));
	free(ref);
	make_open("op-t2");
	CHECK_EQ_INT(open_run("op-t2", "", "--threads 2"), 0);
	same_open_run("op-t2", "op-t1");
	make_open("op-np2");
	CHECK_EQ_INT(open_run("op-np2", MPIRUN " -np 2", "--threads 1"), 0);
	char *out = cli_read("%s/op-np2/out.txt", cli_tmp);
	CHECK_CONTAINS(out, "cluster: 2 ranks, 2 threads in all");
	free(out);
	same_open_run("op-np2", "op-t1");
}

/* An environment genome of 300,000 bytes and more (GEN_Maze's mazes
 * carrying a padding, in a generator of the mind folder's Envs/) reaches
 * the other rank whole: the two-rank run is the plain one's. */
TEST(a_large_environment_genome_reaches_every_rank)
{
	make_open("op-big1");
	make_open("op-big2");
	static const char gen[] =
	    "local openended = require 'lib.openended'\n"
	    "local gen = {}\n"
	    "for k, v in pairs(require('envs.GEN_Maze').generator) do "
	    "gen[k] = v end\n"
	    "local seed, mutate = gen.seed, gen.mutate\n"
	    "local PAD = string.rep('x', 300000)\n"
	    "gen.seed = function() local g = seed(); g.pad = PAD; return g "
	    "end\n"
	    "gen.mutate = function(g, rng) local m = mutate(g, rng); "
	    "m.pad = g.pad; return m end\n"
	    "return openended.env(gen)\n";
	const char *names[] = {"op-big1", "op-big2"};
	for (int k = 0; k < 2; k++) {
		CHECK_EQ_INT(cli_sh("mkdir -p %s/%s/OpenMaze/Envs", cli_tmp,
				    names[k]),
			     0);
		CHECK_EQ_INT(cli_write(gen, "%s/%s/OpenMaze/Envs/Big.lua",
				       cli_tmp, names[k]),
			     0);
		CHECK_EQ_INT(
		    cli_sh("sed 's/^ENV:GEN_Maze/ENV:Big/' "
			   "%s/%s/OpenMaze/Tasks/OpenMaze.simbatch > "
			   "%s/%s/OpenMaze/Tasks/Big.simbatch",
			   cli_tmp, names[k], cli_tmp, names[k]),
		    0);
		CHECK_EQ_INT(
		    cli_sh("%s %s run %s/%s/OpenMaze/Tasks/Big.simbatch "
			   "--seed 3 --generations 3 --no-save --threads 1 "
			   "--run %s/%s/run > %s/%s/out.txt 2>&1",
			   k ? MPIRUN " -np 2" : "", cli_evo, cli_tmp,
			   names[k], cli_tmp, names[k], cli_tmp, names[k]),
		    0);
	}
	/* the padding is in the genomes the run admitted */
	char *envs = cli_read("%s/op-big1/run/envs.csv", cli_tmp);
	CHECK(envs && strlen(envs) > 300000);
	free(envs);
	same_open_run("op-big2", "op-big1");
}

/* A two-rank OPENENDED run whose mpirun and ranks are all killed with
 * SIGKILL in the middle (a machine lost) resumes on two ranks to the
 * uninterrupted run's result. */
TEST(a_killed_openended_cluster_run_resumes_to_the_same_result)
{
	make_open("op-ref");
	CHECK_EQ_INT(open_run("op-ref", "", "--threads 1"), 0);
	make_open("op-k");
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "exec " MPIRUN " -np 2 %s run %s/op-k/OpenMaze/Tasks/"
		 "OpenMaze.simbatch --seed 3 --generations 6 --no-save "
		 "--threads 1 --run %s/op-k/run > %s/op-k/out1.txt 2>&1",
		 cli_evo, cli_tmp, cli_tmp, cli_tmp);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	struct timespec ms = {0, 1000000};
	for (int i = 0; i < 60000 && rows("op-k") < 2; i++)
		nanosleep(&ms, NULL);
	/* mpirun's ranks outlive it when it alone is killed: kill them all */
	pid_t r0 = rank_pid(pid, 0), r1 = rank_pid(pid, 1);
	CHECK(r0 > 0 && r1 > 0);
	if (r0 > 0)
		kill(r0, SIGKILL);
	if (r1 > 0)
		kill(r1, SIGKILL);
	kill(pid, SIGKILL);
	int st = 0;
	waitpid(pid, &st, 0);
	CHECK(WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL);
	int kept = rows("op-k");
	CHECK(kept >= 2 && kept < 6); /* it really was stopped */
	CHECK_EQ_INT(open_run("op-k", MPIRUN " -np 2", "--threads 1 --resume"),
		     0);
	char *out = cli_read("%s/op-k/out.txt", cli_tmp);
	CHECK(out && strstr(out, "resuming after batch"));
	free(out);
	same_open_run("op-k", "op-ref");
}

/* ---- OPENENDED's development --------------------------------------------- */

/* A copy of minds/OpenMaze whose task grows a skill after every batch
 * that admits no maze (OPEN_DEVELOP 1), one maze tried a batch, 3
 * generations of focus (as tests/sim/learn/test_openended.c's). */
static void make_dev(const char *name)
{
	make_open(name);
	CHECK_EQ_INT(cli_sh("sed -i 's/^OPEN_DEVELOP:.*/OPEN_DEVELOP:1/; "
			    "s/^OPEN_FOCUS:.*/OPEN_FOCUS:3/; "
			    "s/^OPEN_ENV_BATCH:.*/OPEN_ENV_BATCH:1/; "
			    "s/^OPEN_PROGRESS:.*/OPEN_PROGRESS:admitted/' "
			    "%s/%s/OpenMaze/Tasks/OpenMaze.simbatch",
			    cli_tmp, name),
		     0);
}

/* name's developing task for 10 batches, seed 3, as open_run. */
static int dev_run(const char *name, const char *launch, const char *extra)
{
	return cli_sh("timeout 300 %s %s run %s/%s/OpenMaze/Tasks/"
		      "OpenMaze.simbatch --seed 3 --generations 10 --no-save "
		      "--run %s/%s/run %s > %s/%s/out.txt 2>&1",
		      launch, cli_evo, cli_tmp, name, cli_tmp, name, extra,
		      cli_tmp, name);
}

/* name's run is reference's (same_open_run), and so are its skills.csv
 * and its grown mind folder's master skill and first skill added. */
static void same_dev_run(const char *name, const char *reference)
{
	same_open_run(name, reference);
	static const char *files[] = {"skills.csv",
				      "Mind/Skills/Maze/Maze.ades",
				      "Mind/Skills/Maze/Maze.net",
				      "Mind/Skills/Explore1/Explore1.net"};
	for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
		char *fa = cli_read("%s/%s/run/%s", cli_tmp, reference,
				    files[k]);
		char *fb = cli_read("%s/%s/run/%s", cli_tmp, name, files[k]);
		CHECK(fa && fb);
		if (fa && fb && strcmp(fa, fb) != 0)
			printf("  %s of %s differs from %s's\n", files[k], name,
			       reference);
		CHECK(fa && fb && strcmp(fa, fb) == 0);
		free(fa);
		free(fb);
	}
}

/* Field k (0-based) of row `row` of a log as cli_fitness_log gives it
 * (generation, best, mean, best_ever, species, evaluations, solved, then
 * the metrics); -1 when there is none. */
static double log_field(const char *log, int row, int k)
{
	const char *p = log ? strchr(log, '\n') : NULL;
	for (int r = 0; p && r < row; r++)
		p = strchr(p + 1, '\n');
	if (!p || !p[1])
		return -1;
	p++;
	for (int i = 0; i < k; i++) {
		p = strpbrk(p, ",\n");
		if (!p || *p == '\n')
			return -1;
		p++;
	}
	return strtod(p, NULL);
}

/* A task that grows its hierarchy on two ranks: each skill added reaches
 * the other rank's workers (its evaluator made anew from the grown mind
 * folder, for the focus and for the agents), so the run is the plain one's
 * with one thread and with two: log, envs.csv, retention.csv, checkpoint,
 * skills.csv and Mind/. */
TEST(a_developing_openended_run_on_two_ranks_is_the_plain_runs)
{
	make_dev("dv-t1");
	CHECK_EQ_INT(dev_run("dv-t1", "", "--threads 1"), 0);
	/* worked out from the log apart from the cluster: a skill after
	 * each batch that admitted no maze (solved 0), at most 3, never
	 * after the last; the master skill has an SK: output per skill */
	char dir[512];
	snprintf(dir, sizeof dir, "%s/dv-t1/run", cli_tmp);
	char *log = cli_fitness_log(dir);
	int want = 0;
	for (int b = 0; b < 10; b++) {
		if (log_field(log, b, 6) == 0 && want < 3 && b < 9)
			want++;
		CHECK(log_field(log, b, 11) == want);
	}
	CHECK(want >= 1);
	CHECK(log_field(log, 10, 0) < 0);
	free(log);
	char *ades = cli_read("%s/dv-t1/run/Mind/Skills/Maze/Maze.ades", cli_tmp);
	char line[128];
	snprintf(line, sizeof line, "output:%d\nMO:TURN\nMO:SPEED\nSK:Explore1\n",
		 2 + want);
	CHECK_CONTAINS(ades, line);
	free(ades);
	make_dev("dv-t2");
	CHECK_EQ_INT(dev_run("dv-t2", "", "--threads 2"), 0);
	same_dev_run("dv-t2", "dv-t1");
	make_dev("dv-np2");
	CHECK_EQ_INT(dev_run("dv-np2", MPIRUN " -np 2", "--threads 1"), 0);
	char *out = cli_read("%s/dv-np2/out.txt", cli_tmp);
	CHECK_CONTAINS(out, "skill Explore1 added after batch");
	/* said once, not again at each skill */
	CHECK(out && cli_count_lines(out, "cluster: 2 ranks, 2 threads in "
					  "all\n") == 1);
	free(out);
	same_dev_run("dv-np2", "dv-t1");
}

/* A developing run on two ranks whose mpirun and ranks are all killed
 * with SIGKILL after its first skill resumes on two ranks with the grown
 * hierarchy (the ranks make theirs anew before the first batch) to the
 * uninterrupted run's result. */
TEST(a_killed_developing_cluster_run_resumes_with_its_skills)
{
	make_dev("dk-ref");
	CHECK_EQ_INT(dev_run("dk-ref", "", "--threads 1"), 0);
	make_dev("dk");
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "exec " MPIRUN " -np 2 %s run %s/dk/OpenMaze/Tasks/"
		 "OpenMaze.simbatch --seed 3 --generations 10 --no-save "
		 "--threads 1 --run %s/dk/run > %s/dk/out1.txt 2>&1",
		 cli_evo, cli_tmp, cli_tmp, cli_tmp);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	struct timespec ms = {0, 1000000};
	char *ck = NULL;
	for (int i = 0; i < 120000; i++) {
		ck = cli_read("%s/dk/run/checkpoint.lua", cli_tmp);
		if (ck && strstr(ck, "Explore1"))
			break;
		free(ck);
		ck = NULL;
		nanosleep(&ms, NULL);
	}
	CHECK(ck != NULL);
	free(ck);
	pid_t r0 = rank_pid(pid, 0), r1 = rank_pid(pid, 1);
	CHECK(r0 > 0 && r1 > 0);
	if (r0 > 0)
		kill(r0, SIGKILL);
	if (r1 > 0)
		kill(r1, SIGKILL);
	kill(pid, SIGKILL);
	int st = 0;
	waitpid(pid, &st, 0);
	CHECK(WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL);
	int kept = rows("dk");
	CHECK(kept >= 2 && kept < 10); /* it really was stopped */
	CHECK_EQ_INT(dev_run("dk", MPIRUN " -np 2", "--threads 1 --resume"), 0);
	char *out = cli_read("%s/dk/out.txt", cli_tmp);
	CHECK_CONTAINS(out, "resuming after batch");
	CHECK_CONTAINS(out, "cluster: 2 ranks, 2 threads in all");
	free(out);
	same_dev_run("dk", "dv-t1");
	same_dev_run("dk", "dk-ref");
}

/* Every rank loads the grown hierarchy from the run folder rank 0 wrote
 * it in: a rank that cannot (here it starts in another folder, as a
 * machine that does not share the run folder) stops the run at the first
 * skill, named, with the path it tried and the way out; no rank hangs. */
TEST(a_rank_that_cannot_read_the_grown_hierarchy_is_named)
{
	make_dev("far/a");
	make_dev("far/b");
	char out[16384] = "";
	int rc = cli_capture(out, sizeof out,
			     "e=$(realpath %s) && timeout 120 " MPIRUN " -np 1 "
			     "--wdir %s/far/a $e run "
			     "OpenMaze/Tasks/OpenMaze.simbatch --seed 3 "
			     "--generations 10 --no-save --threads 1 --run run : "
			     "-np 1 --wdir %s/far/b $e run OpenMaze/Tasks/"
			     "OpenMaze.simbatch --seed 3 --generations 10 "
			     "--no-save --threads 1 --run run",
			     cli_evo, cli_tmp, cli_tmp);
	CHECK(rc != 0 && rc != 124);
	CHECK_CONTAINS(out, "rank 1 (on ");
	CHECK_CONTAINS(out, "the hierarchy rank 0 grew does not load here "
			    "(run/Mind/Tasks/OpenMaze.simbatch: cannot open");
	CHECK_CONTAINS(out, "give --run a folder all the machines share");
	/* it stopped at the first skill: the batch that added it is the
	 * last logged */
	char *log = cli_read("%s/far/a/run/log.csv", cli_tmp);
	CHECK(log && !strstr(log, ",1\n"));
	free(log);
}

/* A rank that runs the task with other settings than rank 0 (here its
 * own --ticks, through mpirun's one-program-per-rank syntax) stops the
 * run at its first batch with a message that names it, and no rank
 * hangs. */
TEST(a_rank_with_other_settings_is_named)
{
	make_mind_pop("bad", 2, 60, 16);
	CHECK_EQ_INT(cli_sh(MPIRUN " -np 1 %s run %s/bad/Avoid/Tasks/"
				   "Small.simbatch --seed 11 --threads 1 --run "
				   "%s/bad/run : -np 1 %s run %s/bad/Avoid/"
				   "Tasks/Small.simbatch --seed 11 --threads 1 "
				   "--ticks 99 > %s/bad/out.txt 2>&1",
			    cli_evo, cli_tmp, cli_tmp, cli_evo, cli_tmp,
			    cli_tmp),
		     1);
	char *out = cli_read("%s/bad/out.txt", cli_tmp);
	CHECK_CONTAINS(out, "rank 1 (on ");
	CHECK_CONTAINS(out, "2 repetitions of 99 ticks");
	CHECK_CONTAINS(out, "start every rank with the same command and files");
	free(out);
}

/* Only LEARNSIM spreads over ranks: a team task under mpirun with two
 * ranks is refused with the reason, before anything is written. */
TEST(a_team_task_is_refused_on_two_ranks)
{
	char out[4096];
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 MPIRUN
				 " -np 2 %s run "
				 "minds/Forager/Tasks/Forage-NEAT.simbatch "
				 "--run %s/team --threads 1 2>&1",
				 cli_evo, cli_tmp) != 0,
		     1);
	CHECK_CONTAINS(out, "a LEARN2DSIMMULTI task runs in one process; "
			    "mpirun with more than one rank spreads LEARNSIM, "
			    "LEARN3DSIM and OPENENDED tasks");
	char *log = cli_read("%s/team/log.csv", cli_tmp);
	CHECK(log == NULL);
	free(log);
}

/* The test binary run as a rank under mpirun (--fake-rank WHAT): a hello
 * as a damaged or foreign rank sends it (WHAT: threads=N, or short for
 * one of 8 bytes) with the settings of make_mind_pop's task otherwise,
 * then the wait for rank 0's STOP, 30 s at most. */
static int fake_rank(const char *what)
{
	MPI_Init(NULL, NULL);
	evo_cluster_hello h;
	memset(&h, 0, sizeof h);
	h.ok = 1;
	h.threads = 1;
	h.reps = 2;
	h.ticks = 60;
	h.seed = 11;
	/* the Avoid skill's, so that rank 0 finds nothing else amiss */
	h.n_in = 11;
	h.n_out = 2;
	snprintf(h.host, sizeof h.host, "fakehost");
	if (strncmp(what, "threads=", 8) == 0)
		h.threads = (int32_t)strtol(what + 8, NULL, 10);
	int len = strcmp(what, "short") == 0 ? 8 : (int)sizeof h;
	MPI_Send(&h, len, MPI_BYTE, 0, EVO_CLUSTER_TAG_HELLO, MPI_COMM_WORLD);
	for (int k = 0; k < 3000; k++) {
		int flag = 0;
		MPI_Status st;
		MPI_Iprobe(0, EVO_CLUSTER_TAG_STOP, MPI_COMM_WORLD, &flag, &st);
		if (flag) {
			MPI_Recv(NULL, 0, MPI_BYTE, 0, EVO_CLUSTER_TAG_STOP,
				 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
			break;
		}
		struct timespec ts = {0, 10000000};
		nanosleep(&ts, NULL);
	}
	MPI_Finalize();
	return 0;
}

static char self[512];

/* A rank whose hello says -1 threads divided by zero in rank 0 (SIGFPE,
 * or UBSan's report); a hello with a count no rank has, or of another
 * size, is no better. Each stops the run at once with the rank named and
 * no rank waiting. */
TEST(a_rank_whose_hello_is_not_evos_is_named)
{
	static const struct {
		const char *what, *want;
	} bad[] = {
	    {"threads=-1", "rank 1 (on fakehost): a hello with -1 threads "
			   "(a rank has 1 to 1024)"},
	    {"threads=0", "rank 1 (on fakehost): a hello with 0 threads"},
	    {"threads=2147483647",
	     "rank 1 (on fakehost): a hello with 2147483647 threads"},
	    {"short", "rank 1: a hello of 8 bytes, where evo's has"},
	};
	make_mind_pop("fake", 2, 60, 16);
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		time_t t0 = time(NULL);
		int rc = cli_sh("timeout 60 " MPIRUN
				" -np 1 %s run %s/fake/Avoid/Tasks/"
				"Small.simbatch --seed 11 --threads 1 --run "
				"%s/fake/run : -np 1 %s --fake-rank %s > "
				"%s/fake/out.txt 2>&1",
				cli_evo, cli_tmp, cli_tmp, self, bad[k].what,
				cli_tmp);
		CHECK_EQ_INT(rc, 1);
		CHECK(time(NULL) - t0 < 30);
		char *out = cli_read("%s/fake/out.txt", cli_tmp);
		CHECK_CONTAINS(out, bad[k].want);
		if (out && !strstr(out, bad[k].want))
			printf("%s", out);
		CHECK(out && !strstr(out, "runtime error") &&
		      !strstr(out, "Floating point"));
		free(out);
	}
}

int main(int argc, char **argv)
{
	if (argc == 3 && strcmp(argv[1], "--fake-rank") == 0)
		return fake_rank(argv[2]);
	/* the fake rank is this binary, named as it was started (mpirun
	 * starts it in this directory) */
	snprintf(self, sizeof self, "%s", argv[0]);
	if (cli_setup("cluster"))
		return 1;
	setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
	setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
	RUN(any_number_of_ranks_and_threads_gives_the_plain_runs_result);
	RUN(a_cmaes_run_on_two_ranks_is_the_plain_runs);
	RUN(a_novelty_run_on_two_ranks_is_the_plain_runs);
	RUN(a_3d_task_spreads_over_ranks_as_a_2d_one);
	RUN(a_killed_rank_stops_the_run_and_resume_with_other_ranks_finishes_it);
	RUN(an_openended_run_on_two_ranks_is_the_plain_runs);
	RUN(a_large_environment_genome_reaches_every_rank);
	RUN(a_killed_openended_cluster_run_resumes_to_the_same_result);
	RUN(a_rank_with_other_settings_is_named);
	RUN(a_rank_whose_hello_is_not_evos_is_named);
	RUN(a_team_task_is_refused_on_two_ranks);
	RUN(a_developing_openended_run_on_two_ranks_is_the_plain_runs);
	RUN(a_killed_developing_cluster_run_resumes_with_its_skills);
	RUN(a_rank_that_cannot_read_the_grown_hierarchy_is_named);
	cli_cleanup();
	return test_summary();
}

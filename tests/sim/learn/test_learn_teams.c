/* LEARN2DSIMMULTI (sim/learn, lua/learn/learnsim.lua, docs/teams.md):
 * a team's skill trains, homogeneous (a genome is a team of clones) and
 * heterogeneous (a genome is a member), with the team's or each member's
 * own fitness; the log does not depend on the number of threads; a run
 * killed with SIGKILL and resumed ends as an uninterrupted one; the
 * trained team beats untrained ones on unseen episodes; a heterogeneous
 * champion is a team of networks that DEMO2DSIMMULTI runs member by
 * member. */
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

static char out[1 << 16];

/* A copy of minds/Forager as <name>/Forager, with a short learning task
 * T.simbatch of `genome`, `fitness`, NUMGEN gens and the extra keys
 * (default: EVALREP 1, POPSIZE 40). */
static int make(const char *name, const char *genome, const char *fitness,
		int gens, const char *extra)
{
	if (cli_sh("rm -rf %s/%s && mkdir -p %s/%s && cp -r minds/Forager "
		   "%s/%s/",
		   cli_tmp, name, cli_tmp, name, cli_tmp, name))
		return -1;
	char text[1024];
	snprintf(text, sizeof text,
		 "TYPE:LEARN2DSIMMULTI\nENV:EXP_Forage\n"
		 "TEAM:Foragers:Forager:BotType8:4:Forage\n"
		 "LEARNINGSKILL:Forage\nLEARNINGMETHOD:NEAT\n"
		 "TEAMGENOME:%s\nTEAMFITNESS:%s\nNUMGEN:%d\n"
		 "TICKLIM:400\n%s",
		 genome, fitness, gens,
		 extra ? extra : "EVALREP:1\nPOPSIZE:40\n");
	return cli_write(text, "%s/%s/Forager/Tasks/T.simbatch", cli_tmp, name);
}

static int train(const char *name, const char *args)
{
	return cli_sh("%s run %s/%s/Forager/Tasks/T.simbatch --seed 5 --run "
		      "%s/%s/run %s > %s/%s/out.txt 2>&1",
		      cli_evo, cli_tmp, name, cli_tmp, name, args, cli_tmp,
		      name);
}

static char *log_of(const char *name)
{
	char dir[512];
	snprintf(dir, sizeof dir, "%s/%s/run", cli_tmp, name);
	return cli_fitness_log(dir);
}

static void same_log(const char *a, const char *b)
{
	char *la = log_of(a), *lb = log_of(b);
	CHECK(la && lb);
	if (la && lb)
		CHECK_EQ_STR(lb, la);
	free(la);
	free(lb);
}

/* One thread and two give the same log, homogeneous and heterogeneous,
 * team and own fitness. */
TEST(one_thread_and_two_give_the_same_log)
{
	static const char *const kinds[][2] = {{"HOMOGENEOUS", "TEAM"},
					       {"HETEROGENEOUS", "TEAM"},
					       {"HETEROGENEOUS", "OWN"},
					       {"HOMOGENEOUS", "OWN"}};
	for (int k = 0; k < 4; k++) {
		char a[16], b[16];
		snprintf(a, sizeof a, "t1-%d", k);
		snprintf(b, sizeof b, "t2-%d", k);
		CHECK_EQ_INT(make(a, kinds[k][0], kinds[k][1], 3, NULL), 0);
		CHECK_EQ_INT(make(b, kinds[k][0], kinds[k][1], 3, NULL), 0);
		CHECK_EQ_INT(train(a, "--threads 1"), 0);
		CHECK_EQ_INT(train(b, "--threads 2"), 0);
		same_log(a, b);
	}
	/* the log's team columns: the learning team, the share of wins */
	char *log = cli_read("%s/t1-0/run/log.csv", cli_tmp);
	CHECK(log && strstr(log, ",metric:collected,metric:team,"
				 "metric:win_rate\n"));
	free(log);
	/* own fitness differs from team fitness */
	char *t = log_of("t1-1"), *o = log_of("t1-2");
	CHECK(t && o && strcmp(t, o) != 0);
	free(t);
	free(o);
}

/* The figure after "collected " on the line that starts with `line`. */
static double collected(const char *text, const char *line)
{
	const char *l = strstr(text, line);
	const char *c = l ? strstr(l, "collected ") : NULL;
	return c ? strtod(c + strlen("collected "), NULL) : -1;
}

/* The trained team gathers more, on episodes training never saw, than
 * untrained teams: by the margin minds/Forager/README.md states for a
 * short run (at least twice as much). */
static void beats_untrained(const char *name, const char *genome, int gens,
			    const char *extra)
{
	CHECK_EQ_INT(make(name, genome, "TEAM", gens, extra), 0);
	CHECK_EQ_INT(train(name, "--threads 2"), 0);
	char *text = cli_read("%s/%s/out.txt", cli_tmp, name);
	CHECK(text != NULL);
	if (!text)
		return;
	double champ = collected(text, "  team Foragers, champion:");
	double fresh = collected(text, "  team Foragers, untrained teams");
	printf("  %s: champion team %.1f, untrained teams %.1f objects\n",
	       genome, champ, fresh);
	CHECK(champ >= 0 && fresh >= 0);
	CHECK(champ >= 2 * fresh);
	CHECK(champ > fresh + 4);
	/* docs/teams.md quotes the replay of a longer run: its lines, but
	 * for the numbers */
	static char doc[2048];
	CHECK_EQ_INT(doc_block("docs/teams.md", "tests/sim/learn/test_learn_teams.c",
			       0, doc, sizeof doc),
		     0);
	CHECK_EQ_INT(doc_lines_missing(doc, text, NULL, 1), 0);
	free(text);
}

TEST(a_trained_homogeneous_team_beats_untrained_ones)
{
	beats_untrained("homo", "HOMOGENEOUS", 8, "EVALREP:2\nPOPSIZE:40\n");
	/* a homogeneous champion is one network */
	char *c = cli_read("%s/homo/Forager/Skills/Forage/Forage.net", cli_tmp);
	char *m =
	    cli_read("%s/homo/Forager/Skills/Forage/Forage.2.net", cli_tmp);
	CHECK(c && strstr(c, "team Foragers"));
	CHECK(m == NULL);
	free(c);
	free(m);
}

TEST(a_trained_heterogeneous_team_beats_untrained_ones)
{
	/* a genome is one member: twice the genomes, for as many teams */
	beats_untrained("hetero", "HETEROGENEOUS", 10,
			"EVALREP:2\nPOPSIZE:80\n");
	/* its champion is a team: one network per member, in the run folder
	 * and in the skill's folder, which DEMO2DSIMMULTI runs member by
	 * member */
	for (int k = 1; k <= 4; k++) {
		char *r =
		    k == 1
			? cli_read("%s/hetero/run/champion.net", cli_tmp)
			: cli_read("%s/hetero/run/champion-%d.net", cli_tmp, k);
		char *s = k == 1 ? cli_read("%s/hetero/Forager/Skills/Forage/"
					    "Forage.net",
					    cli_tmp)
				 : cli_read("%s/hetero/Forager/Skills/Forage/"
					    "Forage.%d.net",
					    cli_tmp, k);
		CHECK(r && s && strcmp(r, s) == 0);
		char want[32];
		snprintf(want, sizeof want, " member %d, ", k);
		CHECK(s && strstr(s, want));
		free(r);
		free(s);
	}
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/hetero/Forager/Tasks/"
				 "Forage-DEMO.simbatch --headless --ticks 50 "
				 "--trace %s/hetero/t.trace",
				 cli_evo, cli_tmp, cli_tmp),
		     0);
	/* members 1 and 2 run other networks: on the same inputs at tick
	 * 0 they would still differ; here it is enough that the run works
	 * and a homogeneous training afterwards removes the members' */
	CHECK_CONTAINS(out, "team Foragers: reward ");
	CHECK_EQ_INT(cli_sh("sed -i 's/HETEROGENEOUS/HOMOGENEOUS/' "
			    "%s/hetero/Forager/Tasks/T.simbatch && sed -i "
			    "'s/^NUMGEN:10$/NUMGEN:1/' "
			    "%s/hetero/Forager/Tasks/T.simbatch",
			    cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_sh("%s run %s/hetero/Forager/Tasks/T.simbatch --run "
			    "%s/hetero/run2 > /dev/null 2>&1",
			    cli_evo, cli_tmp, cli_tmp),
		     0);
	char *m =
	    cli_read("%s/hetero/Forager/Skills/Forage/Forage.2.net", cli_tmp);
	CHECK(m == NULL);
	free(m);
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

/* Killed with SIGKILL after generation 2, resumed: the same log and
 * champion as the run never interrupted. */
static void kill_and_resume(const char *genome)
{
	char ref[32], name[32];
	snprintf(ref, sizeof ref, "ref-%s", genome);
	snprintf(name, sizeof name, "kill-%s", genome);
	CHECK_EQ_INT(make(ref, genome, "TEAM", 6, NULL), 0);
	CHECK_EQ_INT(make(name, genome, "TEAM", 6, NULL), 0);
	CHECK_EQ_INT(train(ref, "--threads 2"), 0);
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/%s/Forager/Tasks/T.simbatch --seed 5 "
		 "--threads 2 --run %s/%s/run > %s/%s/out1.txt 2>&1",
		 cli_evo, cli_tmp, name, cli_tmp, name, cli_tmp, name);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	struct timespec ms = {0, 1000000};
	for (int i = 0; i < 60000 && rows(name) < 3; i++)
		nanosleep(&ms, NULL);
	kill(pid, SIGKILL);
	int st;
	waitpid(pid, &st, 0);
	CHECK(WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL);
	int done = rows(name);
	CHECK(done >= 3 && done < 6);
	CHECK_EQ_INT(train(name, "--threads 2 --resume"), 0);
	same_log(ref, name);
	char *a = cli_read("%s/%s/run/champion.net", cli_tmp, ref);
	char *b = cli_read("%s/%s/run/champion.net", cli_tmp, name);
	CHECK(a && b && strcmp(a, b) == 0);
	free(a);
	free(b);
	char *said = cli_read("%s/%s/out.txt", cli_tmp, name);
	CHECK(said && strstr(said, "resuming after generation"));
	free(said);
}

TEST(a_killed_run_resumes_to_the_same_result)
{
	kill_and_resume("HOMOGENEOUS");
	kill_and_resume("HETEROGENEOUS");
}

/* A copy of minds/Pursuer and minds/Evader under <name>/, with its task
 * `task` shortened to `gens` generations of 60 networks; for the
 * co-evolution test, which checks turns and resume rather than learning,
 * to one episode of 200 ticks per network too. */
static int make_pursuit(const char *name, const char *task, int gens)
{
	int coevo = strstr(task, "COEVO") != NULL;
	return cli_sh(
	    "rm -rf %s/%s && mkdir -p %s/%s && cp -r minds/Pursuer "
	    "minds/Evader %s/%s/ && sed -i -e 's/^NUMGEN:.*/NUMGEN:%d/' "
	    "-e 's/^POPSIZE:.*/POPSIZE:60/' %s "
	    "%s/%s/Pursuer/Tasks/%s.simbatch",
	    cli_tmp, name, cli_tmp, name, cli_tmp, name, gens,
	    coevo ? "-e 's/^EVALREP:.*/EVALREP:1/' "
		    "-e 's/^TICKLIM:.*/TICKLIM:200/'"
		  : "",
	    cli_tmp, name, task);
}

static int train_pursuit(const char *name, const char *task, const char *args)
{
	return cli_sh("%s run %s/%s/Pursuer/Tasks/%s.simbatch --seed 3 --run "
		      "%s/%s/run %s > %s/%s/out.txt 2>&1",
		      cli_evo, cli_tmp, name, task, cli_tmp, name, args,
		      cli_tmp, name);
}

/* Column `col` (0-based) of each row of a log, into v; how many rows. */
static int column(const char *log, int col, double *v, int cap)
{
	int n = 0;
	const char *p = log ? strchr(log, '\n') : NULL;
	while (p && p[1] && n < cap) {
		p++;
		const char *c = p;
		for (int k = 0; k < col && c; k++) {
			c = strchr(c, ',');
			if (c)
				c++;
		}
		v[n++] = c ? strtod(c, NULL) : -1;
		p = strchr(p, '\n');
	}
	return n;
}

/* The pursuers learn against the fixed evader: the share of episodes
 * they win rises over the generations. */
TEST(the_pursuers_win_rate_rises)
{
	CHECK_EQ_INT(make_pursuit("pur", "Pursuit-NEAT", 5), 0);
	CHECK_EQ_INT(train_pursuit("pur", "Pursuit-NEAT", "--threads 2"), 0);
	char *log = cli_read("%s/pur/run/log.csv", cli_tmp);
	CHECK(log &&
	      strstr(log, "metric:caught,metric:team,metric:win_rate\n"));
	double rate[8], team[8];
	int n = column(log, 11, rate, 8);
	CHECK_EQ_INT(column(log, 10, team, 8), 5);
	CHECK_EQ_INT(n, 5);
	printf("  pursuers' win rate by generation:");
	for (int g = 0; g < n; g++)
		printf(" %.3f", rate[g]);
	printf("\n");
	if (n == 5) {
		CHECK(team[0] == 1 && team[4] == 1);
		CHECK((rate[3] + rate[4]) / 2 > rate[0]);
	}
	free(log);
	/* each generation's line says it too */
	char *said = cli_read("%s/pur/out.txt", cli_tmp);
	CHECK(said && strstr(said, "gen 4/5  best ") &&
	      strstr(said, "  Pursuers won "));
	free(said);
}

/* Co-evolution: the teams learn in turns of ALTERNATE generations, each
 * with its population; one thread and two give the same log, and a
 * killed run resumes to the same one. */
TEST(co_evolution_takes_turns_and_resumes)
{
	CHECK_EQ_INT(make_pursuit("co1", "Pursuit-COEVO", 6), 0);
	CHECK_EQ_INT(make_pursuit("co2", "Pursuit-COEVO", 6), 0);
	for (int i = 1; i <= 2; i++)
		CHECK_EQ_INT(
		    cli_sh("sed -i 's/^ALTERNATE:.*/ALTERNATE:2/' "
			   "%s/co%d/Pursuer/Tasks/Pursuit-COEVO.simbatch",
			   cli_tmp, i),
		    0);
	CHECK_EQ_INT(train_pursuit("co1", "Pursuit-COEVO", "--threads 1"), 0);
	CHECK_EQ_INT(train_pursuit("co2", "Pursuit-COEVO", "--threads 2"), 0);
	same_log("co1", "co2");
	char *log = cli_read("%s/co1/run/log.csv", cli_tmp);
	double team[8];
	CHECK_EQ_INT(column(log, 10, team, 8), 6);
	CHECK(team[0] == 1 && team[1] == 1 && team[2] == 2 && team[3] == 2 &&
	      team[4] == 1 && team[5] == 1);
	free(log);
	/* each team's champion, in the run folder and in its own mind */
	char *a = cli_read("%s/co1/run/champion-Pursuers.net", cli_tmp);
	char *b = cli_read("%s/co1/run/champion-Evaders.net", cli_tmp);
	char *c = cli_read("%s/co1/Evader/Skills/Flee/Flee.net", cli_tmp);
	CHECK(a && b && c && strcmp(b, c) == 0);
	free(a);
	free(b);
	free(c);
	/* stopped at generation 3 (the evaders' turn) and resumed */
	CHECK_EQ_INT(make_pursuit("co3", "Pursuit-COEVO", 6), 0);
	CHECK_EQ_INT(cli_sh("sed -i 's/^ALTERNATE:.*/ALTERNATE:2/' "
			    "%s/co3/Pursuer/Tasks/Pursuit-COEVO.simbatch && "
			    "sed -i 's/^NUMGEN:.*/NUMGEN:3/' "
			    "%s/co3/Pursuer/Tasks/Pursuit-COEVO.simbatch",
			    cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(train_pursuit("co3", "Pursuit-COEVO", "--threads 2"), 0);
	CHECK_EQ_INT(cli_sh("sed -i 's/^NUMGEN:.*/NUMGEN:6/' "
			    "%s/co3/Pursuer/Tasks/Pursuit-COEVO.simbatch",
			    cli_tmp),
		     0);
	/* the first part saved its champions into Skills/: put the
	 * shipped networks back, as the uninterrupted run had them */
	CHECK_EQ_INT(cli_sh("cp minds/Evader/Skills/Flee/Flee.net "
			    "%s/co3/Evader/Skills/Flee/ && cp "
			    "minds/Pursuer/Skills/Chase/Chase.net "
			    "%s/co3/Pursuer/Skills/Chase/",
			    cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(
	    train_pursuit("co3", "Pursuit-COEVO", "--threads 2 --resume"), 0);
	same_log("co1", "co3");
}

/* A co-evolution run shorter than the first team's turn: the second team
 * never learns, so the run ends normally, says so, leaves its network as
 * it was and writes no champion for it. */
TEST(a_team_without_a_turn_keeps_its_network)
{
	CHECK_EQ_INT(make_pursuit("co4", "Pursuit-COEVO", 2), 0);
	CHECK_EQ_INT(cli_sh("sed -i 's/^ALTERNATE:.*/ALTERNATE:3/' "
			    "%s/co4/Pursuer/Tasks/Pursuit-COEVO.simbatch",
			    cli_tmp),
		     0);
	CHECK_EQ_INT(train_pursuit("co4", "Pursuit-COEVO", "--threads 2"), 0);
	char *said = cli_read("%s/co4/out.txt", cli_tmp);
	CHECK(said && strstr(said, "team Evaders had no turn in 2 generations "
				   "(ALTERNATE 3)"));
	CHECK(said && strstr(said, "team Pursuers, champion:"));
	CHECK(said && !strstr(said, "team Evaders, champion:"));
	free(said);
	char *shipped = cli_read("minds/Evader/Skills/Flee/Flee.net");
	char *kept = cli_read("%s/co4/Evader/Skills/Flee/Flee.net", cli_tmp);
	CHECK(shipped && kept && strcmp(shipped, kept) == 0);
	free(shipped);
	free(kept);
	char *none = cli_read("%s/co4/run/champion-Evaders.net", cli_tmp);
	CHECK(none == NULL);
	free(none);
}

int main(void)
{
	if (cli_setup("learn-teams"))
		return 1;
	RUN(one_thread_and_two_give_the_same_log);
	RUN(a_trained_homogeneous_team_beats_untrained_ones);
	RUN(a_trained_heterogeneous_team_beats_untrained_ones);
	RUN(a_killed_run_resumes_to_the_same_result);
	RUN(the_pursuers_win_rate_rises);
	RUN(co_evolution_takes_turns_and_resumes);
	RUN(a_team_without_a_turn_keeps_its_network);
	cli_cleanup();
	return test_summary();
}

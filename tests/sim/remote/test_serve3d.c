/* `evo serve` of a 3D task (docs/remote.md), end to end on loopback:
 * `evo run` of a DEMOREMOTESIM task driving `evo serve` of a DEMO3DSIM
 * task writes the trace DEMO3DSIM writes in one process (every tick's
 * sensor values, commands and skills) and prints its rewards, for the
 * wheeled robot and for the blimp; the served world's rays read at tick 0
 * what the geometry gives by hand; `evo serve` of a remote task whose
 * environment is 3D says which task serves it; and `evo serve --can` of a
 * 3D task stands in for a robot's body as of a 2D one. */
#define _POSIX_C_SOURCE 200809L
#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "harness.h"
#include "support/cli.h"
#include "support/serve.h"

static char out[1 << 16], out2[1 << 16];

/* The test's copy of minds/MIND (without its runs), made once. */
static void copy_mind(const char *mind)
{
	cli_sh("[ -d %s/%s ] || (cp -r minds/%s %s/ && rm -rf %s/%s/Runs)",
	       cli_tmp, mind, mind, cli_tmp, cli_tmp, mind);
}

/* `evo serve TASK OPTS`, its output in LOG.serve.log, started and ready. */
static pid_t start_serve(const char *task, const char *opts, const char *log)
{
	char path[512];
	snprintf(path, sizeof path, "%s/%s.serve.log", cli_tmp, log);
	return cli_serve_start(task, opts, path);
}

/* MIND's DEMO3DSIM task TASK served under a name of the test's own, and
 * driven by a DEMOREMOTESIM task naming it (REMOTE, a file of the mind's
 * Tasks/ with its REMOTENAME replaced, or NULL: one written here running
 * SKILL): two episodes of 300 ticks, seed 5, against DEMO3DSIM of TASK. */
static void served_as_demo3dsim(const char *mind, const char *task,
				const char *remote, const char *skill)
{
	char name[64], rtask[512], dtask[512];
	snprintf(name, sizeof name, "%s-%ld", mind, (long)getpid());
	copy_mind(mind);
	snprintf(dtask, sizeof dtask, "%s/%s/Tasks/%s", cli_tmp, mind, task);
	snprintf(rtask, sizeof rtask, "%s/%s/Tasks/R-%s.simbatch", cli_tmp,
		 mind, name);
	if (remote) {
		CHECK_EQ_INT(cli_sh("sed 's/^REMOTENAME:.*/REMOTENAME:%s/' "
				    "%s/%s/Tasks/%s >%s",
				    name, cli_tmp, mind, remote, rtask),
			     0);
	} else {
		char text[256];
		snprintf(text, sizeof text,
			 "TYPE:DEMOREMOTESIM\nMASTERSKILL:%s\nTICKLIM:600\n"
			 "REMOTENAME:%s\n",
			 skill, name);
		CHECK_EQ_INT(cli_write(text, "%s", rtask), 0);
	}
	char opts[128];
	snprintf(opts, sizeof opts, "--name %s", name);
	pid_t srv = start_serve(dtask, opts, name);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s -nog --seed 5 --episodes 2 --ticks 300 "
			     "--trace %s/remote.trace",
			     cli_evo, rtask, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	char found[128];
	snprintf(found, sizeof found, "remote %s: simulator, 1 environment",
		 name);
	CHECK_CONTAINS(out, found);
	CHECK_CONTAINS(out, "episode 2: reward ");
	rc = cli_capture(out2, sizeof out2,
			 "%s run %s -nog --seed 5 --episodes 2 --ticks 300 "
			 "--trace %s/demo.trace",
			 cli_evo, dtask, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	/* the same rewards over the same ticks */
	static char a[4096], b[4096];
	cli_episode_lines(out, a, sizeof a);
	cli_episode_lines(out2, b, sizeof b);
	CHECK(a[0] != 0);
	CHECK_EQ_STR(a, b);
	/* the served world's behaviour: the bot's place in the arena */
	double bx = -1, by = -1;
	const char *beh = strstr(out, "episode 2: ");
	beh = beh ? strstr(beh, ", behaviour (") : NULL;
	CHECK(beh && sscanf(beh, ", behaviour (%lf, %lf)", &bx, &by) == 2);
	CHECK(bx >= 0 && bx <= 1 && by >= 0 && by <= 1);
	/* every tick's sensor values, commands and skills, to the bit */
	char *ta = cli_read("%s/remote.trace", cli_tmp);
	char *tb = cli_read("%s/demo.trace", cli_tmp);
	CHECK(ta && tb && strcmp(ta, tb) == 0);
	/* 5 header lines and one a tick: 2 x 300 when no episode ended
	 * sooner (DEMO3DSIM's lines say) */
	long ticks = 0, t1 = 0, t2 = 0;
	const char *e1 = strstr(out2, "episode 1: reward ");
	const char *e2 = strstr(out2, "episode 2: reward ");
	CHECK(e1 && sscanf(e1, "episode 1: reward %*f over %ld", &t1) == 1);
	CHECK(e2 && sscanf(e2, "episode 2: reward %*f over %ld", &t2) == 1);
	ticks = t1 + t2;
	CHECK(ticks > 0 && ticks <= 600);
	CHECK_EQ_INT(cli_count_lines(ta, ""), 5 + ticks);
	free(ta);
	free(tb);
	double secs;
	CHECK_EQ_INT(cli_serve_stop(srv, &secs), 0);
	CHECK(secs < 1.0);
}

TEST(a_served_wheeled_robot_runs_as_demo3dsim_does)
{
	served_as_demo3dsim("Wheeled3D", "Avoid3D-DEMO.simbatch",
			    "Avoid3D-REMOTESIM.simbatch", NULL);
}

TEST(a_served_blimp_runs_as_demo3dsim_does)
{
	served_as_demo3dsim("Blimp3D", "GoToTarget-DEMO.simbatch", NULL,
			    "GoToTarget");
}

/* A wall whose near face is 1.4 m ahead of the robot's centre, 6 m wide,
 * and the robot at the origin, heading along x. */
static const char wall_env[] =
    "local env = {}\n"
    "function env.init(scene, task)\n"
    "\tscene:box{ x = 1.45, y = 0, z = 0.2, hx = 0.05, hy = 3, hz = 0.2 }\n"
    "\tscene:bot{ x = 0, y = 0 }\n"
    "end\n"
    "return env\n";

/* Wheeled3D's rays (lua/bots/Wheeled3D.lua) leave the chassis' rim (a box
 * of half sides 0.2 and 0.15) at 0, 25, 60, 110, 180, -110, -60 and -25
 * degrees and read distance / 3 m. Against the wall above: S1 leaves at
 * x = 0.2 and meets it 1.2 m on: 0.4, Q16 26214 (26214.4). S2 and S8 leave
 * at x = 0.2 (0.2 / cos 25 < 0.15 / sin 25) and meet it 1.2 / cos 25 =
 * 1.32405 m on: 0.441350, 28924 (28924.39). S3 and S7 leave at
 * x = 0.15 / tan 60 = 0.086603 and meet it (1.4 - 0.086603) / cos 60 =
 * 2.62679 m on: 0.875598, 57383 (57383.21). S4 to S6 point back: 1,
 * 65536. The served world reads these at tick 0, before anything moves. */
TEST(the_served_3d_world_reads_its_rays_as_the_geometry_gives)
{
	char name[64], rtask[512], dtask[512];
	snprintf(name, sizeof name, "wall-%ld", (long)getpid());
	copy_mind("Wheeled3D");
	cli_sh("mkdir -p %s/Wheeled3D/Envs", cli_tmp);
	CHECK_EQ_INT(cli_write(wall_env, "%s/Wheeled3D/Envs/Wall.lua", cli_tmp),
		     0);
	snprintf(dtask, sizeof dtask, "%s/Wheeled3D/Tasks/Wall.simbatch",
		 cli_tmp);
	CHECK_EQ_INT(cli_write("TYPE:DEMO3DSIM\nBOTMODEL:Wheeled3D\n"
			       "MASTERSKILL:Avoid3D\nENV:Wall\nTICKLIM:50\n",
			       "%s", dtask),
		     0);
	snprintf(rtask, sizeof rtask, "%s/Wheeled3D/Tasks/%s.simbatch",
		 cli_tmp, name);
	char text[256];
	snprintf(text, sizeof text,
		 "TYPE:DEMOREMOTESIM\nMASTERSKILL:Avoid3D\nTICKLIM:50\n"
		 "REMOTENAME:%s\n",
		 name);
	CHECK_EQ_INT(cli_write(text, "%s", rtask), 0);
	char opts[128];
	snprintf(opts, sizeof opts, "--name %s", name);
	pid_t srv = start_serve(dtask, opts, name);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s -nog --seed 5 --ticks 3 --trace "
			     "%s/wall.trace",
			     cli_evo, rtask, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	char *t = cli_read("%s/wall.trace", cli_tmp);
	const char *want = "\n0 26214 28924 57383 65536 65536 65536 57383 "
			   "28924 | ";
	CHECK(t && strstr(t, want));
	if (t && !strstr(t, want))
		printf("  tick 0: %.60s\n", strstr(t, "\n0 ") ? strstr(t, "\n0 ") + 1 : t);
	free(t);
	double secs;
	CHECK_EQ_INT(cli_serve_stop(srv, &secs), 0);
}

/* The 2D world cannot build a 3D environment; its message is the
 * environment's, so evo serve says which world it built and which task
 * serves the 3D one. */
TEST(a_remote_task_with_a_3d_environment_is_told_which_task_serves_it)
{
	copy_mind("Wheeled3D");
	CHECK_EQ_INT(cli_write("TYPE:DEMOREMOTESIM\nBOTMODEL:Wheeled3D\n"
			       "MASTERSKILL:Avoid3D\nENV:EXP3D_Avoid\n"
			       "REMOTENAME:nowhere\n",
			       "%s/Wheeled3D/Tasks/Both.simbatch", cli_tmp),
		     0);
	int rc = cli_capture(out, sizeof out,
			     "%s serve %s/Wheeled3D/Tasks/Both.simbatch",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "EXP3D_Avoid.lua:");
	CHECK_CONTAINS(out, "/Wheeled3D/Tasks/Both.simbatch is a DEMOREMOTESIM "
			    "task, served in the 2D world; a 3D world is "
			    "served from its DEMO3DSIM or LEARN3DSIM task, "
			    "with its ENV and BOTMODEL (docs/remote.md)");
}

/* Two free UDP ports, side by side, from this process's id. */
static int udp_ports(void)
{
	for (int p = 20000 + (int)(getpid() % 2000) * 4;; p += 2) {
		if (p > 65000)
			p = 20000;
		int ok = 1;
		for (int k = 0; k < 2; k++) {
			int fd = socket(AF_INET, SOCK_DGRAM, 0);
			struct sockaddr_in sa;
			memset(&sa, 0, sizeof sa);
			sa.sin_family = AF_INET;
			sa.sin_port = htons((uint16_t)(p + k));
			sa.sin_addr.s_addr = htonl(INADDR_ANY);
			ok &= fd >= 0 &&
			      bind(fd, (struct sockaddr *)&sa, sizeof sa) == 0;
			if (fd >= 0)
				close(fd);
		}
		if (ok)
			return p;
	}
}

/* `evo serve --can` of the 3D task stands in for the robot's body over
 * cannelloni: the DEMOREMOTE run gets its 60 ticks and the episode's
 * reward (a REWARD frame, read from the 3D world), and the body stops
 * cleanly. Real time: the reward is DEMO3DSIM's only when no tick came
 * late, so it is compared then. */
TEST(serve_can_of_a_3d_task_stands_in_for_its_body)
{
	copy_mind("Wheeled3D");
	char task[512], url[128], run_url[128], opts[256];
	snprintf(task, sizeof task, "%s/Wheeled3D/Tasks/Robot.simbatch",
		 cli_tmp);
	CHECK_EQ_INT(cli_write("TYPE:DEMOREMOTE\nMASTERSKILL:Avoid3D\n"
			       "TICKLIM:1800\n",
			       "%s", task),
		     0);
	int p = udp_ports();
	snprintf(url, sizeof url, "cannelloni:127.0.0.1:%d?local=%d", p, p + 1);
	snprintf(run_url, sizeof run_url, "cannelloni:127.0.0.1:%d?local=%d",
		 p + 1, p);
	snprintf(opts, sizeof opts, "--can '%s' --tick-ms 40", url);
	char dtask[512];
	snprintf(dtask, sizeof dtask, "%s/Wheeled3D/Tasks/Avoid3D-DEMO.simbatch",
		 cli_tmp);
	pid_t body = start_serve(dtask, opts, "can");
	/* a body that died leaves evo waiting: timeout ends it */
	int rc = cli_capture(out, sizeof out,
			     "timeout 20 %s run %s -nog --seed 5 --ticks 60 "
			     "--can '%s' --trace %s/can.trace",
			     cli_evo, task, run_url, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "8 sensors and 2 actuators, names as in the "
			    "botdesc");
	CHECK_CONTAINS(out, "episode 1: reward ");
	double secs;
	CHECK_EQ_INT(cli_serve_stop(body, &secs), 0);
	char pre[256];
	unsigned long ticks = 0, in_time = 0, late = 0, unanswered = 0,
		      missing = 0;
	snprintf(pre, sizeof pre, "robot %s: ", run_url);
	const char *c = strstr(out, pre);
	c = c ? strstr(c + 1, pre) : NULL; /* the closing line, not the first */
	int parsed = c && sscanf(c + strlen(pre),
				 "%lu ticks: %lu answered in time, %lu late "
				 "(%lu unanswered), %lu missing",
				 &ticks, &in_time, &late, &unanswered,
				 &missing) == 5;
	CHECK(parsed);
	if (!parsed)
		return;
	CHECK_EQ_INT(ticks, 60);
	char *log = cli_read("%s/can.serve.log", cli_tmp);
	int undisturbed = unanswered == 0 && missing == 0 && log &&
			  strstr(log, "; 0 commands came late;");
	free(log);
	if (!undisturbed) {
		printf("  the run was disturbed (%lu late, %lu missing): its "
		       "reward is not compared\n",
		       late, missing);
		return;
	}
	rc = cli_capture(out2, sizeof out2,
			 "%s run %s -nog --seed 5 --ticks 60 --trace "
			 "%s/demo60.trace",
			 cli_evo, dtask, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	static char a[512], b[512];
	cli_episode_lines(out, a, sizeof a);
	cli_episode_lines(out2, b, sizeof b);
	CHECK(a[0] != 0);
	CHECK_EQ_STR(a, b);
	char *ta = cli_read("%s/can.trace", cli_tmp);
	char *tb = cli_read("%s/demo60.trace", cli_tmp);
	CHECK(ta && tb && strcmp(ta, tb) == 0);
	free(ta);
	free(tb);
}

int main(void)
{
	if (cli_setup("serve3d"))
		return 1;
	RUN(a_served_wheeled_robot_runs_as_demo3dsim_does);
	RUN(a_served_blimp_runs_as_demo3dsim_does);
	RUN(the_served_3d_world_reads_its_rays_as_the_geometry_gives);
	RUN(a_remote_task_with_a_3d_environment_is_told_which_task_serves_it);
	RUN(serve_can_of_a_3d_task_stands_in_for_its_body);
	cli_cleanup();
	return test_summary();
}

/* A robot over LCM (docs/remote.md, A robot: free running), end to end on
 * loopback: `evo run` of a DEMOREMOTE task driving `evo serve --robot`
 * writes the trace DEMOSIM writes; a robot killed is reported within the
 * timeout; the stand-in robot goes neutral when commands stop and follows
 * them again when they come back; a robot with other names is refused with
 * the names; late and missing ticks are counted (the test itself plays the
 * robot, tick by tick); a session recorded with lcm-logger and played back
 * with lcm-logplayer gets the very commands it got live; the robot's panel
 * is drawn without a window.
 *
 * Nothing waits a fixed time for something to happen: every wait is for a
 * line in a log or a message, with limits far above what a loaded machine
 * needs. The one fixed pause (a stopped evo left stopped for two of the
 * robot's periods) can only grow under load, which the test allows. */
#define _POSIX_C_SOURCE 200809L
#include <lcm/lcm.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "harness.h"
#include "support/doc_block.h"
#include "remote/link.h"
#include "remote/wire.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/viewer.h"

static char out[1 << 16], out2[1 << 16];

/* Two LCM URLs of this test's own, on ports of their own: other LCM
 * traffic on the machine (other tests' lockstep runs on LCM's default
 * URL) reaches every socket of a URL, and could fill a stopped evo's
 * socket buffer. */
static char test_url[96], test_url2[96];

static double mono(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void pause_ms(long ms)
{
	struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
	nanosleep(&ts, NULL);
}

/* A DEMOREMOTE task of the Avoid mind that names robot `name`, in the
 * test's copy of the mind folder; BOTMODEL and ENV for `evo serve
 * --robot`. */
static void robot_task(const char *name, const char *extra)
{
	cli_sh("[ -d %s/Avoid ] || (cp -r minds/Avoid %s/ && rm -rf "
	       "%s/Avoid/Runs)",
	       cli_tmp, cli_tmp, cli_tmp);
	char text[768];
	snprintf(text, sizeof text,
		 "TYPE:DEMOREMOTE\nBOTMODEL:BotType8\nMASTERSKILL:Avoid\n"
		 "ENV:Roam\nTICKLIM:15000\nREMOTENAME:%s\nLCMURL:%s\n%s",
		 name, test_url, extra);
	cli_write(text, "%s/Avoid/Tasks/%s.simbatch", cli_tmp, name);
}

/* `sh -c "exec CMD"`, with SIGINT and SIGTERM at their defaults. */
static pid_t spawn(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static pid_t spawn(const char *fmt, ...)
{
	char cmd[2048];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(cmd, sizeof cmd, fmt, ap);
	va_end(ap);
	pid_t pid = fork();
	if (pid == 0) {
		signal(SIGINT, SIG_DFL);
		signal(SIGTERM, SIG_DFL);
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	return pid;
}

/* Wait until the file holds mark (at most `limit` seconds): 1, else 0. */
static int wait_mark(const char *path, const char *mark, double limit)
{
	double end = mono() + limit;
	for (;;) {
		char *t = cli_read("%s", path);
		int found = t && strstr(t, mark);
		free(t);
		if (found)
			return 1;
		if (mono() > end)
			return 0;
		pause_ms(2);
	}
}

/* Wait for pid to end, at most `limit` seconds, then SIGKILL it. Its exit
 * status, or -1 when it did not exit by itself. */
static int reap(pid_t pid, double limit)
{
	double end = mono() + limit;
	int st = 0;
	while (waitpid(pid, &st, WNOHANG) != pid) {
		if (mono() > end) {
			kill(pid, SIGKILL);
			waitpid(pid, &st, 0);
			return -1;
		}
		pause_ms(2);
	}
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* Stop pid (SIGSTOP) and wait until every thread of it has stopped: a
 * message sent after this is not read before SIGCONT. 1, or 0. */
static int stop_now(pid_t pid)
{
	int st = 0;
	kill(pid, SIGSTOP);
	return waitpid(pid, &st, WUNTRACED) == pid && WIFSTOPPED(st);
}

/* Signal pid and reap it: its exit status; *secs, how long it took. */
static int stop_with(pid_t pid, int sig, double *secs)
{
	double t0 = mono();
	kill(pid, sig);
	int rc = reap(pid, 10);
	*secs = mono() - t0;
	return rc;
}

/* `evo serve TASK --robot` of robot `name`, started and ready; its output
 * in NAME.serve.log. */
static pid_t start_robot(const char *name, const char *opts)
{
	pid_t pid = spawn("exec %s serve %s/Avoid/Tasks/%s.simbatch --robot "
			  "--name %s %s >%s/%s.serve.log 2>&1",
			  cli_evo, cli_tmp, name, name, opts, cli_tmp, name);
	char log[512];
	snprintf(log, sizeof log, "%s/%s.serve.log", cli_tmp, name);
	wait_mark(log, " serves ", 60);
	return pid;
}

/* The counts of evo's closing line for the robot. */
typedef struct counts {
	unsigned long ticks, in_time, late, unanswered, missing;
} counts;

static int robot_counts(const char *text, const char *name, counts *c)
{
	char pre[128];
	snprintf(pre, sizeof pre, "\nrobot %s: ", name);
	memset(c, 0, sizeof *c);
	for (const char *p = text ? strstr(text, pre) : NULL; p;
	     p = strstr(p + 1, pre))
		if (sscanf(p + strlen(pre),
			   "%lu ticks: %lu answered in time, %lu late (%lu "
			   "unanswered), %lu missing",
			   &c->ticks, &c->in_time, &c->late, &c->unanswered,
			   &c->missing) == 5)
			return 1;
	if (getenv("TEST_ROBOT_SHOW"))
		printf("---- evo said:\n%s----\n", text ? text : "(nothing)");
	return 0;
}

/* ---- against `evo serve --robot` ----------------------------------------- */

/* A real-time run is disturbed when the machine stalls one of its
 * processes for longer than a period: a command then misses its tick, by
 * design. Such a run proves nothing either way; the tests that compare
 * runs make up to this many, and fail when none ran undisturbed. */
#define ATTEMPTS 3

/* docs/remote.md quotes an undisturbed pair run as its sh block runs it
 * (Avoid-ROBOT, --seed 3 --ticks 300, 33.333 ms): its lines are this
 * pair's (robot `name`, evo serve's log `log`) but for the numbers, which
 * differ with the period and the ticks; and its episode line is
 * DEMOSIM's for that seed and ticks, which an undisturbed robot's is. */
static void doc_quotes_the_pair(const char *name, const char *log)
{
	static char doc[2048], demo[4096];
	const char *me = "tests/sim/remote/test_robot.c";
	CHECK_EQ_INT(doc_block("docs/remote.md", me, 0, doc, sizeof doc), 0);
	{
		const char *sub[] = {"avoid-bot", name, NULL};
		CHECK_EQ_INT(doc_lines_missing(doc, out, sub, 1), 0);
	}
	CHECK_EQ_INT(cli_capture(demo, sizeof demo,
				 "%s run minds/Avoid/Tasks/Avoid-DEMO.simbatch "
				 "-nog --seed 3 --ticks 300",
				 cli_evo),
		     0);
	const char *ep = strstr(doc, "episode 1: reward ");
	CHECK(ep != NULL);
	if (ep) {
		char line[160];
		snprintf(line, sizeof line, "%.*s, 0 collision ticks\n",
			 (int)strcspn(ep, "\n"), ep);
		CHECK_CONTAINS(demo, line);
	}
	char *t = cli_read("%s", log);
	CHECK_EQ_INT(doc_block("docs/remote.md", me, 1, doc, sizeof doc), 0);
	{
		const char *sub[] = {"avoid-bot", name, NULL};
		CHECK_EQ_INT(doc_lines_missing(doc, t ? t : "", sub, 1), 0);
	}
	free(t);
}

/* The robot applies each tick's command before it steps and starts its
 * world from evo's seeds: with every command in its period, the mind sees
 * what it sees in DEMOSIM, tick for tick. */
TEST(a_robot_runs_as_demosim_does)
{
	char name[64], log[512], want[160];
	snprintf(name, sizeof name, "robot-%ld", (long)getpid());
	snprintf(log, sizeof log, "%s/%s.serve.log", cli_tmp, name);
	robot_task(name, "");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/Avoid/Tasks/%s.simbatch", cli_evo,
				 cli_tmp, name),
		     0);
	CHECK_EQ_INT(cli_capture(out2, sizeof out2,
				 "%s run minds/Avoid/Tasks/Avoid-DEMO.simbatch "
				 "-nog --seed 5 --ticks 90 --trace "
				 "%s/demo.trace",
				 cli_evo, cli_tmp),
		     0);
	/* DEMOSIM's episode line, but for the collision count */
	const char *line = strstr(out2, "episode 1: reward ");
	const char *end = line ? strstr(line, " ticks") : NULL;
	CHECK(line && end);
	if (!line || !end)
		return;
	char episode[160];
	snprintf(episode, sizeof episode, "%.*s ticks\n", (int)(end - line),
		 line);
	int undisturbed = 0;
	for (int a = 1; a <= ATTEMPTS && !undisturbed; a++) {
		pid_t rob = start_robot(name, "--tick-ms 60");
		int rc = cli_capture(out, sizeof out,
				     "%s run %s/Avoid/Tasks/%s.simbatch -nog "
				     "--seed 5 --ticks 90 --trace "
				     "%s/robot.trace",
				     cli_evo, cli_tmp, name, cli_tmp);
		CHECK_EQ_INT(rc, 0);
		snprintf(want, sizeof want,
			 "remote %s: robot, a tick every 60.000 ms", name);
		CHECK_CONTAINS(out, want);
		/* evo's STOP reached the robot, which went neutral (at tick
		 * 90 when undisturbed: a robot held up goes on ticking) */
		CHECK(wait_mark(log, "evo stopped episode 1 at tick ", 10));
		double secs;
		CHECK_EQ_INT(stop_with(rob, SIGTERM, &secs), 0);
		CHECK(secs < 1.0);
		counts c;
		CHECK(robot_counts(out, name, &c));
		char *t = cli_read("%s", log);
		CHECK_CONTAINS(t, "commanded in time");
		undisturbed = c.unanswered == 0 && c.missing == 0 && t &&
			      strstr(t, "; 0 commands came late;");
		if (undisturbed) {
			CHECK_EQ_INT(c.ticks, 90);
			CHECK_CONTAINS(t, "evo stopped episode 1 at tick 90: "
					  "every actuator neutral");
		}
		if (!undisturbed)
			printf("  attempt %d disturbed: evo %lu late (%lu "
			       "unanswered), %lu missing; the robot: %s",
			       a, c.late, c.unanswered, c.missing,
			       t && strstr(t, "ticks: ") ? strstr(t, "ticks: ")
							 : "(no report)\n");
		free(t);
	}
	CHECK(undisturbed);
	if (!undisturbed)
		return;
	CHECK_CONTAINS(out, episode);
	doc_quotes_the_pair(name, log);
	char *ta = cli_read("%s/robot.trace", cli_tmp);
	char *tb = cli_read("%s/demo.trace", cli_tmp);
	CHECK(ta && tb && strcmp(ta, tb) == 0);
	CHECK_EQ_INT(cli_count_lines(ta, ""), 5 + 90);
	free(ta);
	free(tb);
}

/* An episode the robot ends lasts TICKLIM ticks, as DEMOSIM's (and over
 * CAN, tests/sim/remote/test_can_robot.c): with TICKLIM 60 and no --ticks
 * both sides said 61 ticks. Undisturbed, the reward is DEMOSIM's too. */
TEST(the_robot_ends_an_episode_at_ticklim_as_demosim_does)
{
	char name[64], log[512], text[512];
	snprintf(name, sizeof name, "lim-%ld", (long)getpid());
	snprintf(log, sizeof log, "%s/%s.serve.log", cli_tmp, name);
	robot_task(name, ""); /* the mind folder's copy */
	snprintf(text, sizeof text,
		 "TYPE:DEMOREMOTE\nBOTMODEL:BotType8\nMASTERSKILL:Avoid\n"
		 "ENV:Roam\nTICKLIM:60\nREMOTENAME:%s\nLCMURL:%s\n",
		 name, test_url);
	cli_write(text, "%s/Avoid/Tasks/%s.simbatch", cli_tmp, name);
	cli_write("TYPE:DEMOSIM\nBOTMODEL:BotType8\nMASTERSKILL:Avoid\n"
		  "ENV:Roam\nTICKLIM:60\n",
		  "%s/Avoid/Tasks/Sim60.simbatch", cli_tmp);
	CHECK_EQ_INT(cli_capture(out2, sizeof out2,
				 "%s run %s/Avoid/Tasks/Sim60.simbatch -nog "
				 "--seed 5",
				 cli_evo, cli_tmp),
		     0);
	char sim_line[200] = "";
	const char *l = strstr(out2, "episode 1: reward ");
	const char *end = l ? strstr(l, " ticks") : NULL;
	CHECK(end != NULL);
	if (end)
		snprintf(sim_line, sizeof sim_line, "%.*s ticks\n",
			 (int)(end - l), l);
	CHECK_CONTAINS(sim_line, " over 60 ticks\n");
	int undisturbed = 0;
	for (int a = 1; a <= ATTEMPTS && !undisturbed; a++) {
		pid_t rob = start_robot(name, "--tick-ms 30");
		CHECK_EQ_INT(cli_capture(out, sizeof out,
					 "%s run %s/Avoid/Tasks/%s.simbatch "
					 "-nog --seed 5",
					 cli_evo, cli_tmp, name),
			     0);
		CHECK_CONTAINS(out, " over 60 ticks\n");
		CHECK(wait_mark(log, "episode 1 ended at tick 60: ", 10));
		double secs;
		CHECK_EQ_INT(stop_with(rob, SIGTERM, &secs), 0);
		counts c;
		CHECK(robot_counts(out, name, &c));
		CHECK_EQ_INT(c.ticks, 60);
		undisturbed = c.unanswered == 0 && c.missing == 0 && c.late == 0;
	}
	if (undisturbed)
		CHECK_CONTAINS(out, sim_line);
}

TEST(killing_the_robot_is_reported_within_the_timeout)
{
	char name[64], evlog[512], rlog[512];
	snprintf(name, sizeof name, "killed-%ld", (long)getpid());
	robot_task(name, "REMOTETIMEOUT:0.5\n");
	snprintf(evlog, sizeof evlog, "%s/%s.evo.log", cli_tmp, name);
	snprintf(rlog, sizeof rlog, "%s/%s.serve.log", cli_tmp, name);
	/* its episodes on the URL itself, where the test listens */
	pid_t rob = start_robot(name, "--tick-ms 20 --data-url same");
	/* the robot is killed once evo answers it: its ticks are coming */
	evo_err err;
	char ch[128];
	snprintf(ch, sizeof ch, "EVO_%s_COMMAND", name);
	evo_link *l = evo_link_open(test_url, &err);
	CHECK(l && evo_link_subscribe(l, ch, &err) == 0);
	pid_t ev = spawn("exec %s run %s/Avoid/Tasks/%s.simbatch -nog >%s 2>&1",
			 cli_evo, cli_tmp, name, evlog);
	int answered = 0;
	double limit = mono() + 60;
	while (l && !answered && mono() < limit) {
		evo_link_msg m;
		answered = evo_link_next(l, 50, &m, &err) > 0;
	}
	CHECK(answered);
	evo_link_close(l);
	double t0 = mono();
	kill(rob, SIGKILL);
	reap(rob, 10);
	CHECK(wait_mark(evlog, "silent for", 30));
	double dt = mono() - t0;
	/* said once the timeout has passed since the robot's last tick
	 * (at most one 20 ms period before the kill), and soon after */
	CHECK(dt > 0.45);
	CHECK(dt < 0.5 + 1.5);
	char *t = cli_read("%s", evlog);
	char want[200];
	snprintf(want, sizeof want, "evo: robot %s silent for 0.", name);
	CHECK_CONTAINS(t, want);
	CHECK_CONTAINS(t, "waiting (Ctrl-C stops); a robot goes neutral on "
			  "its own");
	free(t);
	double secs;
	CHECK_EQ_INT(stop_with(ev, SIGTERM, &secs), 0);
	CHECK(secs < 1.0);
	t = cli_read("%s", evlog);
	CHECK_CONTAINS(t, "episode 1: reward ");
	counts c;
	CHECK(robot_counts(t, name, &c));
	CHECK(c.ticks > 0);
	free(t);
}

/* evo stopped (SIGSTOP) longer than the robot's timeout: the robot goes
 * neutral on its own and says so; evo let go on (SIGCONT) answers the
 * newest tick, counts the ones it holds too old as late, and the robot
 * follows its commands again; SIGTERM ends evo, whose STOP makes the
 * robot neutral. */
TEST(the_robot_goes_neutral_when_commands_stop_and_follows_them_again)
{
	char name[64], evlog[512], rlog[512];
	snprintf(name, sizeof name, "quiet-%ld", (long)getpid());
	robot_task(name, "");
	snprintf(evlog, sizeof evlog, "%s/%s.evo.log", cli_tmp, name);
	snprintf(rlog, sizeof rlog, "%s/%s.serve.log", cli_tmp, name);
	pid_t rob = start_robot(name, "--tick-ms 20 --timeout 0.3");
	pid_t ev = spawn("exec %s run %s/Avoid/Tasks/%s.simbatch -nog >%s 2>&1",
			 cli_evo, cli_tmp, name, evlog);
	CHECK(wait_mark(rlog, "episode 1 starts", 60));
	CHECK(stop_now(ev));
	CHECK(wait_mark(rlog, "every actuator neutral", 30));
	/* "no command for 0.32 s, at tick 16: every actuator neutral" */
	char *t = cli_read("%s", rlog);
	double quiet = 0;
	int said = 0;
	for (const char *p = t ? strstr(t, "no command for ") : NULL;
	     p && !said; p = strstr(p + 1, "no command for "))
		said = sscanf(p, "no command for %lf s", &quiet) == 1;
	CHECK(said);
	CHECK(quiet >= 0.3);
	free(t);
	kill(ev, SIGCONT);
	CHECK(wait_mark(rlog, "commands again at tick ", 30));
	double secs;
	CHECK_EQ_INT(stop_with(ev, SIGTERM, &secs), 0);
	CHECK(secs < 1.0);
	CHECK(wait_mark(rlog, "evo stopped episode 1", 10));
	t = cli_read("%s", evlog);
	counts c;
	CHECK(robot_counts(t, name, &c));
	/* what came while evo was stopped was old when it read it */
	CHECK(c.late >= 2);
	CHECK_EQ_INT(c.missing, 0);
	CHECK_CONTAINS(t, "later late ticks are counted");
	free(t);
	CHECK_EQ_INT(stop_with(rob, SIGTERM, &secs), 0);
	t = cli_read("%s", rlog);
	CHECK_CONTAINS(t, " neutral; ");
	CHECK(!strstr(t, " 0 neutral; "));
	free(t);
}

/* The robot's frame, drawn without a window at the end of the run. */
TEST(the_robot_panel_is_drawn_without_a_window)
{
	char name[64], png[512];
	snprintf(name, sizeof name, "panel-%ld", (long)getpid());
	robot_task(name, "");
	snprintf(png, sizeof png, "%s/panel.png", cli_tmp);
	pid_t rob = start_robot(name, "--tick-ms 20");
	int rc =
	    cli_capture(out, sizeof out,
			"%s run %s/Avoid/Tasks/%s.simbatch -nog --ticks 20 "
			"--screenshot %s",
			cli_evo, cli_tmp, name, png);
	CHECK_EQ_INT(rc, 0);
	/* tick 19 but where a loaded machine held evo up past tick 20 */
	const char *shot = strstr(out, "(tick ");
	long shot_tick = -1;
	CHECK(shot && sscanf(shot, "(tick %ld, drawn without a window)",
			     &shot_tick) == 1);
	CHECK(shot_tick >= 19);
	evo_png_image im;
	evo_err err;
	CHECK_EQ_INT(evo_png_read(png, &im, &err), 0);
	CHECK_EQ_INT(im.w, 1024);
	CHECK_EQ_INT(im.h, 720);
	int live = 0, sensor = 0, actuator = 0, skill = 0;
	for (int i = 0; im.pixels && i < im.w * im.h; i++) {
		const uint8_t *q = im.pixels + (size_t)i * im.channels;
		uint32_t c = (uint32_t)q[0] << 16 | (uint32_t)q[1] << 8 | q[2];
		live += c == EVO_VIEW_LINK_OK;
		sensor += c == EVO_VIEW_SENSOR_BAR;
		actuator += c == EVO_VIEW_ACTUATOR_BAR;
		skill += c == EVO_VIEW_BAR;
	}
	CHECK(live > 100);
	CHECK(sensor > 100);
	CHECK(actuator > 100);
	CHECK(skill > 100); /* the master skill, influence 1 */
	evo_png_image_free(&im);
	double secs;
	CHECK_EQ_INT(stop_with(rob, SIGTERM, &secs), 0);
}

TEST(serve_refuses_robot_options_that_do_not_fit)
{
	char name[64];
	snprintf(name, sizeof name, "opts-%ld", (long)getpid());
	robot_task(name, "");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s serve %s/Avoid/Tasks/%s.simbatch "
				 "--tick-ms 20",
				 cli_evo, cli_tmp, name),
		     2);
	CHECK_CONTAINS(out, "--tick-ms is for a robot (--robot)");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s serve %s/Avoid/Tasks/%s.simbatch --robot "
				 "--environments 2",
				 cli_evo, cli_tmp, name),
		     2);
	CHECK_CONTAINS(out, "a robot runs one environment");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s serve %s/Avoid/Tasks/%s.simbatch --robot "
				 "--timeout 0",
				 cli_evo, cli_tmp, name),
		     2);
	CHECK_CONTAINS(out, "--timeout expects seconds");
}

/* ---- the test as the robot ---------------------------------------------- */

static const char *avoid_sensors[] = {"S1", "S2", "S3", "S4",  "S5", "S6",
				      "S7", "S8", "S9", "S10", "DOF"};

typedef struct fake {
	evo_link *l;
	char ch_control[96], ch_command[96], ch_sensors[96];
	evo_wire_hello h;
	unsigned char buf[EVO_WIRE_MAX_BYTES];
	int64_t episode;
	double reset_at; /* when the RESET came (monotonic seconds) */
} fake;

static int fake_open(fake *f, const char *url, const char *name,
		     int32_t tick_us, int other_names)
{
	evo_err err;
	memset(f, 0, sizeof *f);
	f->l = evo_link_open(url, &err);
	snprintf(f->ch_control, sizeof f->ch_control, "EVO_%s_CONTROL", name);
	snprintf(f->ch_command, sizeof f->ch_command, "EVO_%s_COMMAND", name);
	snprintf(f->ch_sensors, sizeof f->ch_sensors, "EVO_%s_SENSORS", name);
	if (!f->l || evo_link_subscribe(f->l, "EVO_WHO", &err) ||
	    evo_link_subscribe(f->l, f->ch_control, &err) ||
	    evo_link_subscribe(f->l, f->ch_command, &err))
		return -1;
	evo_wire_hello *h = &f->h;
	h->protocol = EVO_WIRE_PROTOCOL;
	h->session = 4242;
	h->kind = EVO_REMOTE_ROBOT;
	h->environments = 1;
	h->tick_us = tick_us;
	h->n_sensors = 11;
	h->n_actuators = 2;
	snprintf(h->name, sizeof h->name, "%s", name);
	for (int i = 0; i < 11; i++)
		snprintf(h->sensor[i], EVO_NAME_MAX, "%s", avoid_sensors[i]);
	snprintf(h->actuator[0], EVO_NAME_MAX, "MotL");
	snprintf(h->actuator[1], EVO_NAME_MAX, "MotR");
	if (other_names) {
		snprintf(h->sensor[9], EVO_NAME_MAX, "S11");
		snprintf(h->actuator[1], EVO_NAME_MAX, "Claw");
	}
	return 0;
}

static void fake_publish(fake *f, const char *ch, int n)
{
	evo_err err;
	if (n > 0)
		evo_link_publish(f->l, ch, f->buf, (size_t)n, &err);
}

static void fake_hello(fake *f)
{
	fake_publish(f, "EVO_HELLO",
		     evo_wire_encode_hello(&f->h, f->buf, sizeof f->buf));
}

/* Answer who_t with the hello, until a control_t of op comes (at most
 * 60 s): 1, with its episode kept, or 0. */
static int fake_await_control(fake *f, int op)
{
	double end = mono() + 60;
	while (mono() < end) {
		evo_link_msg m;
		evo_err err;
		if (evo_link_next(f->l, 50, &m, &err) <= 0)
			continue;
		if (strcmp(m.channel, "EVO_WHO") == 0) {
			fake_hello(f);
			continue;
		}
		evo_wire_control c;
		char why[256];
		if (strcmp(m.channel, f->ch_control) == 0 &&
		    evo_wire_decode_control(m.data, m.len, &c, why,
					    sizeof why) == 0 &&
		    (int)c.op == op) {
			f->episode = c.episode;
			f->reset_at = mono();
			return 1;
		}
	}
	return 0;
}

static void fake_sensors(fake *f, int64_t episode, int64_t tick, double s1,
			 double reward)
{
	evo_wire_sensors s = {.session = f->h.session,
			      .episode = episode,
			      .tick = tick,
			      .n = 11,
			      .reward = reward};
	snprintf(s.name, sizeof s.name, "%s", f->h.name);
	for (int i = 0; i < 11; i++)
		s.value[i] = 0.5;
	s.value[0] = s1;
	fake_publish(f, f->ch_sensors,
		     evo_wire_encode_sensors(&s, f->buf, sizeof f->buf));
}

/* A robot sends tick t no sooner than t periods after the RESET: wait
 * until t - 1 of them have passed (evo allows a tick and 1% of slack). */
static void pace(const fake *f, int64_t tick)
{
	double at = f->reset_at + (double)(tick - 1) * f->h.tick_us * 1e-6;
	while (mono() < at)
		pause_ms(5);
}

/* Wait for the command_t of `tick` (at most 60 s): 1, or 0; the ticks of
 * the commands that came before it are added to *others. */
static int fake_await_command(fake *f, int64_t tick, int *others)
{
	double end = mono() + 60;
	while (mono() < end) {
		evo_link_msg m;
		evo_err err;
		if (evo_link_next(f->l, 50, &m, &err) <= 0)
			continue;
		evo_wire_command c;
		char why[256];
		if (strcmp(m.channel, f->ch_command) != 0 ||
		    evo_wire_decode_command(m.data, m.len, &c, why, sizeof why))
			continue;
		if (c.tick == tick)
			return 1;
		(*others)++;
	}
	return 0;
}

/* Ticks 0, 1, 4 (2 and 3 never sent), then 5, 6, 7 sent while evo is
 * stopped and read by it two periods later, 8 with a value out of range,
 * 9, 10, 11, and 12 for the reward; evo answers 0 to 11 (--ticks 12). A
 * tick of an earlier run of episode 1, far past what the robot could have
 * reached since evo's RESET, is dropped as stale: before the first tick
 * and after it (tick 900 between 1 and 4; held, it would have made every
 * true tick after it stale). Each tick is sent no sooner than the robot
 * could have reached it. */
TEST(late_and_missing_ticks_are_counted)
{
	char name[64], evlog[512];
	snprintf(name, sizeof name, "counted-%ld", (long)getpid());
	robot_task(name, "");
	snprintf(evlog, sizeof evlog, "%s/%s.evo.log", cli_tmp, name);
	fake f;
	CHECK_EQ_INT(fake_open(&f, test_url, name, 200000, 0), 0);
	if (!f.l)
		return;
	fake_hello(&f);
	pid_t ev = spawn("exec %s run %s/Avoid/Tasks/%s.simbatch -nog --ticks "
			 "12 >%s 2>&1",
			 cli_evo, cli_tmp, name, evlog);
	CHECK(fake_await_control(&f, EVO_CONTROL_RESET));
	int64_t e = f.episode;
	CHECK_EQ_INT(e, 1);
	int others = 0;
	fake_sensors(&f, e, 500, 0.5, 0);
	fake_sensors(&f, e, 0, 0.5, 0);
	CHECK(fake_await_command(&f, 0, &others));
	fake_sensors(&f, e, 1, 0.5, 0);
	CHECK(fake_await_command(&f, 1, &others));
	fake_sensors(&f, e, 900, 0.5, 0);
	pace(&f, 4);
	fake_sensors(&f, e, 4, 0.5, 0);
	CHECK(fake_await_command(&f, 4, &others));
	CHECK(stop_now(ev));
	pace(&f, 7);
	fake_sensors(&f, e, 5, 0.5, 0);
	fake_sensors(&f, e, 6, 0.5, 0);
	fake_sensors(&f, e, 7, 0.5, 0);
	pause_ms(400); /* two of the robot's 200 ms periods, or more */
	kill(ev, SIGCONT);
	CHECK(fake_await_command(&f, 7, &others));
	pace(&f, 9);
	fake_sensors(&f, e, 8, 1.5, 0);
	fake_sensors(&f, e, 9, 0.5, 0);
	CHECK(fake_await_command(&f, 9, &others));
	for (int t = 10; t < 12; t++) {
		pace(&f, t);
		fake_sensors(&f, e, t, 0.5, 0);
		CHECK(fake_await_command(&f, t, &others));
	}
	pace(&f, 12);
	fake_sensors(&f, e, 12, 0.5, 3.25);
	CHECK(fake_await_control(&f, EVO_CONTROL_STOP));
	CHECK(others <= 2); /* at most the answers to 5 and 6 */
	CHECK_EQ_INT(reap(ev, 30), 0);
	char *t = cli_read("%s", evlog);
	CHECK_CONTAINS(t, "episode 1: reward 3.250000 over 12 ticks");
	counts c;
	CHECK(robot_counts(t, name, &c));
	CHECK_EQ_INT(c.ticks, 12);
	CHECK_EQ_INT(c.missing, 3);
	/* 5, 6 and 7 are late; which of them evo answered, and which it
	 * could tell late from the time of its own sensors or only from the
	 * next one's, depends on when LCM's reader thread took them once evo
	 * went on (it stamps the first one then) */
	CHECK(c.late >= 2);
	CHECK_EQ_INT(c.in_time + c.late, 9);
	CHECK_CONTAINS(t, "tick 4 came after tick 1: 2 ticks missing");
	CHECK_CONTAINS(t, "dropped 3 messages (1 value, 2 stale)");
	CHECK_CONTAINS(t, "the robot cannot have reached it since evo's RESET");
	free(t);
	evo_link_close(f.l);
}

TEST(a_robot_with_other_names_is_refused_with_them)
{
	char name[64];
	snprintf(name, sizeof name, "names-%ld", (long)getpid());
	robot_task(name, "");
	pid_t pid = fork();
	if (pid == 0) {
		fake f;
		if (fake_open(&f, test_url, name, 33333, 1))
			_exit(3);
		fake_hello(&f);
		fake_await_control(&f, EVO_CONTROL_STOP); /* until killed */
		_exit(0);
	}
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog", cli_evo,
			     cli_tmp, name);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "does not fit Avoid.botdesc; it lacks the sensors "
			    "S10; it has the extra sensors S11; it lacks the "
			    "actuators MotR; it has the extra actuators Claw");
	kill(pid, SIGKILL);
	reap(pid, 10);
}

/* ---- recording and replay --------------------------------------------- */

/* Publish probes on url until the log file has bytes: lcm-logger is then
 * listening. 1, or 0 after 60 s. */
static int logger_ready(const char *url, const char *log)
{
	evo_err err;
	evo_link *l = evo_link_open(url, &err);
	if (!l)
		return 0;
	double end = mono() + 60;
	int ok = 0;
	while (!ok && mono() < end) {
		evo_link_publish(l, "TEST_PROBE", "probe", 5, &err);
		pause_ms(20);
		FILE *fp = fopen(log, "rb");
		if (fp) {
			fseek(fp, 0, SEEK_END);
			ok = ftell(fp) > 0;
			fclose(fp);
		}
	}
	evo_link_close(l);
	return ok;
}

/* The command_t of channel ch in an LCM log, as text, one per line. */
static int log_commands(const char *path, const char *ch, char *text,
			size_t cap)
{
	lcm_eventlog_t *log = lcm_eventlog_create(path, "r");
	if (!log)
		return -1;
	size_t k = 0;
	int n = 0;
	text[0] = 0;
	lcm_eventlog_event_t *ev;
	while ((ev = lcm_eventlog_read_next_event(log))) {
		evo_wire_command c;
		char why[256];
		if (strcmp(ev->channel, ch) == 0 &&
		    evo_wire_decode_command(ev->data, ev->datalen, &c, why,
					    sizeof why) == 0 &&
		    k < cap) {
			k += (size_t)snprintf(
			    text + k, cap - k,
			    "%lld %lld %lld:", (long long)c.session,
			    (long long)c.episode, (long long)c.tick);
			for (unsigned j = 0; j < c.n && k < cap; j++)
				k += (size_t)snprintf(text + k, cap - k, " %a",
						      c.value[j]);
			if (k < cap)
				k += (size_t)snprintf(text + k, cap - k, "\n");
			n++;
		}
		lcm_eventlog_free_event(ev);
	}
	lcm_eventlog_destroy(log);
	return n;
}

/* A DEMOREMOTE session of robot `name` against `evo serve --robot` on
 * test_url, recorded by lcm-logger into log; evo's counts in *c. */
static void record(const char *name, const char *log, counts *c)
{
	pid_t lg = spawn("exec lcm-logger -q --flush-interval=10 "
			 "--lcm-url='%s' -f %s >%s/logger1.out 2>&1",
			 test_url, log, cli_tmp);
	CHECK(logger_ready(test_url, log));
	/* lcm-logger records one URL: the robot runs its episodes on it */
	pid_t rob = start_robot(name, "--tick-ms 100 --data-url same");
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog --seed 3 "
			     "--ticks 40 --trace %s/live.trace",
			     cli_evo, cli_tmp, name, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK(robot_counts(out, name, c));
	double secs;
	CHECK_EQ_INT(stop_with(rob, SIGTERM, &secs), 0);
	stop_with(lg, SIGINT, &secs);
}

/* The robot's hello and sensors of log played back by lcm-logplayer on
 * test_url2, where evo runs task `replay` (which names the same robot);
 * what evo sends there recorded by lcm-logger into log2; evo's counts in
 * *c. evo must listen before the log's hello is played: the test waits
 * for its who_t. */
static void replay(const char *name, const char *replay_task, const char *log,
		   const char *log2, counts *c)
{
	pid_t lg2 = spawn("exec lcm-logger -q --flush-interval=10 "
			  "--lcm-url='%s' -f %s >%s/logger2.out 2>&1",
			  test_url2, log2, cli_tmp);
	CHECK(logger_ready(test_url2, log2));
	evo_err err;
	evo_link *l = evo_link_open(test_url2, &err);
	CHECK(l && evo_link_subscribe(l, "EVO_WHO", &err) == 0);
	pid_t ev = spawn("exec %s run %s/Avoid/Tasks/%s.simbatch -nog --seed 3 "
			 "--ticks 40 --trace %s/replay.trace >%s/replay.out "
			 "2>&1",
			 cli_evo, cli_tmp, replay_task, cli_tmp, cli_tmp);
	int heard = 0;
	double end = mono() + 60;
	while (l && !heard && mono() < end) {
		evo_link_msg m;
		heard = evo_link_next(l, 50, &m, &err) > 0 &&
			strcmp(m.channel, "EVO_WHO") == 0;
	}
	CHECK(heard);
	evo_link_close(l);
	CHECK_EQ_INT(cli_sh("lcm-logplayer --lcm-url='%s' -e "
			    "'^(EVO_HELLO|EVO_%s_SENSORS)$' %s >%s/player.out "
			    "2>&1",
			    test_url2, name, log, cli_tmp),
		     0);
	CHECK_EQ_INT(reap(ev, 30), 0);
	/* what the logger has from evo is on disk within 10 ms; it ends on
	 * SIGINT */
	pause_ms(50);
	double secs;
	stop_with(lg2, SIGINT, &secs);
	char *t = cli_read("%s/replay.out", cli_tmp);
	CHECK(robot_counts(t, name, c));
	free(t);
}

/* A DEMOREMOTE session recorded with lcm-logger, the robot's side of it
 * played back with lcm-logplayer to another evo: that evo sends the very
 * commands of the live session, and writes the same trace. Undisturbed
 * runs only (ATTEMPTS): a tick unanswered or missing in either changes
 * what the mind saw. */
TEST(a_recorded_session_replays_to_the_same_commands)
{
	if (cli_sh("command -v lcm-logger >/dev/null && command -v "
		   "lcm-logplayer >/dev/null") != 0) {
		CHECK(!"lcm-logger and lcm-logplayer (Debian's liblcm-bin) "
		       "are needed");
		return;
	}
	char name[64], replay_task[128], text[512];
	snprintf(name, sizeof name, "rec-%ld", (long)getpid());
	robot_task(name, "");
	/* evo's side of the same robot, on the other URL: a remote task
	 * needs no BOTMODEL or ENV */
	snprintf(replay_task, sizeof replay_task, "%s-replay", name);
	snprintf(text, sizeof text,
		 "TYPE:DEMOREMOTE\nMASTERSKILL:Avoid\nREMOTENAME:%s\n"
		 "LCMURL:%s\n",
		 name, test_url2);
	cli_write(text, "%s/Avoid/Tasks/%s.simbatch", cli_tmp, replay_task);
	char log1[512], log2[512];
	snprintf(log1, sizeof log1, "%s/live.lcmlog", cli_tmp);
	snprintf(log2, sizeof log2, "%s/replay.lcmlog", cli_tmp);
	int undisturbed = 0;
	for (int a = 1; a <= ATTEMPTS && !undisturbed; a++) {
		counts c1, c2 = {0};
		record(name, log1, &c1);
		undisturbed =
		    c1.ticks == 40 && c1.unanswered == 0 && c1.missing == 0;
		if (undisturbed) {
			replay(name, replay_task, log1, log2, &c2);
			undisturbed = c2.ticks == 40 && c2.unanswered == 0 &&
				      c2.missing == 0;
		}
		if (!undisturbed)
			printf("  attempt %d disturbed: live %lu ticks, %lu "
			       "unanswered, %lu missing; replayed %lu ticks, "
			       "%lu unanswered, %lu missing\n",
			       a, c1.ticks, c1.unanswered, c1.missing, c2.ticks,
			       c2.unanswered, c2.missing);
	}
	CHECK(undisturbed);
	if (!undisturbed)
		return;
	static char live[1 << 16], replayed[1 << 16];
	char ch[128];
	snprintf(ch, sizeof ch, "EVO_%s_COMMAND", name);
	CHECK_EQ_INT(log_commands(log1, ch, live, sizeof live), 40);
	CHECK_EQ_INT(log_commands(log2, ch, replayed, sizeof replayed), 40);
	CHECK_EQ_STR(replayed, live);
	char *ta = cli_read("%s/live.trace", cli_tmp);
	char *tb = cli_read("%s/replay.trace", cli_tmp);
	CHECK(ta && tb && strcmp(ta, tb) == 0);
	free(ta);
	free(tb);
}

/* TEST_ROBOT_SHOW=1 in the environment: how long each test took. */
#define RUN_TIMED(t)                                                           \
	do {                                                                   \
		double t0_ = mono();                                           \
		RUN(t);                                                        \
		if (getenv("TEST_ROBOT_SHOW"))                                 \
			printf("%s: %.2f s\n", #t, mono() - t0_);              \
	} while (0)

int main(void)
{
	if (cli_setup("robot"))
		return 1;
	int port = 20000 + (int)(getpid() % 10000) * 4;
	snprintf(test_url, sizeof test_url, "udpm://239.255.76.67:%d?ttl=0",
		 port);
	snprintf(test_url2, sizeof test_url2, "udpm://239.255.76.67:%d?ttl=0",
		 port + 1);
	RUN_TIMED(a_robot_runs_as_demosim_does);
	RUN_TIMED(the_robot_ends_an_episode_at_ticklim_as_demosim_does);
	RUN_TIMED(killing_the_robot_is_reported_within_the_timeout);
	RUN_TIMED(
	    the_robot_goes_neutral_when_commands_stop_and_follows_them_again);
	RUN_TIMED(the_robot_panel_is_drawn_without_a_window);
	RUN_TIMED(serve_refuses_robot_options_that_do_not_fit);
	RUN_TIMED(late_and_missing_ticks_are_counted);
	RUN_TIMED(a_robot_with_other_names_is_refused_with_them);
	RUN_TIMED(a_recorded_session_replays_to_the_same_commands);
	cli_cleanup();
	return test_summary();
}

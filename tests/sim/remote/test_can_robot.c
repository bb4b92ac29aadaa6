/* A robot over CAN (docs/can.md, DEMOREMOTE over CAN), end to end on this
 * machine: `evo run` of a DEMOREMOTE task driving `evo serve --can` over
 * slcan (a pseudo-terminal) and over cannelloni (UDP) writes the trace
 * DEMOSIM writes; SocketCAN the same where the kernel has it, else the
 * reason it is not tested; a body that does not fit the botdesc is
 * refused with what is wrong; a body killed is reported within the
 * timeout; a body goes neutral when evo's commands stop and follows them
 * again; bad input from the bus (the test itself plays the body, frame by
 * frame) is counted and reported; the robot's panel is drawn; options
 * that do not fit are refused.
 *
 * Every evo is started with exec and reaped within a limit (then killed);
 * children still running when a test ends are killed. Nothing waits a
 * fixed time for something to happen but where the test plays a stopped
 * evo. */
#define _POSIX_C_SOURCE 200809L
#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <net/if.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "harness.h"
#include "support/doc_block.h"
#include "remote/can.h"
#include "remote/can_robot.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/viewer.h"

static char out[1 << 16];
/* the docs blocks marked as checked here (docs/can.md's, in order, and
 * docs/wire.md's) */
#define THIS_TEST "tests/sim/remote/test_can_robot.c"
static char doc[4096];
/* what docs/can.md and docs/wire.md call the robot's URLs */
#define DOC_SLCAN "slcan:/tmp/avoid-bot"
#define DOC_UDP "cannelloni:127.0.0.1:7001?local=7000"
static int port_base; /* this run's UDP ports: port_base .. + 63 */
static int next_port;

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

/* ---- children -------------------------------------------------------- */

#define MAX_CHILDREN 16
static pid_t children[MAX_CHILDREN];

static void forget(pid_t pid)
{
	for (int i = 0; i < MAX_CHILDREN; i++)
		if (children[i] == pid)
			children[i] = 0;
}

/* Every child still running: killed (a test that failed half-way). */
static void kill_children(void)
{
	for (int i = 0; i < MAX_CHILDREN; i++)
		if (children[i] > 0) {
			kill(children[i], SIGKILL);
			waitpid(children[i], NULL, 0);
			children[i] = 0;
		}
}

/* `sh -c "exec CMD"`, with SIGINT and SIGTERM at their defaults. */
static pid_t spawn(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static pid_t spawn(const char *fmt, ...)
{
	char cmd[4096];
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
	for (int i = 0; i < MAX_CHILDREN; i++)
		if (children[i] == 0) {
			children[i] = pid;
			break;
		}
	return pid;
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
			forget(pid);
			return -1;
		}
		pause_ms(2);
	}
	forget(pid);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
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

/* Stop pid (SIGSTOP) and wait until it has: 1, or 0. */
static int stop_now(pid_t pid)
{
	int st = 0;
	kill(pid, SIGSTOP);
	return waitpid(pid, &st, WUNTRACED) == pid && WIFSTOPPED(st);
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

/* `evo ARGS`, started with exec, its output in out; its exit status (-1
 * when it had to be killed after `limit` seconds). */
static int evo(double limit, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
static int evo(double limit, const char *fmt, ...)
{
	char args[2048];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(args, sizeof args, fmt, ap);
	va_end(ap);
	pid_t pid =
	    spawn("exec %s %s >%s/evo.out 2>&1", cli_evo, args, cli_tmp);
	int rc = reap(pid, limit);
	char *t = cli_read("%s/evo.out", cli_tmp);
	snprintf(out, sizeof out, "%s", t ? t : "");
	free(t);
	return rc;
}

/* ---- tasks, bodies, URLs -------------------------------------------- */

/* Two UDP ports of this run's own, free now. */
static void udp_ports(int *a, int *b)
{
	for (;;) {
		int p = next_port;
		next_port += 2;
		if (next_port >= port_base + 64)
			next_port = port_base;
		int ok = 1;
		for (int k = 0; k < 2; k++) {
			int fd = socket(AF_INET, SOCK_DGRAM, 0);
			struct sockaddr_in sa;
			memset(&sa, 0, sizeof sa);
			sa.sin_family = AF_INET;
			sa.sin_port = htons((uint16_t)(p + k));
			sa.sin_addr.s_addr = htonl(INADDR_ANY);
			ok &= bind(fd, (struct sockaddr *)&sa, sizeof sa) == 0;
			close(fd);
		}
		if (ok) {
			*a = p;
			*b = p + 1;
			return;
		}
	}
}

/* Two cannelloni URLs on ports of this run's own: the body's, which
 * `evo serve --can` opens, and evo's, which sends to the body's port and
 * listens on its own. */
static void udp_urls(char *serve_url, char *run_url, size_t cap)
{
	int a, b;
	udp_ports(&a, &b);
	snprintf(serve_url, cap, "cannelloni:127.0.0.1:%d?local=%d", a, b);
	snprintf(run_url, cap, "cannelloni:127.0.0.1:%d?local=%d", b, a);
}

/* A DEMOREMOTE task of the Avoid mind named `name` in the test's copy of
 * minds/Avoid, with BOTMODEL and ENV for `evo serve --can`. */
static void robot_task(const char *name, const char *extra)
{
	cli_sh("[ -d %s/Avoid ] || (cp -r minds/Avoid %s/ && rm -rf "
	       "%s/Avoid/Runs)",
	       cli_tmp, cli_tmp, cli_tmp);
	char text[1024];
	snprintf(text, sizeof text,
		 "TYPE:DEMOREMOTE\nBOTMODEL:BotType8\nMASTERSKILL:Avoid\n"
		 "ENV:Roam\nTICKLIM:15000\n%s",
		 extra);
	cli_write(text, "%s/Avoid/Tasks/%s.simbatch", cli_tmp, name);
}

/* `evo serve TASK --can URL OPTS` of the Avoid copy's task, ready; its
 * output in NAME.serve.log. */
static pid_t start_body(const char *task, const char *url, const char *opts,
			const char *name)
{
	char log[512];
	snprintf(log, sizeof log, "%s/%s.serve.log", cli_tmp, name);
	unlink(log);
	pid_t pid = spawn("exec %s serve %s --can '%s' %s >%s 2>&1", cli_evo,
			  task, url, opts, log);
	wait_mark(log, " serves ", 60);
	return pid;
}

/* The counts of evo's closing line for the robot at url. */
typedef struct counts {
	unsigned long ticks, in_time, late, unanswered, missing;
} counts;

static int robot_counts(const char *text, const char *url, counts *c)
{
	char pre[512];
	snprintf(pre, sizeof pre, "robot %s: ", url);
	memset(c, 0, sizeof *c);
	for (const char *p = text ? strstr(text, pre) : NULL; p;
	     p = strstr(p + 1, pre))
		if (sscanf(p + strlen(pre),
			   "%lu ticks: %lu answered in time, %lu late (%lu "
			   "unanswered), %lu missing",
			   &c->ticks, &c->in_time, &c->late, &c->unanswered,
			   &c->missing) == 5)
			return 1;
	return 0;
}

/* ---- the trace of DEMOSIM ---------------------------------------------- */

/* A real-time run is disturbed when the machine stalls one of its
 * processes for longer than a period: a command then misses its tick, by
 * design. Such a run proves nothing either way; the tests that compare
 * runs make up to this many, and fail when none ran undisturbed. */
#define ATTEMPTS 3

static char demo_episode[160];

/* DEMOSIM of the Avoid mind, seed 5, 90 ticks: demo.trace, and its
 * episode line but for the collision count. */
static int demosim(void)
{
	static int done;
	if (done)
		return 1;
	if (evo(120,
		"run minds/Avoid/Tasks/Avoid-DEMO.simbatch -nog --seed 5 "
		"--ticks 90 --trace %s/demo.trace",
		cli_tmp) != 0)
		return 0;
	const char *line = strstr(out, "episode 1: reward ");
	const char *end = line ? strstr(line, " ticks") : NULL;
	if (!line || !end)
		return 0;
	snprintf(demo_episode, sizeof demo_episode, "%.*s ticks\n",
		 (int)(end - line), line);
	return done = 1;
}

/* The robot of task `name` on the body's URL `serve_url`, driven with
 * `run_opts` (--can URL, or nothing for the task's CANURL) where evo
 * names it `run_url`: the same trace and episode line as DEMOSIM, in an
 * undisturbed run. */
static int runs_as_demosim(const char *name, const char *serve_url,
			   const char *run_url, const char *run_opts)
{
	CHECK(demosim());
	char task[512], log[512], want[600];
	snprintf(task, sizeof task, "%s/Avoid/Tasks/%s.simbatch", cli_tmp,
		 name);
	snprintf(log, sizeof log, "%s/%s.serve.log", cli_tmp, name);
	CHECK_EQ_INT(evo(60, "check %s", task), 0);
	int undisturbed = 0;
	for (int a = 1; a <= ATTEMPTS && !undisturbed; a++) {
		pid_t body = start_body(task, serve_url, "--tick-ms 60", name);
		int rc = evo(120,
			     "run %s -nog --seed 5 --ticks 90 --trace "
			     "%s/robot.trace %s",
			     task, cli_tmp, run_opts);
		CHECK_EQ_INT(rc, 0);
		snprintf(want, sizeof want,
			 "robot %s: a tick every 60.000 ms; 11 sensors and 2 "
			 "actuators, names as in the botdesc",
			 run_url);
		CHECK_CONTAINS(out, want);
		/* evo's STOP reached the body, which went neutral (at tick
		 * 90 when undisturbed: a body held up goes on ticking) */
		CHECK(wait_mark(log, "evo stopped episode 1 at tick ", 10));
		double secs;
		CHECK_EQ_INT(stop_with(body, SIGTERM, &secs), 0);
		CHECK(secs < 1.0);
		counts c;
		CHECK(robot_counts(out, run_url, &c));
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
			       "unanswered), %lu missing; the body: %s",
			       a, c.late, c.unanswered, c.missing,
			       t && strstr(t, "ticks: ") ? strstr(t, "ticks: ")
							 : "(no report)\n");
		free(t);
	}
	CHECK(undisturbed);
	if (!undisturbed)
		return 0;
	CHECK_CONTAINS(out, demo_episode);
	char *ta = cli_read("%s/robot.trace", cli_tmp);
	char *tb = cli_read("%s/demo.trace", cli_tmp);
	CHECK(ta && tb && strcmp(ta, tb) == 0);
	CHECK_EQ_INT(cli_count_lines(ta, ""), 5 + 90);
	free(ta);
	free(tb);
	/* the frames were all evo's, both ways */
	CHECK(!strstr(out, "dropped"));
	return 1;
}

/* docs/can.md quotes an undisturbed slcan pair as its sh block runs it
 * (Avoid-ROBOT, --seed 3 --ticks 150, 33.3 ms, linked from /tmp/avoid-bot):
 * its lines are this pair's but for the numbers, which differ with the
 * period, the ticks and the pseudo-terminal; and its episode line is
 * DEMOSIM's for that seed and ticks, which an undisturbed body's is. */
static void doc_quotes_the_slcan_pair(const char *serve_url, const char *run_url)
{
	char link[300], task[300], episode[200];
	snprintf(link, sizeof link, "%s", strchr(serve_url, '=') + 1);
	snprintf(task, sizeof task, "%s/Avoid/Tasks/slcan.simbatch", cli_tmp);
	const char *sub[] = {DOC_SLCAN, run_url, NULL};
	CHECK_EQ_INT(doc_block("docs/can.md", THIS_TEST, 0, doc, sizeof doc), 0);
	CHECK_EQ_INT(doc_lines_missing(doc, out, sub, 1), 0);
	const char *ep = strstr(doc, "episode 1: reward ");
	CHECK(ep != NULL);
	snprintf(episode, sizeof episode, "%.*s, 0 collision ticks\n",
		 ep ? (int)strcspn(ep, "\n") : 0, ep ? ep : "");
	CHECK_EQ_INT(evo(120, "run minds/Avoid/Tasks/Avoid-DEMO.simbatch -nog "
			      "--seed 3 --ticks 150"),
		     0);
	CHECK_CONTAINS(out, episode);
	char *t = cli_read("%s/slcan.serve.log", cli_tmp);
	const char *serve_sub[] = {"minds/Avoid/Tasks/Avoid-ROBOT.simbatch", task,
				   "/tmp/avoid-bot", link, NULL};
	CHECK_EQ_INT(doc_block("docs/can.md", THIS_TEST, 2, doc, sizeof doc), 0);
	CHECK_EQ_INT(doc_lines_missing(doc, t ? t : "", serve_sub, 1), 0);
	free(t);
}

/* ---- DEMOREMOTE against evo serve --can ------------------------------- */

TEST(over_slcan_a_robot_runs_as_demosim_does)
{
	char serve_url[300], run_url[300], opts[400];
	robot_task("slcan", "");
	snprintf(serve_url, sizeof serve_url, "slcan-pty:?link=%s/slcan.tty",
		 cli_tmp);
	snprintf(run_url, sizeof run_url, "slcan:%s/slcan.tty", cli_tmp);
	snprintf(opts, sizeof opts, "--can %s", run_url);
	if (runs_as_demosim("slcan", serve_url, run_url, opts))
		doc_quotes_the_slcan_pair(serve_url, run_url);
	/* the body's link went with it */
	CHECK(access(run_url + 6, F_OK) != 0);
}

TEST(over_cannelloni_a_robot_runs_as_demosim_does)
{
	char serve_url[200], run_url[200], extra[300];
	udp_urls(serve_url, run_url, sizeof serve_url);
	/* the task's CANURL, this time */
	snprintf(extra, sizeof extra, "CANURL:%s\n", run_url);
	robot_task("udp", extra);
	runs_as_demosim("udp", serve_url, run_url, "");
}

TEST(over_socketcan_a_robot_runs_as_demosim_does_where_the_kernel_can)
{
	int fd = socket(PF_CAN, SOCK_RAW, 1 /* CAN_RAW */);
	if (fd < 0) {
		printf("  SocketCAN skipped: this kernel has none: "
		       "socket(AF_CAN): %s\n",
		       strerror(errno));
		/* and evo says so too */
		robot_task("socketcan", "CANURL:socketcan:vcan0\n");
		CHECK_EQ_INT(evo(60,
				 "run %s/Avoid/Tasks/socketcan.simbatch "
				 "-nog --ticks 5",
				 cli_tmp),
			     1);
		CHECK_CONTAINS(out, "socketcan:vcan0: this machine has no "
				    "SocketCAN: socket(AF_CAN): ");
		return;
	}
	close(fd);
	if (if_nametoindex("vcan0") == 0) {
		printf("  SocketCAN skipped: the kernel has it, but no vcan0 "
		       "interface (as root: ip link add dev vcan0 type vcan "
		       "&& ip link set up vcan0)\n");
		return;
	}
	robot_task("socketcan", "");
	runs_as_demosim("socketcan", "socketcan:vcan0", "socketcan:vcan0",
			"--can socketcan:vcan0");
}

/* ---- a body that does not fit --------------------------------------- */

TEST(a_body_that_does_not_fit_is_refused_saying_what_differs)
{
	char serve_url[200], run_url[200], task[512];
	udp_urls(serve_url, run_url, sizeof serve_url);
	robot_task("fit", "");
	snprintf(task, sizeof task, "%s/Avoid/Tasks/fit.simbatch", cli_tmp);
	/* other counts: the Collect robot */
	pid_t body = start_body("minds/Collect/Tasks/Collect-DEMO.simbatch",
				serve_url, "--tick-ms 20", "collect");
	CHECK_EQ_INT(evo(60, "run %s -nog --can %s", task, run_url), 1);
	char want[600];
	snprintf(want, sizeof want,
		 "robot %s does not fit Avoid.botdesc: it has 20 sensors and "
		 "3 actuators, Avoid.botdesc 11 and 2",
		 run_url);
	CHECK_CONTAINS(out, want);
	static char first[1 << 16]; /* docs/wire.md quotes both refusals */
	snprintf(first, sizeof first, "%s", out);
	double secs;
	CHECK_EQ_INT(stop_with(body, SIGTERM, &secs), 0);
	char *t = cli_read("%s/collect.serve.log", cli_tmp);
	/* it heard a HELLO of a mind that does not fit it either */
	CHECK_CONTAINS(t, "a mind of 11 sensors and 2 actuators");
	free(t);
	/* the same counts, two sensors the other way round */
	cli_sh("rm -rf %s/Swapped && cp -r minds/Avoid %s/Swapped && sed -i "
	       "-e 's/^S1:proxSensor:0$/S2:proxSensor:22.5/;t' -e "
	       "'s/^S2:proxSensor:22.5$/S1:proxSensor:0/' "
	       "%s/Swapped/Avoid.botdesc && mv %s/Swapped/Avoid.botdesc "
	       "%s/Swapped/Swapped.botdesc",
	       cli_tmp, cli_tmp, cli_tmp, cli_tmp, cli_tmp);
	char *bd = cli_read("%s/Swapped/Swapped.botdesc", cli_tmp);
	CHECK(bd && strstr(bd, "S2:proxSensor:22.5\nS1:proxSensor:0\n"));
	free(bd);
	char swapped_task[512];
	snprintf(swapped_task, sizeof swapped_task,
		 "%s/Swapped/Tasks/Avoid-ROBOT.simbatch", cli_tmp);
	body = start_body(swapped_task, serve_url, "--tick-ms 20", "swapped");
	CHECK_EQ_INT(evo(60, "run %s -nog --can %s", task, run_url), 1);
	snprintf(want, sizeof want,
		 "robot %s does not fit Avoid.botdesc: its sensor and actuator "
		 "names are others, or in another order (its names hash ",
		 run_url);
	CHECK_CONTAINS(out, want);
	/* the hashes docs/wire.md shows */
	CHECK_CONTAINS(out, "(its names hash 517d0d32, Avoid.botdesc's "
			    "18340638)");
	CHECK_CONTAINS(out, "over CAN a value is known by its place in the "
			    "botdesc");
	size_t n = strlen(out);
	snprintf(out + n, sizeof out - n, "%s", first);
	const char *sub[] = {DOC_UDP, run_url, NULL};
	CHECK_EQ_INT(doc_block("docs/wire.md", THIS_TEST, 0, doc, sizeof doc), 0);
	CHECK_EQ_INT(doc_lines_missing(doc, out, sub, 0), 0);
	CHECK_EQ_INT(stop_with(body, SIGTERM, &secs), 0);
}

/* ---- link loss ----------------------------------------------------------- */

/* A body killed once evo answers it: evo says so once the timeout has
 * passed since the body's last frame (at most one 20 ms period before the
 * kill), and soon after; it waits on, and SIGTERM ends it. Over a
 * pseudo-terminal whose other side is gone and over UDP. */
static void killed_body_is_reported(const char *name, const char *serve_url,
				    const char *run_url)
{
	char evlog[512], rlog[512], task[512];
	robot_task(name, "REMOTETIMEOUT:0.5\n");
	snprintf(task, sizeof task, "%s/Avoid/Tasks/%s.simbatch", cli_tmp,
		 name);
	snprintf(evlog, sizeof evlog, "%s/%s.evo.log", cli_tmp, name);
	snprintf(rlog, sizeof rlog, "%s/%s.serve.log", cli_tmp, name);
	pid_t body = start_body(task, serve_url, "--tick-ms 20", name);
	pid_t ev = spawn("exec %s run %s -nog --can '%s' >%s 2>&1", cli_evo,
			 task, run_url, evlog);
	/* ticks come and are answered: the body took a command */
	CHECK(wait_mark(rlog, "episode 1 starts", 60));
	pause_ms(300);
	double t0 = mono();
	kill(body, SIGKILL);
	reap(body, 10);
	CHECK(wait_mark(evlog, "silent for", 30));
	double dt = mono() - t0;
	CHECK(dt > 0.45);
	CHECK(dt < 0.5 + 1.5);
	char *t = cli_read("%s", evlog);
	char want[600];
	snprintf(want, sizeof want, "evo: robot %s silent for 0.", run_url);
	CHECK_CONTAINS(t, want);
	CHECK_CONTAINS(t, "no frames from it; waiting (Ctrl-C stops); a "
			  "robot goes neutral on its own");
	free(t);
	double secs;
	CHECK_EQ_INT(stop_with(ev, SIGTERM, &secs), 0);
	CHECK(secs < 1.0);
	t = cli_read("%s", evlog);
	CHECK_CONTAINS(t, "episode 1: reward ");
	counts c;
	CHECK(robot_counts(t, run_url, &c));
	CHECK(c.ticks > 0 && c.in_time > 0);
	free(t);
}

TEST(killing_the_body_is_reported_within_the_timeout)
{
	char serve_url[300], run_url[300];
	snprintf(serve_url, sizeof serve_url, "slcan-pty:?link=%s/killed.tty",
		 cli_tmp);
	snprintf(run_url, sizeof run_url, "slcan:%s/killed.tty", cli_tmp);
	killed_body_is_reported("killed-slcan", serve_url, run_url);
	udp_urls(serve_url, run_url, sizeof serve_url);
	killed_body_is_reported("killed-udp", serve_url, run_url);
}

/* A body that starts again says BODY, unasked, in the middle of the
 * episode: its episode is lost, and evo ends the run saying so, as over
 * LCM a robot that says hello with a new session ends it. */
TEST(a_body_that_starts_again_ends_the_run)
{
	char serve_url[200], run_url[200], evlog[512], rlog[512], task[512];
	udp_urls(serve_url, run_url, sizeof serve_url);
	robot_task("again", "");
	snprintf(task, sizeof task, "%s/Avoid/Tasks/again.simbatch", cli_tmp);
	snprintf(evlog, sizeof evlog, "%s/again.evo.log", cli_tmp);
	snprintf(rlog, sizeof rlog, "%s/again.serve.log", cli_tmp);
	pid_t body = start_body(task, serve_url, "--tick-ms 20", "again");
	pid_t ev = spawn("exec %s run %s -nog --can '%s' >%s 2>&1", cli_evo,
			 task, run_url, evlog);
	CHECK(wait_mark(rlog, "episode 1 starts", 60));
	/* well past the answers to evo's HELLOs */
	pause_ms(1200);
	kill(body, SIGKILL);
	reap(body, 10);
	body = start_body(task, serve_url, "--tick-ms 20", "again");
	CHECK_EQ_INT(reap(ev, 30), 1);
	char *t = cli_read("%s", evlog);
	char want[600];
	snprintf(want, sizeof want,
		 "robot %s started again (a BODY frame in the middle of "
		 "episode 1): the episode is lost",
		 run_url);
	CHECK_CONTAINS(t, want);
	free(t);
	double secs;
	CHECK_EQ_INT(stop_with(body, SIGTERM, &secs), 0);
}

/* evo stopped (SIGSTOP) longer than the body's timeout: the body goes
 * neutral on its own and says so; evo let go on answers the newest tick,
 * and the body follows its commands again; SIGTERM ends evo, whose STOP
 * makes the body neutral. */
TEST(the_body_goes_neutral_when_commands_stop_and_follows_them_again)
{
	char serve_url[200], run_url[200], evlog[512], rlog[512], task[512];
	udp_urls(serve_url, run_url, sizeof serve_url);
	robot_task("quiet", "");
	snprintf(task, sizeof task, "%s/Avoid/Tasks/quiet.simbatch", cli_tmp);
	snprintf(evlog, sizeof evlog, "%s/quiet.evo.log", cli_tmp);
	snprintf(rlog, sizeof rlog, "%s/quiet.serve.log", cli_tmp);
	pid_t body =
	    start_body(task, serve_url, "--tick-ms 20 --timeout 0.3", "quiet");
	pid_t ev = spawn("exec %s run %s -nog --can '%s' >%s 2>&1", cli_evo,
			 task, run_url, evlog);
	CHECK(wait_mark(rlog, "episode 1 starts", 60));
	CHECK(stop_now(ev));
	CHECK(wait_mark(rlog, "every actuator neutral", 30));
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
	CHECK(robot_counts(t, run_url, &c));
	/* what came while evo was stopped was not answered */
	CHECK(c.late >= 2);
	CHECK_CONTAINS(t, "later late ticks are counted");
	free(t);
	CHECK_EQ_INT(stop_with(body, SIGTERM, &secs), 0);
	t = cli_read("%s", rlog);
	CHECK_CONTAINS(t, " neutral; ");
	CHECK(!strstr(t, " 0 neutral; "));
	free(t);
}

/* ---- the test as the body ----------------------------------------------- */

/* The test's end of a cannelloni link to an evo run, and a UDP socket
 * for datagrams no encoder would make. */
typedef struct fake {
	evo_can *can;
	evo_can_rx rx; /* the body's: what evo sends */
	int raw;
	struct sockaddr_in to;
} fake;

static int fake_open(fake *f, int mine, int evos)
{
	char url[128];
	evo_err err;
	memset(f, 0, sizeof *f);
	snprintf(url, sizeof url, "cannelloni:127.0.0.1:%d?local=%d", evos,
		 mine);
	f->can = evo_can_open(url, &err);
	evo_can_rx_init(&f->rx, 1, 2);
	f->raw = socket(AF_INET, SOCK_DGRAM, 0);
	f->to.sin_family = AF_INET;
	f->to.sin_port = htons((uint16_t)evos);
	f->to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	return f->can ? 0 : -1;
}

static void fake_close(fake *f)
{
	evo_can_close(f->can);
	close(f->raw);
}

static void fake_send(fake *f, unsigned id, unsigned len, const void *data)
{
	evo_can_frame fr = {(uint16_t)id, (uint8_t)len, {0}};
	memcpy(fr.data, data, len);
	evo_err err;
	evo_can_send(f->can, &fr, &err);
}

/* A datagram from another port than the fake's: not from evo's peer. */
static void fake_raw(fake *f, const void *d, size_t n)
{
	(void)!sendto(f->raw, d, n, 0, (struct sockaddr *)&f->to, sizeof f->to);
}

/* Datagrams from the fake's own port, as the peer evo was told of: its
 * endpoint closed a moment so that a raw socket can send from the port.
 * 0, or -1 when the port could not be had again. */
static int fake_raw_from_peer(fake *f, int mine, int evos,
			      const uint8_t *const *d, const size_t *n,
			      int count)
{
	evo_can_close(f->can);
	f->can = NULL;
	int s = socket(AF_INET, SOCK_DGRAM, 0);
	struct sockaddr_in a;
	memset(&a, 0, sizeof a);
	a.sin_family = AF_INET;
	a.sin_port = htons((uint16_t)mine);
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	int ok = s >= 0 && bind(s, (struct sockaddr *)&a, sizeof a) == 0;
	for (int i = 0; ok && i < count; i++)
		(void)!sendto(s, d[i], n[i], 0, (struct sockaddr *)&f->to,
			      sizeof f->to);
	if (s >= 0)
		close(s);
	char url[128];
	evo_err err;
	snprintf(url, sizeof url, "cannelloni:127.0.0.1:%d?local=%d", evos,
		 mine);
	f->can = evo_can_open(url, &err);
	if (!ok || !f->can)
		printf("  the fake's port %d: %s\n", mine,
		       !ok ? strerror(errno) : err.msg);
	return ok && f->can ? 0 : -1;
}

/* Wait (at most 60 s) for an event of evo's; 1 when it came. */
static int fake_await(fake *f, evo_can_event want)
{
	double end = mono() + 60;
	while (mono() < end) {
		evo_can_frame fr;
		evo_err err;
		if (evo_can_recv(f->can, 50, &fr, &err) == 1 &&
		    evo_can_rx_frame(&f->rx, &fr) == want)
			return 1;
	}
	return 0;
}

/* The Avoid robot's sensor frames: sensor i reads v[i]. */
static void fake_sensors(fake *f, const evo_q16 *v, uint64_t frames)
{
	for (unsigned k = 0; k < evo_wire_frames(11); k++) {
		if (!(frames >> k & 1))
			continue;
		evo_can_frame fr;
		evo_wire_pack(EVO_WIRE_SENSOR, v, 11, k, &fr);
		evo_err err;
		evo_can_send(f->can, &fr, &err);
	}
}

static void fake_tick(fake *f, uint32_t tick, int with_mask, uint32_t mask)
{
	uint8_t d[8];
	evo_wire_put_u32(d, tick);
	evo_wire_put_u32(d + 4, mask);
	fake_send(f, EVO_WIRE_TICK, with_mask ? 8 : 4, d);
}

/* Ticks 0 (every frame), 1 (a frame lost: answered INCOMPLETE at once),
 * 3 (2 never sent), 4 (only the changed frame, with its mask), 5 and
 * 6, the last for its reward; between them every kind of bad input a bus
 * can bring, each dropped and counted, none stopping the run. */
TEST(bad_input_from_the_bus_is_counted_and_reported)
{
	int a, b;
	udp_ports(&a, &b);
	char extra[300], task[512];
	snprintf(extra, sizeof extra,
		 "CANURL:cannelloni:127.0.0.1:%d?local=%d\n", a, b);
	robot_task("bad", extra);
	snprintf(task, sizeof task, "%s/Avoid/Tasks/bad.simbatch", cli_tmp);
	fake f;
	CHECK_EQ_INT(fake_open(&f, a, b), 0);
	if (!f.can)
		return;
	pid_t ev = spawn("exec %s run %s -nog --ticks 6 >%s/bad.evo.log 2>&1",
			 cli_evo, task, cli_tmp);
	CHECK(fake_await(&f, EVO_CAN_EV_HELLO));
	CHECK_EQ_INT(f.rx.hello.sensors, 11);
	CHECK_EQ_INT(f.rx.hello.actuators, 2);
	CHECK_EQ_INT(f.rx.hello.version, EVO_WIRE_VERSION);
	/* datagrams from the peer: another version, one cut short, a frame
	 * of another kind (an extended id); and a well-formed one from
	 * another port, which is not the peer's */
	static const uint8_t v1[] = {1, 0, 0, 0, 0};
	static const uint8_t cut[] = {2, 0, 0, 0, 1, 0, 0, 1};
	static const uint8_t ext[] = {2, 0, 0, 0, 1, 0x80, 0, 0x12, 0x34, 0};
	static const uint8_t stranger[] = {2,	 0,    0, 0, 1, 0, 0,
					   0x01, 0xC6, 8, 0, 0, 0, 0,
					   11,	 2,    0x60, 0xEA};
	const uint8_t *raw[] = {v1, cut, ext};
	const size_t raw_len[] = {sizeof v1, sizeof cut, sizeof ext};
	CHECK_EQ_INT(fake_raw_from_peer(&f, a, b, raw, raw_len, 3), 0);
	if (!f.can)
		return;
	fake_raw(&f, stranger, sizeof stranger);
	/* a BODY of no sensors, then the Avoid robot's, with no names hash
	 * and 6 s a tick (every answer in time, however loaded the machine) */
	evo_can_body_info info = {0, 0, 2, 60000}, avoid = {0, 11, 2, 60000};
	evo_can_frame fr;
	evo_can_body_encode(&info, &fr);
	fake_send(&f, fr.id, fr.len, fr.data);
	evo_can_body_encode(&avoid, &fr);
	fake_send(&f, fr.id, fr.len, fr.data);
	CHECK(fake_await(&f, EVO_CAN_EV_RESET));
	CHECK_EQ_INT(f.rx.episode, 1);
	/* frames no body sends or with the wrong length */
	static const uint8_t zero[8] = {0};
	fake_send(&f, 0x050, 2, zero);		     /* another node's */
	fake_send(&f, EVO_WIRE_ACTUATOR, 8, zero);   /* the other way */
	fake_send(&f, EVO_WIRE_SENSOR + 6, 8, zero); /* past 11 sensors */
	fake_send(&f, EVO_WIRE_SENSOR + 5, 8, zero); /* sensor 11: DLC 4 */
	fake_send(&f, EVO_WIRE_TICK, 3, zero);	     /* TICK of 3 bytes */
	double nan = NAN;
	fake_send(&f, EVO_WIRE_REWARD, 8, &nan); /* not finite */
	evo_q16 v[11];
	for (int i = 0; i < 11; i++)
		v[i] = EVO_Q16_ONE;
	v[0] = EVO_Q16_ONE + 1; /* 1.00002: out of range */
	fake_sensors(&f, v, 1);
	v[0] = EVO_Q16_HALF;
	/* tick 0: all six frames */
	fake_sensors(&f, v, 0x3F);
	fake_tick(&f, 0, 0, 0);
	CHECK(fake_await(&f, EVO_CAN_EV_TICKED));
	CHECK(f.rx.tick == 0 && f.rx.complete && f.rx.flags == 0);
	/* tick 1: frame 3 lost */
	fake_sensors(&f, v, 0x37);
	fake_tick(&f, 1, 0, 0);
	CHECK(fake_await(&f, EVO_CAN_EV_TICKED));
	CHECK(f.rx.tick == 1 && f.rx.complete);
	CHECK_EQ_INT(f.rx.flags, EVO_WIRE_F_INCOMPLETE);
	/* tick 3: every frame again */
	fake_sensors(&f, v, 0x3F);
	fake_tick(&f, 3, 0, 0);
	CHECK(fake_await(&f, EVO_CAN_EV_TICKED));
	CHECK(f.rx.tick == 3 && f.rx.flags == 0);
	/* tick 4: only frame 2 changed; then tick 3 again, stale */
	v[4] = 0;
	fake_sensors(&f, v, 0x04);
	fake_tick(&f, 4, 1, 0x04);
	CHECK(fake_await(&f, EVO_CAN_EV_TICKED));
	CHECK(f.rx.tick == 4 && f.rx.flags == 0);
	fake_tick(&f, 3, 1, 0);
	fake_tick(&f, 5, 1, 0);
	CHECK(fake_await(&f, EVO_CAN_EV_TICKED));
	CHECK(f.rx.tick == 5 && f.rx.flags == 0);
	double reward = 2.5;
	fake_send(&f, EVO_WIRE_REWARD, 8, &reward);
	fake_tick(&f, 6, 1, 0);
	CHECK(fake_await(&f, EVO_CAN_EV_STOP));
	CHECK_EQ_INT(f.rx.episode, 1);
	CHECK_EQ_INT(reap(ev, 30), 0);
	char *t = cli_read("%s/bad.evo.log", cli_tmp);
	char url[200], want[600];
	snprintf(url, sizeof url, "cannelloni:127.0.0.1:%d?local=%d", a, b);
	CHECK_CONTAINS(t, "episode 1: reward 2.500000 over 6 ticks");
	counts c;
	CHECK(robot_counts(t, url, &c));
	CHECK_EQ_INT(c.ticks, 6);
	CHECK_EQ_INT(c.in_time, 4);
	CHECK_EQ_INT(c.missing, 2);
	snprintf(want, sizeof want,
		 "evo: robot %s: tick 1 came incomplete (sensor frames "
		 "lacking: mask 0x8)",
		 url);
	CHECK_CONTAINS(t, want);
	/* by reason: 0x050, 0x180, 0x106; 0x105 of 8 bytes, the TICK of 3;
	 * the BODY of no sensors, the reward, the sensor of 1.00002; tick
	 * 1; tick 3 again */
	snprintf(want, sizeof want,
		 "evo: robot %s: dropped 10 frames (3 id, 2 length, 3 value, 1 "
		 "incomplete, 1 stale)",
		 url);
	CHECK_CONTAINS(t, want);
	snprintf(want, sizeof want,
		 "evo: robot %s: dropped 4 pieces of input that were no frames "
		 "of evo's (1 length, 1 not evo's, 1 version, 1 not from the "
		 "peer)",
		 url);
	CHECK_CONTAINS(t, want);
	/* docs/can.md quotes both lines */
	const char *sub[] = {DOC_UDP, url, NULL};
	CHECK_EQ_INT(doc_block("docs/can.md", THIS_TEST, 1, doc, sizeof doc), 0);
	CHECK_EQ_INT(doc_lines_missing(doc, t ? t : "", sub, 0), 0);
	if (getenv("TEST_CAN_ROBOT_SHOW") ||
	    !strstr(t ? t : "", "dropped 10 frames"))
		printf("---- evo said:\n%s----\n", t ? t : "(nothing)");
	free(t);
	fake_close(&f);
}

/* ---- the panel; options ---------------------------------------------------
 */

TEST(the_robot_panel_over_can_is_drawn_without_a_window)
{
	char serve_url[200], run_url[200], png[512], task[512];
	udp_urls(serve_url, run_url, sizeof serve_url);
	robot_task("panel", "");
	snprintf(task, sizeof task, "%s/Avoid/Tasks/panel.simbatch", cli_tmp);
	snprintf(png, sizeof png, "%s/panel.png", cli_tmp);
	pid_t body = start_body(task, serve_url, "--tick-ms 20", "panel");
	CHECK_EQ_INT(evo(60, "run %s -nog --ticks 20 --screenshot %s --can %s",
			 task, png, run_url),
		     0);
	/* tick 19 but where a loaded machine held evo up past tick 20 */
	CHECK_CONTAINS(out, ", drawn without a window)");
	evo_png_image im;
	evo_err err;
	CHECK_EQ_INT(evo_png_read(png, &im, &err), 0);
	int live = 0, sensor = 0, actuator = 0;
	for (int i = 0; im.pixels && i < im.w * im.h; i++) {
		const uint8_t *q = im.pixels + (size_t)i * im.channels;
		uint32_t c = (uint32_t)q[0] << 16 | (uint32_t)q[1] << 8 | q[2];
		live += c == EVO_VIEW_LINK_OK;
		sensor += c == EVO_VIEW_SENSOR_BAR;
		actuator += c == EVO_VIEW_ACTUATOR_BAR;
	}
	CHECK(live > 100);
	CHECK(sensor > 100);
	CHECK(actuator > 100);
	evo_png_image_free(&im);
	double secs;
	CHECK_EQ_INT(stop_with(body, SIGTERM, &secs), 0);
}

TEST(options_and_keys_that_do_not_fit_are_refused)
{
	robot_task("opts", "");
	char task[512];
	snprintf(task, sizeof task, "%s/Avoid/Tasks/opts.simbatch", cli_tmp);
	CHECK_EQ_INT(evo(30, "serve %s --can slcan-pty: --name x", task), 2);
	CHECK_CONTAINS(out, "--name is for LCM; over CAN (--can) a robot is "
			    "its bus");
	CHECK_EQ_INT(evo(30, "serve %s --can slcan-pty: --data-url same", task),
		     2);
	CHECK_CONTAINS(out, "--data-url is for LCM");
	CHECK_EQ_INT(evo(30, "serve %s --can slcan-pty: --tick-ms 7000", task),
		     2);
	CHECK_CONTAINS(out, "--tick-ms over CAN is at most 6553.5");
	CHECK_EQ_INT(evo(30, "serve %s --can can0", task), 1);
	CHECK_CONTAINS(out, "'can0' is no CAN URL evo knows");
	CHECK_EQ_INT(evo(30, "run minds/Avoid/Tasks/Avoid-DEMO.simbatch -nog "
			     "--can slcan:/dev/null"),
		     2);
	CHECK_CONTAINS(out, "--can is for DEMOREMOTE tasks");
	/* CANURL: DEMOREMOTE only, a URL of evo's */
	cli_write("TYPE:DEMOREMOTESIM\nMASTERSKILL:Avoid\nCANURL:slcan-pty:\n",
		  "%s/Avoid/Tasks/sim-can.simbatch", cli_tmp);
	CHECK_EQ_INT(evo(30, "check %s/Avoid/Tasks/sim-can.simbatch", cli_tmp),
		     1);
	CHECK_CONTAINS(out, "CANURL is for DEMOREMOTE tasks (a robot on a CAN "
			    "bus); a DEMOREMOTESIM task's remote is reached "
			    "over LCM");
	robot_task("badurl", "CANURL:can:vcan0\n");
	CHECK_EQ_INT(evo(30, "check %s/Avoid/Tasks/badurl.simbatch", cli_tmp),
		     1);
	CHECK_CONTAINS(out, "badurl.simbatch: CANURL: 'can:vcan0' is no CAN "
			    "URL evo knows");
	CHECK_EQ_INT(
	    evo(30, "run %s/Avoid/Tasks/badurl.simbatch -nog", cli_tmp), 1);
	CHECK_CONTAINS(out, "CANURL: 'can:vcan0' is no CAN URL evo knows");
	/* a link where something that is no link is */
	cli_write("x", "%s/file", cli_tmp);
	CHECK_EQ_INT(
	    evo(30, "serve %s --can 'slcan-pty:?link=%s/file'", task, cli_tmp),
	    1);
	CHECK_CONTAINS(out, "exists and is no symbolic link: evo does not "
			    "replace it");
}

/* An episode the body ends lasts TICKLIM ticks, as DEMOSIM's: with
 * TICKLIM 60 and no --ticks both sides said 61 ticks (the scene's
 * timeout control ends an episode one check after TICKLIM, which DEMOSIM
 * and learning bound). Undisturbed, the reward is DEMOSIM's too. */
TEST(the_body_ends_an_episode_at_ticklim_as_demosim_does)
{
	char serve_url[200], run_url[200], task[512], log[512], want[300];
	robot_task("lim", ""); /* the mind folder's copy */
	cli_write("TYPE:DEMOSIM\nBOTMODEL:BotType8\nMASTERSKILL:Avoid\n"
		  "ENV:Roam\nTICKLIM:60\n",
		  "%s/Avoid/Tasks/Sim60.simbatch", cli_tmp);
	udp_urls(serve_url, run_url, sizeof serve_url);
	snprintf(want, sizeof want,
		 "TYPE:DEMOREMOTE\nBOTMODEL:BotType8\nMASTERSKILL:Avoid\n"
		 "ENV:Roam\nTICKLIM:60\nCANURL:%s\n",
		 run_url);
	cli_write(want, "%s/Avoid/Tasks/Can60.simbatch", cli_tmp);
	CHECK_EQ_INT(evo(60, "run %s/Avoid/Tasks/Sim60.simbatch -nog --seed 5",
			 cli_tmp),
		     0);
	char sim_line[200] = "";
	const char *l = strstr(out, "episode 1: reward ");
	const char *end = l ? strstr(l, " ticks") : NULL;
	CHECK(end != NULL);
	if (end)
		snprintf(sim_line, sizeof sim_line, "%.*s ticks\n",
			 (int)(end - l), l);
	CHECK_CONTAINS(sim_line, " over 60 ticks\n");
	snprintf(task, sizeof task, "%s/Avoid/Tasks/Can60.simbatch", cli_tmp);
	snprintf(log, sizeof log, "%s/lim.serve.log", cli_tmp);
	int undisturbed = 0;
	for (int a = 1; a <= ATTEMPTS && !undisturbed; a++) {
		pid_t body = start_body(task, serve_url, "--tick-ms 30", "lim");
		CHECK_EQ_INT(evo(60, "run %s -nog --seed 5", task), 0);
		CHECK_CONTAINS(out, " over 60 ticks\n");
		CHECK(wait_mark(log, "episode 1 ended at tick 60: ", 10));
		double secs;
		CHECK_EQ_INT(stop_with(body, SIGTERM, &secs), 0);
		counts c;
		CHECK(robot_counts(out, run_url, &c));
		CHECK_EQ_INT(c.ticks, 60);
		undisturbed = c.unanswered == 0 && c.missing == 0 && c.late == 0;
	}
	if (undisturbed)
		CHECK_CONTAINS(out, sim_line);
}

/* TEST_CAN_ROBOT_SHOW=1 in the environment: how long each test took. */
#define RUN_TIMED(t)                                                           \
	do {                                                                   \
		double t0_ = mono();                                           \
		RUN(t);                                                        \
		kill_children();                                               \
		if (getenv("TEST_CAN_ROBOT_SHOW"))                             \
			printf("%s: %.2f s\n", #t, mono() - t0_);              \
	} while (0)

int main(void)
{
	if (cli_setup("can-robot"))
		return 1;
	/* cannelloni ports of this run's own, away from the LCM tests'
	 * (20000 + ...) and test_can's; udp_ports skips any taken */
	port_base = 61000 + (int)(getpid() % 60) * 64;
	next_port = port_base;
	RUN_TIMED(over_slcan_a_robot_runs_as_demosim_does);
	RUN_TIMED(over_cannelloni_a_robot_runs_as_demosim_does);
	RUN_TIMED(the_body_ends_an_episode_at_ticklim_as_demosim_does);
	RUN_TIMED(
	    over_socketcan_a_robot_runs_as_demosim_does_where_the_kernel_can);
	RUN_TIMED(a_body_that_does_not_fit_is_refused_saying_what_differs);
	RUN_TIMED(killing_the_body_is_reported_within_the_timeout);
	RUN_TIMED(a_body_that_starts_again_ends_the_run);
	RUN_TIMED(
	    the_body_goes_neutral_when_commands_stop_and_follows_them_again);
	RUN_TIMED(bad_input_from_the_bus_is_counted_and_reported);
	RUN_TIMED(the_robot_panel_over_can_is_drawn_without_a_window);
	RUN_TIMED(options_and_keys_that_do_not_fit_are_refused);
	kill_children();
	cli_cleanup();
	return test_summary();
}

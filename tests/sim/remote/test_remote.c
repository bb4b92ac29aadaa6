/* Remote simulators over LCM (docs/remote.md), end to end on loopback:
 * `evo run` of a DEMOREMOTESIM task driving `evo serve` writes the very
 * trace DEMOSIM writes in one process; a remote of the test's own, in
 * its own process, checks that evo maps sensor and actuator names in any
 * order, that a remote with other names is refused with the names, and
 * that bad messages are dropped and counted by reason; no evo waits past
 * SIGTERM. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <signal.h>
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
#include "support/serve.h"

static char out[1 << 16], out2[1 << 16];
/* docs/remote.md's blocks marked as checked here, in order, and what the
 * forged hello's keyed run printed (the drops block quotes two runs) */
#define THIS_TEST "tests/sim/remote/test_remote.c"
static char doc[4096], forged_hello_out[1 << 16];

static double mono(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* A task of the Avoid mind that names remote `name`, in the test's copy of
 * the mind folder. */
static void remote_task(const char *name, const char *extra)
{
	cli_sh("[ -d %s/Avoid ] || (cp -r minds/Avoid %s/ && rm -rf "
	       "%s/Avoid/Runs)",
	       cli_tmp, cli_tmp, cli_tmp);
	char text[512];
	snprintf(text, sizeof text,
		 "TYPE:DEMOREMOTESIM\nBOTMODEL:BotType8\nMASTERSKILL:Avoid\n"
		 "ENV:Roam\nTICKLIM:15000\nREMOTENAME:%s\n%s",
		 name, extra);
	cli_write(text, "%s/Avoid/Tasks/%s.simbatch", cli_tmp, name);
}

/* `evo serve` of task `name` under that name, started and ready. */
static pid_t start_serve(const char *name)
{
	char task[512], opts[300], log[512];
	snprintf(task, sizeof task, "%s/Avoid/Tasks/%s.simbatch", cli_tmp, name);
	snprintf(opts, sizeof opts, "--name %s", name);
	snprintf(log, sizeof log, "%s/%s.serve.log", cli_tmp, name);
	return cli_serve_start(task, opts, log);
}

TEST(a_served_world_runs_as_demosim_does)
{
	char name[64];
	snprintf(name, sizeof name, "world-%ld", (long)getpid());
	remote_task(name, "");
	pid_t srv = start_serve(name);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog --seed 5 "
			     "--episodes 2 --ticks 700 --trace %s/remote.trace",
			     cli_evo, cli_tmp, name, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 2: reward ");
	int rc2 = cli_capture(out2, sizeof out2,
			      "%s run minds/Avoid/Tasks/Avoid-DEMO.simbatch "
			      "-nog --seed 5 --episodes 2 --ticks 700 --trace "
			      "%s/demo.trace",
			      cli_evo, cli_tmp);
	CHECK_EQ_INT(rc2, 0);
	static char a[4096], b[4096];
	cli_episode_lines(out, a, sizeof a);
	cli_episode_lines(out2, b, sizeof b);
	CHECK(a[0] != 0);
	CHECK_EQ_STR(a, b);
	/* evo serve sends the episode's behaviour (docs/remote.md): without
	 * env.behaviour, the bot's position in the arena, two values */
	double bx = -1, by = -1;
	const char *beh = strstr(out, "episode 2: ");
	beh = beh ? strstr(beh, ", behaviour (") : NULL;
	CHECK(beh && sscanf(beh, ", behaviour (%lf, %lf)", &bx, &by) == 2);
	CHECK(bx >= 0 && bx <= 1 && by >= 0 && by <= 1);
	char *ta = cli_read("%s/remote.trace", cli_tmp);
	char *tb = cli_read("%s/demo.trace", cli_tmp);
	CHECK(ta && tb && strcmp(ta, tb) == 0);
	/* 5 header lines and 2 x 700 ticks */
	CHECK_EQ_INT(cli_count_lines(ta, ""), 5 + 1400);
	free(ta);
	free(tb);
	double secs;
	CHECK_EQ_INT(cli_serve_stop(srv, &secs), 0);
	CHECK(secs < 1.0);
}

/* ---- a remote of the test's own ------------------------------------------ */

enum fake_mode {
	FAKE_GOOD,
	FAKE_OTHER_NAMES,
	FAKE_NOISY,
	FAKE_NAN,     /* tick 0 reads NaN */
	FAKE_RESTART, /* says hello with a new session instead of tick 0 */
	FAKE_ENVS_100, /* says it runs 100 environments (evo keeps 64) */
	FAKE_OWN_URL   /* names fake_hello_url as its episodes' URL */
};

static char fake_hello_url[240]; /* FAKE_OWN_URL's */

static void publish(evo_link *l, const char *ch, const void *b, int n)
{
	evo_err err;
	if (n > 0)
		evo_link_publish(l, ch, b, (size_t)n, &err);
}

/* Avoid's sensors and actuators, listed in reverse, so that evo must map
 * them by name. The sensors of tick 0 read S1..S3 0.1 (an obstacle close
 * ahead and to the right), S9 and S10 1, DOF 0.3 and the rest 0.5; tick 1
 * ends the episode with reward 7.5. What evo commands at tick 0 goes to
 * the file `got`. */
static const char *fake_url; /* NULL: LCM's default URL */

static void fake_remote(const char *name, enum fake_mode mode, const char *got)
{
	static const char *sensors[] = {"S1", "S2", "S3", "S4", "S5", "S6",
					"S7", "S8", "S9", "S10", "DOF"};
	evo_err err;
	evo_link *l = evo_link_open(fake_url, &err);
	char ch_control[96], ch_command[96], ch_sensors[96];
	snprintf(ch_control, sizeof ch_control, "EVO_%s_CONTROL", name);
	snprintf(ch_command, sizeof ch_command, "EVO_%s_COMMAND", name);
	snprintf(ch_sensors, sizeof ch_sensors, "EVO_%s_SENSORS", name);
	if (!l || evo_link_subscribe(l, "EVO_WHO", &err) ||
	    evo_link_subscribe(l, ch_control, &err) ||
	    evo_link_subscribe(l, ch_command, &err))
		_exit(3);
	evo_wire_hello h = {.protocol = EVO_WIRE_PROTOCOL,
			    .session = 42,
			    .kind = EVO_REMOTE_SIMULATOR,
			    .environments = 1,
			    .n_sensors = 11,
			    .n_actuators = 2};
	snprintf(h.name, sizeof h.name, "%s", name);
	for (int i = 0; i < 11; i++)
		snprintf(h.sensor[i], EVO_NAME_MAX, "%s", sensors[10 - i]);
	if (mode == FAKE_OTHER_NAMES) {
		snprintf(h.sensor[1], EVO_NAME_MAX, "S11");
		snprintf(h.actuator[1], EVO_NAME_MAX, "Claw");
	} else {
		snprintf(h.actuator[1], EVO_NAME_MAX, "MotL");
	}
	snprintf(h.actuator[0], EVO_NAME_MAX, "MotR");
	if (mode == FAKE_ENVS_100)
		h.environments = 100;
	if (mode == FAKE_OWN_URL)
		snprintf(h.url, sizeof h.url, "%s", fake_hello_url);
	static unsigned char buf[EVO_WIRE_MAX_BYTES];
	publish(l, "EVO_HELLO", buf, evo_wire_encode_hello(&h, buf, sizeof buf));
	evo_wire_sensors s = {.session = 42, .n = 11};
	snprintf(s.name, sizeof s.name, "%s", name);
	for (int i = 0; i < 11; i++) {
		const char *n = h.sensor[i];
		s.value[i] = strcmp(n, "S1") == 0 || strcmp(n, "S2") == 0 ||
				     strcmp(n, "S3") == 0
				 ? 0.1
			     : strcmp(n, "S9") == 0 || strcmp(n, "S10") == 0
				 ? 1.0
			     : strcmp(n, "DOF") == 0 ? 0.3
						     : 0.5;
	}
	double limit = mono() + 30;
	while (mono() < limit) {
		evo_link_msg m;
		if (evo_link_next(l, 100, &m, &err) <= 0)
			continue;
		if (strcmp(m.channel, "EVO_WHO") == 0) {
			publish(l, "EVO_HELLO", buf,
				evo_wire_encode_hello(&h, buf, sizeof buf));
		} else if (strcmp(m.channel, ch_control) == 0) {
			evo_wire_control c;
			char why[256];
			if (evo_wire_decode_control(m.data, m.len, &c, why,
						    sizeof why))
				continue;
			if (c.op == EVO_CONTROL_STOP)
				break;
			s.episode = c.episode;
			s.tick = 0;
			if (mode == FAKE_NOISY) {
				/* bytes of no type, another session, a
				 * wrong count, a tick ahead, then the
				 * right message */
				publish(l, ch_sensors, "junk", 4);
				evo_wire_sensors bad = s;
				bad.session = 41;
				publish(l, ch_sensors, buf,
					evo_wire_encode_sensors(&bad, buf,
								sizeof buf));
				bad = s;
				bad.n = 3;
				publish(l, ch_sensors, buf,
					evo_wire_encode_sensors(&bad, buf,
								sizeof buf));
				bad = s;
				bad.env = 100;
				publish(l, ch_sensors, buf,
					evo_wire_encode_sensors(&bad, buf,
								sizeof buf));
				bad = s;
				bad.tick = 5;
				publish(l, ch_sensors, buf,
					evo_wire_encode_sensors(&bad, buf,
								sizeof buf));
			}
			if (mode == FAKE_RESTART) {
				evo_wire_hello again = h;
				again.session = 43;
				publish(l, "EVO_HELLO", buf,
					evo_wire_encode_hello(&again, buf,
							      sizeof buf));
				continue;
			}
			evo_wire_sensors first = s;
			if (mode == FAKE_NAN)
				first.value[3] = NAN;
			publish(l, ch_sensors, buf,
				evo_wire_encode_sensors(&first, buf,
							sizeof buf));
		} else if (strcmp(m.channel, ch_command) == 0) {
			evo_wire_command c;
			char why[256];
			if (evo_wire_decode_command(m.data, m.len, &c, why,
						    sizeof why) ||
			    c.tick != 0)
				continue;
			char text[128];
			snprintf(text, sizeof text, "%u %.6f %.6f\n", c.n,
				 c.value[0], c.value[1]);
			cli_write(text, "%s", got);
			s.tick = 1;
			s.reward = 7.5;
			s.done = 1;
			publish(l, ch_sensors, buf,
				evo_wire_encode_sensors(&s, buf, sizeof buf));
		}
	}
	evo_link_close(l);
	_exit(0);
}

static pid_t start_fake(const char *name, enum fake_mode mode, const char *got)
{
	pid_t pid = fork();
	if (pid == 0)
		fake_remote(name, mode, got);
	return pid;
}

/* The commands of tick 0 are what `evo tick` gives for the same sensor
 * values (MotL 0, MotR 1), in the remote's order (MotR first). */
TEST(names_are_mapped_in_any_order)
{
	char name[64], got[256];
	snprintf(name, sizeof name, "fake-%ld", (long)getpid());
	snprintf(got, sizeof got, "%s/got.txt", cli_tmp);
	remote_task(name, "");
	CHECK_EQ_INT(cli_capture(out2, sizeof out2,
				 "%s tick minds/Avoid --ticks 1 --sensor S1=0.1 "
				 "--sensor S2=0.1 --sensor S3=0.1 --sensor S9=1 "
				 "--sensor S10=1 --sensor DOF=0.3",
				 cli_evo),
		     0);
	CHECK_CONTAINS(out2, "   0   0.0000   1.0000");
	pid_t f = start_fake(name, FAKE_GOOD, got);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog", cli_evo,
			     cli_tmp, name);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward 7.500000 over 1 ticks");
	char *g = cli_read("%s", got);
	CHECK(g && strcmp(g, "2 1.000000 0.000000\n") == 0);
	free(g);
	int st;
	waitpid(f, &st, 0);
}

TEST(a_remote_with_other_names_is_refused_with_them)
{
	char name[64], got[256];
	snprintf(name, sizeof name, "other-%ld", (long)getpid());
	snprintf(got, sizeof got, "%s/got2.txt", cli_tmp);
	remote_task(name, "");
	pid_t f = start_fake(name, FAKE_OTHER_NAMES, got);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog", cli_evo,
			     cli_tmp, name);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "does not fit Avoid.botdesc; it lacks the sensors "
			    "S10; it has the extra sensors S11; it lacks the "
			    "actuators MotL; it has the extra actuators Claw");
	kill(f, SIGKILL);
	int st;
	waitpid(f, &st, 0);
}

/* With only a misfit answering, evo's "no simulator has answered" names
 * it and why it was passed over, instead of saying none answered. */
TEST(waiting_names_the_remote_passed_over)
{
	char misfit[64], got[256], url[96];
	snprintf(misfit, sizeof misfit, "lone-misfit-%ld", (long)getpid());
	snprintf(got, sizeof got, "%s/got-lone.txt", cli_tmp);
	snprintf(url, sizeof url, "udpm://239.255.76.67:%ld?ttl=0",
		 30001 + (long)(getpid() % 10000) * 2);
	remote_task(misfit, "");
	char text[512];
	snprintf(text, sizeof text,
		 "TYPE:DEMOREMOTESIM\nMASTERSKILL:Avoid\nTICKLIM:100\n"
		 "LCMURL:%s\nREMOTETIMEOUT:1\nREMOTENAME:%s,other\n",
		 url, misfit);
	cli_write(text, "%s/Avoid/Tasks/lone-remote.simbatch", cli_tmp);
	fake_url = url;
	pid_t a = start_fake(misfit, FAKE_OTHER_NAMES, got);
	fake_url = NULL;
	/* -k 20: a run that has not ended 20 s after its SIGINT is killed.
	 * Once, under ASan on a loaded machine, evo's exit hung in
	 * LeakSanitizer's check (its tracer attached, the process spinning)
	 * for ten minutes and held make test up. */
	cli_capture(out, sizeof out,
		    "timeout -s INT -k 20 4 %s run "
		    "%s/Avoid/Tasks/lone-remote.simbatch -nog",
		    cli_evo, cli_tmp);
	char want[256];
	snprintf(want, sizeof want,
		 "that fits has answered on %s for ", url);
	CHECK_CONTAINS(out, want);
	snprintf(want, sizeof want,
		 "s; %s answered and was passed over (remote %s does not fit "
		 "Avoid.botdesc; it lacks the sensors S10",
		 misfit, misfit);
	CHECK_CONTAINS(out, want);
	kill(a, SIGKILL);
	int st;
	waitpid(a, &st, 0);
}

/* With several names in REMOTENAME any of them will do: one whose names
 * do not fit is passed over, saying why, and evo waits for one that
 * fits. */
TEST(a_remote_that_does_not_fit_is_passed_over_for_one_that_does)
{
	char misfit[64], fit[64], got[256], url[96];
	snprintf(misfit, sizeof misfit, "misfit-%ld", (long)getpid());
	snprintf(fit, sizeof fit, "fit-%ld", (long)getpid());
	snprintf(got, sizeof got, "%s/got-fit.txt", cli_tmp);
	/* a port of this run's own: no other remote answers here */
	snprintf(url, sizeof url, "udpm://239.255.76.67:%ld?ttl=0",
		 30000 + (long)(getpid() % 10000) * 2);
	remote_task(misfit, "");
	char text[512];
	snprintf(text, sizeof text,
		 "TYPE:DEMOREMOTESIM\nMASTERSKILL:Avoid\nTICKLIM:100\n"
		 "LCMURL:%s\nREMOTETIMEOUT:10\nREMOTENAME:%s,%s\n",
		 url, misfit, fit);
	cli_write(text, "%s/Avoid/Tasks/any-remote.simbatch", cli_tmp);
	fake_url = url;
	pid_t a = start_fake(misfit, FAKE_OTHER_NAMES, got);
	pid_t b = fork();
	if (b == 0) {
		/* after evo has heard the misfit */
		nanosleep(&(struct timespec){1, 500000000}, NULL);
		fake_remote(fit, FAKE_GOOD, got);
	}
	fake_url = NULL;
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/any-remote.simbatch -nog",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	char want[256];
	snprintf(want, sizeof want,
		 "evo: remote %s does not fit Avoid.botdesc; it lacks the "
		 "sensors S10; it has the extra sensors S11",
		 misfit);
	CHECK_CONTAINS(out, want);
	CHECK_CONTAINS(out, "; passed over\n");
	snprintf(want, sizeof want, "remote %s: simulator, 1 environment",
		 fit);
	CHECK_CONTAINS(out, want);
	CHECK_CONTAINS(out, "episode 1: reward 7.500000 over 1 ticks");
	char *g = cli_read("%s", got);
	CHECK(g && strcmp(g, "2 1.000000 0.000000\n") == 0);
	free(g);
	kill(a, SIGKILL);
	int st;
	waitpid(a, &st, 0);
	waitpid(b, &st, 0);
}

TEST(bad_messages_are_dropped_and_counted_by_reason)
{
	char name[64], got[256];
	snprintf(name, sizeof name, "noisy-%ld", (long)getpid());
	snprintf(got, sizeof got, "%s/got3.txt", cli_tmp);
	remote_task(name, "");
	pid_t f = start_fake(name, FAKE_NOISY, got);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog", cli_evo,
			     cli_tmp, name);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 1: reward 7.500000 over 1 ticks");
	CHECK_CONTAINS(out, "dropped a sensors_t (undecodable: not an "
			    "evo_lcm.sensors_t");
	CHECK_CONTAINS(out, "dropped 5 messages (2 undecodable, 1 foreign, 1 "
			    "counts, 1 ahead)");
	int st;
	waitpid(f, &st, 0);
}

/* A value that is not a number, in the very message lockstep waits for,
 * ends the run naming the remote, the tick and the sensor. */
TEST(a_nan_from_a_simulator_ends_the_run_with_where_it_was)
{
	char name[64], got[256];
	snprintf(name, sizeof name, "nan-%ld", (long)getpid());
	snprintf(got, sizeof got, "%s/got4.txt", cli_tmp);
	remote_task(name, "");
	pid_t f = start_fake(name, FAKE_NAN, got);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog", cli_evo,
			     cli_tmp, name);
	CHECK_EQ_INT(rc, 1);
	/* named by the sensor the remote's hello puts 4th (its order is
	 * not the botdesc's) */
	CHECK_CONTAINS(out, "the sensors_t of tick 0 of episode 1 (environment "
			    "0): sensor S8 (value 3) is nan, outside [0, 1]");
	kill(f, SIGKILL);
	int st;
	waitpid(f, &st, 0);
}

/* A simulator that restarts in the middle of a demo: its episode is lost,
 * and the run says so. */
TEST(a_simulator_that_restarts_ends_a_demo_saying_so)
{
	char name[64], got[256];
	snprintf(name, sizeof name, "restart-%ld", (long)getpid());
	snprintf(got, sizeof got, "%s/got5.txt", cli_tmp);
	remote_task(name, "");
	pid_t f = start_fake(name, FAKE_RESTART, got);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog", cli_evo,
			     cli_tmp, name);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "restarted (a new session): the episodes it was "
			    "running are lost");
	kill(f, SIGKILL);
	int st;
	waitpid(f, &st, 0);
}

/* The next sensors_t on link within secs, or 0. */
static int next_sensors(evo_link *l, const char *channel, double secs,
			evo_wire_sensors *s)
{
	evo_err err;
	char why[256];
	double limit = mono() + secs;
	while (mono() < limit) {
		evo_link_msg m;
		if (evo_link_next(l, 20, &m, &err) <= 0 ||
		    strcmp(m.channel, channel) != 0)
			continue;
		if (evo_wire_decode_sensors(m.data, m.len, s, why,
					    sizeof why) == EVO_WIRE_OK)
			return 1;
	}
	return 0;
}

static void send_command(evo_link *l, const char *channel,
			 const evo_wire_command *c)
{
	static unsigned char buf[EVO_WIRE_MAX_BYTES];
	evo_err err;
	int n = evo_wire_encode_command(c, buf, sizeof buf);
	if (n > 0)
		evo_link_publish(l, channel, buf, (size_t)n, &err);
}

/* evo serve, driven by hand: a command with NaN, one ahead of its tick and
 * one with a wrong count get no answer and are counted; a good one steps
 * the world; the same command again gets the same answer without a step;
 * the episode's RESET again past tick 0 is a late copy, dropped, but after
 * a STOP it starts the episode over; the episodes run on the serve's own
 * port, named in its hello. */
TEST(serve_drops_bad_commands_and_repeats_answers)
{
	char name[64];
	snprintf(name, sizeof name, "served-%ld", (long)getpid());
	remote_task(name, "");
	pid_t srv = start_serve(name);
	evo_err err;
	evo_link *main_l = evo_link_open(NULL, &err);
	CHECK(main_l != NULL);
	if (!main_l)
		return;
	evo_link_subscribe(main_l, "EVO_HELLO", &err);
	static unsigned char buf[EVO_WIRE_MAX_BYTES];
	evo_wire_who w = {.protocol = EVO_WIRE_PROTOCOL};
	snprintf(w.from, sizeof w.from, "test");
	evo_wire_hello h;
	int found = 0;
	char why[256];
	for (double limit = mono() + 10; !found && mono() < limit;) {
		int n = evo_wire_encode_who(&w, buf, sizeof buf);
		evo_link_publish(main_l, "EVO_WHO", buf, (size_t)n, &err);
		evo_link_msg m;
		for (double t = mono() + 0.3; !found && mono() < t;)
			if (evo_link_next(main_l, 20, &m, &err) > 0 &&
			    evo_wire_decode_hello(m.data, m.len, &h, why,
						  sizeof why) == EVO_WIRE_OK &&
			    strcmp(h.name, name) == 0)
				found = 1;
	}
	CHECK(found);
	/* its own port: the task's (7667) + 1 .. 2000 */
	CHECK(found && strncmp(h.url, "udpm://239.255.76.67:", 21) == 0 &&
	      strcmp(h.url, EVO_LINK_DEFAULT_URL) != 0);
	evo_link *data = found ? evo_link_open(h.url, &err) : NULL;
	CHECK(data != NULL);
	char ch_sensors[96], ch_command[96], ch_control[96];
	snprintf(ch_sensors, sizeof ch_sensors, "EVO_%s_SENSORS", name);
	snprintf(ch_command, sizeof ch_command, "EVO_%s_COMMAND", name);
	snprintf(ch_control, sizeof ch_control, "EVO_%s_CONTROL", name);
	if (data) {
		evo_link_subscribe(data, ch_sensors, &err);
		evo_wire_control c = {.session = h.session,
				      .op = EVO_CONTROL_RESET,
				      .episode = 1,
				      .layout_seed = 11,
				      .seed = 12};
		snprintf(c.name, sizeof c.name, "%s", name);
		int n = evo_wire_encode_control(&c, buf, sizeof buf);
		evo_link_publish(data, ch_control, buf, (size_t)n, &err);
		evo_wire_sensors s0, s1, s1b, none;
		CHECK(next_sensors(data, ch_sensors, 10, &s0));
		CHECK(s0.tick == 0 && s0.episode == 1 && s0.n == 11);
		evo_wire_command cmd = {.session = h.session,
					.episode = 1,
					.tick = 0,
					.n = 2,
					.value = {0.9, 0.8}};
		snprintf(cmd.name, sizeof cmd.name, "%s", name);
		evo_wire_command bad = cmd;
		bad.value[0] = NAN;
		send_command(data, ch_command, &bad);
		bad = cmd;
		bad.tick = 5;
		send_command(data, ch_command, &bad);
		bad = cmd;
		bad.n = 1;
		send_command(data, ch_command, &bad);
		CHECK(!next_sensors(data, ch_sensors, 0.5, &none));
		send_command(data, ch_command, &cmd);
		CHECK(next_sensors(data, ch_sensors, 10, &s1));
		CHECK(s1.tick == 1);
		send_command(data, ch_command, &cmd);
		CHECK(next_sensors(data, ch_sensors, 10, &s1b));
		CHECK(s1b.tick == 1 && s1b.reward == s1.reward &&
		      memcmp(s1b.value, s1.value, sizeof s1.value) == 0);
		cmd.tick = 1;
		send_command(data, ch_command, &cmd);
		CHECK(next_sensors(data, ch_sensors, 10, &none) &&
		      none.tick == 2);
		/* the episode's RESET again, late: the episode goes on */
		evo_link_publish(data, ch_control, buf, (size_t)n, &err);
		CHECK(!next_sensors(data, ch_sensors, 0.5, &none));
		cmd.tick = 2;
		send_command(data, ch_command, &cmd);
		CHECK(next_sensors(data, ch_sensors, 10, &none) &&
		      none.tick == 3);
		/* after a STOP, the same RESET starts the episode over */
		evo_wire_control stop_c = c;
		stop_c.op = EVO_CONTROL_STOP;
		int n_stop = evo_wire_encode_control(&stop_c, buf, sizeof buf);
		evo_link_publish(data, ch_control, buf, (size_t)n_stop, &err);
		n = evo_wire_encode_control(&c, buf, sizeof buf);
		evo_link_publish(data, ch_control, buf, (size_t)n, &err);
		CHECK(next_sensors(data, ch_sensors, 10, &none) &&
		      none.tick == 0 && none.episode == 1 &&
		      memcmp(none.value, s0.value, sizeof s0.value) == 0);
		evo_link_close(data);
	}
	evo_link_close(main_l);
	double secs;
	CHECK_EQ_INT(cli_serve_stop(srv, &secs), 0);
	char *log = cli_read("%s/%s.serve.log", cli_tmp, name);
	CHECK(log && strstr(log, "dropped a command_t (value: value 0 is nan"));
	CHECK(log && strstr(log, "dropped a control_t (stale: a late copy of "
				 "the RESET of episode 1, now at tick 2)"));
	CHECK(log && strstr(log, "dropped 4 messages"));
	free(log);
}

/* No remote answers: evo says so after REMOTETIMEOUT, keeps waiting, and
 * SIGTERM ends the wait at once. */
TEST(waiting_for_no_remote_says_so_and_stops_on_sigterm)
{
	char name[64];
	snprintf(name, sizeof name, "nobody-%ld", (long)getpid());
	remote_task(name, "REMOTETIMEOUT:0.2\n");
	char cmd[1024], log[512];
	snprintf(log, sizeof log, "%s/nobody.log", cli_tmp);
	/* exec: the signal must reach evo, not a shell that would die of it
	 * and leave evo waiting for ever */
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/Avoid/Tasks/%s.simbatch -nog >%s 2>&1",
		 cli_evo, cli_tmp, name, log);
	int st;
	double secs;
	CHECK_EQ_INT(cli_stop(cmd, log, "has answered", 0.3, SIGTERM, &st,
			      &secs),
		     0);
	/* a stop while waiting ends the run as a stop ends a DEMOSIM: 0 */
	CHECK(WIFEXITED(st) && WEXITSTATUS(st) == 0);
	CHECK(secs < 1.0);
	char *t = cli_read("%s", log);
	CHECK(t && strstr(t, "no simulator named nobody-") &&
	      strstr(t, "waiting (Ctrl-C stops)"));
	free(t);
}

TEST(bad_remote_keys_are_refused)
{
	char name[64];
	snprintf(name, sizeof name, "keys-%ld", (long)getpid());
	remote_task(name, "REMOTETIMEOUT:soon\n");
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog", cli_evo,
			     cli_tmp, name);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "REMOTETIMEOUT: expected a number above 0 and at "
			    "most 3600, found 'soon'");
	cli_write("TYPE:DEMOREMOTESIM\nMASTERSKILL:Avoid\nREMOTENAME:a/b\n",
		  "%s/Avoid/Tasks/badname.simbatch", cli_tmp);
	rc = cli_capture(out, sizeof out,
			 "%s run %s/Avoid/Tasks/badname.simbatch -nog", cli_evo,
			 cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "badname.simbatch:3: REMOTENAME: expected names of "
			    "1 to 63 letters, digits, '_' or '-', joined by ',', "
			    "found 'a/b'");
}

/* ---- hostile peers (docs/remote.md, What LCM protects) ------------------ */

/* A hello that says 100 environments (evo keeps 64 per remote) is refused
 * by the decoder, naming the remote and the field, in DEMOREMOTESIM and
 * in LEARNREMOTESIM alike; before, evo read and wrote past its 64. */
TEST(a_hello_with_100_environments_is_refused_naming_remote_and_field)
{
	char name[64], want[256];
	snprintf(name, sizeof name, "envs-%ld", (long)getpid());
	remote_task(name, "");
	pid_t f = start_fake(name, FAKE_ENVS_100, "/dev/null");
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog", cli_evo,
			     cli_tmp, name);
	CHECK_EQ_INT(rc, 1);
	snprintf(want, sizeof want,
		 "evo: refused the hello of remote %s on "
		 "udpm://239.255.76.67:7667?ttl=0: hello_t from %s: "
		 "environments is 100, outside 1..64",
		 name, name);
	CHECK_CONTAINS(out, want);
	/* docs/remote.md quotes it for a remote named sim1 */
	CHECK_EQ_INT(doc_block("docs/remote.md", THIS_TEST, 0, doc, sizeof doc), 0);
	{
		const char *sub[] = {"sim1", name, NULL};
		CHECK_EQ_INT(doc_lines_missing(doc, out, sub, 0), 0);
	}
	char text[512];
	snprintf(text, sizeof text,
		 "TYPE:LEARNREMOTESIM\nMASTERSKILL:Avoid\nLEARNINGSKILL:Avoid\n"
		 "LEARNINGMETHOD:NEAT\nNUMGEN:1\nNEAT_POPSIZE:4\nTICKLIM:10\n"
		 "REMOTENAME:%s\n",
		 name);
	cli_write(text, "%s/Avoid/Tasks/%s-learn.simbatch", cli_tmp, name);
	rc = cli_capture(out, sizeof out,
			 "%s run %s/Avoid/Tasks/%s-learn.simbatch --run %s/envs",
			 cli_evo, cli_tmp, name, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, want);
	kill(f, SIGKILL);
	int st;
	waitpid(f, &st, 0);
}

/* A hello whose episodes' URL is file://PATH?mode=w: refused, and the
 * file never made (LCM's file provider would have written evo's messages
 * into it). A multicast URL that reaches further than the task's (ttl=1
 * where the task's has 0) is refused too. */
TEST(a_hello_naming_a_file_url_is_refused_and_writes_nothing)
{
	char name[64], want[512], fake_file[200];
	snprintf(name, sizeof name, "fileurl-%ld", (long)getpid());
	snprintf(fake_file, sizeof fake_file, "%s/written.lcmlog", cli_tmp);
	snprintf(fake_hello_url, sizeof fake_hello_url, "file://%s?mode=w",
		 fake_file);
	remote_task(name, "");
	pid_t f = start_fake(name, FAKE_OWN_URL, "/dev/null");
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog", cli_evo,
			     cli_tmp, name);
	CHECK_EQ_INT(rc, 1);
	snprintf(want, sizeof want,
		 "hello_t from %s: url: 'file://%s?mode=w' is not "
		 "udpm://GROUP:PORT",
		 name, fake_file);
	CHECK_CONTAINS(out, want);
	CHECK(access(fake_file, F_OK) != 0);
	kill(f, SIGKILL);
	int st;
	waitpid(f, &st, 0);
	snprintf(fake_hello_url, sizeof fake_hello_url,
		 "udpm://239.255.76.67:7991?ttl=1");
	f = start_fake(name, FAKE_OWN_URL, "/dev/null");
	rc = cli_capture(out, sizeof out,
			 "%s run %s/Avoid/Tasks/%s.simbatch -nog", cli_evo,
			 cli_tmp, name);
	CHECK_EQ_INT(rc, 1);
	snprintf(want, sizeof want,
		 "remote %s: its episodes' URL udpm://239.255.76.67:7991?ttl=1 "
		 "reaches further (ttl=1) than the task's "
		 "udpm://239.255.76.67:7667?ttl=0",
		 name);
	CHECK_CONTAINS(out, want);
	kill(f, SIGKILL);
	waitpid(f, &st, 0);
}

enum forge_mode {
	FORGE_HELLO,  /* hellos of the remote's name with its session + 1 */
	FORGE_SENSORS /* an answer of its own to every command, and every
			 true answer sent again as it was */
};

/* A process on the URL that attacks remote `name` once evo's run is under
 * way: it learns the remote's session and episodes' URL from its hello,
 * waits for evo's RESET, then forges for `secs` seconds. It has no key:
 * what evo sends under one, it reads past the seal. */
static void forger(const char *name, enum forge_mode mode, double secs)
{
	evo_err err;
	evo_link *l = evo_link_open(NULL, &err);
	if (!l || evo_link_subscribe(l, "EVO_HELLO", &err))
		_exit(3);
	static unsigned char buf[EVO_WIRE_MAX_BYTES];
	evo_wire_who w = {.protocol = EVO_WIRE_PROTOCOL};
	snprintf(w.from, sizeof w.from, "forger");
	evo_wire_hello h;
	char why[256];
	double until = mono() + 30, asked = 0;
	for (;;) {
		if (mono() > until)
			_exit(4);
		if (mono() - asked > 0.2) {
			publish(l, "EVO_WHO", buf,
				evo_wire_encode_who(&w, buf, sizeof buf));
			asked = mono();
		}
		evo_link_msg m;
		if (evo_link_next(l, 50, &m, &err) <= 0)
			continue;
		/* sealed or not: the hello's bytes, without a seal */
		if ((evo_wire_decode_hello(m.data, m.len, &h, why, sizeof why) ==
			 0 ||
		     (m.len > 40 &&
		      evo_wire_decode_hello(m.data, m.len - 40, &h, why,
					    sizeof why) == 0)) &&
		    strcmp(h.name, name) == 0)
			break;
	}
	evo_link *d = h.url[0] ? evo_link_open(h.url, &err) : l;
	char ch_control[96], ch_command[96], ch_sensors[96];
	snprintf(ch_control, sizeof ch_control, "EVO_%s_CONTROL", name);
	snprintf(ch_command, sizeof ch_command, "EVO_%s_COMMAND", name);
	snprintf(ch_sensors, sizeof ch_sensors, "EVO_%s_SENSORS", name);
	if (!d || evo_link_subscribe(d, ch_control, &err) ||
	    evo_link_subscribe(d, ch_command, &err) ||
	    evo_link_subscribe(d, ch_sensors, &err))
		_exit(3);
	double end = 0;
	evo_wire_hello forged = h;
	forged.session = h.session + 1;
	double said = 0;
	for (;;) {
		if (end && mono() > end)
			break;
		if (mono() > until + 30)
			_exit(4);
		if (end && mode == FORGE_HELLO && mono() - said > 0.05) {
			publish(l, "EVO_HELLO", buf,
				evo_wire_encode_hello(&forged, buf,
						      sizeof buf));
			said = mono();
		}
		evo_link_msg m;
		if (evo_link_next(d, 10, &m, &err) <= 0)
			continue;
		if (!end && strcmp(m.channel, ch_control) == 0)
			end = mono() + secs;
		if (!end || mode != FORGE_SENSORS)
			continue;
		if (strcmp(m.channel, ch_sensors) == 0) {
			/* a true answer, sent again as it came */
			unsigned char copy[EVO_WIRE_MAX_BYTES];
			memcpy(copy, m.data, m.len);
			publish(d, ch_sensors, copy, (int)m.len);
			continue;
		}
		evo_wire_command c;
		evo_wire_control k;
		evo_wire_sensors s = {.session = h.session,
				      .n = h.n_sensors};
		snprintf(s.name, sizeof s.name, "%s", name);
		if (strcmp(m.channel, ch_command) == 0 &&
		    (evo_wire_decode_command(m.data, m.len, &c, why,
					     sizeof why) == 0 ||
		     (m.len > 40 &&
		      evo_wire_decode_command(m.data, m.len - 40, &c, why,
					      sizeof why) == 0))) {
			s.env = c.env;
			s.episode = c.episode;
			s.tick = c.tick + 1;
		} else if (strcmp(m.channel, ch_control) == 0 &&
			   (evo_wire_decode_control(m.data, m.len, &k, why,
						    sizeof why) == 0 ||
			    (m.len > 40 &&
			     evo_wire_decode_control(m.data, m.len - 40, &k,
						     why, sizeof why) == 0)) &&
			   k.op == EVO_CONTROL_RESET) {
			s.env = k.env;
			s.episode = k.episode;
			s.tick = 0;
		} else {
			continue;
		}
		/* every sensor reads nothing near: a world with no walls */
		for (unsigned i = 0; i < s.n; i++)
			s.value[i] = 1.0;
		publish(d, ch_sensors, buf,
			evo_wire_encode_sensors(&s, buf, sizeof buf));
	}
	if (d != l)
		evo_link_close(d);
	evo_link_close(l);
	_exit(0);
}

static pid_t start_forger(const char *name, enum forge_mode mode, double secs)
{
	pid_t pid = fork();
	if (pid == 0)
		forger(name, mode, secs);
	return pid;
}

static void reap_forger(pid_t f)
{
	int st;
	kill(f, SIGKILL);
	waitpid(f, &st, 0);
}

/* The task's key, in a file beside it. */
static void key_file(void)
{
	cli_write("k3y-of-this-test-0123456789\n", "%s/Avoid/Tasks/lcm.key",
		  cli_tmp);
}

/* A task of remote `name`, its serve and a run of `episodes` x 700 ticks
 * with a trace, while a forger attacks (no forger: mode < 0). The run's
 * exit status; its output in out. */
static int attacked_run(const char *name, const char *extra, int mode,
			const char *trace)
{
	remote_task(name, extra);
	pid_t srv = start_serve(name);
	pid_t f = mode < 0 ? -1 : start_forger(name, (enum forge_mode)mode, 3);
	if (f > 0) {
		/* the forger has heard the hello and listens */
		struct timespec ms = {0, 300000000};
		nanosleep(&ms, NULL);
	}
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/%s.simbatch -nog --seed 5 "
			     "--episodes 2 --ticks 700 --trace %s",
			     cli_evo, cli_tmp, name, trace);
	if (f > 0)
		reap_forger(f);
	double secs;
	cli_serve_stop(srv, &secs);
	return rc;
}

/* Without a key anyone on the URL can say hello as the remote: a hello
 * with the remote's session + 1 while its session answers on is not
 * taken as a restart, and the run ends as it would have, with its trace
 * (before, it ended the run and deleted the trace). */
TEST(a_forged_hello_does_not_end_a_keyless_run)
{
	char name[64], trace[300], ref[300];
	snprintf(name, sizeof name, "hello-%ld", (long)getpid());
	snprintf(trace, sizeof trace, "%s/forged-hello.trace", cli_tmp);
	snprintf(ref, sizeof ref, "%s/forged-hello-ref.trace", cli_tmp);
	CHECK_EQ_INT(attacked_run(name, "", -1, ref), 0);
	int rc = attacked_run(name, "", FORGE_HELLO, trace);
	CHECK_EQ_INT(rc, 0);
	char want[200];
	snprintf(want, sizeof want,
		 "evo: remote %s: a hello under its name with session", name);
	CHECK_CONTAINS(out, want);
	CHECK_CONTAINS(out, "not taken as a restart");
	/* docs/remote.md quotes it for sim1; the sessions vary */
	CHECK_EQ_INT(doc_block("docs/remote.md", THIS_TEST, 1, doc, sizeof doc), 0);
	{
		const char *sub[] = {"sim1", name, NULL};
		CHECK_EQ_INT(doc_lines_missing(doc, out, sub, 1), 0);
	}
	char *a = cli_read("%s", trace), *b = cli_read("%s", ref);
	CHECK(a && b && strlen(a) > 1000 && strcmp(a, b) == 0);
	free(a);
	free(b);
}

/* With a key a forged hello fails the MAC: dropped, counted and shown at
 * the end; the run and its trace are as without it. */
TEST(a_forged_hello_fails_the_key_and_is_counted)
{
	char name[64], trace[300], ref[300];
	snprintf(name, sizeof name, "khello-%ld", (long)getpid());
	snprintf(trace, sizeof trace, "%s/kforged-hello.trace", cli_tmp);
	snprintf(ref, sizeof ref, "%s/kforged-hello-ref.trace", cli_tmp);
	cli_sh("mkdir -p %s/Avoid/Tasks", cli_tmp);
	remote_task(name, "");
	key_file();
	CHECK_EQ_INT(attacked_run(name, "LCMKEYFILE:lcm.key\n", -1, ref), 0);
	CHECK(strstr(out, "k3y") == NULL);
	int rc = attacked_run(name, "LCMKEYFILE:lcm.key\n", FORGE_HELLO, trace);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "evo: LCM at udpm://239.255.76.67:7667?ttl=0: "
			    "dropped a message on EVO_HELLO whose MAC fails the "
			    "key");
	CHECK_CONTAINS(out, " forged and 0 replayed messages (they failed the "
			    "key)");
	CHECK(strstr(out, "dropped 0 forged") == NULL);
	CHECK(strstr(out, "k3y") == NULL);
	snprintf(forged_hello_out, sizeof forged_hello_out, "%s", out);
	char *a = cli_read("%s", trace), *b = cli_read("%s", ref);
	CHECK(a && b && strlen(a) > 1000 && strcmp(a, b) == 0);
	free(a);
	free(b);
}

/* With a key, a process that answers every command with sensors of its
 * own, and sends every true answer again, never wins: the trace is the
 * one of a run nobody attacked, and what was dropped is counted. */
TEST(forged_and_replayed_sensors_never_win_under_a_key)
{
	char name[64], trace[300], ref[300];
	snprintf(name, sizeof name, "ksens-%ld", (long)getpid());
	snprintf(trace, sizeof trace, "%s/ksens.trace", cli_tmp);
	snprintf(ref, sizeof ref, "%s/ksens-ref.trace", cli_tmp);
	remote_task(name, "");
	key_file();
	CHECK_EQ_INT(attacked_run(name, "LCMKEYFILE:lcm.key\n", -1, ref), 0);
	int rc = attacked_run(name, "LCMKEYFILE:lcm.key\n", FORGE_SENSORS,
			      trace);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "whose MAC fails the key");
	CHECK_CONTAINS(out, "replayed)");
	/* docs/remote.md's drops: lines of this run's output or of the forged
	 * hello's before it, for sim1; the counts vary with timing */
	size_t n = strlen(out);
	snprintf(out + n, sizeof out - n, "%s", forged_hello_out);
	CHECK_EQ_INT(doc_block("docs/remote.md", THIS_TEST, 2, doc, sizeof doc), 0);
	{
		/* the remote's drops line: its counts and reasons vary with
		 * timing (one replayed message is "1 message"), so only its
		 * start and its replays are checked; the others line by line */
		char *drops = strstr(doc, "evo: remote sim1: dropped ");
		CHECK(drops != NULL);
		if (drops) {
			char *eol = strchr(drops, '\n');
			CHECK(eol && strstr(drops, " replayed)") < eol);
			memmove(drops, eol ? eol + 1 : "", strlen(eol ? eol + 1 : "") + 1);
		}
		char start[128];
		snprintf(start, sizeof start, "evo: remote %s: dropped ", name);
		CHECK_CONTAINS(out, start);
		const char *sub[] = {"sim1", name, NULL};
		CHECK_EQ_INT(doc_lines_missing(doc, out, sub, 1), 0);
	}
	out[n] = 0;
	char *a = cli_read("%s", trace), *b = cli_read("%s", ref);
	CHECK(a && b && strlen(a) > 1000 && strcmp(a, b) == 0);
	free(a);
	free(b);
}

/* Without a key the same attack is not silent: the second, different
 * answer for a tick ends the run, saying another process answers as the
 * remote. */
TEST(forged_sensors_end_a_keyless_run_saying_so)
{
	char name[64], trace[300];
	snprintf(name, sizeof name, "sens-%ld", (long)getpid());
	snprintf(trace, sizeof trace, "%s/sens.trace", cli_tmp);
	int rc = attacked_run(name, "", FORGE_SENSORS, trace);
	CHECK_EQ_INT(rc, 1);
	char want[200];
	snprintf(want, sizeof want,
		 "remote %s: two different sensors_t for tick ", name);
	CHECK_CONTAINS(out, want);
	snprintf(want, sizeof want, "another process answers as %s on ", name);
	CHECK_CONTAINS(out, want);
}

/* A task names its remotes or shares a key with them; a bad key file is
 * refused naming the file, never showing what it holds. */
TEST(a_task_names_its_remotes_or_has_a_key)
{
	cli_write("TYPE:DEMOREMOTESIM\nMASTERSKILL:Avoid\n",
		  "%s/Avoid/Tasks/anyone.simbatch", cli_tmp);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Avoid/Tasks/anyone.simbatch -nog",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "anyone.simbatch: a remote task names its remotes "
			    "(REMOTENAME:sim1 or REMOTENAME:sim1,sim2) or shares "
			    "a key with them (LCMKEYFILE)");
	cli_write("short-secret\n", "%s/Avoid/Tasks/short.key", cli_tmp);
	cli_write("TYPE:DEMOREMOTESIM\nMASTERSKILL:Avoid\nLCMKEYFILE:short.key\n",
		  "%s/Avoid/Tasks/shortkey.simbatch", cli_tmp);
	rc = cli_capture(out, sizeof out,
			 "%s run %s/Avoid/Tasks/shortkey.simbatch -nog",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "shortkey.simbatch: LCMKEYFILE: key file ");
	CHECK_CONTAINS(out, "short.key: a key is 16 to 256 bytes");
	CHECK(strstr(out, "short-secret") == NULL);
	cli_write("TYPE:DEMOREMOTESIM\nMASTERSKILL:Avoid\nLCMKEYFILE:none.key\n",
		  "%s/Avoid/Tasks/nokey.simbatch", cli_tmp);
	rc = cli_capture(out, sizeof out,
			 "%s run %s/Avoid/Tasks/nokey.simbatch -nog", cli_evo,
			 cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "none.key: No such file or directory");
	/* a shared task's URL opens no other LCM provider either */
	char text[512];
	snprintf(text, sizeof text,
		 "TYPE:DEMOREMOTESIM\nMASTERSKILL:Avoid\nREMOTENAME:x\n"
		 "LCMURL:file://%s/task-written?mode=w\n",
		 cli_tmp);
	cli_write(text, "%s/Avoid/Tasks/fileurl.simbatch", cli_tmp);
	rc = cli_capture(out, sizeof out,
			 "%s run %s/Avoid/Tasks/fileurl.simbatch -nog", cli_evo,
			 cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "fileurl.simbatch: LCMURL: 'file://");
	CHECK_CONTAINS(out, "' is not udpm://GROUP:PORT");
	rc = cli_capture(out, sizeof out,
			 "%s serve %s/Avoid/Tasks/fileurl.simbatch", cli_evo,
			 cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "fileurl.simbatch: LCMURL: 'file://");
	CHECK(cli_sh("test -e %s/task-written", cli_tmp) != 0);
	/* evo serve's own key file, named when it cannot be read */
	rc = cli_capture(out, sizeof out,
			 "%s serve %s/Avoid/Tasks/shortkey.simbatch --key-file "
			 "%s/none.key",
			 cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "shortkey.simbatch: LCMKEYFILE: key file ");
	cli_write("TYPE:DEMOREMOTESIM\nMASTERSKILL:Avoid\nREMOTENAME:x\n",
		  "%s/Avoid/Tasks/named.simbatch", cli_tmp);
	rc = cli_capture(out, sizeof out,
			 "%s serve %s/Avoid/Tasks/named.simbatch --key-file "
			 "%s/Avoid/Tasks/short.key",
			 cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "evo serve: --key-file: key file ");
	CHECK_CONTAINS(out, "short.key: a key is 16 to 256 bytes");
	CHECK(strstr(out, "short-secret") == NULL);
}

int main(void)
{
	if (cli_setup("remote"))
		return 1;
	RUN(a_served_world_runs_as_demosim_does);
	RUN(names_are_mapped_in_any_order);
	RUN(a_remote_with_other_names_is_refused_with_them);
	RUN(a_remote_that_does_not_fit_is_passed_over_for_one_that_does);
	RUN(waiting_names_the_remote_passed_over);
	RUN(bad_messages_are_dropped_and_counted_by_reason);
	RUN(serve_drops_bad_commands_and_repeats_answers);
	RUN(a_nan_from_a_simulator_ends_the_run_with_where_it_was);
	RUN(a_simulator_that_restarts_ends_a_demo_saying_so);
	RUN(waiting_for_no_remote_says_so_and_stops_on_sigterm);
	RUN(bad_remote_keys_are_refused);
	RUN(a_hello_with_100_environments_is_refused_naming_remote_and_field);
	RUN(a_hello_naming_a_file_url_is_refused_and_writes_nothing);
	RUN(a_forged_hello_does_not_end_a_keyless_run);
	RUN(a_forged_hello_fails_the_key_and_is_counted);
	RUN(forged_and_replayed_sensors_never_win_under_a_key);
	RUN(forged_sensors_end_a_keyless_run_saying_so);
	RUN(a_task_names_its_remotes_or_has_a_key);
	cli_cleanup();
	return test_summary();
}

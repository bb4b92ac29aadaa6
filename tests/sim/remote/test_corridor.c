/* A remote simulator evo did not write: remotes/corridor/corridor.py, in
 * Python with the lcm package from PyPI (build/venv, from `make deps`) and
 * the classes lcm-gen makes for Python (build/gen/python). The classes
 * encode every message byte for byte as evo does, and evo decodes them;
 * DEMOREMOTESIM of minds/Corridor runs against the simulator to the goal,
 * with the reward the simulator logs, and the same again for the same
 * seed; and the simulator, driven from here as evo would drive it, answers
 * a repeated RESET or command with its answer again, without stepping,
 * drops a late copy of an episode's RESET,
 * ignores what is not for it, and stops at SIGTERM; LEARNREMOTESIM of
 * Corridor-NEAT against it raises the population's fitness over a few
 * generations, and its champion beats untrained networks under
 * DEMOREMOTESIM on the same episodes. Nothing here is
 * skipped: without build/venv every test fails, saying `make deps`.
 *
 * Each test's simulator and evo share an LCM URL of their own (a port
 * from the test's pid), so remotes of other runs on this machine cannot
 * answer them. */
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
#include "remote/link.h"
#include "remote/wire.h"
#include "support/cli.h"

static char out[1 << 16], out2[1 << 16];
static char venv_python[512], py_path[512], url[128];

static double mono(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void sleep_ms(long ms)
{
	struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
	nanosleep(&t, NULL);
}

/* What is missing of build/venv's python and the generated classes, or
 * NULL: a test without them fails, saying what makes them. */
static char missing[1200];

static const char *python_missing(void)
{
	char init[600];
	snprintf(init, sizeof init, "%s/evo_lcm/__init__.py", py_path);
	if (access(venv_python, X_OK) != 0)
		snprintf(missing, sizeof missing,
			 "%s is missing: run `make deps` (it makes build/venv "
			 "with the lcm package from PyPI)",
			 venv_python);
	else if (access(init, R_OK) != 0)
		snprintf(missing, sizeof missing,
			 "%s is missing: run `make` (it generates the Python "
			 "classes of lcmtypes/evo_remote.lcm)",
			 init);
	else
		return NULL;
	return missing;
}

#define NEED_PYTHON()                                                          \
	do {                                                                   \
		const char *miss_ = python_missing();                          \
		CHECK(miss_ == NULL);                                          \
		if (miss_) {                                                   \
			printf("    %s\n", miss_);                             \
			return;                                                \
		}                                                              \
	} while (0)

/* ---- the simulator as a child process ------------------------------------ */

typedef struct sim {
	pid_t pid;
	char name[64];
	char out[512]; /* its stdout and stderr */
	char log[512]; /* its --log */
} sim;

/* corridor.py under `name` with `envs` environments on the test's URL,
 * and options `more`, started and ready (0), or -1. */
static int sim_start(sim *s, const char *name, int envs, const char *more)
{
	snprintf(s->name, sizeof s->name, "%s", name);
	snprintf(s->out, sizeof s->out, "%s/%s.out", cli_tmp, name);
	snprintf(s->log, sizeof s->log, "%s/%s.log", cli_tmp, name);
	char cmd[4096];
	snprintf(cmd, sizeof cmd,
		 "PYTHONPATH=%s exec %s remotes/corridor/corridor.py --name %s "
		 "--environments %d --url '%s' --log %s %s >%s 2>&1",
		 py_path, venv_python, name, envs, url, s->log, more, s->out);
	s->pid = fork();
	if (s->pid < 0)
		return -1;
	if (s->pid == 0) {
		signal(SIGINT, SIG_DFL);
		signal(SIGTERM, SIG_DFL);
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	double limit = mono() + 30;
	for (;;) {
		char *t = cli_read("%s", s->out);
		int ready = t && strstr(t, " serves ");
		free(t);
		if (ready)
			return 0;
		int st;
		if (mono() > limit || waitpid(s->pid, &st, WNOHANG) == s->pid) {
			char *o = cli_read("%s", s->out);
			printf("  corridor.py did not start: %s\n",
			       o ? o : "(no output)");
			free(o);
			kill(s->pid, SIGKILL);
			waitpid(s->pid, &st, 0);
			s->pid = 0;
			return -1;
		}
		sleep_ms(5);
	}
}

/* SIGTERM; its exit status (-1: killed after 10 s), the time in *secs. */
static int sim_stop(sim *s, double *secs)
{
	*secs = 0;
	if (s->pid <= 0)
		return -1;
	double t0 = mono();
	kill(s->pid, SIGTERM);
	int st = 0, killed = 0;
	while (waitpid(s->pid, &st, WNOHANG) != s->pid) {
		if (mono() - t0 > 10) {
			kill(s->pid, SIGKILL);
			waitpid(s->pid, &st, 0);
			killed = 1;
			break;
		}
		sleep_ms(2);
	}
	*secs = mono() - t0;
	s->pid = 0;
	return !killed && WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* ---- the same messages as peer_encode.py's ------------------------------- */

static evo_wire_hello hello_of(evo_remote_kind kind, int64_t session,
			       const char *data_url, int32_t envs,
			       int32_t tick_us, const char *const *sensors,
			       unsigned ns, const char *const *acts,
			       unsigned na, const char *name)
{
	evo_wire_hello h;
	memset(&h, 0, sizeof h);
	h.protocol = EVO_WIRE_PROTOCOL;
	snprintf(h.name, sizeof h.name, "%s", name);
	h.session = session;
	snprintf(h.url, sizeof h.url, "%s", data_url);
	h.kind = kind;
	h.environments = envs;
	h.tick_us = tick_us;
	h.n_sensors = ns;
	h.n_actuators = na;
	for (unsigned i = 0; i < ns; i++)
		snprintf(h.sensor[i], EVO_NAME_MAX, "%s", sensors[i]);
	for (unsigned i = 0; i < na; i++)
		snprintf(h.actuator[i], EVO_NAME_MAX, "%s", acts[i]);
	return h;
}

static const char *const corridor_sensors[] = {"P1", "P2", "P3", "P4",
					       "P5", "GB", "GD"};
static const char *const corridor_actuators[] = {"MotL", "MotR"};

/* The hex of message `label` in the helper's output, decoded into bytes:
 * their count, or -1. */
static int peer_bytes(const char *text, const char *label, unsigned char *b,
		      size_t cap)
{
	char key[64];
	snprintf(key, sizeof key, "\n%s ", label);
	const char *p = strstr(text, key);
	if (!p && strncmp(text, key + 1, strlen(key + 1)) == 0)
		p = text - 1;
	if (!p)
		return -1;
	p += strlen(key);
	size_t n = 0;
	while (p[0] && p[0] != '\n' && p[1] && n < cap) {
		unsigned v;
		if (sscanf(p, "%2x", &v) != 1)
			return -1;
		b[n++] = (unsigned char)v;
		p += 2;
	}
	return (int)n;
}

static int same_bytes(const char *text, const char *label,
		      const unsigned char *mine, int n)
{
	static unsigned char theirs[EVO_WIRE_MAX_BYTES];
	int k = peer_bytes(text, label, theirs, sizeof theirs);
	if (n <= 0 || k != n || memcmp(theirs, mine, (size_t)n) != 0) {
		printf("  %s: Python's %d bytes and evo's %d differ\n", label,
		       k, n);
		return 0;
	}
	return 1;
}

TEST(python_encodes_every_message_as_evo_does)
{
	NEED_PYTHON();
	int rc = cli_capture(out, sizeof out,
			     "PYTHONPATH=%s %s tests/sim/remote/peer_encode.py",
			     py_path, venv_python);
	CHECK_EQ_INT(rc, 0);
	static unsigned char mine[EVO_WIRE_MAX_BYTES],
	    theirs[EVO_WIRE_MAX_BYTES];
	char why[256];
	int n, k;

	evo_wire_hello h = hello_of(EVO_REMOTE_SIMULATOR, INT64_MAX,
				    "udpm://239.255.76.67:9568?ttl=0", 64, 0,
				    corridor_sensors, 7, corridor_actuators, 2,
				    "corridor-test_1"),
		       hd;
	n = evo_wire_encode_hello(&h, mine, sizeof mine);
	CHECK(same_bytes(out, "hello_sim", mine, n));
	k = peer_bytes(out, "hello_sim", theirs, sizeof theirs);
	CHECK_EQ_INT(
	    evo_wire_decode_hello(theirs, (size_t)k, &hd, why, sizeof why),
	    EVO_WIRE_OK);
	CHECK(hd.session == INT64_MAX && hd.environments == 64 &&
	      hd.kind == EVO_REMOTE_SIMULATOR && hd.n_sensors == 7 &&
	      hd.n_actuators == 2);
	CHECK_EQ_STR(hd.name, "corridor-test_1");
	CHECK_EQ_STR(hd.url, "udpm://239.255.76.67:9568?ttl=0");
	CHECK_EQ_STR(hd.sensor[6], "GD");
	CHECK_EQ_STR(hd.actuator[1], "MotR");

	static const char *const s1[] = {"S1"};
	h = hello_of(EVO_REMOTE_ROBOT, 1, "", 1, 20000, s1, 1, NULL, 0, "r");
	n = evo_wire_encode_hello(&h, mine, sizeof mine);
	CHECK(same_bytes(out, "hello_robot", mine, n));
	k = peer_bytes(out, "hello_robot", theirs, sizeof theirs);
	CHECK_EQ_INT(
	    evo_wire_decode_hello(theirs, (size_t)k, &hd, why, sizeof why),
	    EVO_WIRE_OK);
	CHECK(hd.kind == EVO_REMOTE_ROBOT && hd.tick_us == 20000 &&
	      hd.n_actuators == 0);

	evo_wire_who w = {.protocol = EVO_WIRE_PROTOCOL}, wd;
	snprintf(w.from, sizeof w.from, "evo-4242");
	n = evo_wire_encode_who(&w, mine, sizeof mine);
	CHECK(same_bytes(out, "who", mine, n));
	k = peer_bytes(out, "who", theirs, sizeof theirs);
	CHECK_EQ_INT(
	    evo_wire_decode_who(theirs, (size_t)k, &wd, why, sizeof why),
	    EVO_WIRE_OK);
	CHECK_EQ_STR(wd.from, "evo-4242");
	w.from[0] = 0;
	n = evo_wire_encode_who(&w, mine, sizeof mine);
	CHECK(same_bytes(out, "who_empty", mine, n));

	/* LCM's int64 carries evo's unsigned seeds: 2^64 - 1 and 2^63 are
	 * -1 and -2^63 in Python */
	evo_wire_control c = {.session = 123456789012345LL,
			      .env = 63,
			      .op = EVO_CONTROL_RESET,
			      .episode = (1LL << 53) + 1,
			      .layout_seed = UINT64_MAX,
			      .seed = 1ULL << 63},
			 cd;
	snprintf(c.name, sizeof c.name, "c");
	n = evo_wire_encode_control(&c, mine, sizeof mine);
	CHECK(same_bytes(out, "control_reset", mine, n));
	k = peer_bytes(out, "control_reset", theirs, sizeof theirs);
	CHECK_EQ_INT(
	    evo_wire_decode_control(theirs, (size_t)k, &cd, why, sizeof why),
	    EVO_WIRE_OK);
	CHECK(cd.layout_seed == UINT64_MAX && cd.seed == 1ULL << 63 &&
	      cd.episode == (1LL << 53) + 1 && cd.op == EVO_CONTROL_RESET &&
	      cd.env == 63);
	memset(&c, 0, sizeof c);
	snprintf(c.name, sizeof c.name, "corridor");
	c.session = 7;
	c.op = EVO_CONTROL_STOP;
	n = evo_wire_encode_control(&c, mine, sizeof mine);
	CHECK(same_bytes(out, "control_stop", mine, n));

	evo_wire_sensors s = {.session = 99,
			      .env = 3,
			      .episode = 2,
			      .tick = 399,
			      .n = 7,
			      .value = {0.0, 1.0, 0.1, 1.0 / 3, 5e-324, 0.5,
					0.9999999999999999},
			      .reward = -12.345678901234567,
			      .done = 1},
			 sd;
	snprintf(s.name, sizeof s.name, "corridor");
	n = evo_wire_encode_sensors(&s, mine, sizeof mine);
	CHECK(same_bytes(out, "sensors", mine, n));
	k = peer_bytes(out, "sensors", theirs, sizeof theirs);
	CHECK_EQ_INT(
	    evo_wire_decode_sensors(theirs, (size_t)k, &sd, why, sizeof why),
	    EVO_WIRE_OK);
	CHECK(sd.n == 7 && memcmp(sd.value, s.value, sizeof s.value) == 0 &&
	      sd.reward == s.reward && sd.done == 1 && sd.tick == 399);
	CHECK_EQ_INT(
	    evo_wire_check_values(sd.value, sd.n, &sd.reward, why, sizeof why),
	    EVO_WIRE_OK);
	memset(&s, 0, sizeof s);
	snprintf(s.name, sizeof s.name, "x");
	s.session = -5;
	s.episode = 1;
	s.reward = -0.0;
	n = evo_wire_encode_sensors(&s, mine, sizeof mine);
	CHECK(same_bytes(out, "sensors_none", mine, n));

	evo_wire_command m = {.session = 99,
			      .env = 3,
			      .episode = 2,
			      .tick = 399,
			      .n = 2,
			      .value = {0.25, 0.75}},
			 md;
	snprintf(m.name, sizeof m.name, "corridor");
	n = evo_wire_encode_command(&m, mine, sizeof mine);
	CHECK(same_bytes(out, "command", mine, n));
	k = peer_bytes(out, "command", theirs, sizeof theirs);
	CHECK_EQ_INT(
	    evo_wire_decode_command(theirs, (size_t)k, &md, why, sizeof why),
	    EVO_WIRE_OK);
	CHECK(md.n == 2 && md.value[0] == 0.25 && md.value[1] == 0.75);
}

/* ---- DEMOREMOTESIM against the simulator ------------------------------- */

/* minds/Corridor in the test's folder, its tasks on the test's URL. A
 * learning run takes its only simulator as lost after REMOTETIMEOUT
 * seconds of silence, and ends: 10 s, not 2, so that a busy machine
 * stalling the simulator for a moment does not fail the test. */
static void corridor_mind(void)
{
	cli_sh("[ -d %s/Corridor ] || (cp -r minds/Corridor %s/ && rm -rf "
	       "%s/Corridor/Runs && for t in %s/Corridor/Tasks/*.simbatch; do "
	       "sed -i '/^REMOTENAME:/d' $t && "
	       "printf 'LCMURL:%s\\nREMOTETIMEOUT:10\\nREMOTENAME:"
	       "corridor-demo-%ld,corridor-lock-%ld,corridor-learn-%ld\\n' "
	       ">>$t; done)",
	       cli_tmp, cli_tmp, cli_tmp, cli_tmp, url, (long)getpid(),
	       (long)getpid(), (long)getpid());
}

/* The "reward R over T ticks" of each episode line of evo's output, and
 * of each line of the simulator's log, one per line. */
static void rewards_of(const char *text, char *lines, size_t cap)
{
	size_t k = 0;
	lines[0] = 0;
	for (const char *p = strstr(text, "reward "); p;
	     p = strstr(p + 1, "reward ")) {
		const char *end = strstr(p, " ticks");
		if (!end || k + (size_t)(end - p) + 8 >= cap)
			break;
		k += (size_t)snprintf(lines + k, cap - k, "%.*s ticks\n",
				      (int)(end - p), p);
	}
}

TEST(demoremotesim_runs_to_the_goal_with_the_reward_the_simulator_logs)
{
	NEED_PYTHON();
	corridor_mind();
	char name[64];
	snprintf(name, sizeof name, "corridor-demo-%ld", (long)getpid());
	sim s;
	if (sim_start(&s, name, 1, "--data-url same")) {
		CHECK(0);
		return;
	}
	/* the shipped network, set by hand, reaches the goal */
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Corridor/Tasks/Corridor-DEMO.simbatch "
			     "-nog --seed 7 --episodes 3",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "remote corridor-demo-");
	CHECK_CONTAINS(out, "simulator, 1 environment\n");
	CHECK_CONTAINS(out, "episode 3: reward ");
	char *log = cli_read("%s", s.log);
	CHECK(log && cli_count_lines(log, "env 0 episode ") == 3);
	static char a[4096], b[4096];
	rewards_of(out, a, sizeof a);
	rewards_of(log, b, sizeof b);
	CHECK(a[0] != 0);
	CHECK_EQ_STR(a, b);
	/* every episode ended at the goal, before TICKLIM (400) */
	for (const char *l = log; l && *l;) {
		const char *e = strchr(l, '\n');
		CHECK(e && e - l > 6 && strncmp(e - 6, ", goal", 6) == 0);
		l = e ? e + 1 : NULL;
	}
	for (const char *p = strstr(out, " over "); p;
	     p = strstr(p + 1, " over "))
		CHECK(atol(p + 6) > 0 && atol(p + 6) < 400);
	/* the simulator's behaviour of each episode (docs/remote.md): where
	 * the robot ended, along the 8 m corridor and across it; at the goal
	 * (7.3 m along, within 0.55 m) the first is 0.84 to 0.98 */
	int behaviours = 0;
	for (const char *p = strstr(out, ", behaviour ("); p;
	     p = strstr(p + 1, ", behaviour (")) {
		double x = -1, y = -1;
		CHECK(sscanf(p, ", behaviour (%lf, %lf)", &x, &y) == 2);
		CHECK(x >= 0.84 && x <= 0.98);
		CHECK(y >= 0 && y <= 1);
		behaviours++;
	}
	CHECK_EQ_INT(behaviours, 3);
	free(log);

	/* the same seed: the same episodes, and the same log again */
	rc = cli_capture(out2, sizeof out2,
			 "%s run %s/Corridor/Tasks/Corridor-DEMO.simbatch -nog "
			 "--seed 7 --episodes 3",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_EQ_STR(out2, out);
	log = cli_read("%s", s.log);
	CHECK(log && cli_count_lines(log, "env 0 episode ") == 6);
	const char *second = log;
	for (int i = 0; i < 3 && second; i++) {
		second = strchr(second, '\n');
		second = second ? second + 1 : NULL;
	}
	CHECK(second && strncmp(log, second, (size_t)(second - log)) == 0);
	free(log);

	/* another seed, other corridors */
	rc = cli_capture(out2, sizeof out2,
			 "%s run %s/Corridor/Tasks/Corridor-DEMO.simbatch -nog "
			 "--seed 8 --episodes 3",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	rewards_of(out2, b, sizeof b);
	CHECK(b[0] != 0 && strcmp(a, b) != 0);
	printf("  seed 7: %s", a);

	double secs;
	CHECK_EQ_INT(sim_stop(&s, &secs), 0);
	CHECK(secs < 1.0);
}

/* ---- the simulator driven from here, as evo drives it ---------------------
 */

typedef struct driver {
	evo_link *hello; /* the test's URL: who_t and hello_t */
	evo_link *link;	 /* the episodes' URL (the hello's url): the rest */
	char ch_control[96], ch_command[96], ch_sensors[96];
	const char *name;
	int64_t session;
} driver;

static void publish(driver *d, const char *ch, const unsigned char *b, int n)
{
	evo_err err;
	if (n > 0)
		evo_link_publish(d->link, ch, b, (size_t)n, &err);
}

/* The next sensors_t within ms: 1 with *s and its bytes in raw (*len),
 * 0 when none came. */
static int next_sensors(driver *d, int ms, evo_wire_sensors *s,
			unsigned char *raw, size_t *len)
{
	double limit = mono() + ms / 1000.0;
	evo_err err;
	char why[256];
	while (mono() < limit) {
		evo_link_msg m;
		int left = (int)((limit - mono()) * 1000) + 1;
		if (evo_link_next(d->link, left, &m, &err) <= 0)
			continue;
		if (strcmp(m.channel, d->ch_sensors) != 0)
			continue;
		if (evo_wire_decode_sensors(m.data, m.len, s, why, sizeof why))
			continue;
		if (raw) {
			memcpy(raw, m.data, m.len);
			*len = m.len;
		}
		return 1;
	}
	return 0;
}

static void reset(driver *d, int env, int64_t episode, uint64_t layout,
		  uint64_t seed, int op)
{
	evo_wire_control c = {.session = d->session,
			      .env = env,
			      .op = (evo_wire_control_op)op,
			      .episode = episode,
			      .layout_seed = layout,
			      .seed = seed};
	snprintf(c.name, sizeof c.name, "%s", d->name);
	static unsigned char b[EVO_WIRE_MAX_BYTES];
	publish(d, d->ch_control, b, evo_wire_encode_control(&c, b, sizeof b));
}

static void command(driver *d, const char *name, int64_t session, int env,
		    int64_t episode, int64_t tick, double l, double r,
		    unsigned n)
{
	evo_wire_command c = {.session = session,
			      .env = env,
			      .episode = episode,
			      .tick = tick,
			      .n = n,
			      .value = {l, r, 0.5}};
	snprintf(c.name, sizeof c.name, "%s", name);
	static unsigned char b[EVO_WIRE_MAX_BYTES];
	publish(d, d->ch_command, b, evo_wire_encode_command(&c, b, sizeof b));
}

static double neat_sigmoid(double x)
{
	return 1.0 / (1.0 + exp(-4.9 * x));
}

TEST(the_simulator_repeats_answers_without_stepping_and_ignores_the_rest)
{
	NEED_PYTHON();
	char name[64];
	snprintf(name, sizeof name, "corridor-lock-%ld", (long)getpid());
	driver d = {.name = name};
	evo_err err;
	d.hello = evo_link_open(url, &err);
	snprintf(d.ch_control, sizeof d.ch_control, "EVO_%s_CONTROL", name);
	snprintf(d.ch_command, sizeof d.ch_command, "EVO_%s_COMMAND", name);
	snprintf(d.ch_sensors, sizeof d.ch_sensors, "EVO_%s_SENSORS", name);
	CHECK(d.hello && evo_link_subscribe(d.hello, "EVO_HELLO", &err) == 0);
	if (!d.hello)
		return;
	sim s;
	if (sim_start(&s, name, 2, "")) {
		CHECK(0);
		evo_link_close(d.hello);
		return;
	}

	/* who_t: the hello, with the simulator's names */
	static unsigned char b[EVO_WIRE_MAX_BYTES];
	evo_wire_who w = {.protocol = EVO_WIRE_PROTOCOL};
	snprintf(w.from, sizeof w.from, "test-corridor");
	int nw = evo_wire_encode_who(&w, b, sizeof b);
	CHECK(nw > 0 &&
	      evo_link_publish(d.hello, "EVO_WHO", b, (size_t)nw, &err) == 0);
	evo_wire_hello h;
	int got_hello = 0;
	char why[256];
	for (double limit = mono() + 5; !got_hello && mono() < limit;) {
		evo_link_msg m;
		if (evo_link_next(d.hello, 100, &m, &err) == 1 &&
		    strcmp(m.channel, "EVO_HELLO") == 0 &&
		    evo_wire_decode_hello(m.data, m.len, &h, why, sizeof why) ==
			EVO_WIRE_OK &&
		    strcmp(h.name, name) == 0)
			got_hello = 1;
	}
	CHECK(got_hello);
	if (!got_hello)
		goto out;
	CHECK(h.protocol == EVO_WIRE_PROTOCOL && h.kind == EVO_REMOTE_SIMULATOR &&
	      h.environments == 2 && h.tick_us == 0 && h.n_sensors == 7 &&
	      h.n_actuators == 2);
	for (unsigned i = 0; i < 7; i++)
		CHECK_EQ_STR(h.sensor[i], corridor_sensors[i]);
	CHECK_EQ_STR(h.actuator[0], "MotL");
	CHECK_EQ_STR(h.actuator[1], "MotR");
	d.session = h.session;
	/* its episodes on a port of their own, as evo serve's */
	CHECK(strncmp(h.url, "udpm://239.255.76.67:", 21) == 0 &&
	      strcmp(h.url, url) != 0);
	d.link = evo_link_open(h.url, &err);
	CHECK(d.link && evo_link_subscribe(d.link, d.ch_sensors, &err) == 0);
	if (!d.link)
		goto out;

	/* tick 0 of env 0, and the same RESET again: the same answer */
	static unsigned char a0[EVO_WIRE_MAX_BYTES], again[EVO_WIRE_MAX_BYTES],
	    a1[EVO_WIRE_MAX_BYTES];
	size_t la0 = 0, lagain = 0, la1 = 0, lx;
	evo_wire_sensors sa, sb, sx;
	reset(&d, 0, 1, 11, 22, EVO_CONTROL_RESET);
	CHECK(next_sensors(&d, 2000, &sa, a0, &la0));
	CHECK(sa.env == 0 && sa.episode == 1 && sa.tick == 0 && sa.n == 7 &&
	      sa.reward == 0 && !sa.done);
	CHECK_EQ_INT(
	    evo_wire_check_values(sa.value, sa.n, &sa.reward, why, sizeof why),
	    EVO_WIRE_OK);
	reset(&d, 0, 1, 11, 22, EVO_CONTROL_RESET);
	CHECK(next_sensors(&d, 2000, &sx, again, &lagain));
	CHECK(lagain == la0 && memcmp(again, a0, la0) == 0);
	/* the same episode with another seed is another start; and back */
	reset(&d, 0, 1, 11, 23, EVO_CONTROL_RESET);
	CHECK(next_sensors(&d, 2000, &sx, NULL, NULL));
	CHECK(sx.tick == 0 && memcmp(sx.value, sa.value, sizeof sa.value) != 0);
	reset(&d, 0, 1, 11, 22, EVO_CONTROL_RESET);
	CHECK(next_sensors(&d, 2000, &sx, again, &lagain));
	CHECK(lagain == la0 && memcmp(again, a0, la0) == 0);

	/* env 1, the same seeds: the same world, independent of env 0 */
	reset(&d, 1, 1, 11, 22, EVO_CONTROL_RESET);
	CHECK(next_sensors(&d, 2000, &sb, NULL, NULL));
	CHECK(sb.env == 1 && sb.tick == 0 &&
	      memcmp(sb.value, sa.value, sizeof sa.value) == 0);

	/* tick 0's command, then the same command again: tick 1 again, byte
	 * for byte, without a step */
	command(&d, name, d.session, 0, 1, 0, 0.9, 0.7, 2);
	CHECK(next_sensors(&d, 2000, &sa, a1, &la1));
	CHECK(sa.tick == 1);
	command(&d, name, d.session, 0, 1, 0, 0.9, 0.7, 2);
	CHECK(next_sensors(&d, 2000, &sx, again, &lagain));
	CHECK(lagain == la1 && memcmp(again, a1, la1) == 0);
	command(&d, name, d.session, 1, 1, 0, 0.9, 0.7, 2);
	CHECK(next_sensors(&d, 2000, &sb, NULL, NULL));
	CHECK(sb.env == 1 && sb.tick == 1 && sb.reward == sa.reward &&
	      memcmp(sb.value, sa.value, sizeof sa.value) == 0);
	/* tick 1 in both: had the repeat stepped env 0, they would differ */
	command(&d, name, d.session, 0, 1, 1, 0.9, 0.7, 2);
	CHECK(next_sensors(&d, 2000, &sa, NULL, NULL));
	command(&d, name, d.session, 1, 1, 1, 0.9, 0.7, 2);
	CHECK(next_sensors(&d, 2000, &sb, NULL, NULL));
	CHECK(sa.tick == 2 && sb.tick == 2 && sa.env == 0 && sb.env == 1);
	CHECK(sa.reward == sb.reward && sa.reward != 0 &&
	      memcmp(sb.value, sa.value, sizeof sa.value) == 0);

	/* not for it: junk, another session, another name, an environment
	 * it does not have, a wrong count, a tick ahead, a tick answered long
	 * ago, values out of [0, 1] or NaN: no answer to any */
	publish(&d, d.ch_command, (const unsigned char *)"junk", 4);
	command(&d, name, d.session + 1, 0, 1, 2, 0.5, 0.5, 2);
	command(&d, "someone-else", d.session, 0, 1, 2, 0.5, 0.5, 2);
	command(&d, name, d.session, 2, 1, 2, 0.5, 0.5, 2);
	reset(&d, 2, 1, 11, 22, EVO_CONTROL_RESET);
	command(&d, name, d.session, 0, 1, 2, 0.5, 0.5, 3);
	command(&d, name, d.session, 0, 1, 5, 0.5, 0.5, 2);
	command(&d, name, d.session, 0, 1, 0, 0.5, 0.5, 2);
	command(&d, name, d.session, 0, 1, 2, 1.5, 0.5, 2);
	command(&d, name, d.session, 0, 1, 2, NAN, 0.5, 2);
	CHECK(!next_sensors(&d, 400, &sx, NULL, NULL));
	/* and env 0 still waits for tick 2's command */
	command(&d, name, d.session, 0, 1, 2, 0.9, 0.7, 2);
	CHECK(next_sensors(&d, 2000, &sx, NULL, NULL));
	CHECK(sx.env == 0 && sx.tick == 3);
	/* env 0's RESET again, late: dropped, the episode goes on */
	reset(&d, 0, 1, 11, 22, EVO_CONTROL_RESET);
	CHECK(!next_sensors(&d, 300, &sx, NULL, NULL));
	command(&d, name, d.session, 0, 1, 3, 0.9, 0.7, 2);
	CHECK(next_sensors(&d, 2000, &sx, NULL, NULL));
	CHECK(sx.env == 0 && sx.tick == 4);

	/* env 1 driven to the goal as the shipped network steers; the
	 * command that ended the episode, again: its answer again */
	int done = 0;
	double l = 0.5, r = 0.5;
	for (int t = 2; t < 400 && !done; t++) {
		double P2 = sb.value[1], P3 = sb.value[2], P4 = sb.value[3],
		       GB = sb.value[5];
		l = neat_sigmoid(-1.6 + 2 * GB + P4 + 0.5 * P3);
		r = neat_sigmoid(0.4 - 2 * GB + P2 + 0.5 * P3);
		command(&d, name, d.session, 1, 1, t, l, r, 2);
		if (!next_sensors(&d, 2000, &sb, a1, &la1))
			break;
		done = sb.done;
	}
	CHECK(done);
	CHECK(sb.reward > 50);
	command(&d, name, d.session, 1, 1, sb.tick - 1, l, r, 2);
	CHECK(next_sensors(&d, 2000, &sx, again, &lx));
	CHECK(lx == la1 && memcmp(again, a1, la1) == 0);
	/* but no command after the end */
	command(&d, name, d.session, 1, 1, sb.tick, l, r, 2);
	CHECK(!next_sensors(&d, 300, &sx, NULL, NULL));
	printf("  env 1 reached the goal at tick %lld with reward %.6f\n",
	       (long long)sb.tick, sb.reward);

	/* STOP ends env 0's episode; the same RESET then starts it over */
	reset(&d, 0, 1, 0, 0, EVO_CONTROL_STOP);
	command(&d, name, d.session, 0, 1, 4, 0.9, 0.7, 2);
	CHECK(!next_sensors(&d, 300, &sx, NULL, NULL));
	reset(&d, 0, 1, 11, 22, EVO_CONTROL_RESET);
	CHECK(next_sensors(&d, 2000, &sx, again, &lagain));
	CHECK(lagain == la0 && memcmp(again, a0, la0) == 0);

out:;
	double secs;
	CHECK_EQ_INT(sim_stop(&s, &secs), 0);
	CHECK(secs < 1.0);
	char *o = cli_read("%s", s.out);
	/* junk; session, name, env 2 (command and RESET); the count; the
	 * tick ahead; ticks 0 and 4 (after the goal), env 0's late RESET
	 * and tick 4 (after STOP) stale; 1.5 and NaN */
	CHECK_CONTAINS(o, "dropped a command_t (undecodable: not an "
			  "evo_lcm.command_t");
	CHECK_CONTAINS(o, "corridor: dropped 13 messages (1 undecodable, 4 "
			  "foreign, 1 counts, 2 value, 4 stale, 1 ahead)");
	free(o);
	char *log = cli_read("%s", s.log);
	CHECK_CONTAINS(log, "env 0 episode 1 (layout_seed 11, seed 22): "
			    "reward ");
	CHECK_CONTAINS(log, " over 4 ticks, stopped\n");
	CHECK_CONTAINS(log, "env 1 episode 1 (layout_seed 11, seed 22): ");
	CHECK_CONTAINS(log, ", goal\n");
	free(log);
	evo_link_close(d.link);
	evo_link_close(d.hello);
}

/* ---- LEARNREMOTESIM against the simulator ---------------------------------
 */

/* Column col (0: generation) of each data line of a log.csv, into v; how
 * many lines. */
static int log_column(const char *csv, int col, double *v, int cap)
{
	int n = 0;
	const char *l = csv ? strchr(csv, '\n') : NULL; /* past the header */
	while (l && l[1] && n < cap) {
		l++;
		const char *f = l;
		for (int c = 0; c < col && f; c++) {
			f = strchr(f, ',');
			f = f ? f + 1 : NULL;
		}
		if (!f)
			break;
		v[n++] = atof(f);
		l = strchr(l, '\n');
	}
	return n;
}

/* The mean of the rewards on the episode lines of evo run's output; their
 * count in *n. */
static double mean_reward(const char *text, int *n)
{
	double sum = 0;
	*n = 0;
	/* episode lines only: a drop's sentence says "of episode 2" too */
	for (const char *p = strncmp(text, "episode ", 8) == 0
				 ? text
				 : strstr(text, "\nepisode ");
	     p; p = strstr(p + 1, "\nepisode ")) {
		const char *r = strstr(p, ": reward ");
		if (!r)
			break;
		sum += atof(r + 9);
		++*n;
	}
	return *n ? sum / *n : 0;
}

/* Corridor-NEAT with a population of 24, for 5 generations, on a
 * simulator of 2 environments: the population's mean fitness rises over
 * the generations, and the champion, saved into Skills/, then does better
 * under DEMOREMOTESIM than untrained networks on the same episodes. */
TEST(learnremotesim_trains_a_champion_better_than_untrained_networks)
{
	NEED_PYTHON();
	corridor_mind();
	cli_sh("sed 's/^NEAT_POPSIZE:.*/NEAT_POPSIZE:24/' "
	       "%s/Corridor/Tasks/Corridor-NEAT.simbatch "
	       ">%s/Corridor/Tasks/Small-NEAT.simbatch",
	       cli_tmp, cli_tmp);
	char name[64];
	snprintf(name, sizeof name, "corridor-learn-%ld", (long)getpid());
	sim s;
	if (sim_start(&s, name, 2, "")) {
		CHECK(0);
		return;
	}
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Corridor/Tasks/Small-NEAT.simbatch "
			     "--seed 3 --generations 5 --run %s/learn",
			     cli_evo, cli_tmp, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "NEAT of skill Corridor, seed 3, 2 environments "
			    "on 1 remote simulator");
	CHECK_CONTAINS(out, "champion saved in ");
	char *csv = cli_read("%s/learn/log.csv", cli_tmp);
	double best[8], mean[8];
	int gens = log_column(csv, 1, best, 8);
	CHECK_EQ_INT(log_column(csv, 2, mean, 8), gens);
	CHECK_EQ_INT(gens, 5);
	free(csv);
	if (gens == 5) {
		printf("  mean fitness by generation: %.1f %.1f %.1f %.1f "
		       "%.1f; best %.1f .. %.1f\n",
		       mean[0], mean[1], mean[2], mean[3], mean[4], best[0],
		       best[4]);
		CHECK(mean[4] > mean[0] + 20);
	}
	/* and its own replay on unseen episodes says as much */
	const char *c = strstr(out, "  champion: ");
	const char *u = strstr(out, "  untrained networks (20): ");
	CHECK(c && u);
	if (c && u) {
		double fc = atof(strstr(c, "fitness") + 7),
		       fu = atof(strstr(u, "fitness") + 7);
		printf("  its replay: champion %.1f, untrained networks %.1f\n",
		       fc, fu);
		CHECK(fc > fu + 40);
	}

	/* the champion and untrained networks, on the same episodes: seeds
	 * 21..24, two episodes each */
	double champ = 0, untrained = 0;
	int episodes = 0;
	for (int seed = 21; seed <= 24; seed++) {
		int n1 = 0, n2 = 0;
		rc = cli_capture(
		    out, sizeof out,
		    "%s run %s/Corridor/Tasks/Corridor-DEMO.simbatch "
		    "-nog --seed %d --episodes 2",
		    cli_evo, cli_tmp, seed);
		CHECK_EQ_INT(rc, 0);
		champ += mean_reward(out, &n1);
		rc = cli_capture(
		    out2, sizeof out2,
		    "%s run %s/Corridor/Tasks/Corridor-DEMO.simbatch "
		    "-nog --seed %d --episodes 2 --net Corridor=random",
		    cli_evo, cli_tmp, seed);
		CHECK_EQ_INT(rc, 0);
		untrained += mean_reward(out2, &n2);
		CHECK(n1 == 2 && n2 == 2);
		episodes += n1;
	}
	champ /= 4;
	untrained /= 4;
	printf("  DEMOREMOTESIM over %d episodes: champion mean reward %.1f, "
	       "untrained (random) networks %.1f\n",
	       episodes, champ, untrained);
	CHECK(champ > untrained + 20);
	double secs;
	CHECK_EQ_INT(sim_stop(&s, &secs), 0);
	CHECK(secs < 1.0);
}

/* With a shared key (the task's LCMKEYFILE, corridor.py's --key-file)
 * every message is sealed by one implementation and checked by the
 * other, in Python's hmac and evo's C: the episodes run as without one,
 * and neither side drops anything. */
TEST(a_shared_key_works_between_evo_and_python)
{
	NEED_PYTHON();
	corridor_mind();
	char name[64], more[300];
	snprintf(name, sizeof name, "corridor-key-%ld", (long)getpid());
	cli_write("a-key-shared-with-python\n", "%s/Corridor/Tasks/lcm.key",
		  cli_tmp);
	cli_sh("sed '/^REMOTENAME:/d' %s/Corridor/Tasks/Corridor-DEMO.simbatch "
	       ">%s/Corridor/Tasks/Key.simbatch && printf "
	       "'REMOTENAME:%s\\nLCMKEYFILE:lcm.key\\n' "
	       ">>%s/Corridor/Tasks/Key.simbatch",
	       cli_tmp, cli_tmp, name, cli_tmp);
	snprintf(more, sizeof more, "--key-file %s/Corridor/Tasks/lcm.key",
		 cli_tmp);
	sim s;
	if (sim_start(&s, name, 1, more)) {
		CHECK(0);
		return;
	}
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/Corridor/Tasks/Key.simbatch -nog --seed 7 "
			     "--episodes 2",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "episode 2: reward ");
	CHECK(strstr(out, "dropped") == NULL);
	CHECK(strstr(out, "a-key-shared") == NULL);
	char *log = cli_read("%s", s.log);
	static char a[4096], b[4096];
	rewards_of(out, a, sizeof a);
	rewards_of(log, b, sizeof b);
	CHECK(a[0] != 0);
	CHECK_EQ_STR(a, b);
	free(log);
	/* a keyless evo is not heard: its who_t fails the key */
	cli_sh("sed '/^LCMKEYFILE:/d' %s/Corridor/Tasks/Key.simbatch "
	       ">%s/Corridor/Tasks/NoKey.simbatch",
	       cli_tmp, cli_tmp);
	char cmd[1024], said_path[300];
	snprintf(said_path, sizeof said_path, "%s/nokey.out", cli_tmp);
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/Corridor/Tasks/NoKey.simbatch -nog >%s 2>&1",
		 cli_evo, cli_tmp, said_path);
	int st;
	double secs;
	CHECK_EQ_INT(cli_stop(cmd, s.out, "corridor: dropped a who_t (forged: "
					  "its MAC fails the key)",
			      0, SIGTERM, &st, &secs),
		     0);
	char *nokey = cli_read("%s", said_path);
	CHECK(nokey && !strstr(nokey, "remote corridor-key"));
	free(nokey);
	CHECK_EQ_INT(sim_stop(&s, &secs), 0);
	char *said = cli_read("%s", s.out);
	CHECK(said && strstr(said, "corridor: dropped ") &&
	      strstr(said, " forged)"));
	free(said);
}

int main(void)
{
	if (cli_setup("corridor"))
		return 1;
	const char *v = getenv("EVO_VENV");
	snprintf(venv_python, sizeof venv_python, "%s/bin/python",
		 v && v[0] ? v : "build/venv");
	const char *b = getenv("EVO_BUILD");
	snprintf(py_path, sizeof py_path, "%s/gen/python",
		 b && b[0] ? b : "build");
	/* a port of this run's own; LCM's group */
	snprintf(url, sizeof url, "udpm://239.255.76.67:%ld?ttl=0",
		 20000 + (long)getpid() % 20000);
	RUN(python_encodes_every_message_as_evo_does);
	RUN(demoremotesim_runs_to_the_goal_with_the_reward_the_simulator_logs);
	RUN(the_simulator_repeats_answers_without_stepping_and_ignores_the_rest);
	RUN(learnremotesim_trains_a_champion_better_than_untrained_networks);
	RUN(a_shared_key_works_between_evo_and_python);
	cli_cleanup();
	return test_summary();
}

/* `evo run` end to end (sim/cmd/run.c): every shipped example's DEMOSIM runs
 * headless with the same rewards on every run of a seed; an environment and
 * a bot written in a test's own mind folder run without recompiling;
 * script errors and unknown sensor names end the run with file:line and a
 * non-zero exit and leave no trace behind; traces hold every tick; an
 * environment's own metrics follow each episode's line, headless and in
 * the viewer. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"
#include "support/cli.h"

static void write_file(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");
	if (!f) {
		perror(path);
		return;
	}
	fputs(text, f);
	fclose(f);
}

static void mkdirs(const char *path)
{
	char p[512];
	snprintf(p, sizeof p, "%s", path);
	for (char *s = p + 1; *s; s++)
		if (*s == '/') {
			*s = 0;
			mkdir(p, 0755);
			*s = '/';
		}
	mkdir(p, 0755);
}

/* Number of entries in dir whose name starts with prefix. */
static int count_files(const char *dir, const char *prefix)
{
	DIR *d = opendir(dir);
	int n = 0;
	struct dirent *e;
	while (d && (e = readdir(d)))
		n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
	if (d)
		closedir(d);
	return n;
}

static char out1[1 << 16], out2[1 << 16];

static void same_rewards(const char *task, const char *args)
{
	char cmd[1024];
	snprintf(cmd, sizeof cmd, "%s run %s --headless %s", cli_evo, task,
		 args);
	int a = cli_capture(out1, sizeof out1, "%s", cmd);
	int b = cli_capture(out2, sizeof out2, "%s", cmd);
	CHECK_EQ_INT(a, 0);
	CHECK_EQ_INT(b, 0);
	CHECK_CONTAINS(out1, "episode 1: reward ");
	CHECK_CONTAINS(out1, "episode 2: reward ");
	CHECK_EQ_STR(out1, out2);
	if (a != 0 || strcmp(out1, out2) != 0)
		printf("  %s:\n%s\n---\n%s\n", task, out1, out2);
}

TEST(avoid_demo_is_repeatable)
{
	same_rewards("minds/Avoid/Tasks/Avoid-DEMO.simbatch",
		     "--seed 7 --episodes 2 --ticks 1500");
}

TEST(gto_demo_is_repeatable)
{
	same_rewards("minds/GTO/Tasks/GTO-DEMO.simbatch",
		     "--seed 3 --episodes 2 --ticks 1500");
}

TEST(gtoa_demo_is_repeatable)
{
	same_rewards("minds/GTO/Tasks/GTOA-DEMO.simbatch",
		     "--seed 4 --episodes 2 --ticks 1500");
}

TEST(collect_demo_is_repeatable)
{
	same_rewards("minds/Collect/Tasks/Collect-DEMO.simbatch",
		     "--seed 5 --episodes 2 --ticks 1500");
}

/* Another seed gives other grids, so other rewards. */
TEST(another_seed_gives_another_run)
{
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "%s run minds/Avoid/Tasks/Avoid-DEMO.simbatch -nog "
		 "--seed 1 --ticks 600",
		 cli_evo);
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s", cmd), 0);
	snprintf(cmd, sizeof cmd,
		 "%s run minds/Avoid/Tasks/Avoid-DEMO.simbatch -nog "
		 "--seed 2 --ticks 600",
		 cli_evo);
	CHECK_EQ_INT(cli_capture(out2, sizeof out2, "%s", cmd), 0);
	CHECK(strcmp(out1, out2) != 0);
}

/* A mind folder of the test's own, with its own bot model and
 * environment: found in Bots/ and Envs/, run without recompiling. */
static void make_own_mind(const char *root, const char *env_body,
			  const char *botdesc_extra)
{
	char p[512];
	snprintf(p, sizeof p, "%s/Skills/Go", root);
	mkdirs(p);
	snprintf(p, sizeof p, "%s/Tasks", root);
	mkdirs(p);
	snprintf(p, sizeof p, "%s/Bots", root);
	mkdirs(p);
	snprintf(p, sizeof p, "%s/Envs", root);
	mkdirs(p);
	char text[2048];
	snprintf(text, sizeof text,
		 "SENSORS\nFront:prox\n%sACTUATORS\nLeft:wheel\nRight:wheel\n",
		 botdesc_extra);
	snprintf(p, sizeof p, "%s/Mine.botdesc", root);
	write_file(p, text);
	snprintf(p, sizeof p, "%s/Skills/Go/Go.ades", root);
	write_file(p, "Go\ninput:1\nSE:Front\noutput:2\nMO:Left\nMO:Right\n"
		      "neural\nlayers:0\n");
	snprintf(p, sizeof p, "%s/Skills/Go/Go.net", root);
	/* full speed while the front is clear, stop when it is not */
	write_file(p, "inputs:1\noutputs:2\nnode:1:sigmoid:-4\n"
		      "node:2:sigmoid:-4\noutput:1\noutput:2\nlink:0:1:12\n"
		      "link:0:2:12\n");
	snprintf(p, sizeof p, "%s/Tasks/Go.simbatch", root);
	write_file(p, "TYPE:DEMOSIM\nBOTMODEL:Tiny\nMASTERSKILL:Go\n"
		      "ENV:Corridor\n");
	snprintf(p, sizeof p, "%s/Bots/Tiny.lua", root);
	write_file(p, "return {\n"
		      "  body = { radius = 0.5, density = 1, linear_damping = 2 },\n"
		      "  build = function(bot)\n"
		      "    bot:proximity{ name = 'Front', x = 0.5, range = 5 }\n"
		      "    bot:wheel{ name = 'Left', y = -0.5, max_force = 10 }\n"
		      "    bot:wheel{ name = 'Right', y = 0.5, max_force = 10 }\n"
		      "  end,\n"
		      "}\n");
	snprintf(p, sizeof p, "%s/Envs/Corridor.lua", root);
	write_file(p, env_body);
}

static const char *good_env =
	"local env = {}\n"
	"function env.init(scene, task)\n"
	"  scene:box{ x = 20, y = 0, half_width = 1, half_height = 5 }\n"
	"  env.bot = scene:bot{ x = 0, y = 0 }\n"
	"  scene:reward(function(s) local x = env.bot:pose() return x end)\n"
	"  scene:control('NextOnTimeout', { ticks = 300 })\n"
	"end\n"
	"return env\n";

TEST(own_bot_and_environment_run)
{
	char root[512], cmd[2048];
	snprintf(root, sizeof root, "%s/own/Mine", cli_tmp);
	make_own_mind(root, good_env, "");
	snprintf(cmd, sizeof cmd, "%s run %s/Tasks/Go.simbatch --headless",
		 cli_evo, root);
	int rc = cli_capture(out1, sizeof out1, "%s", cmd);
	CHECK_EQ_INT(rc, 0);
	/* the control ends the episode after 300 checks: 301 ticks */
	CHECK_CONTAINS(out1, "over 301 ticks");
	/* the bot drove towards the wall and stopped short of it: the reward,
	 * the sum of its x over the ticks, is large and positive */
	double reward = 0;
	const char *r = strstr(out1, "reward ");
	if (r)
		reward = atof(r + 7);
	CHECK(reward > 1000);
	if (rc != 0)
		printf("%s\n", out1);
}

/* A failing run: exit 1, the message names file:line, no trace left. A
 * run that hangs is stopped after a minute and fails. */
static void fails_with(const char *sub, const char *env_body,
		       const char *botdesc_extra, const char *want1,
		       const char *want2)
{
	char root[512], cmd[2048], trace_dir[512];
	snprintf(root, sizeof root, "%s/%s/Mine", cli_tmp, sub);
	make_own_mind(root, env_body, botdesc_extra);
	snprintf(trace_dir, sizeof trace_dir, "%s/%s", cli_tmp, sub);
	snprintf(cmd, sizeof cmd,
		 "timeout -s KILL 60 %s run %s/Tasks/Go.simbatch --headless "
		 "--trace %s/t.trace",
		 cli_evo, root, trace_dir);
	int rc = cli_capture(out1, sizeof out1, "%s", cmd);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out1, want1);
	CHECK_CONTAINS(out1, want2);
	CHECK_EQ_INT(count_files(trace_dir, "t.trace"), 0);
	if (rc != 1)
		printf("%s\n", out1);
}

TEST(syntax_error_names_file_and_line)
{
	fails_with("syntax",
		   "local env = {}\nfunction env.init(scene, task)\n"
		   "  scene:bot{ x = 0 y = 0 }\nend\nreturn env\n",
		   "", "Envs/Corridor.lua:3:", "'}' expected");
}

TEST(reward_runtime_error_names_file_and_line)
{
	fails_with("runtime",
		   "local env = {}\n"
		   "function env.init(scene, task)\n"
		   "  env.bot = scene:bot{}\n"
		   "  scene:reward(function(s)\n"
		   "    if s:tick() > 50 then return nil + 1 end\n"
		   "    return 0\n"
		   "  end)\n"
		   "end\n"
		   "return env\n",
		   "", "Envs/Corridor.lua:5:", "arithmetic");
}

TEST(unknown_sensor_names_botdesc_line)
{
	fails_with("sensor", good_env, "Rear:prox\n", "Mine.botdesc:3:",
		   "sensor 'Rear' is not on the bot");
}

TEST(unknown_option_is_an_error)
{
	fails_with("option",
		   "local env = {}\nfunction env.init(scene, task)\n"
		   "  scene:bot{}\n"
		   "  scene:grid{ spacin = 20 }\nend\nreturn env\n",
		   "", "Envs/Corridor.lua:4:", "unknown option 'spacin'");
}

/* The sandbox (docs/lua.md, "What a script may use"): no io, and of os
 * only os.clock; the error names the script's line. */
TEST(io_is_not_available)
{
	fails_with("io",
		   "local env = {}\nfunction env.init(scene, task)\n"
		   "  scene:bot{}\n"
		   "  local f = io.open('/etc/passwd')\nend\nreturn env\n",
		   "", "Envs/Corridor.lua:4:",
		   "io.open is not available in scene scripts");
}

TEST(os_keeps_only_clock)
{
	fails_with("os",
		   "local env = {}\nfunction env.init(scene, task)\n"
		   "  scene:bot{}\n"
		   "  assert(os.clock() >= 0)\n"
		   "  os.execute('true')\nend\nreturn env\n",
		   "", "Envs/Corridor.lua:5:",
		   "os.execute is not available in scene scripts");
}

TEST(no_dofile_or_binary_chunks)
{
	fails_with("dofile",
		   "local env = {}\nfunction env.init(scene, task)\n"
		   "  scene:bot{}\n"
		   "  assert(dofile == nil and loadfile == nil)\n"
		   "  assert(load('return 1')() == 1)\n"
		   "  error(select(2, load(string.dump(function() end))))\n"
		   "end\nreturn env\n",
		   "", "Envs/Corridor.lua:6:", "binary chunk");
}

/* The instruction budget (docs/lua.md): an endless loop in init or in a
 * reward function ends the run at the loop's line, within seconds. */
TEST(endless_init_runs_out_of_budget)
{
	fails_with("budget_init",
		   "local env = {}\nfunction env.init(scene, task)\n"
		   "  scene:bot{}\n"
		   "  while true do end\nend\nreturn env\n",
		   "",
		   "Envs/Corridor.lua:4: the script ran past its budget of "
		   "100000000 instructions in init",
		   "an endless loop?");
}

/* The loop catches errors with pcall: the budget's error still ends it. */
TEST(endless_reward_runs_out_of_budget)
{
	fails_with(
	    "budget_reward",
	    "local env = {}\n"
	    "function env.init(scene, task)\n"
	    "  env.bot = scene:bot{}\n"
	    "  scene:reward(function(s)\n"
	    "    if s:tick() < 20 then return 0 end\n"
	    "    while true do pcall(function() while true do end end) end\n"
	    "  end)\n"
	    "end\n"
	    "return env\n",
	    "",
	    "Envs/Corridor.lua:6: the script ran past its budget of "
	    "1000000 instructions in a reward function",
	    "an endless loop?");
}

/* math.random is seeded from the run's seed at each reset: a bot placed
 * with it gives the same rewards on the same seed, others on another. */
TEST(math_random_follows_the_seed)
{
	char root[512], cmd[2048];
	static char out3[1 << 16];
	snprintf(root, sizeof root, "%s/random/Mine", cli_tmp);
	make_own_mind(
	    root,
	    "local env = {}\n"
	    "function env.init(scene, task)\n"
	    "  env.bot = scene:bot{}\n"
	    "  scene:reward(function(s) local x, y = env.bot:pose() "
	    "return x + y end)\n"
	    "  scene:control('NextOnTimeout', { ticks = 50 })\n"
	    "end\n"
	    "function env.reset(scene, episode)\n"
	    "  env.bot:place(math.random(-20, 20), 10 * math.random(), "
	    "math.random(0, 359))\n"
	    "end\n"
	    "return env\n",
	    "");
	for (int i = 0; i < 3; i++) {
		snprintf(cmd, sizeof cmd,
			 "%s run %s/Tasks/Go.simbatch --headless --episodes 2 "
			 "--seed %d",
			 cli_evo, root, i < 2 ? 5 : 6);
		char *out = i == 0 ? out1 : i == 1 ? out2 : out3;
		CHECK_EQ_INT(cli_capture(out, sizeof out1, "%s", cmd), 0);
		CHECK_CONTAINS(out, "episode 2: reward ");
	}
	CHECK_EQ_STR(out1, out2);
	CHECK(strcmp(out1, out3) != 0);
	/* the two episodes start from other places */
	const char *e2 = strstr(out1, "episode 2: reward ");
	CHECK(e2 && strncmp(out1 + 18, e2 + 18, 12) != 0);
}

/* The trace has a header and one line per tick, each with the botdesc's
 * sensors and actuators. */
TEST(trace_records_every_tick)
{
	char cmd[2048], path[512];
	snprintf(path, sizeof path, "%s/collect.trace", cli_tmp);
	snprintf(cmd, sizeof cmd,
		 "%s run minds/Collect/Tasks/Collect-DEMO.simbatch --headless "
		 "--ticks 500 --trace %s",
		 cli_evo, path);
	CHECK_EQ_INT(cli_capture(out1, sizeof out1, "%s", cmd), 0);
	FILE *f = fopen(path, "r");
	CHECK(f != NULL);
	if (!f)
		return;
	char line[4096];
	int n = 0, bad = 0;
	long expect_tick = 0;
	while (fgets(line, sizeof line, f)) {
		n++;
		if (n == 1)
			CHECK_EQ_STR(line, "evo-trace 2\n");
		if (n == 3)
			CHECK(strncmp(line, "sensors 20 S1 S2", 16) == 0);
		if (n == 4)
			CHECK_EQ_STR(line, "actuators 3 MotL MotR EMAG\n");
		if (n == 5)
			CHECK_EQ_STR(line, "skills 7 Collect GTO+Avoid GTDZ+Avoid "
					   "MoveForward TurnLeft TurnRight "
					   "ClawControl\n");
		if (n <= 5)
			continue;
		/* tick, 20 sensors, '|', 3 actuators, '|', 7 influences; the
		 * master's influence is 1.0 every tick (DESIGN.md) */
		int fields = 0, master = 0;
		long tick = atol(line);
		for (char *t = strtok(line, " \n"); t; t = strtok(NULL, " \n"))
			if (++fields == 27)
				master = atoi(t);
		bad += fields != 33 || tick != expect_tick || master != 65536;
		expect_tick++;
	}
	fclose(f);
	CHECK_EQ_INT(n, 5 + 500);
	CHECK_EQ_INT(bad, 0);
}

/* Corridor, reporting three metrics of its own: the ticks the front
 * sensor read under 0.5 (something within half its range), the reward so
 * far, and the ticks. */
static const char *metered_env =
	"local env = {}\n"
	"function env.init(scene, task)\n"
	"  scene:box{ x = 20, y = 0, half_width = 1, half_height = 5 }\n"
	"  env.bot = scene:bot{ x = 0, y = 0 }\n"
	"  scene:reward(function(s) local x = env.bot:pose() return x end)\n"
	"  scene:control('NextOnTimeout', { ticks = 300 })\n"
	"  env.near = scene:metric('near_wall')\n"
	"  env.paid = scene:metric('paid')\n"
	"  env.steps = scene:metric('steps')\n"
	"end\n"
	"function env.post_step(scene)\n"
	"  if env.bot:value('Front') < 0.5 then env.near:add() end\n"
	"  env.paid:set(scene:episode_reward())\n"
	"  env.steps:add()\n"
	"end\n"
	"return env\n";

/* The text after `key` on episode e's line of out, up to `end` (at most
 * cap - 1 characters); "" when absent. */
static void episode_field(const char *out, int e, const char *key,
			  const char *end, char *buf, size_t cap)
{
	char head[32];
	snprintf(head, sizeof head, "episode %d: ", e);
	buf[0] = 0;
	const char *line = strstr(out, head);
	const char *nl = line ? strchr(line, '\n') : NULL;
	const char *k = line ? strstr(line, key) : NULL;
	if (!k || (nl && k > nl))
		return;
	k += strlen(key);
	size_t n = strcspn(k, end);
	if (n >= cap)
		n = cap - 1;
	memcpy(buf, k, n);
	buf[n] = 0;
}

/* Roam, the Avoid example's environment, starts each episode facing a
 * random way over the whole turn: bot:place takes degrees, and was once
 * given radians, which kept every start within 6.3 degrees of east. Roam
 * itself runs here, with one line added to its reset that reports the
 * start heading as a metric. */
TEST(roam_starts_episodes_facing_every_way)
{
	cli_sh("rm -rf %s/roam && mkdir -p %s/roam && cp -r minds/Avoid "
	       "%s/roam/",
	       cli_tmp, cli_tmp, cli_tmp);
	char *roam = cli_read("minds/Avoid/Envs/Roam.lua");
	CHECK(roam != NULL);
	if (!roam)
		return;
	const char *reset = "\tbot:place(0, 5, scene:random(0, 360))\n";
	char *at = strstr(roam, reset);
	CHECK(at != NULL);
	if (!at) {
		free(roam);
		return;
	}
	static char spy[1 << 14];
	const char *init = "function env.init(scene, task)\n";
	char *in = strstr(roam, init);
	CHECK(in != NULL && in < at);
	if (!in) {
		free(roam);
		return;
	}
	/* declare the metric first thing in init; set it after the place */
	size_t k = 0;
	k += (size_t)snprintf(spy + k, sizeof spy - k, "%.*s%s",
			      (int)(in - roam), roam, init);
	k += (size_t)snprintf(spy + k, sizeof spy - k,
			      "\tenv.heading = scene:metric(\"heading\")\n");
	const char *after_init = in + strlen(init);
	k += (size_t)snprintf(spy + k, sizeof spy - k, "%.*s%s",
			      (int)(at - after_init), after_init, reset);
	k += (size_t)snprintf(spy + k, sizeof spy - k,
			      "\tlocal _, _, a = bot:pose()\n"
			      "\tenv.heading:set(a %% 360)\n%s",
			      at + strlen(reset));
	free(roam);
	CHECK_EQ_INT(cli_write(spy, "%s/roam/Avoid/Envs/Roam.lua", cli_tmp), 0);
	int rc = cli_capture(out1, sizeof out1,
			     "%s run %s/roam/Avoid/Tasks/Avoid-DEMO.simbatch -nog "
			     "--episodes 12 --ticks 1",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 0);
	double lo = 360, hi = -1;
	int n = 0;
	for (const char *p = strstr(out1, "heading "); p;
	     p = strstr(p + 1, "heading ")) {
		double a = atof(p + 8);
		lo = a < lo ? a : lo;
		hi = a > hi ? a : hi;
		n++;
	}
	CHECK_EQ_INT(n, 12);
	/* twelve draws over the whole turn: spread over half of it at least
	 * (all twelve within 180 degrees has a chance of 12 / 2^11) */
	CHECK(hi - lo > 180);
	if (!(hi - lo > 180))
		printf("  headings from %g to %g:\n%s\n", lo, hi, out1);
}

TEST(an_environments_metrics_follow_its_episode_lines)
{
	char root[512], trace[512];
	snprintf(root, sizeof root, "%s/metered/Mine", cli_tmp);
	snprintf(trace, sizeof trace, "%s/metered/t.trace", cli_tmp);
	make_own_mind(root, metered_env, "");
	int rc = cli_capture(out1, sizeof out1,
			     "%s run %s/Tasks/Go.simbatch --headless "
			     "--episodes 2 --trace %s",
			     cli_evo, root, trace);
	CHECK_EQ_INT(rc, 0);
	/* The ticks the front sensor read under 0.5, counted again from the
	 * trace, where each tick's line holds what the mind read: Front,
	 * the botdesc's one sensor, is its second field (Q15.16, 32768 =
	 * 0.5); each episode's ticks start again at 0. */
	long near[3] = {0, 0, 0};
	FILE *f = fopen(trace, "r");
	CHECK(f != NULL);
	char line[512];
	int e = 0;
	while (f && fgets(line, sizeof line, f)) {
		long tick, front;
		if (sscanf(line, "%ld %ld |", &tick, &front) != 2)
			continue;
		e += tick == 0;
		if (e >= 1 && e <= 2 && front < 32768)
			near[e]++;
	}
	if (f)
		fclose(f);
	CHECK_EQ_INT(e, 2);
	for (int k = 1; k <= 2; k++) {
		char want[64], got[160], reward[64], paid[64];
		snprintf(want, sizeof want, "%ld", near[k]); /* a count */
		episode_field(out1, k, ", near_wall ", ",", got, sizeof got);
		CHECK_EQ_STR(got, want);
		/* the bot drove up to the wall and stopped short of it */
		CHECK(near[k] > 0 && near[k] < 301);
		/* paid holds the episode's reward as it ended: the line's */
		episode_field(out1, k, ": reward ", " ", reward, sizeof reward);
		episode_field(out1, k, ", paid ", ",", paid, sizeof paid);
		CHECK(reward[0] != 0);
		CHECK(atof(paid) == atof(reward));
		/* after the other fields, in the order declared */
		episode_field(out1, k, " over ", "\n", got, sizeof got);
		CHECK(strncmp(got, "301 ticks, ", 11) == 0);
		CHECK(strstr(got, " collision ticks, near_wall ") != NULL);
		CHECK(strstr(got, ", steps 301") &&
		      strlen(strstr(got, ", steps ")) == 11);
	}
	if (rc != 0)
		printf("%s\n", out1);
	/* The viewer prints the same line: 5-tick episodes in real time
	 * under a virtual display. */
	rc = cli_capture(out1, sizeof out1,
			 "xvfb-run -a sh -c 'timeout -k 30 -s TERM 20 %s run "
			 "%s/Tasks/Go.simbatch --ticks 5 --episodes 2'",
			 cli_evo, root);
	CHECK_EQ_INT(rc, 0);
	for (int k = 1; k <= 2; k++) {
		char got[128], reward[64], paid[64];
		episode_field(out1, k, " over ", "\n", got, sizeof got);
		CHECK(strncmp(got, "5 ticks, 0 collision ticks, near_wall 0, "
				   "paid ", 46) == 0);
		CHECK(strstr(got, ", steps 5") &&
		      strlen(strstr(got, ", steps ")) == 9);
		episode_field(out1, k, ": reward ", " ", reward, sizeof reward);
		episode_field(out1, k, ", paid ", ",", paid, sizeof paid);
		CHECK(atof(paid) == atof(reward));
	}
	if (rc != 0)
		printf("%s\n", out1);
}

/* EXP_GTDZA reports zones_reached: the ticks its post_step found the bot
 * in the zone (and moved the zone away). Counted again here two ways:
 * from the trace, the ticks whose SENSDZ (what post_step reads, as the
 * mind read it) is true; and from the reward, which pays 100 * (0.8 -
 * 0.5) = 30 for each such tick plus ClosingOnTarget's thousandths. The
 * Collect example's GTDZ+Avoid skill drives BotType8 to zones: on seed 4
 * it reaches some (it was trained in an arena without obstacles, so in
 * EXP_GTDZA's grid it soon touches one, which ends the episode). */
TEST(gtdza_reports_the_zones_reached)
{
	char trace[512];
	snprintf(trace, sizeof trace, "%s/gtdza.trace", cli_tmp);
	CHECK_EQ_INT(cli_sh("rm -rf %s/gtdza && mkdir -p %s/gtdza && "
			    "cp -r minds/Collect %s/gtdza/ && printf "
			    "'TYPE:DEMOSIM\\nBOTMODEL:BotType8\\n"
			    "MASTERSKILL:GTDZ+Avoid\\nENV:EXP_GTDZA\\n"
			    "TICKLIM:3000\\n' > "
			    "%s/gtdza/Collect/Tasks/GTDZA.simbatch",
			    cli_tmp, cli_tmp, cli_tmp, cli_tmp),
		     0);
	int rc = cli_capture(out1, sizeof out1,
			     "%s -nog %s/gtdza/Collect/Tasks/GTDZA.simbatch "
			     "--seed 4 --episodes 3 --trace %s",
			     cli_evo, cli_tmp, trace);
	CHECK_EQ_INT(rc, 0);
	/* SENSDZ's field in a tick's line: its place among the sensors of
	 * the trace's header, after the tick */
	FILE *f = fopen(trace, "r");
	CHECK(f != NULL);
	static char line[8192];
	int col = -1, e = 0;
	long in_zone[4] = {0, 0, 0, 0};
	while (f && fgets(line, sizeof line, f)) {
		if (strncmp(line, "sensors ", 8) == 0) {
			int k = 0;
			for (char *t = strtok(line + 8, " \n"); t;
			     t = strtok(NULL, " \n"), k++)
				if (strcmp(t, "SENSDZ") == 0)
					col = k; /* after the count */
			continue;
		}
		if (col < 1 || line[0] < '0' || line[0] > '9')
			continue;
		char *p = line;
		long tick = strtol(p, &p, 10);
		e += tick == 0;
		long v = -1;
		for (int k = 1; k <= col; k++)
			v = strtol(p, &p, 10);
		if (e >= 1 && e <= 3 && v > 32768)
			in_zone[e]++;
	}
	if (f)
		fclose(f);
	CHECK(col >= 1);
	CHECK_EQ_INT(e, 3);
	long total = 0;
	for (int k = 1; k <= 3; k++) {
		char got[64], want[64], reward[64];
		snprintf(want, sizeof want, "%ld", in_zone[k]);
		episode_field(out1, k, ", zones_reached ", ",\n", got,
			      sizeof got);
		CHECK_EQ_STR(got, want);
		episode_field(out1, k, ": reward ", " ", reward, sizeof reward);
		double r = atof(reward);
		CHECK(r > 30.0 * (double)in_zone[k] - 1 &&
		      r < 30.0 * (double)in_zone[k] + 1);
		total += in_zone[k];
	}
	CHECK(total > 0);
	if (rc != 0 || total == 0)
		printf("%s\n", out1);
}

/* An environment without a control function, in a task without TICKLIM:
 * its one episode never ends. */
static const char *endless_env =
	"local env = {}\n"
	"function env.init(scene, task)\n"
	"  scene:box{ x = 20, y = 0, half_width = 1, half_height = 5 }\n"
	"  scene:bot{ x = 0, y = 0 }\n"
	"end\n"
	"return env\n";

/* SIGTERM and SIGINT stop a headless run whose episode would never end
 * within a second, between two ticks: it exits 0 and keeps its trace,
 * complete up to the last tick (docs/running.md), with no temporary file
 * left behind. */
static void stop_a_long_run(int sig)
{
	char root[256], cmd[2048], path[512], out[512];
	snprintf(root, sizeof root, "%s/endless/Mine", cli_tmp);
	make_own_mind(root, endless_env, "");
	snprintf(path, sizeof path, "%s/long-%d.trace", cli_tmp, sig);
	snprintf(out, sizeof out, "%s/long-%d.out", cli_tmp, sig);
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/Tasks/Go.simbatch --headless "
		 "--trace %s > %s 2>&1",
		 cli_evo, root, path, out);
	int st;
	double s;
	CHECK_EQ_INT(cli_stop(cmd, out, "", 0.5, sig, &st, &s), 0);
	CHECK(WIFEXITED(st) && WEXITSTATUS(st) == 0);
	CHECK(s >= 0 && s < 1.0);
	if (s >= 1.0)
		fprintf(stderr, "    signal %d: %.3f s to stop\n", sig, s);
	CHECK_EQ_INT(cli_sh("ls %s.tmp.* 2>/dev/null | grep -q .", path), 1);
	char *t = cli_read("%s", path);
	CHECK(t != NULL);
	if (!t)
		return;
	size_t len = strlen(t);
	CHECK(len > 0 && t[len - 1] == '\n');
	CHECK(strncmp(t, "evo-trace 2\n", 12) == 0);
	/* After the 5 header lines: each tick's fields (the tick, 1
	 * sensor, '|', 2 actuators, '|', one influence per skill), the
	 * tick one more than the line before, from 0. */
	int n = 0, bad = 0, ticks = 0, skills = -1;
	long prev = -1;
	for (char *line = strtok(t, "\n"); line; line = strtok(NULL, "\n")) {
		if (++n == 5 && strncmp(line, "skills ", 7) == 0)
			skills = atoi(line + 7);
		if (n <= 5)
			continue;
		int fields = 0;
		for (const char *c = line; *c; c++)
			fields += *c != ' ' && (c == line || c[-1] == ' ');
		long tick = atol(line);
		bad += fields != 6 + skills || tick != prev + 1;
		prev = tick;
		ticks++;
	}
	CHECK(ticks > 0);
	CHECK(skills >= 1);
	CHECK_EQ_INT(bad, 0);
	free(t);
}

TEST(sigterm_and_sigint_stop_a_long_run_and_keep_its_trace)
{
#ifdef __SANITIZE_THREAD__
	/* ThreadSanitizer holds an asynchronous signal back until the
	 * thread next enters a function it intercepts, and the tick loop of
	 * this run enters none: under make test-tsan evo would not see the
	 * signal at all. test-plain and test-asan run this test. */
	printf("  (skipped under ThreadSanitizer)\n");
	return;
#endif
	stop_a_long_run(SIGTERM);
	stop_a_long_run(SIGINT);
}

/* A --trace path too long for its temporary file's name is refused
 * before the run, with a message that says so, and nothing is written
 * under a cut name. */
TEST(too_long_trace_path_is_refused)
{
	char path[1400], seg[201];
	memset(seg, 't', 200);
	seg[200] = 0;
	int n = snprintf(path, sizeof path, "%s/tr", cli_tmp);
	for (int k = 0; k < 5; k++)
		n += snprintf(path + n, sizeof path - (size_t)n, "/%s", seg);
	int dir = n;
	n += snprintf(path + n, sizeof path - (size_t)n, "/%.100s.trace", seg);
	CHECK(n > 1100 && n < (int)sizeof path);
	CHECK_EQ_INT(cli_sh("mkdir -p %.*s", dir, path), 0);
	CHECK_EQ_INT(cli_capture(out1, sizeof out1,
				 "%s run minds/Collect/Tasks/Collect-DEMO.simbatch "
				 "--headless --ticks 5 --trace %s",
				 cli_evo, path),
		     1);
	CHECK(strstr(out1, "path too long") != NULL);
	CHECK_EQ_INT(cli_sh("find %s/tr -type f | grep -q .", cli_tmp), 1);
}

/* A count that does not fit the int or long it goes into is refused
 * (exit 2) with the range, never silently cut: --threads 4294967297 was
 * one thread, and --episodes past INT_MAX would have wrapped. */
TEST(out_of_range_counts_are_refused)
{
	static const char *const bad[][2] = {
	    {"--threads 4294967297", "--threads expects a whole number 0..1024"},
	    {"--threads 1025", "--threads expects a whole number 0..1024"},
	    {"--episodes 4294967297",
	     "--episodes expects a whole number 0..2147483647"},
	    {"--ticks 1e30", "--ticks expects a whole number 0.."},
	    {"--ticks 99999999999999999999", "--ticks expects a whole number"},
	    /* it stands for NUMGEN, 1..1000000 (docs/formats.md) */
	    {"--generations 1000001",
	     "--generations expects a whole number 0..1000000"},
	};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		/* No such task: the arguments are read first (exit 2);
		 * had one been let through, the load fails (exit 1). */
		CHECK_EQ_INT(cli_capture(out1, sizeof out1,
					 "%s run %s/no-such.simbatch %s",
					 cli_evo, cli_tmp, bad[k][0]),
			     2);
		CHECK(strstr(out1, bad[k][1]) != NULL);
		if (!strstr(out1, bad[k][1]))
			fprintf(stderr, "    for %s: %s\n", bad[k][0], out1);
	}
}

int main(void)
{
	if (cli_setup("run"))
		return 1;
	RUN(avoid_demo_is_repeatable);
	RUN(gto_demo_is_repeatable);
	RUN(gtoa_demo_is_repeatable);
	RUN(collect_demo_is_repeatable);
	RUN(another_seed_gives_another_run);
	RUN(own_bot_and_environment_run);
	RUN(syntax_error_names_file_and_line);
	RUN(reward_runtime_error_names_file_and_line);
	RUN(unknown_sensor_names_botdesc_line);
	RUN(unknown_option_is_an_error);
	RUN(io_is_not_available);
	RUN(os_keeps_only_clock);
	RUN(no_dofile_or_binary_chunks);
	RUN(endless_init_runs_out_of_budget);
	RUN(endless_reward_runs_out_of_budget);
	RUN(math_random_follows_the_seed);
	RUN(trace_records_every_tick);
	RUN(roam_starts_episodes_facing_every_way);
	RUN(an_environments_metrics_follow_its_episode_lines);
	RUN(gtdza_reports_the_zones_reached);
	RUN(sigterm_and_sigint_stop_a_long_run_and_keep_its_trace);
	RUN(too_long_trace_path_is_refused);
	RUN(out_of_range_counts_are_refused);
	cli_cleanup();
	return test_summary();
}

/* The scene scripts' sandbox and limits (docs/lua.md, "What a script may
 * use" and "Limits"), end to end: a hostile script in a mind folder of
 * the test's own, run by `evo run`, cannot load native code or binary
 * chunks, read files outside the mind folder and lua/, escape the
 * instruction budget, the time limit or the memory limit, or crash evo
 * with an error value; SIGTERM stops it inside a library call; a hostile
 * checkpoint cannot keep --resume busy. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <lauxlib.h>
#include <lua.h>

#include "harness.h"
#include "support/cli.h"

static char out[1 << 16];

static double now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* A mind folder ROOT=cli_tmp/sub/Mine with a bot model of its own and
 * the environment env_body as Envs/Corridor.lua; task_extra is added to
 * its task Tasks/Go.simbatch. */
static void make_mind(const char *sub, const char *env_body,
		      const char *task_extra, char *root, size_t cap)
{
	snprintf(root, cap, "%s/%s/Mine", cli_tmp, sub);
	cli_sh("mkdir -p %s/Skills/Go %s/Tasks %s/Bots %s/Envs", root, root,
	       root, root);
	cli_write("SENSORS\nFront:prox\nACTUATORS\nLeft:wheel\nRight:wheel\n",
		  "%s/Mine.botdesc", root);
	cli_write("Go\ninput:1\nSE:Front\noutput:2\nMO:Left\nMO:Right\n"
		  "neural\nlayers:0\n",
		  "%s/Skills/Go/Go.ades", root);
	cli_write("inputs:1\noutputs:2\nnode:1:sigmoid:-4\nnode:2:sigmoid:-4\n"
		  "output:1\noutput:2\nlink:0:1:12\nlink:0:2:12\n",
		  "%s/Skills/Go/Go.net", root);
	char task[1024];
	snprintf(
	    task, sizeof task,
	    "TYPE:DEMOSIM\nBOTMODEL:Tiny\nMASTERSKILL:Go\nENV:Corridor\n%s",
	    task_extra);
	cli_write(task, "%s/Tasks/Go.simbatch", root);
	cli_write("return {\n"
		  "  body = { radius = 0.5 },\n"
		  "  build = function(bot)\n"
		  "    bot:proximity{ name = 'Front', x = 0.5, range = 5 }\n"
		  "    bot:wheel{ name = 'Left', y = -0.5 }\n"
		  "    bot:wheel{ name = 'Right', y = 0.5 }\n"
		  "  end,\n"
		  "}\n",
		  "%s/Bots/Tiny.lua", root);
	cli_write(env_body, "%s/Envs/Corridor.lua", root);
}

/* Run the task headless for `ticks` ticks (at most `limit` seconds, then
 * SIGKILL); the output in `out`, the exit status returned, the seconds
 * in *secs. */
static int run(const char *root, int ticks, int limit, double *secs)
{
	double t0 = now();
	int rc = cli_capture(out, sizeof out,
			     "timeout -s KILL %d %s run %s/Tasks/Go.simbatch "
			     "--headless --ticks %d",
			     limit, cli_evo, root, ticks);
	if (secs)
		*secs = now() - t0;
	return rc;
}

/* An environment whose init does `body` (after adding its bot) and whose
 * reward function does `reward` before returning 0. */
static void env_with(char *buf, size_t cap, const char *init,
		     const char *reward)
{
	snprintf(buf, cap,
		 "local env = {}\n"
		 "function env.init(scene, task)\n"
		 "  env.bot = scene:bot{}\n"
		 "%s\n"
		 "  scene:reward(function(s)\n"
		 "%s\n"
		 "    return 0\n"
		 "  end)\n"
		 "end\n"
		 "return env\n",
		 init, reward);
}

/* Issue 27, item 1: a script set package.cpath and `require` dlopen()ed
 * a library it shipped, whose constructor ran inside evo. */
TEST(native_code_is_never_loaded)
{
	char root[512], env[2048], init[1024];
	snprintf(root, sizeof root, "%s/native/Mine", cli_tmp);
	snprintf(init, sizeof init,
		 "  package.cpath = '%s/?.so'\n  require 'evil'", root);
	env_with(env, sizeof env, init, "");
	make_mind("native", env, "", root, sizeof root);
	/* a library whose constructor leaves a file behind */
	char src[1024];
	snprintf(src, sizeof src,
		 "#include <stdio.h>\n"
		 "__attribute__((constructor)) static void ran(void)\n"
		 "{ FILE *f = fopen(\"%s/ran\", \"w\"); if (f) fclose(f); }\n",
		 root);
	CHECK_EQ_INT(cli_write(src, "%s/evil.c", root), 0);
	CHECK_EQ_INT(
	    cli_sh("cc -shared -fPIC -o %s/evil.so %s/evil.c", root, root), 0);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:4: package.cpath cannot be set "
			    "in scene scripts");
	char *ran = cli_read("%s/ran", root);
	CHECK(ran == NULL);
	free(ran);
	/* nor is there a loadlib or a searcher to call */
	env_with(env, sizeof env,
		 "  assert(package.loadlib == nil)\n"
		 "  assert(package.searchers == nil)\n"
		 "  error('no loadlib')",
		 "");
	make_mind("native2", env, "", root, sizeof root);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:6: no loadlib");
}

static int write_chunk(lua_State *L, const void *p, size_t n, void *f)
{
	(void)L;
	return fwrite(p, 1, n, f) == n ? 0 : 1;
}

/* Item 2: `require` loaded a binary chunk, which `load` refuses (a
 * patched one crashes the VM). */
TEST(require_loads_text_only)
{
	char root[512], env[2048];
	env_with(env, sizeof env, "  local v = require 'bin'", "");
	make_mind("binary", env, "", root, sizeof root);
	/* a valid binary chunk that returns 42 */
	lua_State *L = luaL_newstate();
	char path[600];
	snprintf(path, sizeof path, "%s/bin.lua", root);
	FILE *f = fopen(path, "wb");
	CHECK(L && f && luaL_loadstring(L, "return 42") == LUA_OK);
	if (L && f)
		CHECK_EQ_INT(lua_dump(L, write_chunk, f, 0), 0);
	if (f)
		fclose(f);
	if (L)
		lua_close(L);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 1);
	CHECK_CONTAINS(out, "bin.lua");
	CHECK_CONTAINS(out, "attempt to load a binary chunk");
}

/* Item 3: package.path = "/etc/?"; require "passwd" read a file outside
 * the mind folder and lua/, and its syntax error printed part of it. A
 * module that is a link to a file outside is refused as well. */
TEST(require_stays_in_the_mind_folder_and_lua)
{
	char root[512], env[2048];
	env_with(env, sizeof env,
		 "  package.path = '/etc/?'\n  require 'passwd'", "");
	make_mind("path", env, "", root, sizeof root);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:4: package.path cannot be set "
			    "in scene scripts");
	CHECK(strstr(out, "root:") == NULL);

	env_with(env, sizeof env, "  require '..etc.passwd'", "");
	make_mind("path2", env, "", root, sizeof root);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:4: require '..etc.passwd': a "
			    "module's name is names of letters");

	/* Mine/leak.lua -> a secret outside the mind folder */
	env_with(env, sizeof env, "  require 'leak'", "");
	make_mind("link", env, "", root, sizeof root);
	CHECK_EQ_INT(
	    cli_write("SECRET text, not Lua\n", "%s/link/secret", cli_tmp), 0);
	CHECK_EQ_INT(cli_sh("ln -s %s/link/secret %s/leak.lua", cli_tmp, root),
		     0);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 1);
	CHECK_CONTAINS(out, "leads out of");
	CHECK(strstr(out, "SECRET") == NULL);
	/* an environment that is a link out of the mind folder is not
	 * found there either */
	CHECK_EQ_INT(
	    cli_write("SECRET text, not Lua\n", "%s/link/secret2", cli_tmp), 0);
	CHECK_EQ_INT(cli_sh("ln -sf %s/link/secret2 %s/Envs/Corridor.lua",
			    cli_tmp, root),
		     0);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 1);
	CHECK_CONTAINS(out, "environment 'Corridor': ");
	CHECK_CONTAINS(out, "Envs/Corridor.lua leads out of its folder");
	CHECK(strstr(out, "SECRET") == NULL);
	/* and a module of the mind folder, required by its dotted name,
	 * still loads */
	env_with(env, sizeof env,
		 "  local m = require 'lib.mine'\n"
		 "  assert(m.x == 7 and package.loaded['lib.mine'] == m)",
		 "");
	make_mind("modules", env, "", root, sizeof root);
	cli_sh("mkdir -p %s/lib", root);
	cli_write("return { x = 7 }\n", "%s/lib/mine.lua", root);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 0);
}

/* Item 4, finalizers: a looping __gc ran with the hooks off, and again at
 * lua_close, with no budget. */
TEST(a_finalizer_is_refused)
{
	char root[512], env[2048];
	env_with(env, sizeof env,
		 "  setmetatable({}, { __gc = function() while true do end "
		 "end })",
		 "");
	make_mind("gc", env, "", root, sizeof root);
	double secs;
	CHECK_EQ_INT(run(root, 10, 20, &secs), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:4: setmetatable: __gc is not "
			    "available in scene scripts");
}

/* Item 4, a message handler that loops after the budget's error (it ran
 * with the hooks off), and a coroutine that swallows it: both end the run
 * at the loop's line. */
TEST(the_budget_holds_through_xpcall_and_coroutines)
{
	char root[512], env[2048];
	env_with(env, sizeof env, "",
		 "    xpcall(function() while true do end end,\n"
		 "           function() while true do end end)");
	make_mind("xpcall", env, "", root, sizeof root);
	CHECK_EQ_INT(run(root, 10, 30, NULL), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:6: the script ran past its "
			    "budget of 1000000 instructions in a reward "
			    "function");

	env_with(env, sizeof env, "",
		 "    local co = coroutine.create(function() while true do "
		 "end end)\n"
		 "    coroutine.resume(co)");
	make_mind("coroutine", env, "", root, sizeof root);
	CHECK_EQ_INT(run(root, 10, 30, NULL), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:6: the script ran past its "
			    "budget of 1000000 instructions in a reward "
			    "function");
}

/* Item 4, the environment's __index read outside a protected call: an
 * error there was a Lua PANIC (SIGABRT), a loop a hang. */
TEST(the_environments_index_runs_under_the_limits)
{
	char root[512];
	static const char *const env =
	    "local env = {}\n"
	    "function env.init(scene, task) scene:bot{} end\n"
	    "return setmetatable(env, { __index = function(t, k)\n"
	    "  if k == 'post_step' then error('no ' .. k) end\n"
	    "end })\n";
	make_mind("index", env, "", root, sizeof root);
	CHECK_EQ_INT(run(root, 10, 30, NULL), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:4: no post_step");
	static const char *const loop =
	    "local env = {}\n"
	    "function env.init(scene, task) scene:bot{} end\n"
	    "return setmetatable(env, { __index = function(t, k)\n"
	    "  if k == 'obstacles' then while true do end end\n"
	    "end })\n";
	make_mind("index2", loop, "", root, sizeof root);
	CHECK_EQ_INT(run(root, 10, 30, NULL), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:4: the script ran past its "
			    "budget of 100000000 instructions in init");
}

/* Item 4, a C library call that takes seconds in a few instructions: a
 * pattern that backtracks, in post_step. The watchdog ends the run at the
 * line that called it, a grace second after the 0.5 s limit. */
TEST(a_library_call_that_does_not_return_is_stopped)
{
	char root[512];
	static const char *const env =
	    "local env = {}\n"
	    "function env.init(scene, task) scene:bot{} end\n"
	    "function env.post_step(scene)\n"
	    "  local s = ('a'):rep(400)\n"
	    "  return s:find('.-.-.-.-b')\n"
	    "end\n"
	    "return env\n";
	make_mind("pattern", env, "", root, sizeof root);
	double secs;
	CHECK_EQ_INT(run(root, 20, 60, &secs), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:5: the script ran past its "
			    "time limit of 0.5 s in post_step");
	CHECK(secs < 10);
	/* called through pcall, whose frame has no line: the line that
	 * called pcall */
	static const char *const via_pcall =
	    "local env = {}\n"
	    "function env.init(scene, task) scene:bot{} end\n"
	    "function env.post_step(scene)\n"
	    "  local s = ('a'):rep(400)\n"
	    "  pcall(s.find, s, '.-.-.-.-b')\n"
	    "end\n"
	    "return env\n";
	make_mind("pattern-pcall", via_pcall, "", root, sizeof root);
	CHECK_EQ_INT(run(root, 20, 60, &secs), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:5: the script ran past its "
			    "time limit of 0.5 s in post_step");
	/* a call that ends, but past its limit, fails too; LUABUDGET:4
	 * makes the limit 2 s, which a 100-character subject keeps */
	static const char *const slow =
	    "local env = {}\n"
	    "function env.init(scene, task) scene:bot{} end\n"
	    "function env.post_step(scene)\n"
	    "  local t = os.clock()\n"
	    "  repeat local x = ('a'):rep(60):find('.-.-.-.-b')\n"
	    "  until os.clock() - t > 0.6\n"
	    "end\n"
	    "return env\n";
	make_mind("pattern2", slow, "", root, sizeof root);
	CHECK_EQ_INT(run(root, 20, 60, &secs), 1);
	CHECK_CONTAINS(out, "the script ran past its time limit of 0.5 s in "
			    "post_step");
	make_mind("pattern3", slow, "LUABUDGET:4\n", root, sizeof root);
	CHECK_EQ_INT(run(root, 2, 60, &secs), 0);
}

/* Item 4: SIGTERM and SIGINT stop evo within a second while a script
 * loops in Lua or hangs in a library call. */
static void stop_while(const char *sub, const char *post_step, int sig,
		       int want_signalled)
{
	char root[512], env[2048], cmd[2048], ready[600];
	snprintf(env, sizeof env,
		 "local env = {}\n"
		 "function env.init(scene, task) scene:bot{} end\n"
		 "function env.post_step(scene)\n"
		 "  print('looping') \n"
		 "%s\n"
		 "end\n"
		 "return env\n",
		 post_step);
	make_mind(sub, env, "LUABUDGET:1000\n", root, sizeof root);
	snprintf(ready, sizeof ready, "%s/%s/out", cli_tmp, sub);
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/Tasks/Go.simbatch --headless --ticks 5 "
		 ">%s 2>&1",
		 cli_evo, root, ready);
	int status = 0;
	double secs = 0;
	CHECK_EQ_INT(cli_stop(cmd, ready, "looping", 0.3, sig, &status, &secs),
		     0);
	CHECK(secs < 1.5);
	if (want_signalled) {
		CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 128 + sig);
		char *text = cli_read("%s", ready);
		CHECK(text && strstr(text, "Envs/Corridor.lua:5: stopped by "
					   "signal"));
		free(text);
	} else {
		/* stopped in Lua: the run ends as a stopped run does */
		CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
	}
}

TEST(sigterm_and_sigint_stop_a_script)
{
#ifdef __SANITIZE_THREAD__
	printf("  (skipped under ThreadSanitizer)\n");
	return;
#endif
	stop_while("stop_lua", "  while true do end", SIGTERM, 0);
	stop_while("stop_lua2", "  while true do end", SIGINT, 0);
	stop_while("stop_c", "  return ('a'):rep(400):find('.-.-.-.-b')",
		   SIGTERM, 1);
	stop_while("stop_c2", "  return ('a'):rep(400):find('.-.-.-.-b')",
		   SIGINT, 1);
}

/* Item 5: an init that kept 1.5 GB of strings ran on. Each state has a
 * memory limit (LUAMEMORY, in MB), which a pcall does not lift. */
TEST(memory_is_limited)
{
	char root[512], env[2048];
	env_with(env, sizeof env,
		 "  local keep = {}\n"
		 "  pcall(function()\n"
		 "    for i = 1, 100 do keep[i] = ('x'):rep(1000000) .. i end\n"
		 "  end)",
		 "");
	make_mind("memory", env, "LUAMEMORY:16\n", root, sizeof root);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 1);
	CHECK_CONTAINS(out, "Envs/Corridor.lua:6: the script's Lua state "
			    "reached its memory limit of 16 MB in init "
			    "(LUAMEMORY raises it");
	/* 100 MB fits the default */
	make_mind("memory2", env, "", root, sizeof root);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 0);
	/* the keys' ranges, at their lines */
	make_mind("memory3", env, "LUAMEMORY:15\n", root, sizeof root);
	CHECK_EQ_INT(run(root, 10, 60, NULL), 1);
	CHECK_CONTAINS(out, "Tasks/Go.simbatch:5: LUAMEMORY: expected a whole "
			    "number from 16 to 65536, found '15'");
	make_mind("memory4", env, "LUABUDGET:1001\n", root, sizeof root);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/Tasks/Go.simbatch", cli_evo,
				 root),
		     1);
	CHECK_CONTAINS(out, "Tasks/Go.simbatch:5: LUABUDGET: expected a whole "
			    "number from 1 to 1000, found '1001'");
}

/* Item 6: error({}) printed "(null)" (NULL passed to %s). Any error
 * value gets the script's line. */
TEST(any_error_value_gets_a_message)
{
	static const struct {
		const char *raise, *want;
	} cases[] = {
	    {"error({})",
	     "Envs/Corridor.lua:6: (an error value of type table)"},
	    {"error(nil)", "Envs/Corridor.lua:6: (an error value of type nil)"},
	    {"error(setmetatable({}, {__tostring = function() return "
	     "'custom' end}))",
	     "Envs/Corridor.lua:6: custom"},
	    {"error(setmetatable({}, {__tostring = function() error({}) "
	     "end}))",
	     "Envs/Corridor.lua:6: (an error value of type table)"},
	    {"error(true)", "Envs/Corridor.lua:6: (an error value of type "
			    "boolean)"},
	};
	for (unsigned i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		char root[512], env[2048], sub[32];
		char body[300];
		snprintf(body, sizeof body, "    if s:tick() > 3 then %s end",
			 cases[i].raise);
		env_with(env, sizeof env, "", body);
		snprintf(sub, sizeof sub, "errval%u", i);
		make_mind(sub, env, "", root, sizeof root);
		CHECK_EQ_INT(run(root, 10, 30, NULL), 1);
		CHECK_CONTAINS(out, cases[i].want);
		CHECK(strstr(out, "(null)") == NULL);
	}
}

/* Item 7: a 45-byte checkpoint.lua with a pattern that backtracks kept
 * --resume busy for over 20 s. A checkpoint is read as data. */
TEST(a_hostile_checkpoint_is_refused_at_once)
{
	char root[512];
	snprintf(root, sizeof root, "%s/resume/XOR", cli_tmp);
	CHECK_EQ_INT(cli_sh("mkdir -p %s/resume && cp -r minds/XOR %s/resume/ "
			    "&& mkdir -p %s/Runs/XOR-NEAT-seed1",
			    cli_tmp, cli_tmp, root),
		     0);
	CHECK_EQ_INT(cli_write("return (\"a\"):rep(400):find(\".-.-.-.-b\")\n",
			       "%s/Runs/XOR-NEAT-seed1/checkpoint.lua", root),
		     0);
	double t0 = now();
	int rc =
	    cli_capture(out, sizeof out,
			"timeout -s KILL 60 %s run %s/Tasks/XOR-NEAT.simbatch "
			"--seed 1 --resume --threads 1",
			cli_evo, root);
	CHECK_EQ_INT(rc, 1);
	CHECK(now() - t0 < 10);
	CHECK_CONTAINS(out, "Runs/XOR-NEAT-seed1/checkpoint.lua:1: not plain "
			    "data as evo writes it");
	/* item 5: reading a checkpoint is bounded in memory too: 18 MB of
	 * text under LUAMEMORY:16, and 12 MB of it in 14 MB of tables and
	 * strings under LUAMEMORY:20 */
	CHECK_EQ_INT(
	    cli_sh("awk 'BEGIN { s = sprintf(\"%%1000s\", \"\"); "
		   "gsub(/ /, \"x\", s); printf \"return {\"; "
		   "for (i = 0; i < 18000; i++) printf \"\\\"%%s\\\",\", "
		   "s; print \"}\" }' > %s/Runs/XOR-NEAT-seed1/"
		   "checkpoint.lua && echo LUAMEMORY:16 >> "
		   "%s/Tasks/XOR-NEAT.simbatch",
		   root, root),
	    0);
	rc = cli_capture(out, sizeof out,
			 "timeout -s KILL 60 %s run %s/Tasks/XOR-NEAT.simbatch "
			 "--seed 1 --resume --threads 1",
			 cli_evo, root);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "Runs/XOR-NEAT-seed1/checkpoint.lua: reading it "
			    "(17 MB) would pass the learning loop's memory "
			    "limit of 16 MB (LUAMEMORY raises it");
	CHECK_EQ_INT(cli_sh("sed -i 's/LUAMEMORY:16/LUAMEMORY:22/' "
			    "%s/Tasks/XOR-NEAT.simbatch && awk 'BEGIN { "
			    "printf \"return {\"; for (i = 0; i < 1200000; "
			    "i++) printf \"{},\"; print \"}\" }' > "
			    "%s/Runs/XOR-NEAT-seed1/checkpoint.lua",
			    root, root),
		     0);
	rc = cli_capture(out, sizeof out,
			 "timeout -s KILL 60 %s run %s/Tasks/XOR-NEAT.simbatch "
			 "--seed 1 --resume --threads 1",
			 cli_evo, root);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "Runs/XOR-NEAT-seed1/checkpoint.lua: reading it "
			    "reached the Lua state's memory limit (LUAMEMORY "
			    "raises it");
}

/* A sibling of items 1 and 3: the learning loop's state has every
 * library (io, os, package.loadlib), and its `require` looked in the mind
 * folder first, so a mind folder that shipped learn/common.lua ran its
 * code there. The loop's modules come from lua/ only. */
TEST(the_learning_loop_loads_evos_modules_only)
{
	char root[512];
	snprintf(root, sizeof root, "%s/learnmods/XOR", cli_tmp);
	CHECK_EQ_INT(cli_sh("mkdir -p %s/learnmods && cp -r minds/XOR "
			    "%s/learnmods/ && mkdir -p %s/learn",
			    cli_tmp, cli_tmp, root),
		     0);
	CHECK_EQ_INT(cli_write("io.open(os.getenv('EVO_MARK'), 'w'):close()\n"
			       "error('the mind folder\\'s module ran')\n",
			       "%s/learn/common.lua", root),
		     0);
	int rc = cli_capture(out, sizeof out,
			     "EVO_MARK=%s/ran timeout -s KILL 120 %s run "
			     "%s/Tasks/XOR-NEAT.simbatch --generations 1 "
			     "--threads 1",
			     root, cli_evo, root);
	CHECK_EQ_INT(rc, 0);
	CHECK(strstr(out, "module ran") == NULL);
	char *ran = cli_read("%s/ran", root);
	CHECK(ran == NULL);
	free(ran);
}

int main(void)
{
	if (cli_setup("lua-sandbox"))
		return 1;
	RUN(native_code_is_never_loaded);
	RUN(require_loads_text_only);
	RUN(require_stays_in_the_mind_folder_and_lua);
	RUN(a_finalizer_is_refused);
	RUN(the_budget_holds_through_xpcall_and_coroutines);
	RUN(the_environments_index_runs_under_the_limits);
	RUN(a_library_call_that_does_not_return_is_stopped);
	RUN(sigterm_and_sigint_stop_a_script);
	RUN(memory_is_limited);
	RUN(any_error_value_gets_a_message);
	RUN(a_hostile_checkpoint_is_refused_at_once);
	RUN(the_learning_loop_loads_evos_modules_only);
	cli_cleanup();
	return test_summary();
}

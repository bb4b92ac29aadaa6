/* evo — the Lua 5.4 layer of a scene: the `evo` module through which bot
 * models (BOTMODEL) and environments (ENV) build a scene, and the hooks
 * that let a Lua function act as a reward or control function.
 *
 * One Lua state per scene, never shared between threads. A bot model or
 * environment named NAME is looked up first in the mind folder (Bots/NAME.lua,
 * Envs/NAME.lua), then in evo's lua/ folder (lua/bots/, lua/envs/).
 * docs/lua.md describes the module. */
#ifndef EVO_LUA_EVO_H
#define EVO_LUA_EVO_H

#include <signal.h>
#include <stddef.h>

#include "base/err.h"
#include "evo/evo.h"
#include "world2d/scene.h"
#include "world3d/scene3d.h"

typedef struct evo_lua evo_lua;

/* A team of the task (docs/teams.md), as the environment sees it. */
typedef struct evo_lua_team {
	const char *name;
	const char *botmodel;
	const char *mind_dir; /* its bot model is looked for here first */
	int size;
} evo_lua_team;

/* The limits of a run's Lua states (docs/lua.md, "Limits"): every
 * instruction budget and time limit of a call into a scene script is
 * multiplied by budget_scale (the task's LUABUDGET, 1..1000), and a state
 * may hold at most memory bytes (LUAMEMORY, in MB). */
typedef struct evo_lua_limits {
	double budget_scale;
	size_t memory;
} evo_lua_limits;

#define EVO_LUA_MEMORY_MB 512 /* LUAMEMORY's default */

/* The defaults: scale 1, EVO_LUA_MEMORY_MB. */
evo_lua_limits evo_lua_default_limits(void);

/* A task's LUABUDGET and LUAMEMORY (in range: the key table checks them at
 * their line); absent keys keep the defaults. 0, or -1 with err set. */
int evo_lua_limits_read(const evo_simbatch *sb, const char *task_path,
			evo_lua_limits *out, evo_err *err);

/* The flag SIGINT and SIGTERM set (a handler's `*flag = sig`): a call
 * into a scene script under way stops at its next instruction count, and
 * one inside a library call that does not return ends the process about
 * half a second later, with exit status 128 + sig. Process-wide; NULL
 * stops watching. */
void evo_lua_watch_stop(volatile sig_atomic_t *flag);

/* A Lua state whose allocator refuses to grow it past `memory` bytes
 * while its record's `enforce` is non-zero; `hit` is set when it refused.
 * Closed with evo_lua_state_close. NULL when out of memory. The learning
 * loop's state (sim/learn/learn.c) is one. */
typedef struct evo_lua_mem {
	size_t used, limit;
	int enforce;
	int hit;
	/* called at the first refusal, inside the allocation (it may only
	 * read the state) */
	void (*on_hit)(void *ctx);
	void *ctx;
} evo_lua_mem;
struct lua_State *evo_lua_state_new(size_t memory, evo_lua_mem **mem);
void evo_lua_state_close(struct lua_State *L, evo_lua_mem *mem);

/* The error value at idx as a message: a string or number as it is,
 * anything else "(an error value of type T)". Never NULL. */
const char *evo_lua_errstr(struct lua_State *L, int idx);

/* In L, a state of evo's own whose memory is mem (the learning loop's),
 * push a guard for a script of a mind folder it runs in a sandbox (an
 * OPENENDED generator, lua/learn/openended.lua): a table with
 * call(what, kind, fn, ...), fn(...) under a scene script's limits of
 * loading ("load") or of reset (any other kind), and require(loaded,
 * env), a scene script's require whose modules have env for globals,
 * and patterns(t), which gives the string table t a scene script's
 * pattern functions (they note the line for the watchdog; docs/lua.md,
 * "Limits" and "What a script may use"). */
void evo_lua_open_guard(struct lua_State *L, evo_lua_mem *mem,
			const evo_lua_limits *limits, const char *mind_dir);

/* Register the module `evo.data` in L: evo.data.read(text, name) reads
 * the plain data serialize.dump writes (lua/learn/serialize.lua: numbers,
 * strings, booleans and tables after "return ") without running it, and
 * raises "NAME:LINE: ..." on anything else. A checkpoint is data. */
void evo_lua_open_data(struct lua_State *L);

typedef struct evo_lua_def {
	/* the scene the scripts build (not owned): a 2D scene, or a 3D one
	 * (DEMO3DSIM, LEARN3DSIM; docs/world3d.md) */
	evo_scene *scene;
	evo_scene3d *scene3d;
	const char *mind_dir; /* searched first; may be NULL */
	const char *lua_dir;  /* evo's lua/ folder; NULL: evo_lua_dir() */
	const char *botmodel; /* BOTMODEL */
	const evo_simbatch *task; /* handed to env.init as a table; may be NULL */
	/* The task's teams (scene:teams(), scene:bot{team = ...}); none in a
	 * one-agent task. Copied. At most EVO_SCENE_MAX_TEAMS. */
	const evo_lua_team *teams;
	int n_teams;
	/* the task's file, for messages about its LUABUDGET and LUAMEMORY */
	const char *task_path;
	/* NULL: read from the task (evo_lua_limits_read), defaults without
	 * one */
	const evo_lua_limits *limits;
} evo_lua_def;

/* The lua/ folder evo uses: $EVO_LUA_DIR, else lua/ beside the folder of
 * the evo program (a build tree), else share/evo/lua under its prefix. */
const char *evo_lua_dir(void);

/* Point the standard `require` of a state of evo's own (the learning
 * loop's) at lua_dir only, and at no C modules. Scene scripts have a
 * loader of their own (docs/lua.md). */
struct lua_State;
void evo_lua_set_path(struct lua_State *L, const char *lua_dir);

/* A Lua state with the evo module, ready to load an environment. Sets
 * the scene's hooks. NULL with err set on failure. */
evo_lua *evo_lua_create(const evo_lua_def *def, evo_err *err);
void evo_lua_destroy(evo_lua *l);

/* Load environment `env` and run its init(scene, task), which adds the
 * bots (built by the bot model), elements, rewards and controls. Returns
 * 0, or -1 with err set to "file:line: message". */
int evo_lua_init_env(evo_lua *l, const char *env, evo_err *err);

/* After evo_scene_reset: the environment's reset(scene, episode), if it
 * has one. */
int evo_lua_reset(evo_lua *l, int episode, evo_err *err);

/* At an episode's end: the environment's behaviour(scene, bot), for the
 * learning agent's bot (docs/lua.md, "What an episode did"). Writes its
 * values, each a number in [0, 1], to out[0 .. max-1] and returns how
 * many (1 .. max); 0 when the environment has no behaviour function; -1
 * with err set ("Envs/Maze.lua:40: env.behaviour returned ...") when it
 * fails or returns anything else. */
int evo_lua_behaviour(evo_lua *l, int bot, double *out, int max,
		      evo_err *err);

/* At an episode's end: the environment's solved(scene, bot), a boolean.
 * Returns 1 and sets *solved, 0 when the environment has no solved
 * function, -1 with err set when it fails or returns anything but a
 * boolean. */
int evo_lua_solved(evo_lua *l, int bot, int *solved, evo_err *err);

/* The file the environment and the bot model were loaded from. */
const char *evo_lua_env_path(const evo_lua *l);
const char *evo_lua_bot_path(const evo_lua *l);

/* The text scene:genome() returns from the next episode on (an OPENENDED
 * run's environment genome, docs/openended.md); not copied: it must
 * outlive the episodes. NULL: scene:genome() returns nil. */
void evo_lua_set_genome(evo_lua *l, const char *genome);

#endif

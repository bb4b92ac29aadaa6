/* The scene scripts' `evo` module (sim/lua/lua_evo.h, docs/lua.md): a Lua
 * state per scene with the module's classes, and the environment's init
 * and reset. The lua/ folder, loading scripts and the sandbox live in
 * lua_sandbox.c, the methods in lua_scene.c, lua_scoring.c, lua_bot.c
 * and lua_element.c (one set for either world, over lua_dim2d.c's or
 * lua_dim3d.c's table), the hooks the tick calls in lua_hooks.c, and
 * what they share in lua_internal.h. */
#define _POSIX_C_SOURCE 200809L
#include "lua/lua_evo.h"

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/rng.h"
#include "lua/lua_internal.h"

/* ---- the module ---------------------------------------------------------- */

/* __index of a class: its method; for a name near one of them
 * (scene:zonee), an error at the script's line naming the one meant, as
 * the names scene:control and bot:target take get; else nil, so Lua
 * says what it always said. Upvalues: the methods table, the noun. */
static int class_index(lua_State *L)
{
	lua_pushvalue(L, 2);
	if (lua_rawget(L, lua_upvalueindex(1)) != LUA_TNIL ||
	    lua_type(L, 2) != LUA_TSTRING)
		return 1;
	const char *names[64];
	size_t n = 0;
	lua_pushnil(L);
	while (lua_next(L, lua_upvalueindex(1)) != 0) {
		if (n < 64 && lua_type(L, -2) == LUA_TSTRING)
			names[n++] = lua_tostring(L, -2);
		lua_pop(L, 1);
	}
	const char *word = lua_tostring(L, 2);
	const char *near = evo_lua_near(word, names, n);
	if (!near)
		return 1;
	const char *noun = lua_tostring(L, lua_upvalueindex(2));
	int an = strchr("aeiou", noun[0]) != NULL;
	return luaL_error(L,
			  "%s:%s: %s %s has no method '%s'; did you mean "
			  "%s:%s?",
			  noun, word, an ? "an" : "a", noun, word, noun, near);
}

/* A class of handles: its methods, set into a table by fill. */
static void new_class(lua_State *L, const char *mt, void (*fill)(lua_State *),
		      const char *noun)
{
	luaL_newmetatable(L, mt);
	lua_newtable(L);
	fill(L);
	lua_pushvalue(L, -1);
	lua_setfield(L, -3, "__methods"); /* the table, for tests/docs */
	lua_pushstring(L, noun);
	lua_pushcclosure(L, class_index, 2);
	lua_setfield(L, -2, "__index");
	lua_pushstring(L, mt);
	lua_setfield(L, -2, "__name");
	lua_pop(L, 1);
}

void evo_lua_set_path(lua_State *L, const char *lua_dir)
{
	lua_getglobal(L, "package");
	lua_pushfstring(L, "%s/?.lua", lua_dir);
	lua_setfield(L, -2, "path");
	lua_pushstring(L, "");
	lua_setfield(L, -2, "cpath");
	lua_pop(L, 1);
}

static int open_evo(lua_State *L)
{
	lua_newtable(L);
	lua_pushnumber(L, EVO_TRUE);
	lua_setfield(L, -2, "TRUE");
	lua_pushnumber(L, EVO_FALSE);
	lua_setfield(L, -2, "FALSE");
	lua_pushstring(L, "nearest_object");
	lua_setfield(L, -2, "NEAREST_OBJECT");
	lua_pushstring(L, "nearest_opponent");
	lua_setfield(L, -2, "NEAREST_OPPONENT");
	lua_pushstring(L, "nearest_teammate");
	lua_setfield(L, -2, "NEAREST_TEAMMATE");
	return 1;
}

/* math.randomseed, kept at setup: a script may replace math or its
 * fields, and the seeding must not depend on that. */
static const char randomseed_key = 0;

/* math.randomseed(seed): Lua 5.4 seeds math.random from the time and an
 * address when it opens math, so a script that draws from it would give
 * other figures on every run. Cannot fail; protected all the same. */
static void seed_math_random(lua_State *L, uint64_t seed)
{
	lua_rawgetp(L, LUA_REGISTRYINDEX, &randomseed_key);
	lua_pushinteger(L, (lua_Integer)seed);
	if (lua_pcall(L, 1, 0, 0) != LUA_OK)
		lua_pop(L, 1);
}

static int setup(lua_State *L)
{
	evo_lua *l = lua_touserdata(L, 1);
	evo_lua_open_sandbox(L);
	lua_pushlightuserdata(L, l);
	lua_rawsetp(L, LUA_REGISTRYINDEX, &evo_lua_ctx_key);
	new_class(L, EVO_LUA_BOT_MT, evo_lua_bot_methods, "bot");
	new_class(L, EVO_LUA_ELEMENT_MT, evo_lua_element_methods, "element");
	new_class(L, EVO_LUA_SCENE_MT, evo_lua_scene_methods, "scene");
	new_class(L, EVO_LUA_METRIC_MT, evo_lua_metric_methods, "metric");
	/* the one scene object */
	lua_newuserdatauv(L, 1, 0);
	luaL_setmetatable(L, EVO_LUA_SCENE_MT);
	lua_rawsetp(L, LUA_REGISTRYINDEX, &evo_lua_scene_key);
	luaL_requiref(L, "evo", open_evo, 0);
	lua_pop(L, 1);
	/* the same numbers in init on every run; each episode's reset seeds
	 * them from the episode's seed (evo_lua_reset) */
	lua_getglobal(L, LUA_MATHLIBNAME);
	lua_getfield(L, -1, "randomseed");
	lua_rawsetp(L, LUA_REGISTRYINDEX, &randomseed_key);
	lua_pop(L, 1);
	seed_math_random(L, 0);
	return 0;
}

/* The first refused allocation: the script's line, for the message. The
 * state is in the middle of an allocation, so this only reads it. */
void evo_lua_memory_hit(void *ctx)
{
	evo_lua *l = ctx;
	lua_Debug ar;
	for (int lv = 0; lua_getstack(l->L, lv, &ar); lv++)
		if (lua_getinfo(l->L, "l", &ar) && ar.currentline > 0) {
			evo_lua_note_where(l, l->L, lv);
			return;
		}
}

/* The hooks of the scene the state builds, 2D or 3D. */
static evo_scene_hooks *scene_hooks(evo_lua *l)
{
	return l->sc ? &l->sc->hooks : &l->sc3->hooks;
}

evo_lua *evo_lua_create(const evo_lua_def *def, evo_err *err)
{
	evo_lua *l = calloc(1, sizeof *l);
	if (!l) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	l->sc = def->scene;
	l->sc3 = def->scene3d;
	l->task = def->task;
	if (!l->sc == !l->sc3) {
		free(l);
		evo_fail(err, "a Lua state builds one scene, 2D or 3D");
		return NULL;
	}
	l->dim = l->sc3 ? &evo_lua_dim3d : &evo_lua_dim2d;
	l->dim->view(l, &l->v);
	l->env_ref = LUA_NOREF;
	snprintf(l->mind_dir, sizeof l->mind_dir, "%s",
		 def->mind_dir ? def->mind_dir : "");
	snprintf(l->lua_dir, sizeof l->lua_dir, "%s",
		 def->lua_dir ? def->lua_dir : evo_lua_dir());
	snprintf(l->botmodel, sizeof l->botmodel, "%s",
		 def->botmodel ? def->botmodel : "");
	if (def->n_teams < 0 || def->n_teams > EVO_SCENE_MAX_TEAMS) {
		free(l);
		evo_fail(err, "%d teams (at most %d)", def->n_teams,
			 EVO_SCENE_MAX_TEAMS);
		return NULL;
	}
	l->n_teams = def->n_teams;
	for (int i = 0; i < def->n_teams; i++) {
		snprintf(l->team[i].name, sizeof l->team[i].name, "%s",
			 def->teams[i].name);
		snprintf(l->team[i].botmodel, sizeof l->team[i].botmodel, "%s",
			 def->teams[i].botmodel);
		snprintf(l->team[i].mind_dir, sizeof l->team[i].mind_dir, "%s",
			 def->teams[i].mind_dir ? def->teams[i].mind_dir : "");
		l->team[i].size = def->teams[i].size;
	}
	if (def->limits)
		l->limits = *def->limits;
	else if (evo_lua_limits_read(def->task, def->task_path, &l->limits,
				     err)) {
		free(l);
		return NULL;
	}
	l->L = evo_lua_state_new(l->limits.memory, &l->mem);
	if (!l->L) {
		free(l);
		evo_fail(err, "cannot create a Lua state");
		return NULL;
	}
	l->watch = evo_lua_watch_add();
	l->mem->on_hit = evo_lua_memory_hit;
	l->mem->ctx = l;
	lua_pushcfunction(l->L, setup);
	lua_pushlightuserdata(l->L, l);
	if (lua_pcall(l->L, 1, 0, 0) != LUA_OK) {
		evo_fail(err, "Lua setup: %s", evo_lua_errstr(l->L, -1));
		evo_lua_destroy(l);
		return NULL;
	}
	evo_scene_hooks *h = scene_hooks(l);
	h->ctx = l;
	h->reward = evo_lua_hook_reward;
	h->control = evo_lua_hook_control;
	return l;
}

void evo_lua_destroy(evo_lua *l)
{
	if (!l)
		return;
	evo_scene_hooks *h = scene_hooks(l);
	if (h->ctx == l)
		memset(h, 0, sizeof *h);
	evo_lua_state_close(l->L, l->mem);
	evo_lua_watch_remove(l->watch);
	free(l);
}

/* fn(l) under the limits of loading and init (init 1) or of reset's,
 * leaving nresults on the stack. 0, or -1 with err set. */
static int call_l(evo_lua *l, lua_CFunction fn, int nresults, int init,
		  const char *what, evo_err *err)
{
	lua_State *L = l->L;
	lua_pushcfunction(L, fn);
	lua_pushlightuserdata(L, l);
	if (evo_lua_pcall(l, 1, nresults,
			  init ? EVO_LUA_BUDGET_INIT : EVO_LUA_BUDGET_RESET,
			  init ? EVO_LUA_TIME_INIT : EVO_LUA_TIME_RESET,
			  what) != LUA_OK) {
		evo_fail(err, "%s", evo_lua_errstr(L, -1));
		lua_pop(L, 1);
		return -1;
	}
	return 0;
}

static int load_env(lua_State *L)
{
	evo_lua *l = lua_touserdata(L, 1);
	evo_lua_run_file(L, l->env_path, "an environment");
	if (lua_getfield(L, -1, "init") != LUA_TFUNCTION)
		luaL_error(L, "%s: the environment has no init(scene, task)",
			   l->env_path);
	lua_pop(L, 1);
	return 1;
}

/* What the environment's table has after init: post_step and obstacles
 * functions. Read in a call of its own: an __index of the table is the
 * script's code. */
static int env_fields(lua_State *L)
{
	evo_lua *l = lua_touserdata(L, 1);
	lua_rawgeti(L, LUA_REGISTRYINDEX, l->env_ref);
	int env = lua_gettop(L);
	lua_pushboolean(L, lua_getfield(L, env, "post_step") == LUA_TFUNCTION);
	lua_replace(L, -2);
	lua_pushboolean(L, lua_getfield(L, env, "obstacles") == LUA_TFUNCTION);
	lua_replace(L, -2);
	return 2;
}

int evo_lua_init_env(evo_lua *l, const char *env, evo_err *err)
{
	int found = evo_lua_find_script(l, NULL, "Envs", "envs", env,
					l->env_path, sizeof l->env_path);
	if (found == -2)
		return evo_fail(err,
				"environment '%s': %s leads out of its folder "
				"(a link?); scripts are loaded from the mind "
				"folder and lua/ only",
				env, l->env_path);
	if (found)
		return evo_fail(err,
				"environment '%s' not found: looked for "
				"%s/Envs/%s.lua and %s/envs/%s.lua",
				env, l->mind_dir[0] ? l->mind_dir : ".", env,
				l->lua_dir, env);
	lua_State *L = l->L;
	if (call_l(l, load_env, 1, 1, "loading the environment", err))
		return -1;
	l->env_ref = luaL_ref(L, LUA_REGISTRYINDEX);
	if (evo_lua_call_env(l, "init", 2, 0, err))
		return -1;
	l->ready = 1;
	if (call_l(l, env_fields, 2, 1, "init", err))
		return -1;
	int has_obstacles = lua_toboolean(L, -1);
	l->has_post_step = lua_toboolean(L, -2);
	lua_pop(L, 2);
	if (l->has_post_step)
		scene_hooks(l)->post_step = evo_lua_hook_post_step;
	if ((l->sc3 ? l->sc3->n_bots : l->sc->n_bots) == 0)
		return evo_fail(err,
				"%s: init added no bot (call scene:bot{...})",
				l->env_path);
	/* an obstacle generator of its own replaces the grid */
	if (has_obstacles && l->sc)
		l->sc->grid.enabled = 0;
	return 0;
}

/* random(lo, hi) for env.obstacles: the grid seed's stream, so every
 * candidate of a generation meets the same obstacles (docs/lua.md). */
static int obstacle_random(lua_State *L)
{
	evo_rng *r = lua_touserdata(L, lua_upvalueindex(1));
	double lo = luaL_optnumber(L, 1, 0), hi = luaL_optnumber(L, 2, 1);
	lua_pushnumber(L, evo_rng_range(r, lo, hi));
	return 1;
}

/* A 3D entry of env.obstacles (at t): what scene:obstacle takes, added
 * through it. Raises with the environment's path and the entry. */
static void add_obstacle3d(lua_State *L, evo_lua *l, int scene, int t,
			   const char *what)
{
	lua_getfield(L, scene, "obstacle");
	lua_pushvalue(L, scene);
	lua_pushvalue(L, t);
	if (lua_pcall(L, 2, 0, 0) != LUA_OK)
		luaL_error(L, "%s: %s: %s", l->env_path, what,
			   lua_tostring(L, -1));
	lua_pop(L, 1); /* the entry */
}

/* env.obstacles(scene, random, episode), when the environment has it: a
 * list of obstacles added for this episode (the tutorial's
 * generateObstaclesParameters): in 2D each {x, y, size, angle, shape}, in
 * 3D each what scene:obstacle takes. Raises with the environment's
 * path. */
static int run_obstacles(lua_State *L)
{
	static const char *const keys[] = {"x",	    "y",     "size",
					   "angle", "shape", NULL};
	evo_lua *l = lua_touserdata(L, 1);
	lua_rawgeti(L, LUA_REGISTRYINDEX, l->env_ref);
	if (lua_getfield(L, -1, "obstacles") != LUA_TFUNCTION)
		return 0;
	/* the scene below the function, kept for 3D's entries */
	lua_rawgetp(L, LUA_REGISTRYINDEX, &evo_lua_scene_key);
	lua_insert(L, -2);
	int scene = lua_gettop(L) - 1;
	lua_pushvalue(L, scene);
	evo_rng *r = lua_newuserdatauv(L, sizeof *r, 0);
	*r = evo_rng_for(*l->v.grid_seed, 0x6f6273 /* "obs" */, 0, 0);
	lua_pushcclosure(L, obstacle_random, 1);
	lua_pushinteger(L, l->episode);
	lua_call(L, 3, 1);
	if (!lua_istable(L, -1))
		return luaL_error(L,
				  "%s: env.obstacles must return a list of "
				  "obstacles, returned %s",
				  l->env_path, luaL_typename(L, -1));
	lua_Integer n = luaL_len(L, -1);
	for (lua_Integer i = 1; i <= n; i++) {
		char what[64];
		snprintf(what, sizeof what, "env.obstacles: obstacle %lld",
			 (long long)i);
		lua_geti(L, -1, i);
		if (!lua_istable(L, -1))
			return luaL_error(L, "%s: %s is %s, not a table",
					  l->env_path, what,
					  luaL_typename(L, -1));
		int t = lua_gettop(L);
		if (l->sc3) {
			add_obstacle3d(L, l, scene, t, what);
			continue;
		}
		evo_lua_check_keys(L, t, what, keys);
		evo_obstacle o;
		memset(&o, 0, sizeof o);
		o.x = evo_lua_opt_num(L, t, "x", 0, what);
		o.y = evo_lua_opt_num(L, t, "y", 0, what);
		double size = evo_lua_opt_num(L, t, "size", 1, what);
		const char *shape =
		    evo_lua_opt_str(L, t, "shape", "circle", what);
		/* as the grid makes them: a circle of radius size, or a
		 * square box of half side size, turned by angle */
		o.radius = o.half_w = o.half_h = size;
		if (strcmp(shape, "circle") == 0) {
			o.shape = EVO_SHAPE_CIRCLE;
		} else if (strcmp(shape, "box") == 0) {
			o.shape = EVO_SHAPE_BOX;
			o.angle = evo_lua_opt_num(L, t, "angle", 0, what) *
				  EVO_LUA_DEG;
		} else {
			return luaL_error(L,
					  "%s: %s: shape must be \"circle\" "
					  "or \"box\", found \"%s\"",
					  l->env_path, what, shape);
		}
		if (evo_scene_add_episode_obstacle(l->sc, &o) < 0)
			return luaL_error(L, "%s: %s: %s", l->env_path, what,
					  l->sc->err.msg);
		lua_pop(L, 1);
	}
	return 0;
}

int evo_lua_reset(evo_lua *l, int episode, evo_err *err)
{
	/* scene:layout_random's stream, the same for every candidate */
	l->layout_rng =
	    evo_rng_for(*l->v.grid_seed, 0x6f6273 /* "obs" */, 0, 0);
	/* math.random is seeded per episode from the scene's rng, itself just
	 * seeded from the episode's seed, through a copy: the scene's stream
	 * (RANDOM sensors, scene:random) stays as it was. */
	evo_rng r = evo_rng_for(l->v.rng->s, 0x4c7561 /* "Lua" */, 0, 0);
	seed_math_random(l->L, evo_rng_next(&r));
	/* the Lua rewards' and controls' own resets, as the C ones were
	 * reset by the scene's reset, then the environment's obstacles and
	 * its reset (both may add an episode's obstacles) */
	if (evo_lua_call_resets(l, &evo_lua_reward_resets_key, err) ||
	    evo_lua_call_resets(l, &evo_lua_control_resets_key, err))
		return -1;
	l->episode = episode;
	l->in_reset = 1;
	int rc = call_l(l, run_obstacles, 0, 0, "obstacles", err);
	if (rc == 0)
		rc = evo_lua_call_env(l, "reset", 1, episode, err);
	l->in_reset = 0;
	return rc;
}

void evo_lua_set_genome(evo_lua *l, const char *genome)
{
	l->genome = genome;
}

const char *evo_lua_env_path(const evo_lua *l)
{
	return l->env_path;
}

const char *evo_lua_bot_path(const evo_lua *l)
{
	return l->bot_path;
}

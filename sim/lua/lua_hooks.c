/* Lua called from the tick: a Lua function as a reward or control
 * function, and the environment's post_step, reset and init (docs/lua.md).
 * A script error here becomes the scene's error, and the step fails. */
#include <stdio.h>
#include <string.h>

#include "lua/lua_internal.h"

/* ---- the instruction budget ---------------------------------------- */

/* The count hook runs every HOOK_EVERY instructions, while a call is
 * under way only: with a hook set, Lua 5.4 checks it at each instruction,
 * so the hook is cleared between calls and a tick without Lua pays
 * nothing. Coroutines the script makes inherit the hook and count to the
 * same budget. */
#define HOOK_EVERY 1000

static void count_hook(lua_State *L, lua_Debug *ar)
{
	(void)ar;
	evo_lua *l = evo_lua_ctx(L);
	if (!l->over) {
		l->used += HOOK_EVERY;
		if (l->used < l->budget)
			return;
		l->over = 1;
		/* level 0 in a hook: the Lua function it interrupted */
		luaL_where(L, 0);
		snprintf(l->over_msg, sizeof l->over_msg,
			 "%sthe script ran past its budget of %ld instructions "
			 "in %s; an endless loop?",
			 lua_tostring(L, -1), l->budget, l->call_what);
		lua_pop(L, 1);
	}
	/* Raise at every instruction from now on, so a pcall in the script
	 * cannot catch the error and loop on. */
	lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
	lua_pushstring(L, l->over_msg);
	lua_error(L);
}

int evo_lua_pcall(evo_lua *l, int nargs, int nresults, long budget,
		  const char *what)
{
	lua_State *L = l->L;
	if (l->in_call)
		return lua_pcall(L, nargs, nresults, 0);
	l->in_call = 1;
	l->budget = budget;
	l->used = 0;
	l->over = 0;
	l->call_what = what;
	lua_sethook(L, count_hook, LUA_MASKCOUNT, HOOK_EVERY);
	int r = lua_pcall(L, nargs, nresults, 0);
	lua_sethook(L, NULL, 0, 0);
	l->in_call = 0;
	if (r != LUA_OK && l->over) {
		lua_pop(L, 1);
		lua_pushstring(L, l->over_msg);
	}
	return r;
}

/* ---- hooks: Lua reward and control functions ------------------------- */

/* Call the function behind ref with the scene; leaves one result. */
static int call_ref(evo_lua *l, int ref, const char *what)
{
	lua_State *L = l->L;
	lua_rawgeti(L, LUA_REGISTRYINDEX, ref);
	lua_rawgetp(L, LUA_REGISTRYINDEX, &evo_lua_scene_key);
	if (evo_lua_pcall(l, 1, 1, EVO_LUA_BUDGET_TICK, what) != LUA_OK) {
		/* the budget's message names the function already */
		if (l->over)
			evo_fail(&l->sc->err, "%s", lua_tostring(L, -1));
		else
			evo_fail(&l->sc->err, "%s (in %s)", lua_tostring(L, -1),
				 what);
		lua_pop(L, 1);
		return -1;
	}
	return 0;
}

int evo_lua_hook_reward(void *c, evo_scene *sc, const evo_reward *r,
			double *out)
{
	evo_lua *l = c;
	(void)sc;
	if (call_ref(l, r->def.lua_ref, "a reward function"))
		return -1;
	int isnum;
	*out = lua_tonumberx(l->L, -1, &isnum);
	int ok = isnum && isfinite(*out);
	if (!ok) {
		/* where the function was written, what it gave, and when */
		lua_State *L = l->L;
		char got[64];
		if (isnum)
			snprintf(got, sizeof got, "%g", *out);
		else
			snprintf(got, sizeof got, "%s", luaL_typename(L, -1));
		lua_Debug ar;
		lua_rawgeti(L, LUA_REGISTRYINDEX, r->def.lua_ref);
		lua_getinfo(L, ">S", &ar);
		evo_fail(&l->sc->err,
			 "%s:%d: the reward function written here returned "
			 "%s at tick %ld, not a finite number",
			 ar.short_src, ar.linedefined, got, l->sc->tick);
	}
	lua_pop(l->L, 1);
	return ok ? 0 : -1;
}

int evo_lua_hook_control(void *c, evo_scene *sc, const evo_control *ctl,
			 int *next)
{
	evo_lua *l = c;
	(void)sc;
	if (call_ref(l, ctl->def.lua_ref, "a control function"))
		return -1;
	*next = lua_toboolean(l->L, -1);
	lua_pop(l->L, 1);
	return 0;
}

/* Call env[name](scene, arg) if the environment has it. */
int evo_lua_call_env(evo_lua *l, const char *name, int with_arg,
		     lua_Integer arg, evo_err *err)
{
	lua_State *L = l->L;
	lua_rawgeti(L, LUA_REGISTRYINDEX, l->env_ref);
	lua_getfield(L, -1, name);
	lua_remove(L, -2);
	if (lua_isnil(L, -1)) {
		lua_pop(L, 1);
		return 0;
	}
	lua_rawgetp(L, LUA_REGISTRYINDEX, &evo_lua_scene_key);
	int nargs = 1;
	if (with_arg == 1) {
		lua_pushinteger(L, arg);
		nargs = 2;
	} else if (with_arg == 2) {
		/* the task: every .simbatch key with its value */
		lua_newtable(L);
		for (unsigned i = 0; l->task && i < l->task->n_pairs; i++) {
			lua_pushstring(L, l->task->pair[i].value);
			lua_setfield(L, -2, l->task->pair[i].key);
		}
		nargs = 2;
	}
	long budget = strcmp(name, "init") == 0	   ? EVO_LUA_BUDGET_INIT
		      : strcmp(name, "reset") == 0 ? EVO_LUA_BUDGET_RESET
						   : EVO_LUA_BUDGET_TICK;
	if (evo_lua_pcall(l, nargs, 0, budget, name) != LUA_OK) {
		evo_fail(err, "%s", lua_tostring(L, -1));
		lua_pop(L, 1);
		return -1;
	}
	return 0;
}

int evo_lua_hook_post_step(void *c, evo_scene *sc)
{
	evo_lua *l = c;
	(void)sc;
	return evo_lua_call_env(l, "post_step", 0, 0, &l->sc->err);
}

const char evo_lua_reward_resets_key = 'r';
const char evo_lua_control_resets_key = 'c';

int evo_lua_call_resets(evo_lua *l, const void *key, evo_err *err)
{
	lua_State *L = l->L;
	if (lua_rawgetp(L, LUA_REGISTRYINDEX, key) != LUA_TTABLE) {
		lua_pop(L, 1);
		return 0;
	}
	lua_Integer n = luaL_len(L, -1);
	for (lua_Integer i = 1; i <= n; i++) {
		lua_geti(L, -1, i);
		lua_rawgetp(L, LUA_REGISTRYINDEX, &evo_lua_scene_key);
		if (evo_lua_pcall(l, 1, 0, EVO_LUA_BUDGET_RESET,
				  "a reset function") != LUA_OK) {
			evo_fail(err, "%s (in a reset function)",
				 lua_tostring(L, -1));
			lua_pop(L, 2);
			return -1;
		}
	}
	lua_pop(L, 1);
	return 0;
}


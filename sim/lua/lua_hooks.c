/* Lua called from the tick: a Lua function as a reward or control
 * function, and the environment's post_step, reset and init (docs/lua.md).
 * A script error here becomes the scene's error, and the step fails. */
#include "lua/lua_internal.h"

/* ---- hooks: Lua reward and control functions ------------------------- */

/* Call the function behind ref with the scene; leaves one result. */
static int call_ref(evo_lua *l, int ref, const char *what)
{
	lua_State *L = l->L;
	lua_rawgeti(L, LUA_REGISTRYINDEX, ref);
	lua_rawgetp(L, LUA_REGISTRYINDEX, &evo_lua_scene_key);
	if (lua_pcall(L, 1, 1, 0) != LUA_OK) {
		evo_fail(&l->sc->err, "%s (in a %s)", lua_tostring(L, -1),
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
	if (call_ref(l, r->def.lua_ref, "reward function"))
		return -1;
	int isnum;
	*out = lua_tonumberx(l->L, -1, &isnum);
	int ok = isnum && isfinite(*out);
	if (!ok)
		evo_fail(&l->sc->err,
			 "a reward function returned %s, not a finite number",
			 luaL_typename(l->L, -1));
	lua_pop(l->L, 1);
	return ok ? 0 : -1;
}

int evo_lua_hook_control(void *c, evo_scene *sc, const evo_control *ctl,
			 int *next)
{
	evo_lua *l = c;
	(void)sc;
	if (call_ref(l, ctl->def.lua_ref, "control function"))
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
	if (lua_pcall(L, nargs, 0, 0) != LUA_OK) {
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

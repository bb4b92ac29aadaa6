/* Lua called from the tick: a Lua function as a reward or control
 * function, and the environment's post_step, reset and init (docs/lua.md).
 * A script error here becomes the scene's error, and the step fails. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "lua/lua_internal.h"

/* ---- the limits of a call ------------------------------------------- */

/* The count hook runs every HOOK_EVERY instructions, while a call is
 * under way only: with a hook set, Lua 5.4 checks it at each instruction,
 * so the hook is cleared between calls and a tick without Lua pays
 * nothing. Coroutines the script makes inherit the hook and count to the
 * same budget. Each run it notes the script's line for the watchdog, and
 * looks at the instruction count, the memory, the clock and the stop
 * flag. */
#define HOOK_EVERY 1000

/* Note the file:line of the Lua function at level (0 in a hook: the one
 * it interrupted; 1 in a C function: its caller), or of the first Lua
 * function above it (a string function called through pcall has pcall
 * for its caller), for the watchdog. */
void evo_lua_note_where(evo_lua *l, lua_State *L, int level)
{
	lua_Debug ar;
	for (;; level++) {
		if (!lua_getstack(L, level, &ar) || !lua_getinfo(L, "Sl", &ar))
			return;
		if (ar.currentline > 0)
			break;
	}
	char w[300];
	snprintf(w, sizeof w, "%s:%d: ", ar.short_src, ar.currentline);
	evo_lua_watch_where(l->watch, w);
}

/* Set the call's sticky message: the script's line, then what. */
static void set_over(evo_lua *l, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
static void set_over(evo_lua *l, const char *fmt, ...)
{
	char where[300], what[1000];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(what, sizeof what, fmt, ap);
	va_end(ap);
	evo_lua_watch_get_where(l->watch, where, sizeof where);
	snprintf(l->over_msg, sizeof l->over_msg, "%s%s", where, what);
	l->over = 1;
}

static const char *mb(size_t bytes, char *buf, size_t cap)
{
	snprintf(buf, cap, "%zu MB", bytes >> 20);
	return buf;
}

/* The limit the call has reached, if any, as its sticky message. */
static void check_limits(evo_lua *l, int in_hook)
{
	char m[32];
	int sig;
	if (l->over)
		return;
	if (l->used >= l->budget)
		set_over(l,
			 "the script ran past its budget of %ld instructions "
			 "in %s; an endless loop? (LUABUDGET raises it, "
			 "docs/lua.md)",
			 l->budget, l->call_what);
	else if (l->mem->hit)
		set_over(l,
			 "the script's Lua state reached its memory limit of "
			 "%s in %s (LUAMEMORY raises it, docs/lua.md)",
			 mb(l->mem->limit, m, sizeof m), l->call_what);
	else if (evo_lua_now() - l->started > l->time_limit &&
		 evo_lua_cpu_now() - l->cpu_started > l->time_limit)
		set_over(l,
			 "the script ran past its time limit of %g s in %s "
			 "(LUABUDGET raises it, docs/lua.md)",
			 l->time_limit, l->call_what);
	else if (in_hook && (sig = evo_lua_stop_signal()) != 0)
		/* only a call still running is stopped: one that ended lets
		 * the run stop as it always does, between ticks */
		set_over(l, "stopped by signal %d in %s", sig, l->call_what);
}

static void count_hook(lua_State *L, lua_Debug *ar)
{
	(void)ar;
	evo_lua *l = evo_lua_ctx(L);
	if (!l->over) {
		/* after a refusal, where the memory ran out (on_memory_hit) */
		if (!l->mem->hit)
			evo_lua_note_where(l, L, 0);
		l->used += HOOK_EVERY;
		check_limits(l, 1);
		if (!l->over)
			return;
	}
	/* Raise at every instruction from now on, so a pcall in the script
	 * cannot catch the error and loop on. */
	lua_sethook(L, count_hook, LUA_MASKCOUNT, 1);
	lua_pushstring(L, l->over_msg);
	lua_error(L);
}

static int tostring_value(lua_State *L)
{
	luaL_tolstring(L, 1, NULL);
	return 1;
}

/* The message handler of a call: a string error stays as it is; any
 * other value (error({}), error(nil), a table with __tostring) becomes a
 * message with the script's line, where the error was raised. */
static int message(lua_State *L)
{
	int t = lua_type(L, 1);
	if (t == LUA_TSTRING || t == LUA_TNUMBER)
		return 1;
	char where[300] = "";
	lua_Debug ar;
	for (int lv = 1; lua_getstack(L, lv, &ar); lv++)
		if (lua_getinfo(L, "Sl", &ar) && ar.currentline > 0) {
			snprintf(where, sizeof where, "%s:%d: ", ar.short_src,
				 ar.currentline);
			break;
		}
	/* its __tostring, if it has one that works, in a call of its own */
	if (luaL_getmetafield(L, 1, "__tostring") != LUA_TNIL) {
		lua_pop(L, 1);
		lua_pushcfunction(L, tostring_value);
		lua_pushvalue(L, 1);
		if (lua_pcall(L, 1, 1, 0) == LUA_OK &&
		    lua_type(L, -1) == LUA_TSTRING) {
			lua_pushfstring(L, "%s%s", where, lua_tostring(L, -1));
			return 1;
		}
		lua_pop(L, 1);
	}
	lua_pushfstring(L, "%s%s", where, evo_lua_errstr(L, 1));
	return 1;
}

int evo_lua_pcall(evo_lua *l, int nargs, int nresults, long budget,
		  double time_limit, const char *what)
{
	lua_State *L = l->L;
	if (l->in_call)
		return lua_pcall(L, nargs, nresults, 0);
	int fn = lua_gettop(L) - nargs;
	if (l->over) {
		lua_settop(L, fn - 1);
		lua_pushstring(L, l->over_msg);
		return LUA_ERRRUN;
	}
	l->in_call = 1;
	l->budget = (long)((double)budget * l->limits.budget_scale);
	l->time_limit = time_limit * l->limits.budget_scale;
	l->used = 0;
	l->call_what = what;
	l->cpu_started = evo_lua_watch_call(l->watch, what, l->time_limit);
	/* until the hook or a pattern sees a line: where the function was
	 * written */
	lua_Debug ar;
	lua_pushvalue(L, fn);
	if (lua_getinfo(L, ">S", &ar) && ar.linedefined > 0) {
		char w[300];
		snprintf(w, sizeof w, "%s:%d: ", ar.short_src, ar.linedefined);
		evo_lua_watch_where(l->watch, w);
	}
	lua_pushcfunction(L, message);
	lua_insert(L, fn);
	l->started = evo_lua_now();
	l->mem->enforce = 1;
	lua_sethook(L, count_hook, LUA_MASKCOUNT, HOOK_EVERY);
	int r = lua_pcall(L, nargs, nresults, fn);
	lua_sethook(L, NULL, 0, 0);
	l->mem->enforce = 0;
	evo_lua_watch_call(l->watch, NULL, -1);
	l->in_call = 0;
	lua_remove(L, fn);
	/* a limit reached stays the error, even when the script caught it
	 * (pcall, a coroutine) or a C call ran past the time in one go */
	check_limits(l, 0);
	if (r == LUA_ERRMEM && !l->over)
		set_over(l, "not enough memory in %s", what);
	if (l->over) {
		lua_settop(L, fn - 1);
		lua_pushstring(L, l->over_msg);
		return r == LUA_OK ? LUA_ERRRUN : r;
	}
	return r;
}

/* ---- hooks: Lua reward and control functions ------------------------- */

/* Call the function behind ref with the scene; leaves one result. */
static int call_ref(evo_lua *l, int ref, const char *what, evo_err *err)
{
	lua_State *L = l->L;
	lua_rawgeti(L, LUA_REGISTRYINDEX, ref);
	lua_rawgetp(L, LUA_REGISTRYINDEX, &evo_lua_scene_key);
	if (evo_lua_pcall(l, 1, 1, EVO_LUA_BUDGET_TICK, EVO_LUA_TIME_TICK,
			  what) != LUA_OK) {
		/* the budget's message names the function already */
		if (l->over)
			evo_fail(err, "%s", evo_lua_errstr(L, -1));
		else
			evo_fail(err, "%s (in %s)", evo_lua_errstr(L, -1), what);
		lua_pop(L, 1);
		return -1;
	}
	return 0;
}

int evo_lua_hook_reward(void *c, evo_err *err, const evo_reward *r,
			double *out)
{
	evo_lua *l = c;
	if (call_ref(l, r->def.lua_ref, "a reward function", err))
		return -1;
	int isnum;
	/* a number, not a string that reads as one ("1.5" is a mistake
	 * Lua would otherwise forgive) */
	int number = lua_type(l->L, -1) == LUA_TNUMBER;
	*out = lua_tonumberx(l->L, -1, &isnum);
	int ok = number && isnum && isfinite(*out);
	if (!ok) {
		/* where the function was written, what it gave, and when */
		lua_State *L = l->L;
		char got[96];
		if (number)
			snprintf(got, sizeof got, "%g", *out);
		else if (lua_type(L, -1) == LUA_TSTRING)
			snprintf(got, sizeof got, "the string \"%.40s\"",
				 lua_tostring(L, -1));
		else
			snprintf(got, sizeof got, "%s", luaL_typename(L, -1));
		lua_Debug ar;
		lua_rawgeti(L, LUA_REGISTRYINDEX, r->def.lua_ref);
		lua_getinfo(L, ">S", &ar);
		evo_fail(err,
			 "%s:%d: the reward function written here returned "
			 "%s at tick %ld, not a finite number",
			 ar.short_src, ar.linedefined, got, evo_lua_tick(l));
	}
	lua_pop(l->L, 1);
	return ok ? 0 : -1;
}

int evo_lua_hook_control(void *c, evo_err *err, const evo_control *ctl,
			 int *next)
{
	evo_lua *l = c;
	if (call_ref(l, ctl->def.lua_ref, "a control function", err))
		return -1;
	*next = lua_toboolean(l->L, -1);
	lua_pop(l->L, 1);
	return 0;
}

/* env[name](scene, arg) if the environment has it; arguments: the
 * evo_lua, name, with_arg, arg. Run as a call of its own, so that an
 * __index of the environment's table runs under the call's limits. */
static int env_call(lua_State *L)
{
	evo_lua *l = lua_touserdata(L, 1);
	const char *name = lua_tostring(L, 2);
	int with_arg = (int)lua_tointeger(L, 3);
	lua_Integer arg = lua_tointeger(L, 4);
	lua_rawgeti(L, LUA_REGISTRYINDEX, l->env_ref);
	if (lua_getfield(L, -1, name) == LUA_TNIL)
		return 0;
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
	lua_call(L, nargs, 0);
	return 0;
}

/* Call env[name](scene, arg) if the environment has it. */
int evo_lua_call_env(evo_lua *l, const char *name, int with_arg,
		     lua_Integer arg, evo_err *err)
{
	lua_State *L = l->L;
	lua_pushcfunction(L, env_call);
	lua_pushlightuserdata(L, l);
	lua_pushstring(L, name);
	lua_pushinteger(L, with_arg);
	lua_pushinteger(L, arg);
	int init = strcmp(name, "init") == 0, reset = strcmp(name, "reset") == 0;
	long budget = init    ? EVO_LUA_BUDGET_INIT
		      : reset ? EVO_LUA_BUDGET_RESET
			      : EVO_LUA_BUDGET_TICK;
	double limit = init    ? EVO_LUA_TIME_INIT
		       : reset ? EVO_LUA_TIME_RESET
			       : EVO_LUA_TIME_TICK;
	if (evo_lua_pcall(l, 4, 0, budget, limit, name) != LUA_OK) {
		evo_fail(err, "%s", evo_lua_errstr(L, -1));
		lua_pop(L, 1);
		return -1;
	}
	return 0;
}

int evo_lua_hook_post_step(void *c, evo_err *err)
{
	return evo_lua_call_env(c, "post_step", 0, 0, err);
}

/* ---- an episode's outcome: env.behaviour and env.solved ---------------- */

/* env[name](scene, bot) -> whether the environment has it, what it
 * returned; arguments: the evo_lua, name, the bot's index. A call of its
 * own, as env_call. */
static int outcome_call(lua_State *L)
{
	evo_lua *l = lua_touserdata(L, 1);
	const char *name = lua_tostring(L, 2);
	int bot = (int)lua_tointeger(L, 3);
	lua_rawgeti(L, LUA_REGISTRYINDEX, l->env_ref);
	if (lua_getfield(L, -1, name) == LUA_TNIL) {
		lua_pushboolean(L, 0);
		lua_pushnil(L);
		return 2;
	}
	lua_pushboolean(L, 1);
	lua_insert(L, -2);
	lua_rawgetp(L, LUA_REGISTRYINDEX, &evo_lua_scene_key);
	evo_lua_push_handle(L, EVO_LUA_BOT_MT, bot);
	lua_call(L, 2, 1);
	return 2;
}

/* Run env[name] for bot; 1 with its result on the stack, 0 when the
 * environment has none, -1 with err set. */
static int call_outcome(evo_lua *l, const char *name, int bot, evo_err *err)
{
	lua_State *L = l->L;
	lua_pushcfunction(L, outcome_call);
	lua_pushlightuserdata(L, l);
	lua_pushstring(L, name);
	lua_pushinteger(L, bot);
	if (evo_lua_pcall(l, 3, 2, EVO_LUA_BUDGET_RESET, EVO_LUA_TIME_RESET,
			  name) != LUA_OK) {
		evo_fail(err, "%s", evo_lua_errstr(L, -1));
		lua_pop(L, 1);
		return -1;
	}
	if (!lua_toboolean(L, -2)) {
		lua_pop(L, 2);
		return 0;
	}
	lua_remove(L, -2);
	return 1;
}

/* "Envs/Maze.lua:40" for env[name], as messages start. */
static void env_fn_where(evo_lua *l, const char *name, char *out, size_t cap)
{
	lua_State *L = l->L;
	lua_Debug ar;
	lua_rawgeti(L, LUA_REGISTRYINDEX, l->env_ref);
	lua_getfield(L, -1, name);
	if (lua_isfunction(L, -1)) {
		lua_getinfo(L, ">S", &ar);
		snprintf(out, cap, "%s:%d", ar.short_src, ar.linedefined);
	} else {
		lua_pop(L, 1);
		snprintf(out, cap, "%s", l->env_path);
	}
	lua_pop(L, 1);
}

int evo_lua_behaviour(evo_lua *l, int bot, double *out, int max,
		      evo_err *err)
{
	int rc = call_outcome(l, "behaviour", bot, err);
	if (rc <= 0)
		return rc;
	lua_State *L = l->L;
	char where[1300];
	size_t n = lua_type(L, -1) == LUA_TTABLE ? lua_rawlen(L, -1) : 0;
	if (n < 1 || n > (size_t)max) {
		env_fn_where(l, "behaviour", where, sizeof where);
		if (lua_type(L, -1) == LUA_TTABLE)
			evo_fail(err,
				 "%s: env.behaviour returned %zu values; a "
				 "behaviour is 1 to %d numbers in [0, 1]",
				 where, n, max);
		else
			evo_fail(err,
				 "%s: env.behaviour returned a %s, not a list "
				 "of 1 to %d numbers in [0, 1]",
				 where, luaL_typename(L, -1), max);
		lua_pop(L, 1);
		return -1;
	}
	for (size_t i = 0; i < n; i++) {
		int t = lua_rawgeti(L, -1, (lua_Integer)i + 1);
		double v = lua_tonumber(L, -1);
		lua_pop(L, 1);
		if (t == LUA_TNUMBER && isfinite(v) && v >= 0 && v <= 1) {
			out[i] = v;
			continue;
		}
		env_fn_where(l, "behaviour", where, sizeof where);
		if (t == LUA_TNUMBER)
			evo_fail(err,
				 "%s: env.behaviour's value %zu is %.17g, not "
				 "in [0, 1] (scale it, for example by the "
				 "arena's size)",
				 where, i + 1, v);
		else
			evo_fail(err,
				 "%s: env.behaviour's value %zu is a %s, not a "
				 "number in [0, 1]",
				 where, i + 1, lua_typename(L, t));
		lua_pop(L, 1);
		return -1;
	}
	lua_pop(L, 1);
	return (int)n;
}

int evo_lua_solved(evo_lua *l, int bot, int *solved, evo_err *err)
{
	int rc = call_outcome(l, "solved", bot, err);
	if (rc <= 0)
		return rc;
	lua_State *L = l->L;
	if (!lua_isboolean(L, -1)) {
		char where[1300];
		env_fn_where(l, "solved", where, sizeof where);
		evo_fail(err,
			 "%s: env.solved returned a %s, not a boolean (true "
			 "when the episode solved the task)",
			 where, luaL_typename(L, -1));
		lua_pop(L, 1);
		return -1;
	}
	*solved = lua_toboolean(L, -1);
	lua_pop(L, 1);
	return 1;
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
				  EVO_LUA_TIME_RESET,
				  "a reset function") != LUA_OK) {
			evo_fail(err, "%s (in a reset function)",
				 evo_lua_errstr(L, -1));
			lua_pop(L, 2);
			return -1;
		}
	}
	lua_pop(L, 1);
	return 0;
}


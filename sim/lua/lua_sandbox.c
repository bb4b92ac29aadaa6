/* The scene scripts' files and what they may use (lua_internal.h,
 * docs/lua.md): the lua/ folder, finding and loading a script (text only,
 * from the mind folder or lua/), the sandbox a scene state runs in
 * (require, load, setmetatable, xpcall and string patterns wrapped; io and
 * os stand-ins), and the `guard` table a mind folder's script gets in a
 * state of evo's own. lua_evo.c creates the states. */
#define _DEFAULT_SOURCE /* realpath */
#define _POSIX_C_SOURCE 200809L
#include <lauxlib.h>
#include <limits.h>
#include <lua.h>
#include <lualib.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/fileio.h"
#include "lua/lua_internal.h"

/* ---- the lua/ folder --------------------------------------------------- */

static int is_dir_with(const char *dir, const char *sub)
{
	char p[1200];
	snprintf(p, sizeof p, "%s/%s", dir, sub);
	return access(p, R_OK) == 0;
}

/* Found once: the evaluator's workers each create a Lua state at the same
 * time, and two realpath calls into one static buffer were a data race
 * (ThreadSanitizer, make test-tsan). Empty when no candidate exists. */
static char exe_lua_dir[1024];
static pthread_once_t exe_lua_dir_once = PTHREAD_ONCE_INIT;

static void find_exe_lua_dir(void)
{
	char exe[1024];
	ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
	if (n <= 0)
		return;
	exe[n] = 0;
	char *slash = strrchr(exe, '/');
	if (slash)
		*slash = 0;
	/* build/evo, build/asan/evo, PREFIX/bin/evo */
	const char *tries[] = {"%s/../lua", "%s/../../lua",
			       "%s/../share/evo/lua"};
	for (unsigned i = 0; i < 3; i++) {
		char raw[1100];
		snprintf(raw, sizeof raw, tries[i], exe);
		if (is_dir_with(raw, "envs") && realpath(raw, exe_lua_dir))
			return;
	}
	exe_lua_dir[0] = 0;
}

const char *evo_lua_dir(void)
{
	const char *env = getenv("EVO_LUA_DIR");
	if (env && env[0])
		return env;
	pthread_once(&exe_lua_dir_once, find_exe_lua_dir);
	return exe_lua_dir[0] ? exe_lua_dir : "lua";
}

/* ---- loading files ------------------------------------------------------- */

/* 1 when path, with every symbolic link followed, is a file inside
 * dir: a script or module found under the mind folder or lua/ may not be
 * a link to a file elsewhere (docs/lua.md, "What a script may use"). */
static int inside(const char *dir, const char *path)
{
	char rd[PATH_MAX], rp[PATH_MAX];
	if (!realpath(dir, rd) || !realpath(path, rp))
		return 0;
	size_t n = strlen(rd);
	return strncmp(rd, rp, n) == 0 && (rp[n] == '/' || n == 1);
}

/* Find NAME.lua in mind_dir/<mind_sub> then lua_dir/<lua_sub>. */
int evo_lua_find_script(const evo_lua *l, const char *dir, const char *mind_sub,
			const char *lua_sub, const char *name, char *out,
			size_t cap)
{
	if (!name[0] || strchr(name, '/') || strstr(name, ".."))
		return -1;
	if (!dir)
		dir = l->mind_dir;
	if (dir[0]) {
		snprintf(out, cap, "%s/%s/%s.lua", dir, mind_sub, name);
		if (evo_file_exists(out))
			return inside(dir, out) ? 0 : -2;
	}
	snprintf(out, cap, "%s/%s/%s.lua", l->lua_dir, lua_sub, name);
	if (!evo_file_exists(out))
		return -1;
	return inside(l->lua_dir, out) ? 0 : -2;
}

/* Load the text of a script file as a chunk named @path; raises. Text
 * only: a binary chunk can crash the Lua VM. */
static void load_text_file(lua_State *L, const char *path)
{
	char *text;
	size_t len;
	evo_err err;
	if (evo_read_file(path, &text, &len, &err)) {
		lua_pushstring(L, err.msg);
		lua_error(L);
	}
	lua_pushfstring(L, "@%s", path);
	int r = luaL_loadbufferx(L, text, len, lua_tostring(L, -1), "t");
	free(text);
	if (r != LUA_OK) {
		/* a syntax error names the file; "attempt to load a binary
		 * chunk" does not */
		const char *msg = evo_lua_errstr(L, -1);
		if (strncmp(msg, path, strlen(path)) != 0)
			lua_pushfstring(L, "%s: %s", path, msg);
		lua_error(L);
	}
	lua_remove(L, -2);
}

/* Run a script file and leave its single result on the stack; raises. */
void evo_lua_run_file(lua_State *L, const char *path, const char *what)
{
	load_text_file(L, path);
	/* an error the script raised without a place (error(msg, 0), or
	 * from a function it tail-called, as a generator's
	 * `return require('lib.openended').env(gen)`) is said at its file */
	int rc = lua_pcall(L, 0, 1, 0);
	if (rc == LUA_ERRRUN && lua_type(L, -1) == LUA_TSTRING &&
	    !strstr(lua_tostring(L, -1), ".lua:"))
		luaL_error(L, "%s: %s", path, lua_tostring(L, -1));
	if (rc != LUA_OK)
		lua_error(L);
	if (!lua_istable(L, -1))
		luaL_error(L, "%s: %s must return a table, returned %s", path,
			   what, luaL_typename(L, -1));
}

int evo_lua_load_model(lua_State *L, evo_lua *l, const char *model,
		       const char *dir)
{
	char path[1200];
	if (!dir)
		dir = l->mind_dir;
	int found = evo_lua_find_script(l, dir, "Bots", "bots", model, path,
					sizeof path);
	if (found == -2)
		luaL_error(L,
			   "bot model '%s': %s leads out of its folder (a "
			   "link?); scripts are loaded from the mind folder "
			   "and lua/ only",
			   model, path);
	if (found)
		luaL_error(L,
			   "bot model '%s' not found: looked for "
			   "%s/Bots/%s.lua and %s/bots/%s.lua",
			   model, dir[0] ? dir : ".", model, l->lua_dir, model);
	snprintf(l->bot_path, sizeof l->bot_path, "%s", path);
	evo_lua_run_file(L, path, "a bot model");
	return 1;
}

/* ---- the sandbox (docs/lua.md, "What a script may use") -------------- */

/* Call the function in upvalue 1 with the arguments, and return what
 * it returns. A stand-in's callee sees the stand-in, a C function, as
 * its caller: an error of its own is given the script's line here. */
static int call_upvalue(lua_State *L)
{
	lua_pushvalue(L, lua_upvalueindex(1));
	lua_insert(L, 1);
	if (lua_pcall(L, lua_gettop(L) - 1, LUA_MULTRET, 0) == LUA_OK)
		return lua_gettop(L);
	if (lua_type(L, -1) == LUA_TSTRING) {
		luaL_where(L, 1);
		const char *w = lua_tostring(L, -1), *colon = strchr(w, ':');
		/* an error from the script's own code has a line already */
		if (colon &&
		    strncmp(lua_tostring(L, -2), w, (size_t)(colon - w + 1)))
			lua_insert(L, -2), lua_concat(L, 2);
		else
			lua_pop(L, 1);
	}
	return lua_error(L);
}

/* `load` of text chunks only: a binary chunk can crash the Lua VM. */
static int load_text(lua_State *L)
{
	if (lua_gettop(L) < 3)
		lua_settop(L, 3);
	lua_pushliteral(L, "t");
	lua_replace(L, 3);
	return call_upvalue(L);
}

/* require(name), evo's own loader: NAME.lua, with dots as folders, in
 * the mind folder, then in lua/; text only; where modules are looked for
 * is evo's, not the script's (package.path does not exist, and the
 * `package` the script sees is read-only). A name is letters, digits,
 * '_' and '-' between dots, so that it cannot climb out of those
 * folders, and a module that is a link to a file elsewhere is not
 * found. */
static int sandbox_require(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	const char *name = luaL_checkstring(L, 1);
	/* a sandbox inside a state of evo's own (evo_lua_open_guard) has
	 * its loaded table and globals as upvalues 1 and 2 */
	int own_env = lua_istable(L, lua_upvalueindex(2));
	lua_settop(L, 1);
	if (own_env)
		lua_pushvalue(L, lua_upvalueindex(1)); /* 2 */
	else
		luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
	lua_pushvalue(L, 1);
	if (lua_rawget(L, 2) != LUA_TNIL)
		return 1;
	lua_pop(L, 1);
	char rel[256];
	size_t n = strlen(name), seg = 0;
	int ok = n > 0 && n < sizeof rel;
	for (size_t i = 0; ok && i <= n; i++) {
		char c = name[i];
		if (c == '.' || c == 0) {
			ok = seg > 0;
			seg = 0;
			rel[i] = c ? '/' : 0;
		} else {
			ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
			     (c >= '0' && c <= '9') || c == '_' || c == '-';
			seg++;
			rel[i] = c;
		}
	}
	if (!ok)
		return luaL_error(L,
				  "require '%s': a module's name is names of "
				  "letters, digits, '_' and '-' joined by '.' "
				  "(docs/lua.md, \"What a script may use\")",
				  name);
	const char *dirs[2] = {l->mind_dir, l->lua_dir};
	char path[2][1400];
	for (int k = 0; k < 2; k++) {
		snprintf(path[k], sizeof path[k], "%s/%s.lua",
			 dirs[k][0] ? dirs[k] : ".", rel);
		if (!dirs[k][0] || !evo_file_exists(path[k]))
			continue;
		if (!inside(dirs[k], path[k]))
			return luaL_error(L,
					  "require '%s': %s leads out of %s "
					  "(a link?); scene scripts load "
					  "modules from the mind folder and "
					  "lua/ only",
					  name, path[k], dirs[k]);
		load_text_file(L, path[k]);
		if (own_env) {
			lua_pushvalue(L, lua_upvalueindex(2));
			lua_setupvalue(L, -2, 1); /* its _ENV */
		}
		lua_pushvalue(L, 1);
		lua_pushstring(L, path[k]);
		lua_call(L, 2, 1);
		if (lua_isnil(L, -1)) {
			lua_pop(L, 1);
			lua_pushboolean(L, 1);
		}
		lua_pushvalue(L, 1);
		lua_pushvalue(L, -2);
		lua_rawset(L, 2);
		return 1;
	}
	return luaL_error(L, "module '%s' not found: looked for %s and %s",
			  name, l->mind_dir[0] ? path[0] : "(no mind folder)",
			  path[1]);
}

/* __newindex of the read-only `package`. */
static int package_read_only(lua_State *L)
{
	return luaL_error(L,
			  "package.%s cannot be set in scene scripts: require "
			  "finds modules in the mind folder and lua/ only "
			  "(docs/lua.md, \"What a script may use\")",
			  luaL_optstring(L, 2, "?"));
}

/* setmetatable, without __gc: a finalizer runs with the hooks off, when
 * the collector decides and again at lua_close, where no limit can stop
 * it (docs/lua.md). */
static int sandbox_setmetatable(lua_State *L)
{
	if (lua_type(L, 2) == LUA_TTABLE) {
		lua_pushliteral(L, "__gc");
		if (lua_rawget(L, 2) != LUA_TNIL)
			return luaL_error(L,
					  "setmetatable: __gc is not "
					  "available in scene scripts: evo "
					  "cannot bound the time a finalizer "
					  "takes (docs/lua.md)");
		lua_pop(L, 1);
	}
	return call_upvalue(L);
}

/* The message handler xpcall is given, around the script's: once a limit
 * is reached the script's handler is not called (it would run with the
 * hooks off, after the hook's error) and the limit's message is the
 * result. */
static int sandbox_handler(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	if (l->over) {
		lua_pushstring(L, l->over_msg);
		return 1;
	}
	lua_pushvalue(L, lua_upvalueindex(1));
	lua_insert(L, 1);
	lua_call(L, lua_gettop(L) - 1, 1);
	return 1;
}

static int sandbox_xpcall(lua_State *L)
{
	luaL_checktype(L, 2, LUA_TFUNCTION);
	lua_pushvalue(L, 2);
	lua_pushcclosure(L, sandbox_handler, 1);
	lua_replace(L, 2);
	return call_upvalue(L);
}

/* string.find, match, gmatch and gsub: a pattern that backtracks can
 * take seconds in one call, where no hook runs; the line that made the
 * call is noted first, for the watchdog's message. */
static int sandbox_pattern(lua_State *L)
{
	evo_lua_note_where(evo_lua_ctx(L), L, 1);
	return call_upvalue(L);
}

/* Replace t[name] (t at idx) by a C closure of fn over the old value. */
static void wrap(lua_State *L, int idx, const char *name, lua_CFunction fn)
{
	idx = lua_absindex(L, idx);
	lua_getfield(L, idx, name);
	lua_pushcclosure(L, fn, 1);
	lua_setfield(L, idx, name);
}

/* The pattern functions of the string table at idx, by sandbox_pattern. */
static void wrap_patterns(lua_State *L, int idx)
{
	static const char *const patterns[] = {"find", "match", "gmatch",
					       "gsub"};
	for (unsigned i = 0; i < 4; i++)
		wrap(L, idx, patterns[i], sandbox_pattern);
}

/* __index of the stand-ins for io and os: any name but the ones they
 * keep is an error at the script's line. */
static int not_available(lua_State *L)
{
	const char *lib = lua_tostring(L, lua_upvalueindex(1));
	const char *why = strcmp(lib, LUA_IOLIBNAME) == 0
			      ? "they may not read or write files"
			      : "of os they have os.clock only";
	return luaL_error(L,
			  "%s.%s is not available in scene scripts: %s "
			  "(docs/lua.md, \"What a script may use\")",
			  lib, luaL_optstring(L, 2, "?"), why);
}

/* A global table `lib` whose unknown names raise not_available; for os,
 * it keeps os.clock. */
static void stand_in(lua_State *L, const char *lib)
{
	lua_newtable(L);
	if (strcmp(lib, LUA_OSLIBNAME) == 0) {
		luaL_requiref(L, LUA_OSLIBNAME, luaopen_os, 0);
		lua_getfield(L, -1, "clock");
		lua_setfield(L, -3, "clock");
		lua_pop(L, 1);
	}
	lua_newtable(L);
	lua_pushstring(L, lib);
	lua_pushcclosure(L, not_available, 1);
	lua_setfield(L, -2, "__index");
	lua_setmetatable(L, -2);
	luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
	lua_pushvalue(L, -2);
	lua_setfield(L, -2, lib); /* require "os" gives the stand-in */
	lua_pop(L, 1);
	lua_setglobal(L, lib);
}

/* The libraries a scene script gets: the base library without dofile and
 * loadfile, load of text only, setmetatable without __gc, xpcall whose
 * handler does not run past a limit; evo's require (sandbox_require),
 * with a read-only `package` that has `loaded` only; coroutine, string
 * (its pattern functions note their caller's line), table, math, utf8;
 * io and os as stand-ins that say what is missing, os keeping os.clock.
 * No debug. The learning loop's state (sim/learn/learn.c) is evo's own
 * code and keeps every library. */
void evo_lua_open_sandbox(lua_State *L)
{
	static const luaL_Reg libs[] = {
	    {LUA_GNAME, luaopen_base},	     {LUA_COLIBNAME, luaopen_coroutine},
	    {LUA_TABLIBNAME, luaopen_table}, {LUA_STRLIBNAME, luaopen_string},
	    {LUA_MATHLIBNAME, luaopen_math}, {LUA_UTF8LIBNAME, luaopen_utf8},
	};
	for (unsigned i = 0; i < sizeof libs / sizeof libs[0]; i++) {
		luaL_requiref(L, libs[i].name, libs[i].func, 1);
		lua_pop(L, 1);
	}
	lua_pushglobaltable(L);
	int g = lua_gettop(L);
	lua_pushnil(L);
	lua_setfield(L, g, "dofile");
	lua_pushnil(L);
	lua_setfield(L, g, "loadfile");
	wrap(L, g, "load", load_text);
	wrap(L, g, "setmetatable", sandbox_setmetatable);
	wrap(L, g, "xpcall", sandbox_xpcall);
	lua_pushcfunction(L, sandbox_require);
	lua_setfield(L, g, "require");
	/* package: an empty table whose __index shows `loaded` */
	lua_newtable(L);
	lua_newtable(L);
	lua_newtable(L);
	luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
	lua_setfield(L, -2, "loaded");
	lua_setfield(L, -2, "__index");
	lua_pushcfunction(L, package_read_only);
	lua_setfield(L, -2, "__newindex");
	lua_pushboolean(L, 0);
	lua_setfield(L, -2, "__metatable");
	lua_setmetatable(L, -2);
	luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
	lua_pushvalue(L, -2);
	lua_setfield(L, -2, LUA_LOADLIBNAME);
	lua_pop(L, 1);
	lua_setfield(L, g, LUA_LOADLIBNAME);
	lua_getfield(L, g, LUA_STRLIBNAME);
	wrap_patterns(L, -1);
	lua_pop(L, 2);
	stand_in(L, LUA_IOLIBNAME);
	stand_in(L, LUA_OSLIBNAME);
}

/* ---- a mind folder's script in a state of evo's own ------------------- */

static int guard_gc(lua_State *L)
{
	evo_lua *l = lua_touserdata(L, 1);
	evo_lua_watch_remove(l->watch);
	l->watch = NULL;
	return 0;
}

/* guard.call(what, kind, fn, ...): fn(...) under the limits of a scene
 * script's call of that kind ("load": loading and init, else reset's);
 * returns what fn returns, or raises its error, at its file:line. */
static int guard_call(lua_State *L)
{
	evo_lua *l = evo_lua_ctx(L);
	const char *what = luaL_checkstring(L, 1);
	int load = strcmp(luaL_checkstring(L, 2), "load") == 0;
	luaL_checktype(L, 3, LUA_TFUNCTION);
	lua_State *outer = l->L;
	void (*on_hit)(void *) = l->mem->on_hit;
	void *hit_ctx = l->mem->ctx;
	int enforce = l->mem->enforce;
	l->L = L;
	l->mem->on_hit = evo_lua_memory_hit;
	l->mem->ctx = l;
	int r =
	    evo_lua_pcall(l, lua_gettop(L) - 3, LUA_MULTRET,
			  load ? EVO_LUA_BUDGET_INIT : EVO_LUA_BUDGET_RESET,
			  load ? EVO_LUA_TIME_INIT : EVO_LUA_TIME_RESET, what);
	l->L = outer;
	l->mem->on_hit = on_hit;
	l->mem->ctx = hit_ctx;
	l->mem->enforce = enforce;
	if (r != LUA_OK)
		return lua_error(L);
	return lua_gettop(L) - 2;
}

/* guard.require(loaded, env): a scene script's require, that loads
 * modules into loaded, their globals being env. */
static int guard_require(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	lua_settop(L, 2);
	lua_pushcclosure(L, sandbox_require, 2);
	return 1;
}

/* guard.patterns(t): a scene script's string.find, match, gmatch and
 * gsub in the string table t, which note their caller's line for the
 * watchdog. */
static int guard_patterns(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	wrap_patterns(L, 1);
	return 0;
}

void evo_lua_open_guard(lua_State *L, evo_lua_mem *mem,
			const evo_lua_limits *limits, const char *mind_dir)
{
	evo_lua *l = lua_newuserdatauv(L, sizeof *l, 0);
	memset(l, 0, sizeof *l);
	l->L = L;
	l->mem = mem;
	l->limits = *limits;
	l->env_ref = LUA_NOREF;
	snprintf(l->mind_dir, sizeof l->mind_dir, "%s", mind_dir);
	snprintf(l->lua_dir, sizeof l->lua_dir, "%s", evo_lua_dir());
	l->watch = evo_lua_watch_add();
	lua_newtable(L);
	lua_pushcfunction(L, guard_gc);
	lua_setfield(L, -2, "__gc");
	lua_setmetatable(L, -2);
	lua_rawsetp(L, LUA_REGISTRYINDEX, &evo_lua_ctx_key);
	lua_newtable(L);
	lua_pushcfunction(L, guard_call);
	lua_setfield(L, -2, "call");
	lua_pushcfunction(L, guard_require);
	lua_setfield(L, -2, "require");
	lua_pushcfunction(L, guard_patterns);
	lua_setfield(L, -2, "patterns");
}

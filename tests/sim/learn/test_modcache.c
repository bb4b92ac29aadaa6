/* The learning loop's modules compiled once a process
 * (sim/learn/lua_modcache.c): a second Lua state that requires a module
 * gets the first state's compiled code (the file, changed in between, is
 * not read again), and an error raised in it names the file and line as
 * when compiled from the file. */
#define _POSIX_C_SOURCE 200809L
#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "learn/lua_modcache.h"
#include "lua/lua_evo.h"
#include "support/cli.h"

static char dir[512], file[600];

static void write_module(const char *text)
{
	FILE *f = fopen(file, "w");
	CHECK(f != NULL);
	if (f) {
		fputs(text, f);
		fclose(f);
	}
}

static lua_State *state(void)
{
	lua_State *L = luaL_newstate();
	luaL_openlibs(L);
	evo_lua_set_path(L, dir);
	evo_lua_modcache_install(L);
	return L;
}

/* require 'mc_probe' in L, then m.value(); the value, or "error: MSG". */
static void call(lua_State *L, const char *what, char *out, size_t cap)
{
	char code[200];
	snprintf(code, sizeof code, "return require('mc_probe').%s()", what);
	if (luaL_dostring(L, code) == LUA_OK)
		snprintf(out, cap, "%s", lua_tostring(L, -1));
	else
		snprintf(out, cap, "error: %s", lua_tostring(L, -1));
	lua_settop(L, 0);
}

TEST(a_second_state_gets_the_first_states_code)
{
	write_module("local M = {}\n"
		     "function M.value() return 'one' end\n"
		     "function M.fail()\n"
		     "  error('boom')\n"
		     "end\n"
		     "return M\n");
	lua_State *a = state();
	char got[300];
	call(a, "value", got, sizeof got);
	CHECK_EQ_STR(got, "one");
	/* the file changes: a new state still runs what the first
	 * compiled, with its lines */
	write_module("return { value = function() return 'two' end }\n");
	lua_State *b = state();
	call(b, "value", got, sizeof got);
	CHECK_EQ_STR(got, "one");
	call(b, "fail", got, sizeof got);
	CHECK_CONTAINS(got, "mc_probe.lua:4: boom");
	/* the second value require gives is the file's name, as Lua's */
	CHECK(luaL_dostring(b,
			    "package.loaded.mc_probe = nil\n"
			    "return select(2, require('mc_probe'))") == LUA_OK);
	CHECK_CONTAINS(lua_tostring(b, -1), "/mc_probe.lua");
	lua_close(a);
	lua_close(b);
}

TEST(a_module_that_is_not_there_is_said_as_lua_says_it)
{
	lua_State *L = state();
	CHECK(luaL_dostring(L, "require('mc_absent')") != LUA_OK);
	CHECK_EQ_INT(lua_gettop(L), 1);
	const char *msg = lua_tostring(L, -1);
	CHECK_CONTAINS(msg, "module 'mc_absent' not found");
	CHECK_CONTAINS(msg, "mc_absent.lua");
	lua_close(L);
}

int main(void)
{
	snprintf(dir, sizeof dir, "%s/evo-test-modcache-XXXXXX",
		 cli_tmp_root());
	if (!mkdtemp(dir)) {
		perror(dir);
		return 1;
	}
	snprintf(file, sizeof file, "%s/mc_probe.lua", dir);
	RUN(a_second_state_gets_the_first_states_code);
	RUN(a_module_that_is_not_there_is_said_as_lua_says_it);
	unlink(file);
	rmdir(dir);
	return test_summary();
}

/* Runs the Lua unit tests: every tests/lua/test_*.lua returns a table of
 * named test functions; each runs under pcall in a fresh Lua state, so one
 * test cannot leave state behind for the next. A test fails when it raises
 * (the tests' check() helper raises with file:line). Modules are found
 * under EVO_LUA_DIR (default "lua"), so require "learn.neat" loads
 * lua/learn/neat.lua; the tests under EVO_LUA_TESTS (default "tests/lua").
 * Ends with "N passed, N failed" and exits non-zero on failure. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>

#include "learn/lua_linalg.h"
#include "learn/lua_neat.h"
#include "learn/lua_novelty.h"
#include "lua/lua_evo.h"

#define MAX_FILES 64
#define MAX_TESTS 256
#define NAME_MAX_LEN 128

static int passed_count, failed_count;

static const char *env_or(const char *name, const char *fallback)
{
	const char *v = getenv(name);
	return v && *v ? v : fallback;
}

static int cmp_names(const void *a, const void *b)
{
	return strcmp((const char *)a, (const char *)b);
}

static double now_seconds(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* A state with the standard libraries and package.path pointing at the
 * module folder first. Returns NULL (after a message) on failure. */
static lua_State *new_state(const char *lua_dir)
{
	lua_State *L = luaL_newstate();
	if (!L) {
		printf("cannot create a Lua state\n");
		return NULL;
	}
	luaL_openlibs(L);
	lua_getglobal(L, "package");
	lua_pushfstring(L, "%s/?.lua;%s/?/init.lua", lua_dir, lua_dir);
	lua_setfield(L, -2, "path");
	lua_pop(L, 1);
	evo_lua_open_data(L); /* serialize.load reads with it */
	evo_lua_open_linalg(L); /* learn.cmaes's eigendecomposition */
	evo_lua_open_neat(L); /* the learning loop's kernels, as it has them */
	evo_lua_open_novelty(L); /* novelty search's kNN, the same */
	return L;
}

/* Loads the test file and leaves its table on the stack. */
static int load_tests(lua_State *L, const char *path)
{
	if (luaL_loadfile(L, path) != LUA_OK || lua_pcall(L, 0, 1, 0) != LUA_OK) {
		printf("FAIL %s\n  %s\n", path, evo_lua_errstr(L, -1));
		return 0;
	}
	if (!lua_istable(L, -1)) {
		printf("FAIL %s\n  expected the file to return a table of tests\n", path);
		return 0;
	}
	return 1;
}

/* The sorted names of the test functions in the table on top of the stack. */
static int test_names(lua_State *L, char names[][NAME_MAX_LEN], int max)
{
	int n = 0;
	lua_pushnil(L);
	while (lua_next(L, -2)) {
		if (lua_type(L, -2) == LUA_TSTRING && lua_isfunction(L, -1) && n < max) {
			snprintf(names[n], NAME_MAX_LEN, "%s", lua_tostring(L, -2));
			n++;
		}
		lua_pop(L, 1);
	}
	qsort(names, (size_t)n, sizeof names[0], cmp_names);
	return n;
}

static void run_file(const char *lua_dir, const char *path)
{
	static char names[MAX_TESTS][NAME_MAX_LEN];
	lua_State *L = new_state(lua_dir);
	int n;

	if (!L || !load_tests(L, path)) {
		failed_count++;
		if (L)
			lua_close(L);
		return;
	}
	n = test_names(L, names, MAX_TESTS);
	lua_close(L);
	for (int i = 0; i < n; i++) {
		double t0 = now_seconds();
		int ok;

		L = new_state(lua_dir);
		if (!L || !load_tests(L, path)) {
			failed_count++;
			if (L)
				lua_close(L);
			continue;
		}
		lua_getfield(L, -1, names[i]);
		ok = lua_pcall(L, 0, 0, 0) == LUA_OK;
		if (ok) {
			passed_count++;
			printf("ok   %s %s (%.2f s)\n", path, names[i], now_seconds() - t0);
		} else {
			failed_count++;
			printf("FAIL %s %s\n  %s\n", path, names[i], evo_lua_errstr(L, -1));
		}
		lua_close(L);
	}
}

int main(void)
{
	static char files[MAX_FILES][NAME_MAX_LEN];
	const char *lua_dir = env_or("EVO_LUA_DIR", "lua");
	const char *test_dir = env_or("EVO_LUA_TESTS", "tests/lua");
	int n = 0;
	DIR *d = opendir(test_dir);

	if (!d) {
		printf("FAIL cannot open %s\n", test_dir);
		failed_count++;
	} else {
		struct dirent *e;
		while ((e = readdir(d)) != NULL) {
			size_t len = strlen(e->d_name);
			if (strncmp(e->d_name, "test_", 5) == 0 && len > 4 &&
			    strcmp(e->d_name + len - 4, ".lua") == 0 && n < MAX_FILES &&
			    len < NAME_MAX_LEN) {
				memcpy(files[n], e->d_name, len + 1);
				n++;
			}
		}
		closedir(d);
		qsort(files, (size_t)n, sizeof files[0], cmp_names);
		if (n == 0) {
			printf("FAIL no test_*.lua in %s\n", test_dir);
			failed_count++;
		}
	}
	for (int i = 0; i < n; i++) {
		size_t size = strlen(test_dir) + strlen(files[i]) + 2;
		char *path = malloc(size);

		if (!path) {
			printf("FAIL out of memory\n");
			failed_count++;
			break;
		}
		snprintf(path, size, "%s/%s", test_dir, files[i]);
		run_file(lua_dir, path);
		free(path);
	}
	printf("%d passed, %d failed\n", passed_count, failed_count);
	return failed_count != 0;
}

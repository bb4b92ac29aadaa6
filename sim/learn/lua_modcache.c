/* The learning loop's modules compiled once a process: see
 * lua_modcache.h. */
#define _POSIX_C_SOURCE 200809L /* strdup */
#include "learn/lua_modcache.h"

#include <lauxlib.h>
#include <lua.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* Files of lua/ that a process requires: a handful. */
#define MAX_CHUNKS 32

typedef struct chunk {
	char *path; /* the file package.searchpath found */
	char *code; /* its bytecode */
	size_t len;
} chunk;

static pthread_mutex_t cache_mu = PTHREAD_MUTEX_INITIALIZER;
static chunk cache[MAX_CHUNKS];
static int n_cached;

typedef struct dump_buf {
	char *data;
	size_t len, cap;
	int failed;
} dump_buf;

static int dump_writer(lua_State *L, const void *p, size_t sz, void *ud)
{
	(void)L;
	dump_buf *b = ud;
	if (b->failed)
		return 1;
	if (b->len + sz > b->cap) {
		size_t cap = b->cap ? b->cap : 4096;
		while (cap < b->len + sz)
			cap *= 2;
		char *d = realloc(b->data, cap);
		if (!d) {
			b->failed = 1;
			return 1;
		}
		b->data = d;
		b->cap = cap;
	}
	memcpy(b->data + b->len, p, sz);
	b->len += sz;
	return 0;
}

/* The cached bytecode of path loaded onto L's stack: 1, or 0 when path
 * has none. */
static int load_cached(lua_State *L, const char *path)
{
	int found = 0;
	pthread_mutex_lock(&cache_mu);
	for (int i = 0; i < n_cached && !found; i++)
		if (strcmp(cache[i].path, path) == 0)
			found = luaL_loadbufferx(L, cache[i].code, cache[i].len,
						 path, "b") == LUA_OK;
	pthread_mutex_unlock(&cache_mu);
	return found;
}

/* Keep the bytecode of the Lua function at the top of L's stack as
 * path's (nothing when it cannot: the next state compiles again). */
static void keep(lua_State *L, const char *path)
{
	dump_buf b = {0};
	if (lua_dump(L, dump_writer, &b, 0) != 0 || b.failed) {
		free(b.data);
		return;
	}
	char *p = strdup(path);
	pthread_mutex_lock(&cache_mu);
	int have = 0;
	for (int i = 0; i < n_cached; i++)
		have |= strcmp(cache[i].path, path) == 0;
	if (!have && p && n_cached < MAX_CHUNKS) {
		cache[n_cached++] = (chunk){p, b.data, b.len};
		p = NULL;
		b.data = NULL;
	}
	pthread_mutex_unlock(&cache_mu);
	free(p);
	free(b.data);
}

/* require's searcher for Lua files (upvalue 1: Lua's own): the file
 * package.searchpath finds along package.path, from the cache when an
 * earlier state compiled it; else Lua's searcher, whose result is kept.
 * Returns what a searcher returns: the loader and the file's name, or
 * Lua's message of where it looked. */
static int cached_searcher(lua_State *L)
{
	luaL_checkstring(L, 1);
	/* package.searchpath(name, package.path) */
	lua_getglobal(L, "package");
	lua_getfield(L, -1, "searchpath");
	lua_pushvalue(L, 1);
	lua_getfield(L, -3, "path");
	if (lua_type(L, -1) == LUA_TSTRING &&
	    lua_type(L, -3) == LUA_TFUNCTION) {
		lua_call(L, 2, 1);
		if (lua_type(L, -1) == LUA_TSTRING) {
			const char *file = lua_tostring(L, -1);
			if (load_cached(L, file)) {
				lua_pushvalue(L, -2); /* the file's name */
				return 2;
			}
		}
	}
	lua_settop(L, 1);
	/* Lua's own searcher: compiles, or says why not */
	lua_pushvalue(L, lua_upvalueindex(1));
	lua_pushvalue(L, 1);
	lua_call(L, 1, 2);
	if (lua_type(L, -2) == LUA_TFUNCTION &&
	    lua_type(L, -1) == LUA_TSTRING) {
		const char *file = lua_tostring(L, -1);
		lua_pushvalue(L, -2);
		keep(L, file);
		lua_pop(L, 1);
	}
	return 2;
}

void evo_lua_modcache_install(lua_State *L)
{
	lua_getglobal(L, "package");
	if (lua_getfield(L, -1, "searchers") == LUA_TTABLE &&
	    lua_rawgeti(L, -1, 2) == LUA_TFUNCTION) {
		lua_pushcclosure(L, cached_searcher, 1);
		lua_rawseti(L, -2, 2);
	} else {
		lua_pop(L, 1);
	}
	lua_pop(L, 2);
}

/* libFuzzer target for evo.data.read (sim/lua/lua_data.c), the reader of
 * checkpoints. Besides crashes and sanitizer reports it checks the
 * reader's promises: anything it refuses gets an error that starts with
 * the text's name and a line, "f.lua:N: ", and it never runs the text. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <lauxlib.h>
#include <lua.h>

#include "lua/lua_evo.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static lua_State *L;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (!L) {
		L = luaL_newstate();
		if (!L)
			abort();
		evo_lua_open_data(L);
	}
	lua_settop(L, 0);
	luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
	if (lua_getfield(L, -1, "evo.data") != LUA_TTABLE ||
	    lua_getfield(L, -1, "read") != LUA_TFUNCTION)
		abort();
	lua_pushlstring(L, (const char *)data, size);
	lua_pushliteral(L, "f.lua");
	if (lua_pcall(L, 2, 1, 0) != LUA_OK) {
		const char *msg = lua_tostring(L, -1);
		if (!msg || strncmp(msg, "f.lua:", 6) != 0 || msg[6] < '0' ||
		    msg[6] > '9')
			abort();
	}
	lua_settop(L, 0);
	lua_gc(L, LUA_GCCOLLECT);
	return 0;
}

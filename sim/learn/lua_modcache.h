/* evo — the learning loop's Lua modules compiled once a process: `evo
 * run` checks a task's options in a Lua state of their own before the
 * loop's state starts (sim/learn/learn.c), and both require the same
 * modules of lua/learn (common, neat, netfile, rng, ...). The first state
 * to require a module compiles it as Lua does and keeps its bytecode
 * (lua_dump, debug information kept: messages and tracebacks name the
 * same file and lines); later states load that bytecode instead of
 * compiling the file again. Compiling was a tenth of a run of XOR. */
#ifndef EVO_LUA_MODCACHE_H
#define EVO_LUA_MODCACHE_H

struct lua_State;

/* Put the caching searcher in place of package.searchers[2] (Lua files
 * along package.path) of L; call after luaL_openlibs and
 * evo_lua_set_path. */
void evo_lua_modcache_install(struct lua_State *L);

#endif

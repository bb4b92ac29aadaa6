/* The learning loop's kernels in C (module evo.neat, sim/learn/lua_neat.c):
 * what lua/learn/neat.lua and lua/learn/serialize.lua would otherwise do
 * in the interpreter on every generation. */
#ifndef EVO_LUA_NEAT_H
#define EVO_LUA_NEAT_H

#include "evo/formats.h"

struct lua_State;

/* Registers evo.neat in L (package.loaded), for `require "evo.neat"`. */
void evo_lua_open_neat(struct lua_State *L);

/* When the value at idx is a network evo.neat.pack_net made: fills *d
 * (header and the nodes and links it has; the arrays past them are left
 * as they are) and returns 1. Otherwise returns 0 and leaves *d alone. */
int evo_lua_net_unpack(struct lua_State *L, int idx, evo_netdesc *d);

#endif

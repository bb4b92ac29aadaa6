/* evo — novelty search's k-nearest-neighbour novelty in C: the module
 * evo.novelty (sim/learn/lua_novelty.c), for lua/learn/novelty.lua. */
#ifndef EVO_LUA_NOVELTY_H
#define EVO_LUA_NOVELTY_H

struct lua_State;

/* The novelty of each of n points (row-major, d numbers each): the mean
 * Euclidean distance to its k nearest neighbours among the other n - 1
 * points and the m points of archive (a point is not its own neighbour).
 * With fewer than k neighbours, the mean over all of them; with none, 0.
 * The k smallest distances are summed in ascending order, so the result
 * is the same to the last bit as sorting every distance and summing the
 * first k (novelty.knn_lua). nearest is scratch for k doubles. */
void evo_novelty_knn(int n, const double *points, int m, const double *archive,
		     int d, int k, double *nearest, double *out);

/* Registers evo.novelty in L (package.loaded), for require "evo.novelty". */
void evo_lua_open_novelty(struct lua_State *L);

#endif

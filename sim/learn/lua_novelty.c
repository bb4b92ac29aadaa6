/* evo — evo.novelty: the k-nearest-neighbour novelty novelty search
 * ranks a generation by (lua/learn/novelty.lua), in C: a generation of 250
 * against an archive of thousands is a million distances, which the
 * interpreter would take longer over than the maze takes to run them.
 *
 *	local kernel = require "evo.novelty"
 *	local novelty = kernel.knn(points, archive, d, k)
 *
 * points and archive are flat lists of numbers, d per point (archive may
 * be empty); novelty[i] is point i's mean distance to its k nearest
 * neighbours among the other points and the archive. novelty.lua's
 * knn_lua is the reference it must equal bit for bit
 * (tests/lua/test_novelty.lua). */
#include <lauxlib.h>
#include <lua.h>
#include <math.h>
#include <stdlib.h>

#include "learn/lua_linalg.h"
#include "learn/lua_novelty.h"

/* Bounds on what knn takes, far above any task (a descriptor of a few
 * numbers, k = 15, a population of at most 10,000) and low enough that
 * n * d and k never overflow what they are counted in. */
#define MAX_DIMS   4096
#define MAX_K	   100000
#define MAX_POINTS 100000000

static double distance(const double *a, const double *b, int d)
{
	double s = 0;
	for (int j = 0; j < d; j++) {
		double t = a[j] - b[j];
		s += t * t;
	}
	return sqrt(s);
}

/* Keeps nearest[0..*c) the *c smallest distances offered so far (at most
 * k), ascending. */
static void offer(double *nearest, int *c, int k, double x)
{
	int i = *c;
	if (i == k) {
		if (!(x < nearest[k - 1]))
			return;
		i = k - 1;
	} else {
		++*c;
	}
	while (i > 0 && nearest[i - 1] > x) {
		nearest[i] = nearest[i - 1];
		i--;
	}
	nearest[i] = x;
}

void evo_novelty_knn(int n, const double *points, int m, const double *archive,
		     int d, int k, double *nearest, double *out)
{
	for (int i = 0; i < n; i++) {
		const double *p = points + (size_t)i * (size_t)d;
		int c = 0;
		for (int j = 0; j < n; j++)
			if (j != i)
				offer(nearest, &c, k,
				      distance(p,
					       points + (size_t)j * (size_t)d,
					       d));
		for (int a = 0; a < m; a++)
			offer(nearest, &c, k,
			      distance(p, archive + (size_t)a * (size_t)d, d));
		double sum = 0;
		for (int q = 0; q < c; q++)
			sum += nearest[q];
		out[i] = c > 0 ? sum / c : 0;
	}
}

/* The numbers of the list at idx, into a fresh userdata left on the
 * stack; *count is how many. what names the list in messages. */
static double *read_list(lua_State *L, int idx, const char *what, int *count)
{
	lua_Integer len = luaL_len(L, idx);
	if (len < 0 || len > MAX_POINTS)
		luaL_error(L, "knn: %s holds %I numbers (at most %d)", what,
			   len, MAX_POINTS);
	double *v = lua_newuserdatauv(L, ((size_t)len + 1) * sizeof *v, 0);
	evo_lua_finite_list(L, idx, len, v, "knn", what);
	*count = (int)len;
	return v;
}

/* knn(points, archive, d, k) -> the novelty of each point. */
static int l_knn(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	lua_Integer d = luaL_checkinteger(L, 3);
	lua_Integer k = luaL_checkinteger(L, 4);
	luaL_argcheck(L, d >= 1 && d <= MAX_DIMS, 3,
		      "d must be from 1 to 4096");
	luaL_argcheck(L, k >= 1 && k <= MAX_K, 4, "k must be from 1 to 100000");
	int np, na;
	const double *points = read_list(L, 1, "points", &np);
	const double *archive = read_list(L, 2, "archive", &na);
	if (np % d || na % d)
		return luaL_error(L,
				  "knn: %d and %d numbers are not whole points "
				  "of %d",
				  np, na, (int)d);
	int n = np / (int)d, m = na / (int)d;
	double *nearest = lua_newuserdatauv(L, (size_t)k * sizeof *nearest, 0);
	double *out = lua_newuserdatauv(L, ((size_t)n + 1) * sizeof *out, 0);
	evo_novelty_knn(n, points, m, archive, (int)d, (int)k, nearest, out);
	lua_createtable(L, n, 0);
	for (int i = 0; i < n; i++) {
		lua_pushnumber(L, out[i]);
		lua_rawseti(L, -2, i + 1);
	}
	return 1;
}

static const luaL_Reg novelty_fns[] = {{"knn", l_knn}, {NULL, NULL}};

static int open_novelty(lua_State *L)
{
	luaL_newlib(L, novelty_fns);
	return 1;
}

void evo_lua_open_novelty(lua_State *L)
{
	luaL_requiref(L, "evo.novelty", open_novelty, 0);
	lua_pop(L, 1);
}

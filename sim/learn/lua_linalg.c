/* evo — evo.linalg: the symmetric eigendecomposition CMA-ES needs
 * (lua/learn/cmaes.lua) and the nearest-centroid search of MAP-Elites'
 * CVT archive (lua/learn/mapelites.lua), in C so a method written in Lua
 * does not pay the interpreter for an O(n^3) or O(points * centroids)
 * kernel.
 *
 *	local linalg = require "evo.linalg"
 *	local values, vectors, sweeps = linalg.eigh(n, a)
 *	local cell = linalg.nearest(d, centroids, points)
 *
 * nearest: centroids and points are flat lists of d-vectors; cell[i] is
 * the 1-based index of the centroid nearest to point i (squared Euclidean
 * distance, summed over the coordinates in order; the first of equals).
 *
 * eigh: *
 * a is a flat row-major list of n * n numbers (symmetric; the upper
 * triangle is read); values a list of n eigenvalues, vectors a flat
 * row-major n * n list whose column j is the unit eigenvector of
 * values[j]. Cyclic Jacobi (Golub & Van Loan, "Matrix Computations",
 * 8.5): slow beside QR for large n, but simple, accurate for the small
 * eigenvalues a covariance matrix ends with, and the same bits on every
 * machine that rounds IEEE doubles the same way. */
#include <lauxlib.h>
#include <lua.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "learn/lua_linalg.h"

/* The largest matrix evo.linalg takes: CMA-ES switches to its diagonal
 * variant long before (docs/learning.md). */
#define MAX_N 4096

/* Sum of squares of the off-diagonal upper triangle. */
static double off_norm(int n, const double *a)
{
	double s = 0;
	for (int p = 0; p < n; p++)
		for (int q = p + 1; q < n; q++)
			s += a[p * n + q] * a[p * n + q];
	return s;
}

static double diag_norm(int n, const double *a)
{
	double s = 0;
	for (int p = 0; p < n; p++)
		s += a[p * n + p] * a[p * n + p];
	return s;
}

/* One rotation zeroing a[p][q] of the symmetric a (both triangles kept),
 * accumulated into v. */
static void rotate(int n, double *a, double *v, int p, int q)
{
	double apq = a[p * n + q];
	if (apq == 0)
		return;
	double theta = (a[q * n + q] - a[p * n + p]) / (2 * apq);
	double t =
	    (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1));
	double c = 1 / sqrt(t * t + 1), s = t * c;
	for (int k = 0; k < n; k++) {
		double akp = a[k * n + p], akq = a[k * n + q];
		a[k * n + p] = c * akp - s * akq;
		a[k * n + q] = s * akp + c * akq;
	}
	for (int k = 0; k < n; k++) {
		double apk = a[p * n + k], aqk = a[q * n + k];
		a[p * n + k] = c * apk - s * aqk;
		a[q * n + k] = s * apk + c * aqk;
	}
	a[p * n + q] = a[q * n + p] = 0;
	for (int k = 0; k < n; k++) {
		double vkp = v[k * n + p], vkq = v[k * n + q];
		v[k * n + p] = c * vkp - s * vkq;
		v[k * n + q] = s * vkp + c * vkq;
	}
}

int evo_linalg_eigh(int n, double *a, double *values, double *vectors)
{
	for (int i = 0; i < n; i++)
		for (int j = 0; j < i; j++)
			a[i * n + j] = a[j * n + i];
	for (int i = 0; i < n * n; i++)
		vectors[i] = 0;
	for (int i = 0; i < n; i++)
		vectors[i * n + i] = 1;
	int sweeps = 0;
	while (off_norm(n, a) > 1e-30 * diag_norm(n, a)) {
		if (++sweeps > 100)
			return -1;
		for (int p = 0; p < n; p++)
			for (int q = p + 1; q < n; q++)
				rotate(n, a, vectors, p, q);
	}
	for (int i = 0; i < n; i++)
		values[i] = a[i * n + i];
	return sweeps;
}

/* values, vectors, sweeps = eigh(n, a) */
static int l_eigh(lua_State *L)
{
	lua_Integer n = luaL_checkinteger(L, 1);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_argcheck(L, n >= 1 && n <= MAX_N, 1, "n must be from 1 to 4096");
	luaL_argcheck(L, luaL_len(L, 2) == n * n, 2,
		      "a must hold n * n numbers");
	size_t nn = (size_t)(n * n);
	double *a = lua_newuserdatauv(L, (2 * nn + (size_t)n) * sizeof *a, 0);
	double *vec = a + nn, *val = vec + nn;
	for (size_t i = 0; i < nn; i++) {
		lua_geti(L, 2, (lua_Integer)i + 1);
		int ok;
		a[i] = lua_tonumberx(L, -1, &ok);
		if (!ok || !isfinite(a[i]))
			return luaL_error(L,
					  "eigh: a[%d] is not a finite number",
					  (int)i + 1);
		lua_pop(L, 1);
	}
	int sweeps = evo_linalg_eigh((int)n, a, val, vec);
	if (sweeps < 0)
		return luaL_error(L, "eigh: no convergence in 100 sweeps");
	lua_createtable(L, (int)n, 0);
	for (lua_Integer i = 0; i < n; i++) {
		lua_pushnumber(L, val[i]);
		lua_rawseti(L, -2, i + 1);
	}
	lua_createtable(L, (int)nn, 0);
	for (size_t i = 0; i < nn; i++) {
		lua_pushnumber(L, vec[i]);
		lua_rawseti(L, -2, (lua_Integer)i + 1);
	}
	lua_pushinteger(L, sweeps);
	return 3;
}

void evo_lua_finite_list(lua_State *L, int idx, long long len, double *v,
			 const char *fn, const char *what)
{
	for (lua_Integer i = 0; i < len; i++) {
		lua_geti(L, idx, i + 1);
		int ok;
		v[i] = lua_tonumberx(L, -1, &ok);
		if (!ok || !isfinite(v[i]))
			luaL_error(L, "%s: %s[%I] is not a finite number", fn,
				   what, i + 1);
		lua_pop(L, 1);
	}
}
/* A flat list of finite numbers at idx, in a userdata left on the stack;
 * its length a multiple of d. */
static double *vector_list(lua_State *L, int idx, lua_Integer d,
			   lua_Integer *count, const char *what)
{
	luaL_checktype(L, idx, LUA_TTABLE);
	lua_Integer len = luaL_len(L, idx);
	if (len % d || len > (lua_Integer)1 << 28)
		luaL_error(L, "nearest: %s holds %I numbers, not a whole number "
			      "of %I-vectors",
			   what, len, d);
	double *v = lua_newuserdatauv(L, (size_t)(len ? len : 1) * sizeof *v, 0);
	evo_lua_finite_list(L, idx, len, v, "nearest", what);
	*count = len / d;
	return v;
}

/* cell = nearest(d, centroids, points) */
static int l_nearest(lua_State *L)
{
	lua_Integer d = luaL_checkinteger(L, 1);
	luaL_argcheck(L, d >= 1 && d <= 1024, 1, "d must be from 1 to 1024");
	lua_Integer nc, np;
	const double *c = vector_list(L, 2, d, &nc, "centroids");
	const double *p = vector_list(L, 3, d, &np, "points");
	if (nc < 1 && np > 0)
		return luaL_error(L, "nearest: no centroids");
	lua_createtable(L, (int)np, 0);
	for (lua_Integer i = 0; i < np; i++) {
		const double *x = p + i * d;
		lua_Integer best = 0;
		double best_d = INFINITY;
		for (lua_Integer k = 0; k < nc; k++) {
			const double *y = c + k * d;
			double s = 0;
			for (lua_Integer j = 0; j < d && s < best_d; j++)
				s += (x[j] - y[j]) * (x[j] - y[j]);
			if (s < best_d) {
				best_d = s;
				best = k;
			}
		}
		lua_pushinteger(L, best + 1);
		lua_rawseti(L, -2, i + 1);
	}
	return 1;
}

static const luaL_Reg linalg_fns[] = {
    {"eigh", l_eigh}, {"nearest", l_nearest}, {NULL, NULL}};

static int open_linalg(lua_State *L)
{
	luaL_newlib(L, linalg_fns);
	return 1;
}

void evo_lua_open_linalg(lua_State *L)
{
	luaL_requiref(L, "evo.linalg", open_linalg, 0);
	lua_pop(L, 1);
}

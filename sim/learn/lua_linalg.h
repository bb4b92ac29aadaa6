/* evo — the linear algebra the learning methods' Lua needs at C speed:
 * the module evo.linalg (sim/learn/lua_linalg.c). */
#ifndef EVO_LUA_LINALG_H
#define EVO_LUA_LINALG_H

struct lua_State;

/* Eigenvalues and eigenvectors of the symmetric n x n matrix a (row-major,
 * read from its upper triangle), by cyclic Jacobi rotations: values[j] is
 * the j-th eigenvalue, and column j of vectors (vectors[i * n + j]) its
 * unit eigenvector. a is overwritten. Deterministic: the same input gives
 * the same bits. Returns the number of sweeps, or -1 when 100 sweeps did
 * not bring the off-diagonal part to rounding level. */
int evo_linalg_eigh(int n, double *a, double *values, double *vectors);

/* Read the first len values of the list at stack index idx into v, each
 * a finite number, else a Lua error "fn: what[i] is not a finite
 * number" (1-based i). For evo.linalg's and evo.novelty's vectors. */
void evo_lua_finite_list(struct lua_State *L, int idx, long long len,
			 double *v, const char *fn, const char *what);

/* Registers evo.linalg in L (package.loaded), for require "evo.linalg". */
void evo_lua_open_linalg(struct lua_State *L);

#endif

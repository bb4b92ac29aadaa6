/* evo.neat's generator (sim/learn/neat_internal.h): learn.rng's
 * xoshiro256** on the generator's own four words (rng_next, rng_unit,
 * rng_normal), MAP-Elites' isoline variation, and a kernel's hold on a
 * generator while it draws (neat_rng_begin, neat_rng_done); and the
 * check of a binding's table arguments (neat_want_tables,
 * neat_check_tables). */
#include <lauxlib.h>
#include <limits.h>
#include <lua.h>
#include <math.h>
#include <stdint.h>

#include "learn/neat_internal.h"

/* The four words of generator `self` (learn.rng: self.s holds them as
 * Lua integers) into s; leaves self.s on the stack. */
static void rng_read(lua_State *L, int self, uint64_t s[4])
{
	if (rget(L, self, K_S) != LUA_TTABLE)
		luaL_error(L, "rng: no state (self.s)");
	for (int k = 0; k < 4; k++)
		lua_rawgeti(L, -1 - k, k + 1);
	for (int k = 0; k < 4; k++)
		s[k] = (uint64_t)lua_tointeger(L, k - 4);
	lua_pop(L, 4);
}

/* The four words back into the table self.s at the top of the stack,
 * popped. */
static void rng_write(lua_State *L, const uint64_t s[4])
{
	for (int k = 0; k < 4; k++) {
		lua_pushinteger(L, (lua_Integer)s[k]);
		lua_rawseti(L, -2, k + 1);
	}
	lua_pop(L, 1);
}

/* The next 64-bit word of the generator `self`, its state moved on in
 * place, as Rng:next does it in Lua. */
static uint64_t rng_next(lua_State *L, int self)
{
	uint64_t s[4];
	rng_read(L, self, s);
	uint64_t result = xoshiro_next(s);
	rng_write(L, s);
	return result;
}

/* rng_next(self) -> the next word, a Lua integer (Rng:next). */
int neat_l_rng_next(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_pushinteger(L, (lua_Integer)rng_next(L, 1));
	return 1;
}

/* rng_unit(self) -> uniform in [0, 1) from the top 53 bits (Rng:unit). */
int neat_l_rng_unit(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_pushnumber(L, unit_of(rng_next(L, 1)));
	return 1;
}

/* Rng:normal's Box-Muller on the words s: 1 - unit, then unit, the same
 * libm calls in the same order as the Lua (math.log, math.cos, math.sqrt;
 * math.pi is lmathlib.c's PI, this literal). */
#define LUA_PI 3.141592653589793238462643383279502884
static double normal_of(uint64_t s[4])
{
	double u1 = 1.0 - unit_of(xoshiro_next(s));
	double u2 = unit_of(xoshiro_next(s));
	return sqrt(-2.0 * log(u1)) * cos(2.0 * LUA_PI * u2);
}

/* rng_normal(self) -> a standard normal draw (Rng:normal). */
int neat_l_rng_normal(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	uint64_t s[4];
	rng_read(L, 1, s);
	double z = normal_of(s);
	rng_write(L, s);
	lua_pushnumber(L, z);
	return 1;
}

/* isoline(xi, xj, iso, line, rng) -> a new list w, w[k] = xi[k] + iso
 * N(0, 1) + t (xj[k] - xi[k]) with t = line N(0, 1) drawn first
 * (mapelites.isoline_lua); rng is learn.rng's, its words read once. */
int neat_l_isoline(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	double iso = luaL_checknumber(L, 3), line = luaL_checknumber(L, 4);
	luaL_checktype(L, 5, LUA_TTABLE);
	lua_Integer n = luaL_len(L, 1);
	uint64_t s[4];
	rng_read(L, 5, s); /* leaves rng.s at the top */
	int state = lua_gettop(L);
	double t = line * normal_of(s);
	lua_createtable(L, n > 0 && n < INT_MAX ? (int)n : 0, 0);
	for (lua_Integer k = 1; k <= n; k++) {
		lua_rawgeti(L, 1, k);
		lua_rawgeti(L, 2, k);
		double a = lua_tonumber(L, -2), b = lua_tonumber(L, -1);
		lua_pop(L, 2);
		double w = a + iso * normal_of(s) + t * (b - a);
		lua_pushnumber(L, w);
		lua_rawseti(L, -2, k);
	}
	lua_pushvalue(L, state);
	rng_write(L, s);
	return 1;
}

/* Starts drawing from the generator at stack slot `rng` (it may push a
 * value: call it where the stack's top does not matter). */
void neat_rng_begin(lua_State *L, int rng, rng_src *r)
{
	r->rng = lua_absindex(L, rng);
	lua_getfield(L, r->rng, "unit");
	r->ours = lua_tocfunction(L, -1) == neat_l_rng_unit;
	lua_pop(L, 1);
	if (r->ours) {
		rng_read(L, r->rng, r->s);
		r->state = lua_gettop(L);
	}
}

/* The words drawn from, back in the generator. */
void neat_rng_done(lua_State *L, rng_src *r)
{
	if (!r->ours)
		return;
	lua_pushvalue(L, r->state);
	rng_write(L, r->s);
}

void neat_want_tables(lua_State *L, int first, int last)
{
	for (int i = first; i <= last; i++)
		luaL_checktype(L, i, LUA_TTABLE);
}

void neat_check_tables(lua_State *L, int n)
{
	neat_want_tables(L, 1, n);
	lua_settop(L, n);
}

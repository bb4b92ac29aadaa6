/* evo.neat's speciation and selection (sim/learn/neat_internal.h): NEAT's
 * compatibility distance, speciate and assign, copy_genome, and the
 * kernels that rank a species' members and share its offspring (rank,
 * ranked, tally, share, best_of). */
#include <lauxlib.h>
#include <limits.h>
#include <lua.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "learn/neat_internal.h"

dist_opts neat_dist_opts_of(lua_State *L, int o)
{
	dist_opts d = {num_field(L, o, K_C1), num_field(L, o, K_C2),
		       num_field(L, o, K_C3),
		       num_field(L, o, K_NORMALIZE_BELOW)};
	return d;
}

/* c1*E/N + c2*D/N + c3*W: E excess and D disjoint genes, W the mean
 * weight difference of the matching ones, N the larger genome's gene
 * count (1 when both have fewer than normalize_below); neat.distance_lua's
 * arithmetic in its order. */
double neat_distance_of(const genes *a, const genes *b, const dist_opts *o)
{
	lua_Integer na = a->n, nb = b->n, i = 0, j = 0, matching = 0,
		    disjoint = 0;
	double wdiff = 0.0;
	while (i < na && j < nb) {
		lua_Integer xi = a->g[i].innov, yi = b->g[j].innov;
		if (xi == yi) {
			matching++;
			double d = a->g[i].weight - b->g[j].weight;
			wdiff += d < 0 ? -d : d;
			i++;
			j++;
		} else if (xi < yi) {
			disjoint++;
			i++;
		} else {
			disjoint++;
			j++;
		}
	}
	lua_Integer excess = (na - i) + (nb - j);
	lua_Integer n = na > nb ? na : nb;
	if ((double)n < o->normalize_below)
		n = 1;
	double w = matching > 0 ? wdiff / (double)matching : 0.0;
	return o->c1 * (double)excess / (double)n +
	       o->c2 * (double)disjoint / (double)n + o->c3 * w;
}

/* distance(a, b, o): NEAT's compatibility distance (distance_of). */
int neat_l_distance(lua_State *L)
{
	luaL_checktype(L, 3, LUA_TTABLE);
	const genes *a = neat_genome_genes(L, 1, 0);
	const genes *b = neat_genome_genes(L, 2, 0);
	dist_opts o = neat_dist_opts_of(L, 3);
	lua_pushnumber(L, neat_distance_of(a, b, &o));
	return 1;
}

/* speciate(genomes, reps, o, threshold) -> home, opened: home[i] is the species
 * of genome i, as neat.lua's speciate assigns them: the first species
 * whose representative (reps[k], k in order) is within distance
 * `threshold` (distance(genome, rep) < threshold), else a new species
 * numbered #reps + 1, #reps + 2, ... in the order they are opened, whose
 * representative is that genome; and the genomes that opened them, in
 * that order. */
int neat_l_speciate(lua_State *L)
{
	neat_want_tables(L, 1, 3);
	double threshold = luaL_checknumber(L, 4);
	dist_opts o = neat_dist_opts_of(L, 3);
	int ng = (int)lua_rawlen(L, 1), nr = (int)lua_rawlen(L, 2);
	/* every rep's and genome's genes (kept on the stack while read),
	 * then the reps' indices into them (the old ones and the new) */
	luaL_checkstack(L, nr + ng + 8, "speciate: too many genomes");
	const genes **all = neat_scratch(L, (size_t)(nr + ng) * (sizeof *all +
								sizeof(int)));
	int *rep = (int *)(void *)(all + nr + ng);
	for (int k = 0; k < nr + ng; k++) {
		lua_rawgeti(L, k < nr ? 2 : 1, k < nr ? k + 1 : k - nr + 1);
		all[k] = neat_genome_genes(L, -1, 0);
		lua_remove(L, -2);
	}
	int n_rep = nr;
	for (int k = 0; k < nr; k++)
		rep[k] = k;
	lua_createtable(L, ng, 0);
	int homes = lua_gettop(L);
	lua_createtable(L, 0, 0);
	int opened = lua_gettop(L);
	for (int i = 0; i < ng; i++) {
		const genes *g = all[nr + i];
		int home = 0;
		while (home < n_rep && !(neat_distance_of(g, all[rep[home]], &o) <
					 threshold))
			home++;
		if (home == n_rep) {
			rep[n_rep++] = nr + i;
			lua_pushinteger(L, i + 1);
			lua_rawseti(L, opened, n_rep - nr);
		}
		lua_pushinteger(L, home + 1);
		lua_rawseti(L, homes, i + 1);
	}
	return 2;
}

/* assign(species, homes, genomes): genome i joins species[homes[i]]: its
 * index appended to that species' members, its species field that
 * species' id (neat.lua's speciate, once the species exist). */
int neat_l_assign(lua_State *L)
{
	neat_check_tables(L, 3);
	lua_Integer n = (lua_Integer)lua_rawlen(L, 2);
	for (lua_Integer i = 1; i <= n; i++) {
		lua_rawgeti(L, 2, i);
		lua_Integer h = lua_tointeger(L, -1);
		if (lua_rawgeti(L, 1, h) != LUA_TTABLE) /* 5: the species */
			luaL_error(L, "assign: genome %I's species %I is none",
				   (LUAI_UACINT)i, (LUAI_UACINT)h);
		rget(L, 5, K_MEMBERS); /* 6 */
		luaL_checktype(L, 6, LUA_TTABLE);
		lua_pushinteger(L, i);
		lua_rawseti(L, 6, (lua_Integer)lua_rawlen(L, 6) + 1);
		if (lua_rawgeti(L, 3, i) != LUA_TTABLE) /* 7: the genome */
			luaL_error(L, "assign: genome %I is none", (LUAI_UACINT)i);
		rget(L, 5, K_ID);
		rset(L, 7, K_SPECIES);
		lua_settop(L, 3);
	}
	return 0;
}

/* Pushes a copy of the genome at g (l_copy_genome's). */
void neat_push_copy(lua_State *L, int g)
{
	g = lua_absindex(L, g);
	lua_createtable(L, 0, GENOME_FIELDS);
	int copy = lua_gettop(L);
	rget(L, g, K_NODES);
	int src = copy + 1;
	luaL_checktype(L, src, LUA_TTABLE);
	lua_createtable(L, (int)lua_rawlen(L, src), 0);
	for (lua_Integer i = 1; lua_rawgeti(L, src, i) != LUA_TNIL; i++)
		lua_rawseti(L, src + 1, i);
	lua_pop(L, 1);
	rset(L, copy, K_NODES);
	lua_pop(L, 1);
	const genes *gs = neat_genome_genes(L, g, 0);
	genes *c = neat_new_genes(L, gs->n);
	memcpy(c->g, gs->g, (size_t)gs->n * sizeof *c->g);
	rset(L, copy, K_LINKS);
	lua_settop(L, copy);
}

/* copy_genome(g) -> a copy of g's nodes and genes (neat.copy_genome):
 * the genes copied (they change: weights, enabled), the node list a new
 * list of the same node tables (a node never changes once made:
 * mutations add nodes to a genome's own list). */
int neat_l_copy_genome(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_settop(L, 1);
	neat_push_copy(L, 1);
	return 1;
}

/* A member's place: fitness, then its random key, then its index. */
typedef struct ranked {
	double fitness, key;
	lua_Integer index;
} ranked;

static int by_rank(const void *pa, const void *pb)
{
	const ranked *a = pa, *b = pb;
	if (a->fitness != b->fitness)
		return a->fitness > b->fitness ? -1 : 1;
	if (a->key != b->key)
		return a->key < b->key ? -1 : 1;
	return (a->index > b->index) - (a->index < b->index);
}

/* rank(members, keys) -> the indices 1 .. #members, fittest first, equal
 * fitness by smaller key, then by smaller index: the order tell's
 * table.sort gives (a strict total order has one sorted order). */
int neat_l_rank(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	lua_Integer n = (lua_Integer)lua_rawlen(L, 1);
	ranked *r = lua_newuserdatauv(L, (size_t)(n ? n : 1) * sizeof *r, 0);
	for (lua_Integer i = 0; i < n; i++) {
		lua_rawgeti(L, 1, i + 1);
		r[i].fitness = num_field(L, -1, K_FITNESS);
		lua_pop(L, 1);
		lua_rawgeti(L, 2, i + 1);
		r[i].key = lua_tonumber(L, -1);
		lua_pop(L, 1);
		r[i].index = i + 1;
	}
	qsort(r, (size_t)n, sizeof *r, by_rank);
	lua_createtable(L, (int)n, 0);
	for (lua_Integer i = 0; i < n; i++) {
		lua_pushinteger(L, r[i].index);
		lua_rawseti(L, -2, i + 1);
	}
	return 1;
}

/* The value at idx is a fitness tell takes: a number, not NaN. */
static void check_fitness(lua_State *L, int idx)
{
	if (lua_type(L, idx) != LUA_TNUMBER ||
	    (!lua_isinteger(L, idx) && isnan(lua_tonumber(L, idx))))
		luaL_error(L, "tell: fitness must be a number");
}

/* Push species[k] (species at stack index `species`) and its members
 * table, both checked to be tables, at the next two indices: its member
 * count. */
static lua_Integer push_members(lua_State *L, int species, lua_Integer k)
{
	int top = lua_gettop(L);
	lua_rawgeti(L, species, k);
	luaL_checktype(L, top + 1, LUA_TTABLE);
	rget(L, top + 1, K_MEMBERS);
	luaL_checktype(L, top + 2, LUA_TTABLE);
	return (lua_Integer)lua_rawlen(L, top + 2);
}

/* Push member j of a members table and then its genome (of genomes). */
static void push_member(lua_State *L, int genomes, int members, lua_Integer j)
{
	lua_rawgeti(L, members, j);
	lua_rawgeti(L, genomes, lua_tointeger(L, -1));
}

/* tally(genomes, score, species) -> least, most: each genome's fitness
 * set (genomes[i].fitness = score[i], checked as tell checks it), the
 * least of them, and for each species the most of its members'
 * (math.max from -math.huge, in member order): tell's first loops. */
int neat_l_tally(lua_State *L)
{
	neat_check_tables(L, 3);
	lua_Integer n = (lua_Integer)lua_rawlen(L, 1);
	if ((lua_Integer)lua_rawlen(L, 2) != n)
		luaL_error(L, "tell: one fitness per genome");
	lua_pushnumber(L, HUGE_VAL); /* 4: the least */
	for (lua_Integer i = 1; i <= n; i++) {
		lua_rawgeti(L, 2, i); /* 5 */
		check_fitness(L, 5);
		if (lua_rawgeti(L, 1, i) != LUA_TTABLE)
			luaL_error(L, "tell: genome %I is none", (LUAI_UACINT)i);
		lua_pushvalue(L, 5);
		rset(L, 6, K_FITNESS);
		if (lua_compare(L, 5, 4, LUA_OPLT))
			lua_copy(L, 5, 4);
		lua_settop(L, 4);
	}
	lua_Integer ns = (lua_Integer)lua_rawlen(L, 3);
	lua_createtable(L, ns > 0 && ns < INT_MAX ? (int)ns : 0, 0); /* 5 */
	for (lua_Integer k = 1; k <= ns; k++) {
		lua_Integer m = push_members(L, 3, k); /* 6, 7 */
		lua_pushnumber(L, -HUGE_VAL);	       /* 8: the most */
		for (lua_Integer j = 1; j <= m; j++) {
			push_member(L, 1, 7, j);
			rget(L, -1, K_FITNESS); /* 11 */
			if (lua_compare(L, 8, 11, LUA_OPLT))
				lua_copy(L, 11, 8);
			lua_settop(L, 8);
		}
		lua_rawseti(L, 5, k);
		lua_settop(L, 5);
	}
	return 2;
}

/* share(genomes, species, shift) -> sums: explicit fitness sharing. Each
 * member g of each species gets g.adjusted = (g.fitness + shift) /
 * #members (Lua's arithmetic), and sums[k] is species k's sum of them,
 * added in member order from 0. */
int neat_l_share(lua_State *L)
{
	neat_want_tables(L, 1, 2);
	luaL_checknumber(L, 3);
	lua_settop(L, 3);
	lua_Integer ns = (lua_Integer)lua_rawlen(L, 2);
	lua_createtable(L, ns > 0 && ns < INT_MAX ? (int)ns : 0, 0); /* 4 */
	for (lua_Integer k = 1; k <= ns; k++) {
		lua_Integer m = push_members(L, 2, k); /* 5, 6 */
		lua_pushinteger(L, 0);		       /* 7: the sum */
		for (lua_Integer j = 1; j <= m; j++) {
			push_member(L, 1, 6, j); /* 9 */
			luaL_checktype(L, 9, LUA_TTABLE);
			rget(L, 9, K_FITNESS);
			lua_pushvalue(L, 3);
			lua_arith(L, LUA_OPADD);
			lua_pushinteger(L, m);
			lua_arith(L, LUA_OPDIV); /* 10: adjusted */
			lua_pushvalue(L, 10);
			rset(L, 9, K_ADJUSTED);
			lua_pushvalue(L, 7);
			lua_insert(L, 10);
			lua_arith(L, LUA_OPADD);
			lua_copy(L, 10, 7);
			lua_settop(L, 7);
		}
		lua_rawseti(L, 4, k);
		lua_settop(L, 4);
	}
	return 1;
}

/* best_of(fitness, best) -> i: the first genome of the greatest fitness
 * above `best` (any, when best is nil), or nil when none is above it;
 * each fitness checked as tell checks it (note_best's loop, which keeps
 * a copy of each genome that beats the best so far: the last copy is of
 * this one). */
int neat_l_best_of(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_settop(L, 2);
	lua_Integer n = (lua_Integer)lua_rawlen(L, 1), best = 0;
	for (lua_Integer i = 1; i <= n; i++) {
		lua_rawgeti(L, 1, i); /* 3 */
		check_fitness(L, 3);
		if (lua_isnil(L, 2) || lua_compare(L, 2, 3, LUA_OPLT)) {
			lua_copy(L, 3, 2);
			best = i;
		}
		lua_settop(L, 2);
	}
	if (best)
		lua_pushinteger(L, best);
	else
		lua_pushnil(L);
	return 1;
}

/* ranked(genomes, members, rng) -> the genomes genomes[members[k]],
 * fittest first, equal fitness by a key rng:unit() drawn for each member
 * in member order, then by place: fast.draws and fast.rank in one, the
 * same draws and the same order. */
int neat_l_ranked(lua_State *L)
{
	neat_check_tables(L, 3);
	lua_Integer n = (lua_Integer)lua_rawlen(L, 2);
	if (n >= INT_MAX)
		luaL_error(L, "ranked: %I members", (LUAI_UACINT)n);
	ranked *r = lua_newuserdatauv(L, (size_t)(n ? n : 1) * sizeof *r, 0);
	lua_createtable(L, (int)n, 0); /* 5: the members' genomes */
	for (lua_Integer i = 0; i < n; i++) {
		lua_rawgeti(L, 2, i + 1);
		if (lua_rawgeti(L, 1, lua_tointeger(L, -1)) != LUA_TTABLE)
			luaL_error(L, "ranked: member %I is no genome",
				   (LUAI_UACINT)(i + 1));
		r[i].fitness = num_field(L, -1, K_FITNESS);
		r[i].index = i + 1;
		lua_rawseti(L, 5, i + 1);
		lua_pop(L, 1);
	}
	rng_src src;
	neat_rng_begin(L, 3, &src);
	for (lua_Integer i = 0; i < n; i++)
		r[i].key = draw(L, &src);
	neat_rng_done(L, &src);
	lua_settop(L, 5);
	qsort(r, (size_t)n, sizeof *r, by_rank);
	lua_createtable(L, (int)n, 0);
	for (lua_Integer i = 0; i < n; i++) {
		lua_rawgeti(L, 5, r[i].index);
		lua_rawseti(L, -2, i + 1);
	}
	return 1;
}

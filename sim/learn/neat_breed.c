/* evo.neat's breeding (sim/learn/neat_internal.h): crossover of two
 * genomes and a species' offspring (breed), draw for draw as
 * lua/learn/neat.lua's. */
#include <lauxlib.h>
#include <lua.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "learn/neat_internal.h"

/* A number as Lua's == sees it: a number's value, NaN (equal to
 * nothing) for any other value. */
static double eq_number(lua_State *L, int idx)
{
	int isnum;
	double v = lua_tonumberx(L, idx, &isnum);
	return isnum ? v : NAN;
}

/* The slot (1-based) of the last gene of b with innovation x, 0 when b has
 * none (what a map from innovation to gene, filled in b's order, gives).
 * `by` holds b's genes sorted by innovation, then slot. */
static int gene_with(const keyed *by, int n, double x)
{
	int lo = 0, hi = n; /* the first entry whose innovation is above x */
	while (lo < hi) {
		int mid = (lo + hi) / 2;
		if (by[mid].key <= x)
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo > 0 && by[lo - 1].key == x ? by[lo - 1].slot : 0;
}

static int by_key_slot(const void *a, const void *b)
{
	const keyed *x = a, *y = b;
	if (x->key != y->key)
		return x->key < y->key ? -1 : 1;
	return (x->slot > y->slot) - (x->slot < y->slot);
}

static cross_opts cross_opts_of(lua_State *L, int o)
{
	cross_opts c;
	rget(L, o, K_TIE_SMALLER);
	c.tie_smaller = lua_toboolean(L, -1);
	lua_pop(L, 1);
	c.mate_avg_prob = num_field(L, o, K_MATE_AVG_PROB);
	c.disable_prob = num_field(L, o, K_DISABLE_PROB);
	return c;
}

/* Pushes the child of genomes a and b of fitness fa and fb (stack slots;
 * the fitnesses compared as Lua compares them), as neat.crossover makes
 * it, drawing from r, and returns 1; returns 0 and pushes nothing when
 * the parents are of equal fitness and tie_smaller is off (the paper's
 * way, which neat.crossover keeps in Lua). */
static int push_child(lua_State *L, int a, int fa, int b, int fb,
		      const cross_opts *co, rng_src *r)
{
	int top = lua_gettop(L);
	if (lua_compare(L, fa, fb, LUA_OPLT)) { /* fb > fa */
		int t = a;
		a = b;
		b = t;
	}
	int equal = lua_compare(L, fa, fb, LUA_OPEQ);
	if (equal && !co->tie_smaller)
		return 0;
	const genes *ag = neat_genome_genes(L, a, 0);
	const genes *bg = neat_genome_genes(L, b, 0);
	if (equal && bg->n < ag->n) {
		const genes *t = ag;
		ag = bg;
		bg = t;
		int ti = a;
		a = b;
		b = ti;
	}
	double average = draw(L, r) < co->mate_avg_prob;
	double disable = co->disable_prob;
	int na = ag->n, nb = bg->n;
	rget(L, a, K_NODES);
	int an = lua_gettop(L);
	rget(L, b, K_NODES);
	int bn = lua_gettop(L);
	luaL_checktype(L, an, LUA_TTABLE);
	luaL_checktype(L, bn, LUA_TTABLE);
	int ma = (int)lua_rawlen(L, an), mb = (int)lua_rawlen(L, bn);
	/* scratch: b's genes by innovation; the child's genes' ends; the
	 * ids of the child's nodes */
	keyed *by = neat_scratch(L, (size_t)nb * sizeof *by +
				   (size_t)2 * (size_t)na * sizeof(double) +
				   (size_t)(ma + mb) * sizeof(double));
	double *ends = (double *)(void *)(by + nb);
	double *have = ends + 2 * (size_t)na;
	int sorted = 1;
	for (int i = 0; i < nb; i++) {
		by[i].key = (double)bg->g[i].innov;
		by[i].slot = i + 1;
		if (i > 0 && !(by[i].key > by[i - 1].key))
			sorted = 0;
	}
	if (!sorted)
		qsort(by, (size_t)nb, sizeof *by, by_key_slot);
	/* the child and its genes */
	lua_createtable(L, 0, GENOME_FIELDS);
	int child = lua_gettop(L);
	genes *cg = neat_new_genes(L, na);
	rset(L, child, K_LINKS);
	int n = 0;
	for (int i = 0; i < na; i++) {
		const gene *l = &ag->g[i];
		gene *c = &cg->g[n];
		int slot = gene_with(by, nb, (double)l->innov);
		if (slot) {
			const gene *m = &bg->g[slot - 1];
			*c = draw(L, r) < 0.5 ? *l : *m;
			if (!l->enabled || !m->enabled)
				c->enabled = draw(L, r) >= disable;
			if (average) {
				c->weight = (l->weight + m->weight) / 2;
				c->weight_int = 0;
			}
		} else {
			*c = *l;
		}
		ends[2 * n] = (double)c->from;
		ends[2 * n + 1] = (double)c->to;
		n++;
	}
	/* nodes: all of a's, then b's that the child's genes need */
	lua_createtable(L, ma + 1, 0);
	int nodes = lua_gettop(L);
	lua_pushvalue(L, nodes);
	rset(L, child, K_NODES);
	int k = 0;
	for (int i = 1; i <= ma; i++) {
		lua_rawgeti(L, an, i);
		rget(L, -1, K_ID);
		have[k] = eq_number(L, -1);
		lua_pop(L, 1);
		lua_rawseti(L, nodes, ++k); /* shared: nodes never change */
	}
	for (int i = 1; i <= mb; i++) {
		lua_rawgeti(L, bn, i);
		rget(L, -1, K_ID);
		double id = eq_number(L, -1);
		lua_pop(L, 1);
		int seen = 0, needed = 0;
		for (int h = 0; h < k && !seen; h++)
			seen = have[h] == id;
		for (int e = 0; e < 2 * n && !seen && !needed; e++)
			needed = ends[e] == id;
		if (needed) {
			have[k] = id;
			lua_rawseti(L, nodes, ++k);
		} else {
			lua_pop(L, 1);
		}
	}
	/* a's genes are in innovation order, and so are the child's, but
	 * for a parent made out of order (by hand) */
	int in_order = 1;
	for (int i = 1; i < n && in_order; i++)
		in_order = cg->g[i - 1].innov < cg->g[i].innov;
	if (!in_order)
		qsort(cg->g, (size_t)n, sizeof *cg->g, neat_by_innov);
	/* the nodes are in id order unless b gave some (have[] holds
	 * their ids in list order) */
	in_order = 1;
	for (int i = 1; i < k && in_order; i++)
		in_order = have[i - 1] < have[i];
	if (!in_order)
		neat_sort_list(L, nodes, K_ID);
	lua_pushvalue(L, child);
	lua_replace(L, top + 1);
	lua_settop(L, top + 1);
	return 1;
}

/* crossover(a, fa, b, fb, o, rng) -> child, as neat.crossover makes it,
 * or nothing when the parents are of equal fitness and o.tie_smaller is
 * off (push_child). */
int neat_l_crossover(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	luaL_checktype(L, 5, LUA_TTABLE);
	luaL_checktype(L, 6, LUA_TTABLE);
	lua_settop(L, 6);
	cross_opts co = cross_opts_of(L, 5);
	rng_src r;
	neat_rng_begin(L, 6, &r); /* may push rng.s */
	if (!push_child(L, 1, 2, 3, 4, &co, &r))
		return 0;
	neat_rng_done(L, &r);
	return 1;
}

/* ------------------------------------------------------------------ */
/* A species' offspring (neat.lua's breed_lua, draw for draw) */

/* What breed reads of the options, once for all its children. */
typedef struct breed_opts {
	double mutate_only, interspecies, mate_only;
	double neat_add_node, neat_add_link, weight_mut, toggle, reenable;
	wm_opts wm;
	cross_opts co;
	dist_opts dist;
	struct_opts st;
} breed_opts;

static breed_opts breed_opts_of(lua_State *L, int o)
{
	breed_opts b;
	b.st = neat_struct_opts_of(L, o);
	b.mutate_only = num_field(L, o, K_MUTATE_ONLY_PROB);
	b.interspecies = num_field(L, o, K_INTERSPECIES_PROB);
	b.mate_only = num_field(L, o, K_MATE_ONLY_PROB);
	b.neat_add_node = num_field(L, o, K_ADD_NODE_PROB);
	b.neat_add_link = num_field(L, o, K_ADD_LINK_PROB);
	b.weight_mut = num_field(L, o, K_WEIGHT_MUT_PROB);
	b.toggle = num_field(L, o, K_TOGGLE_PROB);
	b.reenable = num_field(L, o, K_REENABLE_PROB);
	b.wm = neat_wm_opts_of(L, o);
	b.co = cross_opts_of(L, o);
	b.dist = neat_dist_opts_of(L, o);
	return b;
}

/* The generator's words read again from rng.s (after Lua drew from it). */
static void rng_reread(lua_State *L, rng_src *r)
{
	if (!r->ours)
		return;
	for (int k = 0; k < 4; k++) {
		lua_rawgeti(L, r->state, k + 1);
		r->s[k] = (uint64_t)lua_tointeger(L, -1);
		lua_pop(L, 1);
	}
}

/* neat.mutate on the genome at g (l_mutate's draws, add_node, add_link);
 * the toggle and re-enable draws that may follow a weight mutation, when
 * the options ask for them, by more(pop, g, rng, 0) in Lua (neat.lua's
 * mutate_rest), with the generator's words handed over and taken back. */
static void breed_mutate(lua_State *L, int g, const breed_opts *b,
			 rng_src *r, int pop, int more)
{
	int top = lua_gettop(L);
	if (draw(L, r) < b->neat_add_node) {
		neat_add_node(L, pop, g, &b->st, r);
	} else if (draw(L, r) < b->neat_add_link) {
		neat_add_link(L, pop, g, &b->st, r);
	} else {
		if (draw(L, r) < b->weight_mut)
			neat_mutate_genes(L, neat_genome_genes(L, g, 1), &b->wm, r);
		if (b->toggle > 0 || b->reenable > 0) {
			neat_rng_done(L, r);
			lua_pushvalue(L, more);
			lua_pushvalue(L, pop);
			lua_pushvalue(L, g);
			lua_pushvalue(L, r->rng);
			lua_pushinteger(L, 0);
			lua_call(L, 4, 0);
			rng_reread(L, r);
		}
	}
	lua_settop(L, top);
}

/* Pushes the second parent of a crossover: from another species with
 * chance interspecies (alive[k].members[j] of popl), else one of the
 * `parents` first of sorted. */
static void push_mate(lua_State *L, const breed_opts *b, rng_src *r,
		      int sorted, lua_Integer parents, int alive, int popl)
{
	lua_Integer n_alive = (lua_Integer)lua_rawlen(L, alive);
	if (draw(L, r) < b->interspecies && n_alive > 1) {
		lua_rawgeti(L, alive, pick(draw(L, r), n_alive));
		luaL_checktype(L, -1, LUA_TTABLE);
		rget(L, -1, K_MEMBERS);
		luaL_checktype(L, -1, LUA_TTABLE);
		lua_Integer m = (lua_Integer)lua_rawlen(L, -1);
		lua_rawgeti(L, -1, pick(draw(L, r), m));
		lua_Integer gi = lua_tointeger(L, -1);
		lua_pop(L, 3);
		lua_rawgeti(L, popl, gi);
	} else {
		lua_rawgeti(L, sorted, pick(draw(L, r), parents));
	}
	luaL_checktype(L, -1, LUA_TTABLE);
}

/* breed(pop, children, sorted, n, parents, alive, popl, more): n children
 * of one species appended to children, as neat.lua's breed_lua makes
 * them with the C kernels: each of a parent drawn among the `parents`
 * first of sorted, copied and mutated (a lone parent, or with chance
 * mutate_only_prob), else crossed with a mate (push_mate) and mutated
 * unless a draw under mate_only_prob leaves a child of two different
 * genomes as it is. The draws are pop.rng's, in breed_lua's order; only
 * the toggles and re-enables are more(pop, g, rng, 0)'s, in Lua. Only for
 * options with tie_smaller (breed_lua crosses equals the paper's way). */
int neat_l_breed(lua_State *L)
{
	neat_want_tables(L, 1, 3);
	lua_Integer n = luaL_checkinteger(L, 4);
	lua_Integer parents = luaL_checkinteger(L, 5);
	neat_want_tables(L, 6, 7);
	luaL_checktype(L, 8, LUA_TFUNCTION);
	lua_settop(L, 8);
	if (parents < 1 || parents > (lua_Integer)lua_rawlen(L, 3))
		luaL_error(L, "breed: %I parents of a species of %I", parents,
			   (lua_Integer)lua_rawlen(L, 3));
	luaL_checkstack(L, 40, "breed");
	rget(L, 1, K_OPTIONS); /* 9 */
	luaL_checktype(L, 9, LUA_TTABLE);
	breed_opts b = breed_opts_of(L, 9);
	if (!b.co.tie_smaller)
		luaL_error(L, "breed: only with tie_smaller (else breed_lua)");
	rget(L, 1, K_RNG); /* 10 */
	luaL_checktype(L, 10, LUA_TTABLE);
	rng_src r;
	neat_rng_begin(L, 10, &r); /* may push rng.s */
	int base = lua_gettop(L);
	lua_Integer next = (lua_Integer)lua_rawlen(L, 2);
	for (lua_Integer k = 0; k < n; k++) {
		lua_settop(L, base);
		lua_rawgeti(L, 3, pick(draw(L, &r), parents));
		int p1 = base + 1;
		luaL_checktype(L, p1, LUA_TTABLE);
		int child;
		if (parents == 1 || draw(L, &r) < b.mutate_only) {
			neat_push_copy(L, p1);
			child = lua_gettop(L);
			breed_mutate(L, child, &b, &r, 1, 8);
		} else {
			push_mate(L, &b, &r, 3, parents, 6, 7);
			int p2 = base + 2;
			rget(L, p1, K_FITNESS);
			rget(L, p2, K_FITNESS);
			push_child(L, p1, base + 3, p2, base + 4, &b.co, &r);
			child = lua_gettop(L);
			/* a child of one genome with itself (or a twin) is
			 * a copy: always mutated */
			int mutate = draw(L, &r) >= b.mate_only ||
				     lua_rawequal(L, p1, p2);
			if (!mutate) {
				const genes *ga = neat_genome_genes(L, p1, 0);
				const genes *gb = neat_genome_genes(L, p2, 0);
				mutate = neat_distance_of(ga, gb, &b.dist) == 0;
				lua_settop(L, child);
			}
			if (mutate)
				breed_mutate(L, child, &b, &r, 1, 8);
		}
		lua_pushvalue(L, child);
		lua_rawseti(L, 2, ++next);
	}
	lua_settop(L, base);
	neat_rng_done(L, &r);
	return 0;
}

/* evo.neat's mutations (sim/learn/neat_internal.h): weight mutation
 * (mutate_weights, mutate, draws) and the structural mutations add_link
 * and add_node with the population's innovation registry, draw for draw
 * as lua/learn/neat.lua's. */
#include <lauxlib.h>
#include <lua.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "learn/neat_internal.h"

/* ------------------------------------------------------------------ */
/* Weight mutation and crossover (lua/learn/neat.lua's, draw for draw) */

/* x's weight = clamp(w, m) as neat.lua's, m the option weight_max
 * (`max_int`: an integer): m itself above it, -m below -m (an integer m
 * stays one), else w. */
static void set_clamped(gene *x, double w, double m, int max_int)
{
	if (w > m) {
		x->weight = m;
		x->weight_int = (uint8_t)max_int;
	} else if (w < -m) {
		x->weight = -m;
		x->weight_int = (uint8_t)max_int;
	} else {
		x->weight = w;
		x->weight_int = 0;
	}
}

wm_opts neat_wm_opts_of(lua_State *L, int o)
{
	wm_opts w;
	rget(L, o, K_WEIGHT_MAX);
	w.max = lua_tonumber(L, -1);
	w.max_int = lua_isinteger(L, -1);
	lua_pop(L, 1);
	rget(L, o, K_WEIGHT_MUTATION);
	w.code = is_key(L, -1, K_CODE);
	lua_pop(L, 1);
	w.perturb_prob = num_field(L, o, K_PERTURB_PROB);
	w.severe_prob = num_field(L, o, K_SEVERE_PROB);
	w.perturb_power = num_field(L, o, K_PERTURB_POWER);
	w.replace_power = num_field(L, o, K_REPLACE_POWER);
	return w;
}

/* neat.lua's mutate_weights ("code" and "paper") on genes gs with options
 * w, drawing from r: the same draws in the same order. */
void neat_mutate_genes(lua_State *L, genes *gs, const wm_opts *w, rng_src *r)
{
	lua_Integer n = gs->n;
	double perturb = w->perturb_prob, replace = 1.0;
	double newest_after = HUGE_VAL;
	if (w->code) {
		int severe = draw(L, r) < w->severe_prob;
		perturb = severe ? 0.7 : 1.0;
		replace = severe ? 0.9 : 1.0;
		if (!severe && n >= 10)
			newest_after = (double)n * 0.8;
	}
	for (lua_Integer k = 1; k <= n; k++) {
		gene *x = &gs->g[k - 1];
		double p = perturb, rr = replace;
		if ((double)(k - 1) > newest_after) {
			p = 0.5;
			rr = 0.7;
		}
		double u = draw(L, r);
		if (u < p)
			set_clamped(x,
				    x->weight +
					(draw(L, r) * 2 - 1) * w->perturb_power,
				    w->max, w->max_int);
		else if (u < rr)
			set_clamped(x, (draw(L, r) * 2 - 1) * w->replace_power,
				    w->max, w->max_int);
	}
}

/* mutate_genes on genome g with the options at o (stack slots). */
static void mutate_weights_with(lua_State *L, int g, int o, rng_src *r)
{
	int top = lua_gettop(L);
	genes *gs = neat_genome_genes(L, g, 1);
	wm_opts w = neat_wm_opts_of(L, o);
	neat_mutate_genes(L, gs, &w, r);
	lua_settop(L, top);
}

/* mutate_weights(g, o, rng): neat.lua's mutate_weights. */
int neat_l_mutate_weights(lua_State *L)
{
	neat_check_tables(L, 3);
	rng_src r;
	neat_rng_begin(L, 3, &r);
	mutate_weights_with(L, 1, 2, &r);
	neat_rng_done(L, &r);
	return 0;
}

/* mutate(g, o, rng) -> what neat.mutate does next: its first draws, as
 * neat.lua makes them, in C. 1: an add-node mutation (left to Lua), 2: an
 * add-link one (left to Lua), 0: neither, and the weights were mutated
 * (with chance weight_mut_prob) here; the toggle and re-enable draws
 * that may follow are Lua's. */
int neat_l_mutate(lua_State *L)
{
	neat_check_tables(L, 3);
	rng_src r;
	neat_rng_begin(L, 3, &r);
	int what = 0;
	if (draw(L, &r) < num_field(L, 2, K_ADD_NODE_PROB))
		what = 1;
	else if (draw(L, &r) < num_field(L, 2, K_ADD_LINK_PROB))
		what = 2;
	else if (draw(L, &r) < num_field(L, 2, K_WEIGHT_MUT_PROB))
		mutate_weights_with(L, 1, 2, &r);
	neat_rng_done(L, &r);
	lua_pushinteger(L, what);
	return 1;
}

/* draws(rng, n) -> { rng:unit(), ... }: n draws, in order. */
int neat_l_draws(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_Integer n = luaL_checkinteger(L, 2);
	lua_settop(L, 1);
	rng_src r;
	neat_rng_begin(L, 1, &r);
	lua_createtable(L, n > 0 && n < INT32_MAX ? (int)n : 0, 0);
	int t = lua_gettop(L);
	for (lua_Integer k = 1; k <= n; k++) {
		lua_pushnumber(L, draw(L, &r));
		lua_rawseti(L, t, k);
	}
	lua_pushvalue(L, t);
	lua_remove(L, t);
	neat_rng_done(L, &r);
	return 1;
}

struct_opts neat_struct_opts_of(lua_State *L, int o)
{
	struct_opts t;
	rget(L, o, K_RECURRENT);
	t.recurrent = lua_toboolean(L, -1);
	rget(L, o, K_SPLIT_BIAS);
	t.split_bias = lua_toboolean(L, -1);
	rget(L, o, K_SPLIT_OLDER);
	t.split_older = lua_toboolean(L, -1);
	rget(L, o, K_ADD_LINK_TRIES);
	t.add_link_tries = lua_tointeger(L, -1);
	rget(L, o, K_WEIGHT_MAX);
	t.max = lua_tonumber(L, -1);
	t.max_int = lua_isinteger(L, -1);
	lua_pop(L, 5);
	t.recur_only_prob = num_field(L, o, K_RECUR_ONLY_PROB);
	t.new_link_power = num_field(L, o, K_NEW_LINK_POWER);
	return t;
}

/* pop[key], a whole number (the registry's counters). */
static lua_Integer int_field(lua_State *L, int pop, enum key key)
{
	rget(L, pop, key);
	int ok;
	lua_Integer v = lua_tointegerx(L, -1, &ok);
	if (!ok)
		luaL_error(L, "neat: the population's %s is %s, not a whole "
			      "number",
			   neat_key_names[key], luaL_typename(L, -1));
	lua_pop(L, 1);
	return v;
}

static void set_int_field(lua_State *L, int pop, enum key key, lua_Integer v)
{
	lua_pushinteger(L, v);
	rset(L, pop, key);
}

/* The registry table pop[key] (gen_links, gen_splits), pushed. */
static void push_registry(lua_State *L, int pop, enum key key)
{
	if (rget(L, pop, key) != LUA_TTABLE)
		luaL_error(L, "neat: the population has no %s table",
			   neat_key_names[key]);
}

/* neat.lua's link_innovation: the innovation of a link from -> to, the
 * same for every genome that gains it this generation. */
static lua_Integer link_innovation(lua_State *L, int pop, lua_Integer from,
				   lua_Integer to)
{
	push_registry(L, pop, K_GEN_LINKS);
	lua_pushfstring(L, "%I>%I", (LUAI_UACINT)from, (LUAI_UACINT)to);
	lua_pushvalue(L, -1);
	int ok;
	lua_rawget(L, -3);
	lua_Integer inn = lua_tointegerx(L, -1, &ok);
	lua_pop(L, 1);
	if (!ok) {
		inn = int_field(L, pop, K_NEXT_INNOV) + 1;
		set_int_field(L, pop, K_NEXT_INNOV, inn);
		lua_pushinteger(L, inn);
		lua_rawset(L, -3);
	} else {
		lua_pop(L, 1);
	}
	lua_pop(L, 1);
	return inn;
}

/* neat.lua's split_innovation: the node and the two innovations of a
 * split of the link of innovation `innov`, the same for every genome that
 * splits it this generation. */
static void split_innovation(lua_State *L, int pop, lua_Integer innov,
			     lua_Integer out[3])
{
	push_registry(L, pop, K_GEN_SPLITS);
	lua_pushfstring(L, "%I", (LUAI_UACINT)innov);
	lua_pushvalue(L, -1);
	if (lua_rawget(L, -3) == LUA_TTABLE) {
		int t = lua_gettop(L);
		out[0] = int_field(L, t, K_NODE);
		out[1] = int_field(L, t, K_INN_IN);
		out[2] = int_field(L, t, K_INN_OUT);
		lua_pop(L, 3);
		return;
	}
	lua_pop(L, 1);
	lua_Integer inn = int_field(L, pop, K_NEXT_INNOV);
	out[0] = int_field(L, pop, K_NEXT_NODE) + 1;
	out[1] = inn + 1;
	out[2] = inn + 2;
	set_int_field(L, pop, K_NEXT_NODE, out[0]);
	set_int_field(L, pop, K_NEXT_INNOV, inn + 2);
	lua_createtable(L, 0, 3);
	enum key keys[3] = {K_NODE, K_INN_IN, K_INN_OUT};
	for (int k = 0; k < 3; k++) {
		lua_pushinteger(L, out[k]);
		rset(L, -2, keys[k]);
	}
	lua_rawset(L, -3);
	lua_pop(L, 1);
}

/* Genome g's genes with `extra` more genes (given) added, sorted by
 * innovation, as g.links: a new block, as add_gene and sort_genes make it. */
static genes *add_genes(lua_State *L, int g, const gene *extra, int extra_n)
{
	int top = lua_gettop(L);
	genes *old = neat_genome_genes(L, g, 1);
	genes *gs = neat_new_genes(L, old->n + extra_n);
	memcpy(gs->g, old->g, (size_t)old->n * sizeof *gs->g);
	memcpy(gs->g + old->n, extra, (size_t)extra_n * sizeof *extra);
	int sorted = 1;
	for (int i = 1; i < gs->n && sorted; i++)
		sorted = gs->g[i - 1].innov < gs->g[i].innov;
	if (!sorted)
		qsort(gs->g, (size_t)gs->n, sizeof *gs->g, neat_by_innov);
	rset(L, g, K_LINKS);
	lua_settop(L, top);
	return gs;
}

/* Push genome g's nodes table (checked to be one) and read it into *nl:
 * the table's stack index. */
static int push_nodes(lua_State *L, int g, node_list *nl)
{
	rget(L, g, K_NODES);
	luaL_checktype(L, -1, LUA_TTABLE);
	int nodes = lua_gettop(L);
	*nl = neat_read_node_list(L, nodes);
	return nodes;
}

/* neat.lua's mutate_add_link on genome g of population pop (stack slots):
 * a link between two unlinked nodes, one that keeps the genome acyclic
 * unless `recurrent`; with recurrent and recur_only_prob, one that closes
 * a cycle with that chance and one that does not otherwise. Pushes the new
 * gene as a gene table, or nil when add_link_tries pairs gave none. */
void neat_add_link(lua_State *L, int pop, int g, const struct_opts *t,
		   rng_src *r)
{
	int top = lua_gettop(L);
	node_list nl;
	int nodes = push_nodes(L, g, &nl);
	int graded = t->recurrent && t->recur_only_prob > 0;
	int recur = graded && draw(L, r) < t->recur_only_prob;
	/* the nodes a self-loop may go round, needed only then */
	int *targets = NULL, nt = 0;
	if (recur) {
		targets = lua_newuserdatauv(L, (size_t)(nl.n + 1) * sizeof *targets, 0);
		for (int k = 0; k < nl.n; k++)
			if (nl.kind[k] != 'i' && nl.kind[k] != 'b')
				targets[nt++] = k;
	}
	int base = lua_gettop(L);
	for (lua_Integer tr = 0; tr < t->add_link_tries; tr++) {
		lua_settop(L, base);
		int a, b;
		if (recur && draw(L, r) < 0.5) {
			if (nt == 0)
				luaL_error(L, "neat: a self-loop with no node "
					      "to go round");
			a = targets[pick(draw(L, r), nt) - 1];
			b = a;
		} else {
			a = (int)pick(draw(L, r), nl.n) - 1;
			b = (int)pick(draw(L, r), nl.n) - 1;
		}
		if (nl.kind[b] == 'i' || nl.kind[b] == 'b')
			continue;
		const genes *gs = neat_genome_genes(L, g, 1);
		lua_Integer from = nl.id[a], to = nl.id[b];
		int exists = 0;
		for (int i = 0; i < gs->n && !exists; i++)
			exists = gs->g[i].from == from && gs->g[i].to == to;
		int ok = 1;
		if (!t->recurrent)
			ok = !neat_genes_reach(L, gs, to, from);
		else if (graded)
			ok = neat_genes_reach(L, gs, to, from) == recur;
		if (exists || !ok)
			continue;
		gene x = {link_innovation(L, pop, from, to), from, to, 0, 0, 1};
		set_clamped(&x, (draw(L, r) * 2 - 1) * t->new_link_power,
			    t->max, t->max_int);
		add_genes(L, g, &x, 1);
		neat_sort_list(L, nodes, K_ID);
		lua_settop(L, top);
		neat_push_gene_table(L, &x);
		return;
	}
	lua_settop(L, top);
	lua_pushnil(L);
}

/* neat.lua's mutate_add_node on genome g of population pop (stack
 * slots), its link chosen there: an enabled link not from the bias node
 * (unless split_bias), with split_older in a genome of fewer than 15
 * links the first taken with chance 0.7 in innovation order, else one
 * drawn uniformly. The link is disabled; from -> new gets weight 1, new ->
 * to the old weight. Pushes the new node's id, or nil (no link to split,
 * none taken, or the genome already has the node). */
void neat_add_node(lua_State *L, int pop, int g, const struct_opts *t,
		   rng_src *r)
{
	int top = lua_gettop(L);
	node_list nl;
	int nodes = push_nodes(L, g, &nl);
	int has_bias = 0;
	lua_Integer bias_id = 0;
	for (int k = 0; k < nl.n && !t->split_bias && !has_bias; k++)
		if (nl.kind[k] == 'b') {
			has_bias = 1;
			bias_id = nl.id[k];
		}
	genes *gs = neat_genome_genes(L, g, 1);
	int *enabled = lua_newuserdatauv(L, (size_t)(gs->n + 1) * sizeof *enabled, 0);
	int ne = 0;
	for (int i = 0; i < gs->n; i++)
		if (gs->g[i].enabled && !(has_bias && gs->g[i].from == bias_id))
			enabled[ne++] = i;
	int link = -1;
	if (ne > 0 && t->split_older && gs->n < 15) {
		for (int k = 0; k < ne && link < 0; k++)
			if (draw(L, r) < 0.7)
				link = enabled[k];
	} else if (ne > 0) {
		link = enabled[pick(draw(L, r), ne) - 1];
	}
	if (link < 0) {
		lua_settop(L, top);
		lua_pushnil(L);
		return;
	}
	lua_Integer s[3]; /* node, innovation in, innovation out */
	split_innovation(L, pop, gs->g[link].innov, s);
	/* nl's block is on the stack above top: read it before it goes */
	int split = 0;
	for (int k = 0; k < nl.n; k++)
		split |= nl.id[k] == s[0];
	lua_settop(L, top);
	if (split) { /* already split this generation */
		lua_pushnil(L);
		return;
	}
	gene *old = &gs->g[link];
	old->enabled = 0;
	/* the new node, in the genome's own list */
	rget(L, g, K_NODES);
	nodes = lua_gettop(L);
	lua_createtable(L, 0, 3);
	lua_pushinteger(L, s[0]);
	rset(L, -2, K_ID);
	lua_pushvalue(L, lua_upvalueindex(K_HIDDEN));
	rset(L, -2, K_KIND);
	rget(L, pop, K_OPTIONS);
	rget(L, -1, K_ACTIVATION);
	rset(L, -3, K_ACT);
	lua_pop(L, 1);
	lua_rawseti(L, nodes, (lua_Integer)lua_rawlen(L, nodes) + 1);
	gene x[2] = {{s[1], old->from, s[0], 1.0, 0, 1},
		     {s[2], s[0], old->to, old->weight, old->weight_int, 1}};
	add_genes(L, g, x, 2);
	neat_sort_list(L, nodes, K_ID);
	lua_settop(L, top);
	lua_pushinteger(L, s[0]);
}

/* A structural mutation of genome g (argument 2) of pop (1) with the
 * generator rng (3), under pop's options: add_link or add_node. */
typedef void (*structural_fn)(lua_State *L, int pop, int g,
			      const struct_opts *t, rng_src *r);
static int structural(lua_State *L, structural_fn mutation)
{
	neat_check_tables(L, 3);
	rget(L, 1, K_OPTIONS); /* 4 */
	luaL_checktype(L, 4, LUA_TTABLE);
	struct_opts t = neat_struct_opts_of(L, 4);
	rng_src r;
	neat_rng_begin(L, 3, &r);
	mutation(L, 1, 2, &t, &r);
	neat_rng_done(L, &r);
	return 1;
}

/* add_link(pop, g, rng) -> the new gene, or nil: add_link. */
int neat_l_add_link(lua_State *L)
{
	return structural(L, neat_add_link);
}

/* add_node(pop, g, rng) -> the new node's id, or nil: add_node. */
int neat_l_add_node(lua_State *L)
{
	return structural(L, neat_add_node);
}

/* evo.neat: the learning loop's hot kernels in C, for the loop's Lua state
 * (sim/learn/learn.c) and the Lua tests' (tests/sim/lua/test_lua_scripts.c).
 * The loop stays in Lua; what it did in the interpreter on every genome of
 * every generation is done here, with the same arithmetic in the same
 * order, so a run gives the same numbers bit for bit:
 *
 *   distance(a, b, o)  NEAT's compatibility distance of two genomes
 *                      (lua/learn/neat.lua's neat.distance_lua)
 *   speciate(genomes, reps, o, threshold)  each genome's species, as
 *                      neat.lua's speciate finds them with distance
 *   copy_genome(g)     neat.copy_genome_lua's copy, the node tables shared
 *   pack_net(g)        a genome as the network evo.evaluate runs, packed
 *                      in a userdata (neat.to_net and learn.c's reading
 *                      of its table, in one step)
 *   dump(v)            plain Lua data as text (serialize.dump_lua's
 *                      text, byte for byte), for the checkpoints
 *   rng_next(r), rng_unit(r), rng_normal(r)  learn.rng's Rng:next,
 *                      Rng:unit and Rng:normal, on the generator's own
 *                      four words (r.s)
 *   isoline(xi, xj, iso, line, r)  learn.mapelites' isoline variation
 *                      (mapelites.isoline_lua), the same draws
 *   mutate_weights(g, o, rng), crossover(a, fa, b, fb, o, rng)
 *                      neat.lua's, with the same random draws in the
 *                      same order
 *   rank(members, keys) the order tell sorts a species' members into
 *   genes(list), add_gene(g, gene), sort_genes(g), reaches(g, from, to)
 *                      a genome's genes as flat arrays (below), for
 *                      neat.lua's structural mutations
 *
 * A genome is { nodes = { {id, kind, act, value}, ... }, links = genes },
 * genes one userdata (evo.neat.genes) holding the link genes { innov,
 * from, to, weight, enabled } in an array, sorted by innovation: the
 * kernels work on the array, with no Lua table per gene. Lua reads and
 * writes a gene as before (#links, links[i].weight = w, ipairs) through
 * a small reference to it; dump writes genes as the list of gene tables
 * they stand for, so checkpoints keep their text, and neat.load turns
 * those tables back into genes. The kernels also take a genome whose
 * links are a list of gene tables (the tests make them by hand). Genes
 * change in place (weights, enabled); nodes never do once made, so
 * copies and children share them. Field names are looked up through the
 * module's upvalues (enum key): lua_getfield would intern its C string on
 * every call, which cost as much as the kernels' own work. */
#include "learn/lua_neat.h"

#include <ctype.h>
#include <lauxlib.h>
#include <limits.h>
#include <lua.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/g17.h"
#include "evo/fixed.h"
#include "mind/net_build.h"

#define NET_TYPE "evo.neat.net"
#define BUF_TYPE "evo.neat.buffer"
/* How deep dump follows tables into tables (a checkpoint is 6 deep). */
#define DUMP_MAX_DEPTH 100

/* The field names and strings the kernels look up, held as upvalues of
 * every function of the module: a raw get with an interned string is a
 * hash probe, where lua_getfield would intern its C string each time. */
enum key {
	K_INNOV = 1, K_FROM, K_TO, K_WEIGHT, K_ENABLED, K_ID, K_KIND, K_ACT,
	K_VALUE, K_S, K_LINKS, K_NODES, K_FITNESS, K_NORMALIZE_BELOW, K_C1,
	K_C2, K_C3, K_WEIGHT_MAX, K_PERTURB_PROB, K_WEIGHT_MUTATION,
	K_SEVERE_PROB, K_PERTURB_POWER, K_REPLACE_POWER, K_TIE_SMALLER,
	K_MATE_AVG_PROB, K_DISABLE_PROB, K_INPUT, K_OUTPUT, K_BIAS, K_HIDDEN,
	K_CODE, K_ADD_NODE_PROB, K_ADD_LINK_PROB, K_WEIGHT_MUT_PROB,
	K_MUTATE_ONLY_PROB, K_INTERSPECIES_PROB, K_MATE_ONLY_PROB,
	K_TOGGLE_PROB, K_REENABLE_PROB, K_MEMBERS, K_OPTIONS, K_RNG,
	K_RECURRENT, K_RECUR_ONLY_PROB, K_ADD_LINK_TRIES, K_NEW_LINK_POWER,
	K_SPLIT_BIAS, K_SPLIT_OLDER, K_ACTIVATION, K_GEN_LINKS, K_GEN_SPLITS,
	K_NEXT_INNOV, K_NEXT_NODE, K_NODE, K_INN_IN, K_INN_OUT, K_INPUTS,
	K_OUTPUTS, K_OUTPUTS_IDS, K_SPECIES, K_ADJUSTED, K_COUNT,
	/* not a key: the genes' metatable, the last upvalue */
	UP_GENES_MT = K_COUNT,
	N_UPVALUES = K_COUNT
};

static const char *const KEY_NAMES[K_COUNT] = {
    NULL,	    "innov",	     "from",	      "to",
    "weight",	    "enabled",	     "id",	      "kind",
    "act",	    "value",	     "s",	      "links",
    "nodes",	    "fitness",	     "normalize_below", "c1",
    "c2",	    "c3",	     "weight_max",    "perturb_prob",
    "weight_mutation", "severe_prob", "perturb_power", "replace_power",
    "tie_smaller",  "mate_avg_prob", "disable_prob",  "input",
    "output",	    "bias",	     "hidden",	      "code",
    "add_node_prob", "add_link_prob", "weight_mut_prob",
    "mutate_only_prob", "interspecies_prob", "mate_only_prob",
    "toggle_prob",  "reenable_prob", "members",	      "options",
    "rng",	    "recurrent",     "recur_only_prob", "add_link_tries",
    "new_link_power", "split_bias",  "split_older",   "activation",
    "gen_links",    "gen_splits",    "next_innov",    "next_node",
    "node",	    "inn_in",	     "inn_out",	      "inputs",
    "outputs",	    "outputs_ids",   "species",	      "adjusted",
};

/* Pushes t[key] (t a plain table: no metamethods) and returns its type. */
static int rget(lua_State *L, int t, enum key key)
{
	if (t < 0)
		t = lua_gettop(L) + t + 1;
	lua_pushvalue(L, lua_upvalueindex(key));
	return lua_rawget(L, t);
}

/* t[key] = the value on top of the stack, popped. */
static void rset(lua_State *L, int t, enum key key)
{
	if (t < 0)
		t = lua_gettop(L) + t + 1;
	lua_pushvalue(L, lua_upvalueindex(key));
	lua_insert(L, -2);
	lua_rawset(L, t);
}

/* Is the value at idx the string `key`? */
static int is_key(lua_State *L, int idx, enum key key)
{
	return lua_rawequal(L, idx, lua_upvalueindex(key));
}


/* ------------------------------------------------------------------ */
/* A genome's genes: one userdata of flat arrays */

#define GENES_TYPE "evo.neat.genes"
#define GENE_TYPE "evo.neat.gene"

/* A link gene. The weight keeps its Lua type: a weight clamped to an
 * integer weight_max is that integer, and the checkpoint writes it so. */
typedef struct gene {
	lua_Integer innov, from, to;
	double weight;
	uint8_t weight_int; /* the weight is a Lua integer */
	uint8_t enabled;
} gene;

/* The genes of one genome, sorted by innovation, in a block of its own:
 * a genome that gains genes gets a new block (structural mutations are
 * rare; copies and children are made at their size). */
typedef struct genes {
	int n;
	gene g[];
} genes;

static genes *new_genes(lua_State *L, int n)
{
	genes *gs = lua_newuserdatauv(L, sizeof(genes) + (size_t)(n ? n : 1) *
							      sizeof(gene),
				      0);
	gs->n = n;
	lua_pushvalue(L, lua_upvalueindex(UP_GENES_MT));
	lua_setmetatable(L, -2);
	return gs;
}

/* The genes at idx, NULL when it holds none (the metatable compared
 * with the one held as an upvalue: luaL_testudata would look it up by
 * name on every call). */
static genes *to_genes(lua_State *L, int idx)
{
	if (lua_type(L, idx) != LUA_TUSERDATA || !lua_getmetatable(L, idx))
		return NULL;
	int is = lua_rawequal(L, -1, lua_upvalueindex(UP_GENES_MT));
	lua_pop(L, 1);
	return is ? lua_touserdata(L, idx) : NULL;
}

/* Pushes gene field `key` of gs->g[i] as Lua has it. */
static void push_gene_field(lua_State *L, const gene *x, enum key key)
{
	switch (key) {
	case K_INNOV:
		lua_pushinteger(L, x->innov);
		break;
	case K_FROM:
		lua_pushinteger(L, x->from);
		break;
	case K_TO:
		lua_pushinteger(L, x->to);
		break;
	case K_WEIGHT:
		if (x->weight_int)
			lua_pushinteger(L, (lua_Integer)x->weight);
		else
			lua_pushnumber(L, x->weight);
		break;
	case K_ENABLED:
		lua_pushboolean(L, x->enabled);
		break;
	default:
		lua_pushnil(L);
	}
}

/* The value at idx as a gene's integer field (innovation, node id). */
static lua_Integer gene_int(lua_State *L, int idx, const char *what)
{
	int ok;
	lua_Integer v = lua_tointegerx(L, idx, &ok);
	if (!ok)
		luaL_error(L, "evo.neat: a gene's %s is %s, not a whole number",
			   what, luaL_typename(L, idx));
	return v;
}

/* Sets gene field `key` from the value at idx. */
static void set_gene_field(lua_State *L, gene *x, enum key key, int idx)
{
	switch (key) {
	case K_INNOV:
		x->innov = gene_int(L, idx, "innov");
		break;
	case K_FROM:
		x->from = gene_int(L, idx, "from");
		break;
	case K_TO:
		x->to = gene_int(L, idx, "to");
		break;
	case K_WEIGHT:
		if (lua_type(L, idx) != LUA_TNUMBER)
			luaL_error(L, "evo.neat: a gene's weight is %s",
				   luaL_typename(L, idx));
		x->weight_int = (uint8_t)lua_isinteger(L, idx);
		x->weight = lua_tonumber(L, idx);
		break;
	case K_ENABLED:
		x->enabled = (uint8_t)lua_toboolean(L, idx);
		break;
	default:
		luaL_error(L, "evo.neat: a gene has no field '%s'",
			   lua_tostring(L, idx - 1));
	}
}

/* Which gene field the string at idx names; 0 for none. */
static enum key gene_key(lua_State *L, int idx)
{
	for (int k = K_INNOV; k <= K_ENABLED; k++)
		if (is_key(L, idx, (enum key)k))
			return (enum key)k;
	return (enum key)0;
}

/* A gene table { innov, from, to, weight, enabled } at idx into *x. */
static void gene_from_table(lua_State *L, int idx, gene *x)
{
	idx = lua_absindex(L, idx);
	for (int k = K_INNOV; k <= K_ENABLED; k++) {
		rget(L, idx, (enum key)k);
		set_gene_field(L, x, (enum key)k, lua_gettop(L));
		lua_pop(L, 1);
	}
}

/* Pushes gene x as a table, as the Lua genomes hold genes. */
static void push_gene_table(lua_State *L, const gene *x)
{
	lua_createtable(L, 0, 5);
	for (int k = K_INNOV; k <= K_ENABLED; k++) {
		push_gene_field(L, x, (enum key)k);
		rset(L, -2, (enum key)k);
	}
}

/* Pushes the genes of list `list` (a table of gene tables, or genes). */
static genes *push_genes_of(lua_State *L, int list)
{
	list = lua_absindex(L, list);
	genes *gs = to_genes(L, list);
	if (gs) {
		lua_pushvalue(L, list);
		return gs;
	}
	luaL_checktype(L, list, LUA_TTABLE);
	int n = (int)lua_rawlen(L, list);
	gs = new_genes(L, n);
	for (int i = 0; i < n; i++) {
		lua_rawgeti(L, list, i + 1);
		gene_from_table(L, -1, &gs->g[i]);
		lua_pop(L, 1);
	}
	return gs;
}

/* The genes of genome g (a stack slot), pushed; a genome whose links are
 * still a table of gene tables (tests make them) gets them as genes,
 * stored back in g.links when `store`. */
static genes *genome_genes(lua_State *L, int g, int store)
{
	g = lua_absindex(L, g);
	luaL_checktype(L, g, LUA_TTABLE);
	rget(L, g, K_LINKS);
	genes *gs = to_genes(L, -1);
	if (gs)
		return gs;
	if (!lua_istable(L, -1))
		luaL_error(L, "evo.neat: a genome without links");
	gs = push_genes_of(L, -1);
	lua_remove(L, -2);
	if (store) {
		lua_pushvalue(L, -1);
		rset(L, g, K_LINKS);
	}
	return gs;
}

/* A gene of a genome's genes as Lua code sees it: a small userdata
 * naming the genes (its user value) and the index, whose fields read and
 * write the gene in place. */
typedef struct gene_ref {
	int i;
} gene_ref;

static gene *ref_gene(lua_State *L, int idx)
{
	gene_ref *r = luaL_checkudata(L, idx, GENE_TYPE);
	lua_getiuservalue(L, idx, 1);
	genes *gs = to_genes(L, -1);
	lua_pop(L, 1); /* the reference keeps the genes alive */
	if (!gs || r->i >= gs->n)
		luaL_error(L, "evo.neat: a gene past its genome's end");
	return &gs->g[r->i];
}

static int gene_index(lua_State *L)
{
	gene *x = ref_gene(L, 1);
	push_gene_field(L, x, gene_key(L, 2));
	return 1;
}

static int gene_newindex(lua_State *L)
{
	gene *x = ref_gene(L, 1);
	enum key k = gene_key(L, 2);
	if (!k)
		luaL_error(L, "evo.neat: a gene has no field '%s'",
			   luaL_tolstring(L, 2, NULL));
	set_gene_field(L, x, k, 3);
	return 0;
}

/* Two references to the same gene are equal (==). */
static int gene_eq(lua_State *L)
{
	gene_ref *a = luaL_testudata(L, 1, GENE_TYPE);
	gene_ref *b = luaL_testudata(L, 2, GENE_TYPE);
	if (!a || !b || a->i != b->i) {
		lua_pushboolean(L, 0);
		return 1;
	}
	lua_getiuservalue(L, 1, 1);
	lua_getiuservalue(L, 2, 1);
	lua_pushboolean(L, lua_rawequal(L, -1, -2));
	return 1;
}

/* genes[i]: a reference to gene i (1-based), nil past the end; a
 * method's name: the method. */
static int genes_index(lua_State *L)
{
	genes *gs = luaL_checkudata(L, 1, GENES_TYPE);
	if (lua_type(L, 2) == LUA_TSTRING) {
		lua_pushvalue(L, 2);
		lua_rawget(L, lua_upvalueindex(UP_GENES_MT));
		return 1;
	}
	lua_Integer i = luaL_checkinteger(L, 2);
	if (i < 1 || i > gs->n)
		return 0;
	gene_ref *r = lua_newuserdatauv(L, sizeof *r, 1);
	r->i = (int)i - 1;
	luaL_setmetatable(L, GENE_TYPE);
	lua_pushvalue(L, 1);
	lua_setiuservalue(L, -2, 1);
	return 1;
}

static int genes_len(lua_State *L)
{
	genes *gs = luaL_checkudata(L, 1, GENES_TYPE);
	lua_pushinteger(L, gs->n);
	return 1;
}

/* genes:plain() -> the genes as a list of gene tables (the Lua form:
 * checkpoints' text, copies of saved data). */
static int genes_plain(lua_State *L)
{
	genes *gs = luaL_checkudata(L, 1, GENES_TYPE);
	lua_createtable(L, gs->n, 0);
	for (int i = 0; i < gs->n; i++) {
		push_gene_table(L, &gs->g[i]);
		lua_rawseti(L, -2, i + 1);
	}
	return 1;
}

static int by_innov(const void *a, const void *b)
{
	lua_Integer x = ((const gene *)a)->innov, y = ((const gene *)b)->innov;
	return (x > y) - (x < y);
}

/* genes(list) -> genes holding a list of gene tables (or a copy of
 * genes), in the list's order. */
static int l_genes(lua_State *L)
{
	if (to_genes(L, 1)) {
		genes *src = to_genes(L, 1);
		genes *gs = new_genes(L, src->n);
		memcpy(gs->g, src->g, (size_t)src->n * sizeof *gs->g);
		return 1;
	}
	push_genes_of(L, 1);
	return 1;
}

/* add_gene(g, gene) -> g's genes with `gene` (a gene table) added and
 * sorted by innovation, as g.links (a new block; the old one is left
 * as it was). */
static int l_add_gene(lua_State *L)
{
	luaL_checktype(L, 2, LUA_TTABLE);
	lua_settop(L, 2);
	genes *old = genome_genes(L, 1, 0);
	genes *gs = new_genes(L, old->n + 1);
	memcpy(gs->g, old->g, (size_t)old->n * sizeof *gs->g);
	gene_from_table(L, 2, &gs->g[old->n]);
	lua_pushvalue(L, -1);
	rset(L, 1, K_LINKS);
	return 1;
}

/* sort_genes(g): g's genes sorted by innovation (distinct ones). */
static int l_sort_genes(lua_State *L)
{
	genes *gs = genome_genes(L, 1, 1);
	int sorted = 1;
	for (int i = 1; i < gs->n && sorted; i++)
		sorted = gs->g[i - 1].innov < gs->g[i].innov;
	if (!sorted)
		qsort(gs->g, (size_t)gs->n, sizeof *gs->g, by_innov);
	return 0;
}

/* Does a path from node `from` reach node `to` over genes gs, enabled or
 * not (neat.lua's reaches)? Its room is a userdata, left on the stack. */
static int genes_reach(lua_State *L, const genes *gs, lua_Integer from,
		       lua_Integer to)
{
	if (from == to)
		return 1;
	/* the nodes seen, as a stack of those still to walk from */
	lua_Integer *seen = lua_newuserdatauv(L, 2 * ((size_t)gs->n + 1) *
							 sizeof *seen, 0);
	lua_Integer *stack = seen + gs->n + 1;
	int n_seen = 1, top = 1;
	seen[0] = stack[0] = from;
	while (top > 0) {
		lua_Integer n = stack[--top];
		for (int i = 0; i < gs->n; i++) {
			if (gs->g[i].from != n)
				continue;
			lua_Integer t = gs->g[i].to;
			int was = 0;
			for (int k = 0; k < n_seen && !was; k++)
				was = seen[k] == t;
			if (was)
				continue;
			if (t == to)
				return 1;
			seen[n_seen++] = t;
			stack[top++] = t;
		}
	}
	return 0;
}

/* reaches(g, from, to): does a path from node `from` reach node `to`
 * over g's genes, enabled or not (neat.lua's reaches). */
static int l_reaches(lua_State *L)
{
	lua_Integer from = luaL_checkinteger(L, 2), to = luaL_checkinteger(L, 3);
	genes *gs = genome_genes(L, 1, 0);
	lua_pushboolean(L, genes_reach(L, gs, from, to));
	return 1;
}

static const luaL_Reg GENES_METHODS[] = {
    {"__index", genes_index},
    {"__len", genes_len},
    {"plain", genes_plain},
    {"__plain", genes_plain},
    {NULL, NULL},
};

static const luaL_Reg GENE_METHODS[] = {
    {"__index", gene_index},
    {"__newindex", gene_newindex},
    {"__eq", gene_eq},
    {NULL, NULL},
};

/* ------------------------------------------------------------------ */
/* Compatibility distance */

/* Field `key` of the table at idx as a number; 0 when it is none. */
static double num_field(lua_State *L, int idx, enum key key)
{
	rget(L, idx, key);
	double v = lua_tonumber(L, -1);
	lua_pop(L, 1);
	return v;
}

/* The options the distance reads. */
typedef struct dist_opts {
	double c1, c2, c3, normalize_below;
} dist_opts;

static dist_opts dist_opts_of(lua_State *L, int o)
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
static double distance_of(const genes *a, const genes *b, const dist_opts *o)
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

static void *scratch(lua_State *L, size_t bytes);

/* distance(a, b, o): NEAT's compatibility distance (distance_of). */
static int l_distance(lua_State *L)
{
	luaL_checktype(L, 3, LUA_TTABLE);
	const genes *a = genome_genes(L, 1, 0);
	const genes *b = genome_genes(L, 2, 0);
	dist_opts o = dist_opts_of(L, 3);
	lua_pushnumber(L, distance_of(a, b, &o));
	return 1;
}

/* speciate(genomes, reps, o, threshold) -> home, opened: home[i] is the species
 * of genome i, as neat.lua's speciate assigns them: the first species
 * whose representative (reps[k], k in order) is within distance
 * `threshold` (distance(genome, rep) < threshold), else a new species
 * numbered #reps + 1, #reps + 2, ... in the order they are opened, whose
 * representative is that genome; and the genomes that opened them, in
 * that order. */
static int l_speciate(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	double threshold = luaL_checknumber(L, 4);
	dist_opts o = dist_opts_of(L, 3);
	int ng = (int)lua_rawlen(L, 1), nr = (int)lua_rawlen(L, 2);
	/* every rep's and genome's genes (kept on the stack while read),
	 * then the reps' indices into them (the old ones and the new) */
	luaL_checkstack(L, nr + ng + 8, "speciate: too many genomes");
	const genes **all = scratch(L, (size_t)(nr + ng) * (sizeof *all +
								sizeof(int)));
	int *rep = (int *)(void *)(all + nr + ng);
	for (int k = 0; k < nr + ng; k++) {
		lua_rawgeti(L, k < nr ? 2 : 1, k < nr ? k + 1 : k - nr + 1);
		all[k] = genome_genes(L, -1, 0);
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
		while (home < n_rep && !(distance_of(g, all[rep[home]], &o) <
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
static int l_assign(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	lua_settop(L, 3);
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

/* Room in a genome table for its nodes and links and for the fields the
 * loop sets on it (fitness, adjusted, species): no table grows twice
 * every generation. */
#define GENOME_FIELDS 5

/* Pushes a copy of the genome at g (l_copy_genome's). */
static void push_copy(lua_State *L, int g)
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
	const genes *gs = genome_genes(L, g, 0);
	genes *c = new_genes(L, gs->n);
	memcpy(c->g, gs->g, (size_t)gs->n * sizeof *c->g);
	rset(L, copy, K_LINKS);
	lua_settop(L, copy);
}

/* copy_genome(g) -> a copy of g's nodes and genes (neat.copy_genome):
 * the genes copied (they change: weights, enabled), the node list a new
 * list of the same node tables (a node never changes once made:
 * mutations add nodes to a genome's own list). */
static int l_copy_genome(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_settop(L, 1);
	push_copy(L, 1);
	return 1;
}

/* ------------------------------------------------------------------ */
/* Networks from genomes */

/* A network as evo.evaluate takes it: evo_netdesc's header, then n_nodes
 * nodes and n_links links (only as many as the network has). */
typedef struct packed_net {
	uint16_t n_in, n_out, n_nodes, n_links;
	uint16_t out_id[EVO_MAX_SKILL_IO];
	evo_netdesc_node node[];
} packed_net;

static evo_netdesc_link *packed_links(packed_net *p)
{
	return (evo_netdesc_link *)(void *)(p->node + p->n_nodes);
}

/* A genome node's id and the id it gets in the network. */
typedef struct id_map {
	lua_Integer id;
	uint16_t to;
} id_map;

static int by_id(const void *a, const void *b)
{
	lua_Integer x = ((const id_map *)a)->id, y = ((const id_map *)b)->id;
	return (x > y) - (x < y);
}

/* The network id of genome node `id`, or -1 when the genome has none. */
static int map_id(const id_map *map, int n, lua_Integer id)
{
	id_map key = {id, 0};
	const id_map *m = bsearch(&key, map, (size_t)n, sizeof *map, by_id);
	return m ? m->to : -1;
}

/* The last activation name looked up, and its number: a genome's nodes
 * share a few interned strings, alive while the genome is read, and the
 * same pointer is the same name. */
typedef struct act_cache {
	const char *last;
	unsigned last_a;
} act_cache;

static unsigned act_of(lua_State *L, const char *act, act_cache *c)
{
	if (act && act == c->last)
		return c->last_a;
	unsigned a = 0;
	while (act && evo_act_name(a) && strcmp(evo_act_name(a), act))
		a++;
	if (!act || !evo_act_name(a))
		luaL_error(L, "pack_net: unknown activation '%s'",
			   act ? act : "nil");
	c->last = act;
	c->last_a = a;
	return a;
}

/* The genome's nodes read once: kinds, ids, activations. */
typedef struct genome_nodes {
	int n;			/* nodes */
	int n_in, n_out, n_hidden; /* inputs, outputs, hidden nodes */
	int has_bias;
	lua_Integer bias_id;
	double bias_value;
	char kind[EVO_NET_MAX_NODES + EVO_MAX_SKILL_IO + 2]; /* i o h b */
	lua_Integer id[EVO_NET_MAX_NODES + EVO_MAX_SKILL_IO + 2];
	uint8_t act[EVO_NET_MAX_NODES + EVO_MAX_SKILL_IO + 2];
} genome_nodes;

#define GENOME_MAX_NODES (EVO_NET_MAX_NODES + EVO_MAX_SKILL_IO + 2)

static void read_nodes(lua_State *L, int list, genome_nodes *g)
{
	lua_Integer n = (lua_Integer)lua_rawlen(L, list);
	if (n > GENOME_MAX_NODES)
		luaL_error(L, "pack_net: a genome of %I nodes (a network "
			      "has at most %d)",
			   n, EVO_NET_MAX_NODES);
	memset(g, 0, offsetof(genome_nodes, kind));
	g->n = (int)n;
	act_cache cache = {NULL, 0};
	for (int k = 0; k < g->n; k++) {
		lua_rawgeti(L, list, k + 1);
		int t = lua_gettop(L);
		rget(L, t, K_KIND);
		int kind = lua_gettop(L);
		rget(L, t, K_ID);
		g->id[k] = lua_tointeger(L, -1);
		char c = is_key(L, kind, K_INPUT)    ? 'i'
			 : is_key(L, kind, K_OUTPUT) ? 'o'
			 : is_key(L, kind, K_BIAS)   ? 'b'
			 : is_key(L, kind, K_HIDDEN) ? 'h'
						     : '?';
		g->kind[k] = c;
		if (c == 'i') {
			g->n_in++;
		} else if (c == 'o' || c == 'h') {
			rget(L, t, K_ACT);
			g->act[k] = (uint8_t)act_of(L, lua_tostring(L, -1), &cache);
			lua_pop(L, 1);
			g->n_out += c == 'o';
			g->n_hidden += c == 'h';
		} else if (c == 'b') {
			/* the last bias node counts, as in neat.to_net */
			rget(L, t, K_VALUE);
			g->has_bias = 1;
			g->bias_id = g->id[k];
			g->bias_value =
			    lua_isnil(L, -1) ? 1.0 : lua_tonumber(L, -1);
			lua_pop(L, 1);
		}
		lua_pop(L, 3);
	}
}

/* pack_net(genome) -> the network neat.to_net would give, as a userdata
 * evo.evaluate reads directly: inputs keep their ids, outputs then hidden
 * nodes (in the genome's node order) take the next ids, enabled links
 * from the bias node become their target's bias (weight times the bias
 * node's value, summed in link order), the other enabled links stay in
 * link order. */
static int l_pack_net(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_settop(L, 1);
	rget(L, 1, K_NODES);
	luaL_checktype(L, 2, LUA_TTABLE);
	const genes *gs = genome_genes(L, 1, 0); /* 3 */
	static _Thread_local genome_nodes g;
	read_nodes(L, 2, &g);
	if (g.n_out > EVO_MAX_SKILL_IO)
		luaL_error(L, "pack_net: %d outputs", g.n_out);
	lua_Integer n_links = gs->n;
	if (n_links > EVO_NET_MAX_LINKS * 2)
		luaL_error(L, "pack_net: a genome of %I links", n_links);
	int n_nodes = g.n_out + g.n_hidden;
	size_t size = sizeof(packed_net) +
		      (size_t)n_nodes * sizeof(evo_netdesc_node) +
		      (size_t)n_links * sizeof(evo_netdesc_link);
	packed_net *p = lua_newuserdatauv(L, size, 0);
	luaL_setmetatable(L, NET_TYPE);
	memset(p, 0, sizeof *p);
	p->n_in = (uint16_t)g.n_in;
	p->n_out = (uint16_t)g.n_out;
	p->n_nodes = (uint16_t)n_nodes;
	id_map map[GENOME_MAX_NODES];
	double bias[GENOME_MAX_NODES];
	int n_map = 0, next = g.n_in, n_out = 0;
	for (int pass = 0; pass < 3; pass++)
		for (int k = 0; k < g.n; k++) {
			char want = pass == 0 ? 'i' : pass == 1 ? 'o' : 'h';
			if (g.kind[k] != want)
				continue;
			if (pass == 0) {
				map[n_map++] = (id_map){g.id[k],
							(uint16_t)g.id[k]};
				continue;
			}
			evo_netdesc_node *nd = &p->node[next - g.n_in];
			nd->id = (uint16_t)next;
			nd->act = g.act[k];
			nd->line = 0;
			bias[next - g.n_in] = 0.0;
			if (pass == 1)
				p->out_id[n_out++] = (uint16_t)next;
			map[n_map++] = (id_map){g.id[k], (uint16_t)next};
			next++;
		}
	qsort(map, (size_t)n_map, sizeof *map, by_id);
	evo_netdesc_link *lk = packed_links(p);
	int n = 0;
	for (lua_Integer i = 1; i <= n_links; i++) {
		const gene *x = &gs->g[i - 1];
		if (x->enabled) {
			lua_Integer from = x->from, to = x->to;
			double w = x->weight;
			int t = map_id(map, n_map, to);
			if (t < g.n_in)
				luaL_error(L, "pack_net: link %I ends at node "
					      "%I, which is no output or "
					      "hidden node of the genome",
					   i, to);
			if (g.has_bias && from == g.bias_id) {
				bias[t - g.n_in] += w * g.bias_value;
			} else {
				int f = map_id(map, n_map, from);
				if (f < 0)
					luaL_error(L, "pack_net: link %I starts "
						      "at node %I, which the "
						      "genome does not have",
						   i, from);
				if (n == EVO_NET_MAX_LINKS)
					luaL_error(L, "pack_net: more than %d "
						      "links",
						   EVO_NET_MAX_LINKS);
				lk[n++] = (evo_netdesc_link){
				    (uint16_t)f, (uint16_t)t,
				    evo_net_weight_q16(w), 0};
			}
		}
	}
	p->n_links = (uint16_t)n;
	for (int k = 0; k < n_nodes; k++)
		p->node[k].bias = evo_net_weight_q16(bias[k]);
	return 1;
}

int evo_lua_net_unpack(lua_State *L, int idx, evo_netdesc *d)
{
	packed_net *p = luaL_testudata(L, idx, NET_TYPE);
	if (!p)
		return 0;
	d->n_in = p->n_in;
	d->n_out = p->n_out;
	d->n_nodes = p->n_nodes;
	d->n_links = p->n_links;
	memcpy(d->out_id, p->out_id, sizeof d->out_id);
	memcpy(d->node, p->node, (size_t)p->n_nodes * sizeof *d->node);
	memcpy(d->link, packed_links(p), (size_t)p->n_links * sizeof *d->link);
	return 1;
}

/* ------------------------------------------------------------------ */
/* Plain data as text */

/* A table already written: where its text is in the buffer. */
typedef struct written {
	const void *table; /* NULL: a free slot */
	size_t at, len;
} written;

/* The text being made, and the tables written into it: a table met
 * again (genomes share their node tables) is the same text, copied. */
typedef struct buffer {
	char *b;
	size_t len, cap;
	written *seen; /* open addressing on the table's address */
	size_t n_seen, seen_cap;
} buffer;

static void free_buffer_of(buffer *b)
{
	free(b->b);
	b->b = NULL;
	free(b->seen);
	b->seen = NULL;
}

static int free_buffer(lua_State *L)
{
	free_buffer_of(luaL_checkudata(L, 1, BUF_TYPE));
	return 0;
}

/* The slot of `table` in b->seen: its entry, or the free slot it would
 * take. */
static written *seen_slot(const buffer *b, const void *table)
{
	size_t h = ((uintptr_t)table >> 4) * 0x9E3779B97F4A7C15u;
	for (size_t i = h & (b->seen_cap - 1);; i = (i + 1) & (b->seen_cap - 1))
		if (b->seen[i].table == table || !b->seen[i].table)
			return &b->seen[i];
}

/* Notes that `table`'s text is b->b[at .. b->len). */
static void note_written(lua_State *L, buffer *b, const void *table,
			 size_t at)
{
	if (2 * (b->n_seen + 1) > b->seen_cap) {
		size_t cap = b->seen_cap ? 2 * b->seen_cap : 256;
		written *old = b->seen;
		size_t old_cap = b->seen_cap;
		b->seen = calloc(cap, sizeof *b->seen);
		if (!b->seen) {
			b->seen = old;
			luaL_error(L, "serialize: out of memory");
		}
		b->seen_cap = cap;
		for (size_t i = 0; i < old_cap; i++)
			if (old[i].table)
				*seen_slot(b, old[i].table) = old[i];
		free(old);
	}
	written *w = seen_slot(b, table);
	if (!w->table)
		b->n_seen++;
	*w = (written){table, at, b->len - at};
}

/* Room for n more bytes in b. */
static void reserve(lua_State *L, buffer *b, size_t n)
{
	if (b->cap - b->len < n) {
		size_t cap = b->cap ? b->cap : 4096;
		while (cap - b->len < n)
			cap *= 2;
		char *nb = realloc(b->b, cap);
		if (!nb)
			luaL_error(L, "serialize: out of memory");
		b->b = nb;
		b->cap = cap;
	}
}

static void put(lua_State *L, buffer *b, const char *s, size_t n)
{
	reserve(L, b, n);
	memcpy(b->b + b->len, s, n);
	b->len += n;
}

static void puts_(lua_State *L, buffer *b, const char *s)
{
	put(L, b, s, strlen(s));
}

/* The decimal digits of x (not LUA_MININTEGER) into s; their count. */
static size_t int_text(char *s, lua_Integer x)
{
	char tmp[24];
	size_t n = 0, k = 0;
	uint64_t u = x < 0 ? (uint64_t)0 - (uint64_t)x : (uint64_t)x;
	do {
		tmp[n++] = (char)('0' + u % 10);
		u /= 10;
	} while (u);
	if (x < 0)
		s[k++] = '-';
	while (n)
		s[k++] = tmp[--n];
	return k;
}

/* As serialize.lua's number(): integers as they are (the smallest as an
 * expression), floats with 17 digits and a ".0" when they would read as
 * an integer, inf and nan as expressions. */
static void put_number(lua_State *L, buffer *b, int idx)
{
	char s[64];
	if (lua_isinteger(L, idx)) {
		lua_Integer x = lua_tointeger(L, idx);
		if (x == LUA_MININTEGER)
			puts_(L, b, "(-9223372036854775807-1)");
		else
			put(L, b, s, int_text(s, x));
		return;
	}
	double x = lua_tonumber(L, idx);
	if (x > -0x1p53 && x < 0x1p53 && x == (double)(int64_t)x &&
	    (x != 0 || !signbit(x))) {
		/* a whole float: "%.17g" gives its digits (it has fewer
		 * than 17), and ".0" follows */
		size_t n = int_text(s, (lua_Integer)x);
		memcpy(s + n, ".0", 2);
		put(L, b, s, n + 2);
	} else if (x != x) {
		puts_(L, b, "(0/0)");
	} else if (x > 1.7976931348623157e308) {
		puts_(L, b, "(1/0)");
	} else if (x < -1.7976931348623157e308) {
		puts_(L, b, "(-1/0)");
	} else {
		evo_g17(x, s, sizeof s); /* "%.17g" */
		if (!strpbrk(s, ".eEn"))
			strcat(s, ".0");
		puts_(L, b, s);
	}
}

/* As string.format("%q", s). */
static void put_string(lua_State *L, buffer *b, int idx)
{
	size_t len;
	const char *s = lua_tolstring(L, idx, &len);
	put(L, b, "\"", 1);
	for (size_t i = 0; i < len; i++) {
		unsigned char c = (unsigned char)s[i];
		size_t run = 0; /* characters written as they are, from i */
		while (i + run < len && s[i + run] != '"' &&
		       s[i + run] != '\\' && s[i + run] != '\n' &&
		       !iscntrl((unsigned char)s[i + run]))
			run++;
		if (run) {
			put(L, b, s + i, run);
			i += run - 1;
		} else if (c == '"' || c == '\\' || c == '\n') {
			char e[2] = {'\\', (char)c};
			put(L, b, e, 2);
		} else if (iscntrl(c)) {
			char e[8];
			/* s[len] is the string's terminating zero */
			unsigned char next = (unsigned char)s[i + 1];
			snprintf(e, sizeof e, isdigit(next) ? "\\%03d" : "\\%d",
				 (int)c);
			puts_(L, b, e);
		}
	}
	put(L, b, "\"", 1);
}

/* n when the table at idx has exactly the keys 1 .. n (n = #t), else -1. */
static lua_Integer list_length(lua_State *L, int idx)
{
	lua_Integer n = (lua_Integer)lua_rawlen(L, idx);
	for (lua_Integer i = 1; i <= n; i++) {
		int nil = lua_rawgeti(L, idx, i) == LUA_TNIL;
		lua_pop(L, 1);
		if (nil)
			return -1;
	}
	lua_Integer count = 0;
	lua_pushnil(L);
	while (lua_next(L, idx)) {
		lua_pop(L, 1);
		if (++count > n) {
			lua_pop(L, 1);
			return -1;
		}
	}
	return n;
}

/* A record's key as the sort compares it: its stack slot, its type, and
 * a string key's bytes (read once, not at every comparison). */
typedef struct rkey {
	int slot, type;
	const char *s;
	size_t len;
} rkey;

/* serialize.lua's key order: by type name, then by value (Lua's <).
 * Strings compare byte by byte, a prefix first: what Lua's < does in the
 * C locale, which evo never leaves. */
static int key_less(lua_State *L, const rkey *a, const rkey *b)
{
	if (a->type != b->type)
		return strcmp(lua_typename(L, a->type),
			      lua_typename(L, b->type)) < 0;
	if (a->type == LUA_TSTRING) {
		int c = memcmp(a->s, b->s, a->len < b->len ? a->len : b->len);
		return c < 0 || (c == 0 && a->len < b->len);
	}
	return lua_compare(L, a->slot, b->slot, LUA_OPLT);
}

/* Sorts the n keys k[0 .. n-1] (insertion of each into the sorted ones
 * before it: a record has a few; the keys are distinct, so any sort
 * gives one order). */
static void sort_keys(lua_State *L, rkey *k, int n)
{
	for (int i = 1; i < n; i++) {
		rkey x = k[i];
		int j = i;
		for (; j > 0 && key_less(L, &x, &k[j - 1]); j--)
			k[j] = k[j - 1];
		k[j] = x;
	}
}

/* Merge sort of the n keys k[0 .. n-1], tmp as room: for big maps. */
static void merge_keys(lua_State *L, rkey *k, rkey *tmp, int n)
{
	for (int w = 1; w < n; w *= 2) {
		for (int lo = 0; lo < n; lo += 2 * w) {
			int mid = lo + w < n ? lo + w : n;
			int hi = lo + 2 * w < n ? lo + 2 * w : n;
			int a = lo, c = mid, o = lo;
			while (a < mid && c < hi)
				tmp[o++] = key_less(L, &k[c], &k[a]) ? k[c++]
								      : k[a++];
			while (a < mid)
				tmp[o++] = k[a++];
			while (c < hi)
				tmp[o++] = k[c++];
		}
		memcpy(k, tmp, (size_t)n * sizeof *k);
	}
}

static void put_value(lua_State *L, buffer *b, int idx, int depth);

/* Genes as the list of gene tables they stand for (genes:plain()'s
 * text): each gene's fields in key order. */
static void put_genes(lua_State *L, buffer *b, const genes *gs)
{
	static const char *const name[] = {
	    NULL, "[\"innov\"]=", "[\"from\"]=", "[\"to\"]=",
	    "[\"weight\"]=", "[\"enabled\"]="};
	static const enum key order[] = {K_ENABLED, K_FROM, K_INNOV, K_TO,
					 K_WEIGHT};
	luaL_checkstack(L, 2, "serialize: genes");
	put(L, b, "{", 1);
	for (int i = 0; i < gs->n; i++) {
		put(L, b, "{", 1);
		for (int k = 0; k < 5; k++) {
			puts_(L, b, name[order[k]]);
			push_gene_field(L, &gs->g[i], order[k]);
			if (order[k] == K_ENABLED)
				puts_(L, b, lua_toboolean(L, -1) ? "true"
								 : "false");
			else
				put_number(L, b, lua_gettop(L));
			lua_pop(L, 1);
			put(L, b, ",", 1);
		}
		put(L, b, "},", 2);
	}
	put(L, b, "}", 1);
}

static void put_record(lua_State *L, buffer *b, int idx, int depth)
{
	/* every key and its value onto the stack, in pairs from base */
	int base = lua_gettop(L) + 1, n = 0;
	lua_pushnil(L);
	while (lua_next(L, idx)) {
		luaL_checkstack(L, 3, "serialize: a table of too many keys");
		lua_pushvalue(L, -2); /* the pair stays, a copy iterates */
		n++;
	}
	/* a record's few keys are sorted in an array here, a big map's in
	 * a userdata */
	rkey small[16];
	rkey *k = n <= 16 ? small
			  : lua_newuserdatauv(L, 2 * (size_t)n * sizeof *k, 0);
	for (int i = 0; i < n; i++) {
		k[i].slot = base + 2 * i;
		k[i].type = lua_type(L, k[i].slot);
		k[i].s = k[i].type == LUA_TSTRING
			     ? lua_tolstring(L, k[i].slot, &k[i].len)
			     : NULL;
	}
	if (n <= 16)
		sort_keys(L, k, n);
	else
		merge_keys(L, k, k + n, n);
	for (int i = 0; i < n; i++) {
		put(L, b, "[", 1);
		put_value(L, b, k[i].slot, depth);
		put(L, b, "]=", 2);
		put_value(L, b, k[i].slot + 1, depth);
		put(L, b, ",", 1);
	}
	lua_settop(L, base - 1);
}

static void put_value(lua_State *L, buffer *b, int idx, int depth)
{
	switch (lua_type(L, idx)) {
	case LUA_TNUMBER:
		put_number(L, b, idx);
		return;
	case LUA_TSTRING:
		put_string(L, b, idx);
		return;
	case LUA_TBOOLEAN:
		puts_(L, b, lua_toboolean(L, idx) ? "true" : "false");
		return;
	case LUA_TTABLE:
		break;
	case LUA_TUSERDATA:
		if (to_genes(L, idx)) {
			put_genes(L, b, to_genes(L, idx));
			return;
		}
		/* fall through */
	default:
		luaL_error(L, "serialize: cannot save a %s",
			   luaL_typename(L, idx));
	}
	const void *table = lua_topointer(L, idx);
	const written *w = b->seen_cap ? seen_slot(b, table) : NULL;
	if (w && w->table) {
		size_t at = w->at, n = w->len;
		reserve(L, b, n); /* (w may move no more: no lookup follows) */
		memcpy(b->b + b->len, b->b + at, n);
		b->len += n;
		return;
	}
	if (depth >= DUMP_MAX_DEPTH)
		luaL_error(L, "serialize: tables nested more than %d deep",
			   DUMP_MAX_DEPTH);
	size_t at = b->len;
	luaL_checkstack(L, 8, "serialize: tables nested too deep");
	put(L, b, "{", 1);
	lua_Integer len = list_length(L, idx);
	if (len >= 0) {
		for (lua_Integer i = 1; i <= len; i++) {
			lua_rawgeti(L, idx, i);
			put_value(L, b, lua_gettop(L), depth + 1);
			lua_pop(L, 1);
			put(L, b, ",", 1);
		}
	} else {
		put_record(L, b, idx, depth + 1);
	}
	put(L, b, "}", 1);
	note_written(L, b, table, at);
}

/* dump(v) -> "return " .. v's text .. "\n", as serialize.dump_lua. */
static int l_dump(lua_State *L)
{
	luaL_checkany(L, 1);
	lua_settop(L, 1);
	buffer *b = lua_newuserdatauv(L, sizeof *b, 0);
	memset(b, 0, sizeof *b);
	luaL_setmetatable(L, BUF_TYPE);
	puts_(L, b, "return ");
	put_value(L, b, 1, 0);
	put(L, b, "\n", 1);
	lua_pushlstring(L, b->b, b->len);
	free_buffer_of(b);
	return 1;
}

/* ------------------------------------------------------------------ */
/* learn.rng's generator: xoshiro256** on the object's four words */

/* xoshiro256**'s step on the four words s: the next word. */
static uint64_t xoshiro_next(uint64_t s[4])
{
	uint64_t x = s[1] * 5;
	uint64_t result = ((x << 7) | (x >> 57)) * 9;
	uint64_t t = s[1] << 17;
	s[2] ^= s[0];
	s[3] ^= s[1];
	s[1] ^= s[2];
	s[0] ^= s[3];
	s[2] ^= t;
	s[3] = (s[3] << 45) | (s[3] >> 19);
	return result;
}

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
static int l_rng_next(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_pushinteger(L, (lua_Integer)rng_next(L, 1));
	return 1;
}

static double unit_of(uint64_t word)
{
	return (double)(word >> 11) * (1.0 / 9007199254740992.0);
}

/* rng_unit(self) -> uniform in [0, 1) from the top 53 bits (Rng:unit). */
static int l_rng_unit(lua_State *L)
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
static int l_rng_normal(lua_State *L)
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
static int l_isoline(lua_State *L)
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

/* A kernel's generator: learn.rng's (`ours`: its words are read once into
 * s, drawn from in C and written back by rng_done), or a test's own,
 * whose unit method is called for each draw. */
typedef struct rng_src {
	int rng;  /* its stack slot */
	int ours; /* learn.rng's, with rng_unit as its unit */
	int state; /* ours: the stack slot of rng.s */
	uint64_t s[4];
} rng_src;

/* Starts drawing from the generator at stack slot `rng` (it may push a
 * value: call it where the stack's top does not matter). */
static void rng_begin(lua_State *L, int rng, rng_src *r)
{
	r->rng = lua_absindex(L, rng);
	lua_getfield(L, r->rng, "unit");
	r->ours = lua_tocfunction(L, -1) == l_rng_unit;
	lua_pop(L, 1);
	if (r->ours) {
		rng_read(L, r->rng, r->s);
		r->state = lua_gettop(L);
	}
}

/* The words drawn from, back in the generator. */
static void rng_done(lua_State *L, rng_src *r)
{
	if (!r->ours)
		return;
	lua_pushvalue(L, r->state);
	rng_write(L, r->s);
}

/* rng:unit() of the kernel's generator. */
static double draw(lua_State *L, rng_src *r)
{
	if (r->ours)
		return unit_of(xoshiro_next(r->s));
	lua_getfield(L, r->rng, "unit");
	lua_pushvalue(L, r->rng);
	lua_call(L, 1, 1);
	double u = lua_tonumber(L, -1);
	lua_pop(L, 1);
	return u;
}

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

/* The options a weight mutation reads. */
typedef struct wm_opts {
	double max; /* weight_max */
	int max_int; /* weight_max is a Lua integer */
	int code; /* weight_mutation is "code" */
	double perturb_prob, severe_prob, perturb_power, replace_power;
} wm_opts;

static wm_opts wm_opts_of(lua_State *L, int o)
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
static void mutate_genes(lua_State *L, genes *gs, const wm_opts *w,
			 rng_src *r)
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
	genes *gs = genome_genes(L, g, 1);
	wm_opts w = wm_opts_of(L, o);
	mutate_genes(L, gs, &w, r);
	lua_settop(L, top);
}

/* mutate_weights(g, o, rng): neat.lua's mutate_weights. */
static int l_mutate_weights(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	lua_settop(L, 3);
	rng_src r;
	rng_begin(L, 3, &r);
	mutate_weights_with(L, 1, 2, &r);
	rng_done(L, &r);
	return 0;
}

/* mutate(g, o, rng) -> what neat.mutate does next: its first draws, as
 * neat.lua makes them, in C. 1: an add-node mutation (left to Lua), 2: an
 * add-link one (left to Lua), 0: neither, and the weights were mutated
 * (with chance weight_mut_prob) here; the toggle and re-enable draws
 * that may follow are Lua's. */
static int l_mutate(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	lua_settop(L, 3);
	rng_src r;
	rng_begin(L, 3, &r);
	int what = 0;
	if (draw(L, &r) < num_field(L, 2, K_ADD_NODE_PROB))
		what = 1;
	else if (draw(L, &r) < num_field(L, 2, K_ADD_LINK_PROB))
		what = 2;
	else if (draw(L, &r) < num_field(L, 2, K_WEIGHT_MUT_PROB))
		mutate_weights_with(L, 1, 2, &r);
	rng_done(L, &r);
	lua_pushinteger(L, what);
	return 1;
}

/* draws(rng, n) -> { rng:unit(), ... }: n draws, in order. */
static int l_draws(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_Integer n = luaL_checkinteger(L, 2);
	lua_settop(L, 1);
	rng_src r;
	rng_begin(L, 1, &r);
	lua_createtable(L, n > 0 && n < INT32_MAX ? (int)n : 0, 0);
	int t = lua_gettop(L);
	for (lua_Integer k = 1; k <= n; k++) {
		lua_pushnumber(L, draw(L, &r));
		lua_rawseti(L, t, k);
	}
	lua_pushvalue(L, t);
	lua_remove(L, t);
	rng_done(L, &r);
	return 1;
}

/* A number field of the table at idx as a key to sort by. */
typedef struct keyed {
	double key;
	int slot; /* the table's index in the list being sorted */
} keyed;

static int by_key(const void *a, const void *b)
{
	double x = ((const keyed *)a)->key, y = ((const keyed *)b)->key;
	return (x > y) - (x < y);
}

/* Sorts the list at `list` by each element's field `field` (distinct
 * values: innovations, node ids), as table.sort does with a < on them. */
static void sort_list(lua_State *L, int list, enum key field)
{
	lua_Integer n = (lua_Integer)lua_rawlen(L, list);
	if (n < 2)
		return;
	keyed *k = lua_newuserdatauv(L, (size_t)n * sizeof *k, 0);
	int sorted = 1;
	for (lua_Integer i = 0; i < n; i++) {
		lua_rawgeti(L, list, i + 1);
		k[i].key = num_field(L, -1, field);
		k[i].slot = (int)i + 1;
		lua_pop(L, 1);
		if (i > 0 && k[i].key < k[i - 1].key)
			sorted = 0;
	}
	if (!sorted) {
		qsort(k, (size_t)n, sizeof *k, by_key);
		int base = lua_gettop(L);
		luaL_checkstack(L, (int)n, "sort: too long a list");
		for (lua_Integer i = 0; i < n; i++)
			lua_rawgeti(L, list, k[i].slot);
		for (lua_Integer i = n; i >= 1; i--)
			lua_rawseti(L, list, i);
		lua_settop(L, base);
	}
	lua_pop(L, 1);
}

/* Scratch memory for a kernel: one block per thread, grown as needed
 * and kept (still reachable, so never a leak), so a kernel that raises an
 * error leaks nothing. */
static void *scratch(lua_State *L, size_t bytes)
{
	static _Thread_local void *block;
	static _Thread_local size_t size;
	if (bytes > size) {
		size_t n = size ? size : 4096;
		while (n < bytes)
			n *= 2;
		void *b = realloc(block, n);
		if (!b)
			luaL_error(L, "evo.neat: out of memory");
		block = b;
		size = n;
	}
	return block;
}

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
static int l_rank(lua_State *L)
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

/* tally(genomes, score, species) -> least, most: each genome's fitness
 * set (genomes[i].fitness = score[i], checked as tell checks it), the
 * least of them, and for each species the most of its members'
 * (math.max from -math.huge, in member order): tell's first loops. */
static int l_tally(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	lua_settop(L, 3);
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
		lua_rawgeti(L, 3, k); /* 6 */
		luaL_checktype(L, 6, LUA_TTABLE);
		rget(L, 6, K_MEMBERS); /* 7 */
		luaL_checktype(L, 7, LUA_TTABLE);
		lua_pushnumber(L, -HUGE_VAL); /* 8: the most */
		lua_Integer m = (lua_Integer)lua_rawlen(L, 7);
		for (lua_Integer j = 1; j <= m; j++) {
			lua_rawgeti(L, 7, j);
			lua_rawgeti(L, 1, lua_tointeger(L, -1));
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
static int l_share(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checknumber(L, 3);
	lua_settop(L, 3);
	lua_Integer ns = (lua_Integer)lua_rawlen(L, 2);
	lua_createtable(L, ns > 0 && ns < INT_MAX ? (int)ns : 0, 0); /* 4 */
	for (lua_Integer k = 1; k <= ns; k++) {
		lua_rawgeti(L, 2, k); /* 5 */
		luaL_checktype(L, 5, LUA_TTABLE);
		rget(L, 5, K_MEMBERS); /* 6 */
		luaL_checktype(L, 6, LUA_TTABLE);
		lua_Integer m = (lua_Integer)lua_rawlen(L, 6);
		lua_pushinteger(L, 0); /* 7: the sum */
		for (lua_Integer j = 1; j <= m; j++) {
			lua_rawgeti(L, 6, j);
			lua_rawgeti(L, 1, lua_tointeger(L, -1)); /* 9 */
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
static int l_best_of(lua_State *L)
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
static int l_ranked(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	lua_settop(L, 3);
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
	rng_begin(L, 3, &src);
	for (lua_Integer i = 0; i < n; i++)
		r[i].key = draw(L, &src);
	rng_done(L, &src);
	lua_settop(L, 5);
	qsort(r, (size_t)n, sizeof *r, by_rank);
	lua_createtable(L, (int)n, 0);
	for (lua_Integer i = 0; i < n; i++) {
		lua_rawgeti(L, 5, r[i].index);
		lua_rawseti(L, -2, i + 1);
	}
	return 1;
}

/* The options crossover reads. */
typedef struct cross_opts {
	int tie_smaller;
	double mate_avg_prob, disable_prob;
} cross_opts;

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
	const genes *ag = genome_genes(L, a, 0);
	const genes *bg = genome_genes(L, b, 0);
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
	keyed *by = scratch(L, (size_t)nb * sizeof *by +
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
	genes *cg = new_genes(L, na);
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
		qsort(cg->g, (size_t)n, sizeof *cg->g, by_innov);
	/* the nodes are in id order unless b gave some (have[] holds
	 * their ids in list order) */
	in_order = 1;
	for (int i = 1; i < k && in_order; i++)
		in_order = have[i - 1] < have[i];
	if (!in_order)
		sort_list(L, nodes, K_ID);
	lua_pushvalue(L, child);
	lua_replace(L, top + 1);
	lua_settop(L, top + 1);
	return 1;
}

/* crossover(a, fa, b, fb, o, rng) -> child, as neat.crossover makes it,
 * or nothing when the parents are of equal fitness and o.tie_smaller is
 * off (push_child). */
static int l_crossover(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	luaL_checktype(L, 5, LUA_TTABLE);
	luaL_checktype(L, 6, LUA_TTABLE);
	lua_settop(L, 6);
	cross_opts co = cross_opts_of(L, 5);
	rng_src r;
	rng_begin(L, 6, &r); /* may push rng.s */
	if (!push_child(L, 1, 2, 3, 4, &co, &r))
		return 0;
	rng_done(L, &r);
	return 1;
}

/* ------------------------------------------------------------------ */
/* Structural mutations (neat.lua's mutate_add_link and mutate_add_node,
 * draw for draw, with the population's innovation registry) */

/* What the structural mutations read of the options, once. */
typedef struct struct_opts {
	int recurrent, split_bias, split_older;
	double recur_only_prob, new_link_power;
	lua_Integer add_link_tries;
	double max; /* weight_max */
	int max_int;
} struct_opts;

static struct_opts struct_opts_of(lua_State *L, int o)
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
			   KEY_NAMES[key], luaL_typename(L, -1));
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
			   KEY_NAMES[key]);
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

/* A genome's nodes read: ids and kinds ('i' input, 'b' bias, 'o'
 * output, 'h' hidden, '?' other), in a userdata left on the stack. */
typedef struct node_list {
	int n;
	lua_Integer *id;
	char *kind;
} node_list;

static node_list read_node_list(lua_State *L, int nodes)
{
	node_list nl;
	nl.n = (int)lua_rawlen(L, nodes);
	nl.id = lua_newuserdatauv(L, (size_t)(nl.n + 1) * (sizeof *nl.id + 1),
				  0);
	nl.kind = (char *)(nl.id + nl.n + 1);
	for (int k = 0; k < nl.n; k++) {
		lua_rawgeti(L, nodes, k + 1);
		luaL_checktype(L, -1, LUA_TTABLE);
		rget(L, -1, K_ID);
		nl.id[k] = gene_int(L, -1, "node id");
		rget(L, -2, K_KIND);
		nl.kind[k] = is_key(L, -1, K_INPUT)    ? 'i'
			     : is_key(L, -1, K_BIAS)   ? 'b'
			     : is_key(L, -1, K_OUTPUT) ? 'o'
			     : is_key(L, -1, K_HIDDEN) ? 'h'
						       : '?';
		lua_pop(L, 3);
	}
	return nl;
}

/* Genome g's genes with `extra` more genes (given) added, sorted by
 * innovation, as g.links: a new block, as add_gene and sort_genes make it. */
static genes *add_genes(lua_State *L, int g, const gene *extra, int extra_n)
{
	int top = lua_gettop(L);
	genes *old = genome_genes(L, g, 1);
	genes *gs = new_genes(L, old->n + extra_n);
	memcpy(gs->g, old->g, (size_t)old->n * sizeof *gs->g);
	memcpy(gs->g + old->n, extra, (size_t)extra_n * sizeof *extra);
	int sorted = 1;
	for (int i = 1; i < gs->n && sorted; i++)
		sorted = gs->g[i - 1].innov < gs->g[i].innov;
	if (!sorted)
		qsort(gs->g, (size_t)gs->n, sizeof *gs->g, by_innov);
	rset(L, g, K_LINKS);
	lua_settop(L, top);
	return gs;
}

static lua_Integer pick(double u, lua_Integer n);

/* neat.lua's mutate_add_link on genome g of population pop (stack slots):
 * a link between two unlinked nodes, one that keeps the genome acyclic
 * unless `recurrent`; with recurrent and recur_only_prob, one that closes
 * a cycle with that chance and one that does not otherwise. Pushes the new
 * gene as a gene table, or nil when add_link_tries pairs gave none. */
static void add_link(lua_State *L, int pop, int g, const struct_opts *t,
		     rng_src *r)
{
	int top = lua_gettop(L);
	rget(L, g, K_NODES);
	luaL_checktype(L, -1, LUA_TTABLE);
	int nodes = lua_gettop(L);
	node_list nl = read_node_list(L, nodes);
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
		const genes *gs = genome_genes(L, g, 1);
		lua_Integer from = nl.id[a], to = nl.id[b];
		int exists = 0;
		for (int i = 0; i < gs->n && !exists; i++)
			exists = gs->g[i].from == from && gs->g[i].to == to;
		int ok = 1;
		if (!t->recurrent)
			ok = !genes_reach(L, gs, to, from);
		else if (graded)
			ok = genes_reach(L, gs, to, from) == recur;
		if (exists || !ok)
			continue;
		gene x = {link_innovation(L, pop, from, to), from, to, 0, 0, 1};
		set_clamped(&x, (draw(L, r) * 2 - 1) * t->new_link_power,
			    t->max, t->max_int);
		add_genes(L, g, &x, 1);
		sort_list(L, nodes, K_ID);
		lua_settop(L, top);
		push_gene_table(L, &x);
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
static void add_node(lua_State *L, int pop, int g, const struct_opts *t,
		     rng_src *r)
{
	int top = lua_gettop(L);
	rget(L, g, K_NODES);
	luaL_checktype(L, -1, LUA_TTABLE);
	int nodes = lua_gettop(L);
	node_list nl = read_node_list(L, nodes);
	int has_bias = 0;
	lua_Integer bias_id = 0;
	for (int k = 0; k < nl.n && !t->split_bias && !has_bias; k++)
		if (nl.kind[k] == 'b') {
			has_bias = 1;
			bias_id = nl.id[k];
		}
	genes *gs = genome_genes(L, g, 1);
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
	sort_list(L, nodes, K_ID);
	lua_settop(L, top);
	lua_pushinteger(L, s[0]);
}

/* add_link(pop, g, rng) -> the new gene, or nil: add_link. */
static int l_add_link(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	lua_settop(L, 3);
	rget(L, 1, K_OPTIONS); /* 4 */
	luaL_checktype(L, 4, LUA_TTABLE);
	struct_opts t = struct_opts_of(L, 4);
	rng_src r;
	rng_begin(L, 3, &r);
	add_link(L, 1, 2, &t, &r);
	rng_done(L, &r);
	return 1;
}

/* add_node(pop, g, rng) -> the new node's id, or nil: add_node. */
static int l_add_node(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	lua_settop(L, 3);
	rget(L, 1, K_OPTIONS); /* 4 */
	luaL_checktype(L, 4, LUA_TTABLE);
	struct_opts t = struct_opts_of(L, 4);
	rng_src r;
	rng_begin(L, 3, &r);
	add_node(L, 1, 2, &t, &r);
	rng_done(L, &r);
	return 1;
}

/* Sets field `key` of the table at t to integer v. */
static void set_int(lua_State *L, int t, enum key key, lua_Integer v)
{
	t = lua_absindex(L, t);
	lua_pushinteger(L, v);
	rset(L, t, key);
}

/* to_net(genome) -> the table neat.to_net gives: { inputs, outputs, nodes
 * = { {id, act, bias}, ... }, outputs_ids, links = { {from, to, weight},
 * ... } }, its ids and biases pack_net's (the same map, the same sums in
 * the same order), each node's act the genome's string, each weight as
 * the gene holds it. */
static int l_to_net(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_settop(L, 1);
	rget(L, 1, K_NODES); /* 2 */
	luaL_checktype(L, 2, LUA_TTABLE);
	const genes *gs = genome_genes(L, 1, 0); /* 3 */
	node_list nl = read_node_list(L, 2); /* 4 */
	int n_in = 0, n_out = 0, n_map = 0, has_bias = 0;
	lua_Integer bias_id = 0;
	double bias_value = 1.0;
	for (int k = 0; k < nl.n; k++) {
		n_in += nl.kind[k] == 'i';
		n_out += nl.kind[k] == 'o';
		if (nl.kind[k] == 'b') { /* the last bias node counts */
			has_bias = 1;
			bias_id = nl.id[k];
			lua_rawgeti(L, 2, k + 1);
			bias_value = rget(L, -1, K_VALUE) == LUA_TNIL
					 ? 1.0
					 : lua_tonumber(L, -1);
			lua_pop(L, 2);
		}
	}
	/* the genome's ids to the network's, and each node's bias */
	id_map *map = lua_newuserdatauv(L, (size_t)(nl.n + 1) *
					       (sizeof *map + sizeof(double)),
					0); /* 5 */
	double *bias = (double *)(void *)(map + nl.n + 1);
	lua_createtable(L, 0, 5); /* 6: the network */
	int net = 6;
	set_int(L, net, K_INPUTS, n_in);
	set_int(L, net, K_OUTPUTS, n_out);
	lua_createtable(L, nl.n, 0); /* 7: nodes */
	lua_createtable(L, n_out, 0); /* 8: outputs_ids */
	int next = n_in, n_nodes = 0, n_outs = 0;
	for (int pass = 0; pass < 3; pass++)
		for (int k = 0; k < nl.n; k++) {
			char want = pass == 0 ? 'i' : pass == 1 ? 'o' : 'h';
			if (nl.kind[k] != want)
				continue;
			if (pass == 0) {
				map[n_map++] = (id_map){nl.id[k],
							(uint16_t)nl.id[k]};
				continue;
			}
			if (next > UINT16_MAX)
				luaL_error(L, "to_net: too many nodes");
			map[n_map++] = (id_map){nl.id[k], (uint16_t)next};
			bias[next - n_in] = 0.0;
			lua_createtable(L, 0, 3);
			set_int(L, -1, K_ID, next);
			lua_rawgeti(L, 2, k + 1);
			rget(L, -1, K_ACT);
			lua_remove(L, -2);
			rset(L, -2, K_ACT);
			lua_rawseti(L, 7, ++n_nodes);
			if (pass == 1) {
				lua_pushinteger(L, next);
				lua_rawseti(L, 8, ++n_outs);
			}
			next++;
		}
	qsort(map, (size_t)n_map, sizeof *map, by_id);
	lua_createtable(L, gs->n, 0); /* 9: links */
	int n_links = 0;
	for (int i = 0; i < gs->n; i++) {
		const gene *x = &gs->g[i];
		if (!x->enabled)
			continue;
		int t = map_id(map, n_map, x->to);
		if (t < n_in)
			luaL_error(L, "to_net: link %d ends at node %I, which is "
				      "no output or hidden node of the genome",
				   i + 1, (LUAI_UACINT)x->to);
		if (has_bias && x->from == bias_id) {
			bias[t - n_in] += x->weight * bias_value;
			continue;
		}
		int f = map_id(map, n_map, x->from);
		if (f < 0)
			luaL_error(L, "to_net: link %d starts at node %I, which "
				      "the genome does not have",
				   i + 1, (LUAI_UACINT)x->from);
		lua_createtable(L, 0, 3);
		set_int(L, -1, K_FROM, f);
		set_int(L, -1, K_TO, t);
		push_gene_field(L, x, K_WEIGHT);
		rset(L, -2, K_WEIGHT);
		lua_rawseti(L, 9, ++n_links);
	}
	for (int k = 1; k <= n_nodes; k++) {
		lua_rawgeti(L, 7, k);
		lua_pushnumber(L, bias[k - 1]);
		rset(L, -2, K_BIAS);
		lua_pop(L, 1);
	}
	lua_pushvalue(L, 7);
	rset(L, net, K_NODES);
	lua_pushvalue(L, 8);
	rset(L, net, K_OUTPUTS_IDS);
	lua_pushvalue(L, 9);
	rset(L, net, K_LINKS);
	lua_settop(L, net);
	return 1;
}

/* ------------------------------------------------------------------ */
/* A species' offspring (neat.lua's breed_lua, draw for draw) */

/* What breed reads of the options, once for all its children. */
typedef struct breed_opts {
	double mutate_only, interspecies, mate_only;
	double add_node, add_link, weight_mut, toggle, reenable;
	wm_opts wm;
	cross_opts co;
	dist_opts dist;
	struct_opts st;
} breed_opts;

static breed_opts breed_opts_of(lua_State *L, int o)
{
	breed_opts b;
	b.st = struct_opts_of(L, o);
	b.mutate_only = num_field(L, o, K_MUTATE_ONLY_PROB);
	b.interspecies = num_field(L, o, K_INTERSPECIES_PROB);
	b.mate_only = num_field(L, o, K_MATE_ONLY_PROB);
	b.add_node = num_field(L, o, K_ADD_NODE_PROB);
	b.add_link = num_field(L, o, K_ADD_LINK_PROB);
	b.weight_mut = num_field(L, o, K_WEIGHT_MUT_PROB);
	b.toggle = num_field(L, o, K_TOGGLE_PROB);
	b.reenable = num_field(L, o, K_REENABLE_PROB);
	b.wm = wm_opts_of(L, o);
	b.co = cross_opts_of(L, o);
	b.dist = dist_opts_of(L, o);
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
	if (draw(L, r) < b->add_node) {
		add_node(L, pop, g, &b->st, r);
	} else if (draw(L, r) < b->add_link) {
		add_link(L, pop, g, &b->st, r);
	} else {
		if (draw(L, r) < b->weight_mut)
			mutate_genes(L, genome_genes(L, g, 1), &b->wm, r);
		if (b->toggle > 0 || b->reenable > 0) {
			rng_done(L, r);
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

/* 1 + floor(u * n): a place in a list of n drawn as neat.lua draws it. */
static lua_Integer pick(double u, lua_Integer n)
{
	return 1 + (lua_Integer)floor(u * (double)n);
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
static int l_breed(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	lua_Integer n = luaL_checkinteger(L, 4);
	lua_Integer parents = luaL_checkinteger(L, 5);
	luaL_checktype(L, 6, LUA_TTABLE);
	luaL_checktype(L, 7, LUA_TTABLE);
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
	rng_begin(L, 10, &r); /* may push rng.s */
	int base = lua_gettop(L);
	lua_Integer next = (lua_Integer)lua_rawlen(L, 2);
	for (lua_Integer k = 0; k < n; k++) {
		lua_settop(L, base);
		lua_rawgeti(L, 3, pick(draw(L, &r), parents));
		int p1 = base + 1;
		luaL_checktype(L, p1, LUA_TTABLE);
		int child;
		if (parents == 1 || draw(L, &r) < b.mutate_only) {
			push_copy(L, p1);
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
				const genes *ga = genome_genes(L, p1, 0);
				const genes *gb = genome_genes(L, p2, 0);
				mutate = distance_of(ga, gb, &b.dist) == 0;
				lua_settop(L, child);
			}
			if (mutate)
				breed_mutate(L, child, &b, &r, 1, 8);
		}
		lua_pushvalue(L, child);
		lua_rawseti(L, 2, ++next);
	}
	lua_settop(L, base);
	rng_done(L, &r);
	return 0;
}

/* ------------------------------------------------------------------ */

static const luaL_Reg FUNCS[] = {
    {"rng_next", l_rng_next},
    {"rng_unit", l_rng_unit},
    {"rng_normal", l_rng_normal},
    {"isoline", l_isoline},
    {"mutate_weights", l_mutate_weights},
    {"mutate", l_mutate},
    {"draws", l_draws},
    {"crossover", l_crossover},
    {"breed", l_breed},
    {"add_link", l_add_link},
    {"add_node", l_add_node},
    {"rank", l_rank},
    {"ranked", l_ranked},
    {"tally", l_tally},
    {"share", l_share},
    {"best_of", l_best_of},
    {"assign", l_assign},
    {"distance", l_distance},
    {"speciate", l_speciate},
    {"copy_genome", l_copy_genome},
    {"pack_net", l_pack_net},
    {"to_net", l_to_net},
    {"genes", l_genes},
    {"add_gene", l_add_gene},
    {"sort_genes", l_sort_genes},
    {"reaches", l_reaches},
    {"dump", l_dump},
    {NULL, NULL},
};

/* The kernels' upvalues: the keys, then the genes' metatable (at mt). */
static void push_upvalues(lua_State *L, int mt)
{
	luaL_checkstack(L, N_UPVALUES, "evo.neat's upvalues");
	for (int k = 1; k < K_COUNT; k++)
		lua_pushstring(L, KEY_NAMES[k]);
	lua_pushvalue(L, mt);
}

static int open_neat(lua_State *L)
{
	if (luaL_newmetatable(L, BUF_TYPE)) {
		lua_pushcfunction(L, free_buffer);
		lua_setfield(L, -2, "__gc");
	}
	lua_pop(L, 1);
	luaL_newmetatable(L, NET_TYPE);
	lua_pop(L, 1);
	/* the genes' and a gene's metatables and the module's functions,
	 * each with the keys and the genes' metatable as upvalues */
	luaL_newmetatable(L, GENE_TYPE);
	lua_pop(L, 1);
	luaL_newmetatable(L, GENES_TYPE);
	int genes_mt = lua_gettop(L);
	const char *types[2] = {GENE_TYPE, GENES_TYPE};
	const luaL_Reg *regs[2] = {GENE_METHODS, GENES_METHODS};
	for (int m = 0; m < 2; m++) {
		luaL_getmetatable(L, types[m]);
		push_upvalues(L, genes_mt);
		luaL_setfuncs(L, regs[m], N_UPVALUES);
		lua_pop(L, 1);
	}
	luaL_newlibtable(L, FUNCS);
	push_upvalues(L, genes_mt);
	luaL_setfuncs(L, FUNCS, N_UPVALUES);
	lua_remove(L, genes_mt);
	return 1;
}

void evo_lua_open_neat(lua_State *L)
{
	luaL_requiref(L, "evo.neat", open_neat, 0);
	lua_pop(L, 1);
}

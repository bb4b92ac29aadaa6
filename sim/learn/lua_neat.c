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
 *   rng_next(r), rng_unit(r)  learn.rng's Rng:next and Rng:unit, on the
 *                      generator's own four words (r.s)
 *   mutate_weights(g, o, rng), crossover(a, fa, b, fb, o, rng)
 *                      neat.lua's, with the same random draws in the
 *                      same order
 *   rank(members, keys) the order tell sorts a species' members into
 *
 * A genome is { nodes = { {id, kind, act, value}, ... }, links = { {innov,
 * from, to, weight, enabled}, ... } }, links sorted by innovation. Genes
 * change in place (weights, enabled); nodes never do once made, so
 * copies and children share them. Field names are looked up through the
 * module's upvalues (enum key): lua_getfield would intern its C string on
 * every call, which cost as much as the kernels' own work. */
#include "learn/lua_neat.h"

#include <ctype.h>
#include <lauxlib.h>
#include <lua.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
	K_CODE, K_ADD_NODE_PROB, K_ADD_LINK_PROB, K_WEIGHT_MUT_PROB, K_COUNT
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
/* Compatibility distance */

/* Field `key` of the table at idx as a number; 0 when it is none. */
static double num_field(lua_State *L, int idx, enum key key)
{
	rget(L, idx, key);
	double v = lua_tonumber(L, -1);
	lua_pop(L, 1);
	return v;
}

/* A genome's genes as the distance reads them: innovations and weights
 * in list order. */
typedef struct genes {
	const double *innov, *weight;
	lua_Integer n;
} genes;

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
		double xi = a->innov[i], yi = b->innov[j];
		if (xi == yi) {
			matching++;
			double d = a->weight[i] - b->weight[j];
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

/* The number of genes of genome `g` (a stack slot). */
static lua_Integer gene_count(lua_State *L, int g)
{
	rget(L, g, K_LINKS);
	luaL_checktype(L, -1, LUA_TTABLE);
	lua_Integer n = (lua_Integer)lua_rawlen(L, -1);
	lua_pop(L, 1);
	return n;
}

/* Genome g's genes into innov[] and weight[] (room for gene_count). */
static void read_genes(lua_State *L, int g, double *innov, double *weight,
		       genes *out)
{
	rget(L, g, K_LINKS);
	int list = lua_gettop(L);
	lua_Integer n = (lua_Integer)lua_rawlen(L, list);
	for (lua_Integer i = 0; i < n; i++) {
		lua_rawgeti(L, list, i + 1);
		innov[i] = num_field(L, -1, K_INNOV);
		weight[i] = num_field(L, -1, K_WEIGHT);
		lua_pop(L, 1);
	}
	lua_pop(L, 1);
	out->innov = innov;
	out->weight = weight;
	out->n = n;
}

static void *scratch(lua_State *L, size_t bytes);

/* distance(a, b, o): NEAT's compatibility distance (distance_of). */
static int l_distance(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	lua_Integer na = gene_count(L, 1), nb = gene_count(L, 2);
	double *buf = scratch(L, 2 * (size_t)(na + nb) * sizeof *buf);
	genes a, b;
	read_genes(L, 1, buf, buf + na, &a);
	read_genes(L, 2, buf + 2 * na, buf + 2 * na + nb, &b);
	dist_opts o = dist_opts_of(L, 3);
	lua_pushnumber(L, distance_of(&a, &b, &o));
	return 1;
}

/* speciate(genomes, reps, o, threshold) -> home: home[i] is the species
 * of genome i, as neat.lua's speciate assigns them: the first species
 * whose representative (reps[k], k in order) is within distance
 * `threshold` (distance(genome, rep) < threshold), else a new species
 * numbered #reps + 1, #reps + 2, ... in the order they are opened, whose
 * representative is that genome. */
static int l_speciate(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	double threshold = luaL_checknumber(L, 4);
	dist_opts o = dist_opts_of(L, 3);
	int ng = (int)lua_rawlen(L, 1), nr = (int)lua_rawlen(L, 2);
	size_t total = 0;
	for (int k = 1; k <= nr; k++) {
		lua_rawgeti(L, 2, k);
		total += (size_t)gene_count(L, lua_gettop(L));
		lua_pop(L, 1);
	}
	for (int k = 1; k <= ng; k++) {
		lua_rawgeti(L, 1, k);
		total += (size_t)gene_count(L, lua_gettop(L));
		lua_pop(L, 1);
	}
	/* genes of every rep and genome, then each one's genes, then the
	 * reps' indices into them (the old ones and the new) */
	size_t bytes = 2 * total * sizeof(double) +
		       (size_t)(nr + ng) * sizeof(genes) +
		       (size_t)(nr + ng) * sizeof(int);
	double *buf = scratch(L, bytes);
	genes *all = (genes *)(void *)(buf + 2 * total);
	int *rep = (int *)(void *)(all + nr + ng);
	size_t at = 0;
	for (int k = 0; k < nr + ng; k++) {
		lua_rawgeti(L, k < nr ? 2 : 1, k < nr ? k + 1 : k - nr + 1);
		int g = lua_gettop(L);
		lua_Integer n = gene_count(L, g);
		read_genes(L, g, buf + at, buf + at + (size_t)n, &all[k]);
		at += 2 * (size_t)n;
		lua_pop(L, 1);
	}
	int n_rep = nr;
	for (int k = 0; k < nr; k++)
		rep[k] = k;
	lua_createtable(L, ng, 0);
	for (int i = 0; i < ng; i++) {
		const genes *g = &all[nr + i];
		int home = 0;
		while (home < n_rep && !(distance_of(g, &all[rep[home]], &o) <
					 threshold))
			home++;
		if (home == n_rep)
			rep[n_rep++] = nr + i;
		lua_pushinteger(L, home + 1);
		lua_rawseti(L, -2, i + 1);
	}
	return 1;
}

/* copy_genome(g) -> a copy of g's nodes and genes (neat.copy_genome). */
static void push_gene_copy(lua_State *L);

/* Gene lists are copied gene by gene (genes change: weights, enabled);
 * node lists hold the same node tables (a node never changes once made:
 * mutations add nodes to a genome's own list). */
static void share_node(lua_State *L)
{
	lua_pushvalue(L, -1);
}

static void copy_list(lua_State *L, int g, int copy, enum key list,
		      void (*push_copy)(lua_State *L))
{
	rget(L, g, list);
	int src = lua_gettop(L);
	luaL_checktype(L, src, LUA_TTABLE);
	lua_createtable(L, (int)lua_rawlen(L, src), 0);
	int dst = src + 1;
	for (lua_Integer i = 1; lua_rawgeti(L, src, i) != LUA_TNIL; i++) {
		push_copy(L);
		lua_rawseti(L, dst, i);
		lua_pop(L, 1);
	}
	lua_pop(L, 1);
	rset(L, copy, list);
	lua_pop(L, 1);
}

static int l_copy_genome(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	lua_settop(L, 1);
	lua_createtable(L, 0, 2);
	copy_list(L, 1, 2, K_NODES, share_node);
	copy_list(L, 1, 2, K_LINKS, push_gene_copy);
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
	rget(L, 1, K_NODES);
	rget(L, 1, K_LINKS);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	static _Thread_local genome_nodes g;
	read_nodes(L, 2, &g);
	if (g.n_out > EVO_MAX_SKILL_IO)
		luaL_error(L, "pack_net: %d outputs", g.n_out);
	lua_Integer n_links = (lua_Integer)lua_rawlen(L, 3);
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
		lua_rawgeti(L, 3, i);
		rget(L, -1, K_ENABLED);
		int enabled = lua_toboolean(L, -1);
		lua_pop(L, 1);
		if (enabled) {
			lua_Integer from = (lua_Integer)num_field(L, -1, K_FROM);
			lua_Integer to = (lua_Integer)num_field(L, -1, K_TO);
			double w = num_field(L, -1, K_WEIGHT);
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
		lua_pop(L, 1);
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

typedef struct buffer {
	char *b;
	size_t len, cap;
} buffer;

static int free_buffer(lua_State *L)
{
	buffer *b = luaL_checkudata(L, 1, BUF_TYPE);
	free(b->b);
	b->b = NULL;
	return 0;
}

static void put(lua_State *L, buffer *b, const char *s, size_t n)
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
		snprintf(s, sizeof s, "%.17g", x);
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
	default:
		luaL_error(L, "serialize: cannot save a %s",
			   luaL_typename(L, idx));
	}
	if (depth >= DUMP_MAX_DEPTH)
		luaL_error(L, "serialize: tables nested more than %d deep",
			   DUMP_MAX_DEPTH);
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
	free(b->b);
	b->b = NULL;
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
	for (int k = 0; k < 4; k++) {
		lua_rawgeti(L, -1, k + 1);
		s[k] = (uint64_t)lua_tointeger(L, -1);
		lua_pop(L, 1);
	}
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

/* clamp(w, m) as neat.lua's, m the value at stack slot `max` (the
 * option weight_max): m itself above it, -m below -m (an integer m stays
 * one), else w; pushed. */
static void push_clamped(lua_State *L, double w, int max)
{
	double m = lua_tonumber(L, max);
	if (w > m) {
		lua_pushvalue(L, max); /* the value of weight_max, as it is */
	} else if (w < -m) {
		if (lua_isinteger(L, max))
			lua_pushinteger(L, (lua_Integer)(0u - (lua_Unsigned)
							     lua_tointeger(L, max)));
		else
			lua_pushnumber(L, -m);
	} else {
		lua_pushnumber(L, w);
	}
}

/* neat.lua's mutate_weights ("code" and "paper") on genome g with options
 * o (stack slots), drawing from r: the same draws in the same order. */
static void mutate_weights_with(lua_State *L, int g, int o, rng_src *r)
{
	int top = lua_gettop(L);
	rget(L, g, K_LINKS);
	int links = top + 1;
	luaL_checktype(L, links, LUA_TTABLE);
	rget(L, o, K_WEIGHT_MAX);
	int max = top + 2;
	lua_Integer n = (lua_Integer)lua_rawlen(L, links);
	double perturb = num_field(L, o, K_PERTURB_PROB), replace = 1.0;
	double newest_after = HUGE_VAL;
	rget(L, o, K_WEIGHT_MUTATION);
	int code = is_key(L, -1, K_CODE);
	lua_pop(L, 1);
	if (code) {
		int severe = draw(L, r) < num_field(L, o, K_SEVERE_PROB);
		perturb = severe ? 0.7 : 1.0;
		replace = severe ? 0.9 : 1.0;
		if (!severe && n >= 10)
			newest_after = (double)n * 0.8;
	}
	double pp = num_field(L, o, K_PERTURB_POWER);
	double rp = num_field(L, o, K_REPLACE_POWER);
	for (lua_Integer k = 1; k <= n; k++) {
		if (lua_rawgeti(L, links, k) == LUA_TNIL)
			break; /* ipairs stops there */
		double p = perturb, rr = replace;
		if ((double)(k - 1) > newest_after) {
			p = 0.5;
			rr = 0.7;
		}
		double u = draw(L, r);
		if (u < p) {
			double w = num_field(L, -1, K_WEIGHT);
			push_clamped(L, w + (draw(L, r) * 2 - 1) * pp, max);
			rset(L, -2, K_WEIGHT);
		} else if (u < rr) {
			push_clamped(L, (draw(L, r) * 2 - 1) * rp, max);
			rset(L, -2, K_WEIGHT);
		}
		lua_pop(L, 1);
	}
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

/* A copy of the gene at the top of the stack, pushed. */
static void push_gene_copy(lua_State *L)
{
	int src = lua_gettop(L), dst = src + 1;
	lua_createtable(L, 0, 5);
	/* the fields in rget/rset's order, four calls each instead of their
	 * eight: a copy is made for every gene of every child */
	for (int f = K_INNOV; f <= K_ENABLED; f++) {
		lua_pushvalue(L, lua_upvalueindex(f));
		lua_pushvalue(L, -1);
		lua_rawget(L, src);
		lua_rawset(L, dst);
	}
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

/* crossover(a, fa, b, fb, o, rng) -> child, as neat.crossover makes it,
 * or nothing when the parents are of equal fitness and o.tie_smaller is
 * off (the paper's way, which neat.crossover keeps in Lua). */
static int l_crossover(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	luaL_checktype(L, 5, LUA_TTABLE);
	luaL_checktype(L, 6, LUA_TTABLE);
	lua_settop(L, 6);
	int a = 1, b = 3;
	if (lua_compare(L, 2, 4, LUA_OPLT)) { /* fb > fa */
		a = 3;
		b = 1;
	}
	int equal = lua_compare(L, 2, 4, LUA_OPEQ);
	rget(L, 5, K_TIE_SMALLER);
	int tie_smaller = lua_toboolean(L, -1);
	lua_pop(L, 1);
	if (equal && !tie_smaller)
		return 0;
	rget(L, a, K_LINKS); /* 7 */
	rget(L, b, K_LINKS); /* 8 */
	luaL_checktype(L, 7, LUA_TTABLE);
	luaL_checktype(L, 8, LUA_TTABLE);
	if (equal && lua_rawlen(L, 8) < lua_rawlen(L, 7)) {
		int t = a;
		a = b;
		b = t;
		lua_rotate(L, 7, 1); /* swap 7 and 8 */
	}
	const int al = 7, bl = 8;
	rng_src r;
	rng_begin(L, 6, &r); /* may push rng.s: 9 */
	double average = draw(L, &r) < num_field(L, 5, K_MATE_AVG_PROB);
	double disable = num_field(L, 5, K_DISABLE_PROB);
	int na = (int)lua_rawlen(L, al), nb = (int)lua_rawlen(L, bl);
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
		lua_rawgeti(L, bl, i + 1);
		by[i].key = num_field(L, -1, K_INNOV);
		by[i].slot = i + 1;
		lua_pop(L, 1);
		if (i > 0 && !(by[i].key > by[i - 1].key))
			sorted = 0;
	}
	if (!sorted)
		qsort(by, (size_t)nb, sizeof *by, by_key_slot);
	/* the child and its links */
	lua_createtable(L, 0, 2);
	int child = lua_gettop(L);
	lua_createtable(L, na, 0);
	int links = lua_gettop(L);
	lua_pushvalue(L, links);
	rset(L, child, K_LINKS);
	int n = 0;
	for (int i = 1; i <= na; i++) {
		lua_rawgeti(L, al, i);
		int l = lua_gettop(L);
		int slot = gene_with(by, nb, num_field(L, l, K_INNOV));
		if (slot) {
			lua_rawgeti(L, bl, slot);
			int m = l + 1;
			int pick = draw(L, &r) < 0.5 ? l : m;
			rget(L, l, K_ENABLED);
			rget(L, m, K_ENABLED);
			int somewhere =
			    !lua_toboolean(L, -2) || !lua_toboolean(L, -1);
			lua_pop(L, 2);
			lua_pushvalue(L, pick);
			push_gene_copy(L);
			if (somewhere) {
				lua_pushboolean(L, draw(L, &r) >= disable);
				rset(L, -2, K_ENABLED);
			}
			if (average) {
				double wl = num_field(L, l, K_WEIGHT);
				double wm = num_field(L, m, K_WEIGHT);
				lua_pushnumber(L, (wl + wm) / 2);
				rset(L, -2, K_WEIGHT);
			}
		} else {
			lua_pushvalue(L, l);
			push_gene_copy(L);
		}
		rget(L, -1, K_FROM);
		ends[2 * n] = eq_number(L, -1);
		rget(L, -2, K_TO);
		ends[2 * n + 1] = eq_number(L, -1);
		lua_pop(L, 2);
		lua_rawseti(L, links, ++n);
		lua_settop(L, links);
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
	sort_list(L, links, K_INNOV);
	sort_list(L, nodes, K_ID);
	rng_done(L, &r);
	lua_pushvalue(L, child);
	return 1;
}

/* ------------------------------------------------------------------ */

static const luaL_Reg FUNCS[] = {
    {"rng_next", l_rng_next},
    {"rng_unit", l_rng_unit},
    {"mutate_weights", l_mutate_weights},
    {"mutate", l_mutate},
    {"draws", l_draws},
    {"crossover", l_crossover},
    {"rank", l_rank},
    {"distance", l_distance},
    {"speciate", l_speciate},
    {"copy_genome", l_copy_genome},
    {"pack_net", l_pack_net},
    {"dump", l_dump},
    {NULL, NULL},
};

static int open_neat(lua_State *L)
{
	if (luaL_newmetatable(L, BUF_TYPE)) {
		lua_pushcfunction(L, free_buffer);
		lua_setfield(L, -2, "__gc");
	}
	lua_pop(L, 1);
	luaL_newmetatable(L, NET_TYPE);
	lua_pop(L, 1);
	luaL_newlibtable(L, FUNCS);
	for (int k = 1; k < K_COUNT; k++)
		lua_pushstring(L, KEY_NAMES[k]);
	luaL_setfuncs(L, FUNCS, K_COUNT - 1);
	return 1;
}

void evo_lua_open_neat(lua_State *L)
{
	luaL_requiref(L, "evo.neat", open_neat, 0);
	lua_pop(L, 1);
}

/* evo.neat: the learning loop's hot kernels in C, for the loop's Lua state
 * (sim/learn/learn.c) and the Lua tests' (tests/sim/lua/test_lua_scripts.c).
 * The loop stays in Lua; what it did in the interpreter on every genome of
 * every generation is done here, with the same arithmetic in the same
 * order, so a run gives the same numbers bit for bit:
 *
 *   distance(a, b, o)  NEAT's compatibility distance of two genomes
 *                      (lua/learn/neat.lua's neat.distance_lua)
 *   pack_net(g)        a genome as the network evo.evaluate runs, packed
 *                      in a userdata (neat.to_net and learn.c's reading
 *                      of its table, in one step)
 *   dump(v)            plain Lua data as text (serialize.dump_lua's
 *                      text, byte for byte), for the checkpoints
 *
 * A genome is { nodes = { {id, kind, act, value}, ... }, links = { {innov,
 * from, to, weight, enabled}, ... } }, links sorted by innovation. */
#include "learn/lua_neat.h"

#include <ctype.h>
#include <lauxlib.h>
#include <lua.h>
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

/* ------------------------------------------------------------------ */
/* Compatibility distance */

/* Field `key` of the table at idx as a number; 0 when it is none. */
static double num_field(lua_State *L, int idx, const char *key)
{
	lua_getfield(L, idx, key);
	double v = lua_tonumber(L, -1);
	lua_pop(L, 1);
	return v;
}

/* Innovation and weight of gene i of the link list at `list`. */
static void gene_at(lua_State *L, int list, lua_Integer i, double *innov,
		    double *weight)
{
	lua_rawgeti(L, list, i);
	*innov = num_field(L, -1, "innov");
	*weight = num_field(L, -1, "weight");
	lua_pop(L, 1);
}

/* distance(a, b, o) = c1*E/N + c2*D/N + c3*W: E excess and D disjoint
 * genes, W the mean weight difference of the matching ones, N the larger
 * genome's gene count (1 when both have fewer than o.normalize_below). */
static int l_distance(lua_State *L)
{
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	luaL_checktype(L, 3, LUA_TTABLE);
	lua_getfield(L, 1, "links");
	lua_getfield(L, 2, "links");
	luaL_checktype(L, 4, LUA_TTABLE);
	luaL_checktype(L, 5, LUA_TTABLE);
	lua_Integer na = (lua_Integer)lua_rawlen(L, 4);
	lua_Integer nb = (lua_Integer)lua_rawlen(L, 5);
	lua_Integer i = 1, j = 1, matching = 0, disjoint = 0;
	double wdiff = 0.0, xi = 0, xw = 0, yi = 0, yw = 0;
	if (na >= 1)
		gene_at(L, 4, 1, &xi, &xw);
	if (nb >= 1)
		gene_at(L, 5, 1, &yi, &yw);
	while (i <= na && j <= nb) {
		int step_a = 0, step_b = 0;
		if (xi == yi) {
			matching++;
			double d = xw - yw;
			wdiff += d < 0 ? -d : d;
			step_a = step_b = 1;
		} else if (xi < yi) {
			disjoint++;
			step_a = 1;
		} else {
			disjoint++;
			step_b = 1;
		}
		if (step_a && ++i <= na)
			gene_at(L, 4, i, &xi, &xw);
		if (step_b && ++j <= nb)
			gene_at(L, 5, j, &yi, &yw);
	}
	lua_Integer excess = (na - i + 1) + (nb - j + 1);
	lua_Integer n = na > nb ? na : nb;
	if ((double)n < num_field(L, 3, "normalize_below"))
		n = 1;
	double w = matching > 0 ? wdiff / (double)matching : 0.0;
	double c1 = num_field(L, 3, "c1"), c2 = num_field(L, 3, "c2"),
	       c3 = num_field(L, 3, "c3");
	lua_pushnumber(L, c1 * (double)excess / (double)n +
			      c2 * (double)disjoint / (double)n + c3 * w);
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

static unsigned act_of(lua_State *L, const char *act)
{
	unsigned a = 0;
	while (act && evo_act_name(a) && strcmp(evo_act_name(a), act))
		a++;
	if (!act || !evo_act_name(a))
		luaL_error(L, "pack_net: unknown activation '%s'",
			   act ? act : "nil");
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
	for (int k = 0; k < g->n; k++) {
		lua_rawgeti(L, list, k + 1);
		int t = lua_gettop(L);
		lua_getfield(L, t, "kind");
		const char *kind = lua_tostring(L, -1);
		lua_getfield(L, t, "id");
		g->id[k] = lua_tointeger(L, -1);
		char c = !kind			     ? '?'
			 : strcmp(kind, "input") == 0  ? 'i'
			 : strcmp(kind, "output") == 0 ? 'o'
			 : strcmp(kind, "bias") == 0   ? 'b'
			 : strcmp(kind, "hidden") == 0 ? 'h'
						       : '?';
		g->kind[k] = c;
		if (c == 'i') {
			g->n_in++;
		} else if (c == 'o' || c == 'h') {
			lua_getfield(L, t, "act");
			g->act[k] = (uint8_t)act_of(L, lua_tostring(L, -1));
			lua_pop(L, 1);
			g->n_out += c == 'o';
			g->n_hidden += c == 'h';
		} else if (c == 'b') {
			/* the last bias node counts, as in neat.to_net */
			lua_getfield(L, t, "value");
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
	lua_getfield(L, 1, "nodes");
	lua_getfield(L, 1, "links");
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
		lua_getfield(L, -1, "enabled");
		int enabled = lua_toboolean(L, -1);
		lua_pop(L, 1);
		if (enabled) {
			lua_Integer from = (lua_Integer)num_field(L, -1, "from");
			lua_Integer to = (lua_Integer)num_field(L, -1, "to");
			double w = num_field(L, -1, "weight");
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
		else {
			snprintf(s, sizeof s, LUA_INTEGER_FMT, x);
			puts_(L, b, s);
		}
		return;
	}
	double x = lua_tonumber(L, idx);
	if (x != x) {
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
		if (c == '"' || c == '\\' || c == '\n') {
			char e[2] = {'\\', (char)c};
			put(L, b, e, 2);
		} else if (iscntrl(c)) {
			char e[8];
			/* s[len] is the string's terminating zero */
			unsigned char next = (unsigned char)s[i + 1];
			snprintf(e, sizeof e, isdigit(next) ? "\\%03d" : "\\%d",
				 (int)c);
			puts_(L, b, e);
		} else {
			put(L, b, (const char *)&s[i], 1);
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

/* serialize.lua's key order: by type name, then by value (Lua's <). */
static int key_less(lua_State *L, int a, int b)
{
	int ta = lua_type(L, a), tb = lua_type(L, b);
	if (ta != tb)
		return strcmp(lua_typename(L, ta), lua_typename(L, tb)) < 0;
	return lua_compare(L, a, b, LUA_OPLT);
}

/* Sorts the n keys at stack slots base .. base+n-1 (insertion into a
 * merge of runs: the keys are distinct, so any sort gives one order). */
static void sort_keys(lua_State *L, int base, int n, int *ix, int *tmp)
{
	for (int w = 1; w < n; w *= 2) {
		for (int lo = 0; lo < n; lo += 2 * w) {
			int mid = lo + w < n ? lo + w : n;
			int hi = lo + 2 * w < n ? lo + 2 * w : n;
			int a = lo, c = mid, k = lo;
			while (a < mid && c < hi)
				tmp[k++] = key_less(L, base + ix[c], base + ix[a])
					       ? ix[c++]
					       : ix[a++];
			while (a < mid)
				tmp[k++] = ix[a++];
			while (c < hi)
				tmp[k++] = ix[c++];
		}
		memcpy(ix, tmp, (size_t)n * sizeof *ix);
	}
}

static void put_value(lua_State *L, buffer *b, int idx, int depth);

static void put_record(lua_State *L, buffer *b, int idx, int depth)
{
	int base = lua_gettop(L) + 1, n = 0;
	lua_pushnil(L);
	while (lua_next(L, idx)) {
		lua_pop(L, 1);
		luaL_checkstack(L, 3, "serialize: a table of too many keys");
		lua_pushvalue(L, -1); /* the key stays, a copy iterates */
		n++;
	}
	/* the keys are at base .. base+n-1 */
	int *ix = lua_newuserdatauv(L, 2 * (size_t)(n ? n : 1) * sizeof *ix, 0);
	for (int k = 0; k < n; k++)
		ix[k] = k;
	sort_keys(L, base, n, ix, ix + n);
	for (int k = 0; k < n; k++) {
		int key = base + ix[k];
		put(L, b, "[", 1);
		put_value(L, b, key, depth);
		put(L, b, "]=", 2);
		lua_pushvalue(L, key);
		lua_rawget(L, idx);
		put_value(L, b, lua_gettop(L), depth);
		lua_pop(L, 1);
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

static const luaL_Reg FUNCS[] = {
    {"distance", l_distance},
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
	luaL_newlib(L, FUNCS);
	return 1;
}

void evo_lua_open_neat(lua_State *L)
{
	luaL_requiref(L, "evo.neat", open_neat, 0);
	lua_pop(L, 1);
}

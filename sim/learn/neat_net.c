/* evo.neat's networks (sim/learn/neat_internal.h): a genome packed as the
 * network evo.evaluate runs (pack_net, evo_lua_net_unpack) and as the
 * network table neat.to_net makes (to_net). */
#include <lauxlib.h>
#include <lua.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "evo/fixed.h"
#include "learn/lua_neat.h"
#include "learn/neat_internal.h"
#include "mind/net_build.h"

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

/* A network's numbering of a genome's n nodes (kinds and ids): each
 * input keeps its id; the outputs and then the hidden nodes, each in the
 * genome's order, are numbered n_in, n_in + 1, ... Appends every node's
 * (id, number) to map (*n_map of them), and fills order with the index
 * of the node numbered n_in + j at j; returns how many were numbered. */
static int number_nodes(const char *kind, const lua_Integer *id, int n,
			int n_in, id_map *map, int *n_map, int *order)
{
	int numbered = 0;
	for (int pass = 0; pass < 3; pass++)
		for (int k = 0; k < n; k++) {
			char want = pass == 0 ? 'i' : pass == 1 ? 'o' : 'h';
			if (kind[k] != want)
				continue;
			lua_Integer to = pass == 0 ? id[k] : n_in + numbered;
			map[(*n_map)++] = (id_map){id[k], (uint16_t)to};
			if (pass > 0)
				order[numbered++] = k;
		}
	return numbered;
}

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
int neat_l_pack_net(lua_State *L)
{
	neat_check_tables(L, 1);
	rget(L, 1, K_NODES);
	luaL_checktype(L, 2, LUA_TTABLE);
	const genes *gs = neat_genome_genes(L, 1, 0); /* 3 */
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
	int n_map = 0, n_out = 0, order[GENOME_MAX_NODES];
	int numbered =
	    number_nodes(g.kind, g.id, g.n, g.n_in, map, &n_map, order);
	for (int j = 0; j < numbered; j++) {
		int k = order[j], next = g.n_in + j;
		evo_netdesc_node *nd = &p->node[j];
		nd->id = (uint16_t)next;
		nd->act = g.act[k];
		nd->line = 0;
		bias[j] = 0.0;
		if (g.kind[k] == 'o')
			p->out_id[n_out++] = (uint16_t)next;
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

node_list neat_read_node_list(lua_State *L, int nodes)
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
		nl.id[k] = neat_gene_int(L, -1, "node id");
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
int neat_l_to_net(lua_State *L)
{
	neat_check_tables(L, 1);
	rget(L, 1, K_NODES); /* 2 */
	luaL_checktype(L, 2, LUA_TTABLE);
	const genes *gs = neat_genome_genes(L, 1, 0); /* 3 */
	node_list nl = neat_read_node_list(L, 2); /* 4 */
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
	id_map *map = lua_newuserdatauv(
	    L, (size_t)(nl.n + 1) * (sizeof *map + sizeof(double) + sizeof(int)),
	    0); /* 5 */
	double *bias = (double *)(void *)(map + nl.n + 1);
	int *order = (int *)(void *)(bias + nl.n + 1);
	lua_createtable(L, 0, 5); /* 6: the network */
	int net = 6;
	set_int(L, net, K_INPUTS, n_in);
	set_int(L, net, K_OUTPUTS, n_out);
	lua_createtable(L, nl.n, 0); /* 7: nodes */
	lua_createtable(L, n_out, 0); /* 8: outputs_ids */
	int n_nodes = 0, n_outs = 0;
	int numbered =
	    number_nodes(nl.kind, nl.id, nl.n, n_in, map, &n_map, order);
	if (n_in + numbered - 1 > UINT16_MAX)
		luaL_error(L, "to_net: too many nodes");
	for (int j = 0; j < numbered; j++) {
		int k = order[j], next = n_in + j;
		bias[j] = 0.0;
		lua_createtable(L, 0, 3);
		set_int(L, -1, K_ID, next);
		lua_rawgeti(L, 2, k + 1);
		rget(L, -1, K_ACT);
		lua_remove(L, -2);
		rset(L, -2, K_ACT);
		lua_rawseti(L, 7, ++n_nodes);
		if (nl.kind[k] == 'o') {
			lua_pushinteger(L, next);
			lua_rawseti(L, 8, ++n_outs);
		}
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
		neat_push_gene_field(L, x, K_WEIGHT);
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

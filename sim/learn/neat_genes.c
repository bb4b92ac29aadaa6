/* evo.neat's genes (sim/learn/neat_internal.h): a genome's link genes as
 * one userdata of flat arrays, sorted by innovation, with the gene
 * references Lua reads and writes them through, and the kernels genes,
 * add_gene, sort_genes and reaches. */
#include <lauxlib.h>
#include <lua.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "learn/neat_internal.h"

genes *neat_new_genes(lua_State *L, int n)
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
genes *neat_to_genes(lua_State *L, int idx)
{
	if (lua_type(L, idx) != LUA_TUSERDATA || !lua_getmetatable(L, idx))
		return NULL;
	int is = lua_rawequal(L, -1, lua_upvalueindex(UP_GENES_MT));
	lua_pop(L, 1);
	return is ? lua_touserdata(L, idx) : NULL;
}

/* Pushes gene field `key` of gs->g[i] as Lua has it. */
void neat_push_gene_field(lua_State *L, const gene *x, enum key key)
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
lua_Integer neat_gene_int(lua_State *L, int idx, const char *what)
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
		x->innov = neat_gene_int(L, idx, "innov");
		break;
	case K_FROM:
		x->from = neat_gene_int(L, idx, "from");
		break;
	case K_TO:
		x->to = neat_gene_int(L, idx, "to");
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
void neat_push_gene_table(lua_State *L, const gene *x)
{
	lua_createtable(L, 0, 5);
	for (int k = K_INNOV; k <= K_ENABLED; k++) {
		neat_push_gene_field(L, x, (enum key)k);
		rset(L, -2, (enum key)k);
	}
}

/* Pushes the genes of list `list` (a table of gene tables, or genes). */
static genes *push_genes_of(lua_State *L, int list)
{
	list = lua_absindex(L, list);
	genes *gs = neat_to_genes(L, list);
	if (gs) {
		lua_pushvalue(L, list);
		return gs;
	}
	luaL_checktype(L, list, LUA_TTABLE);
	int n = (int)lua_rawlen(L, list);
	gs = neat_new_genes(L, n);
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
genes *neat_genome_genes(lua_State *L, int g, int store)
{
	g = lua_absindex(L, g);
	luaL_checktype(L, g, LUA_TTABLE);
	rget(L, g, K_LINKS);
	genes *gs = neat_to_genes(L, -1);
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
	genes *gs = neat_to_genes(L, -1);
	lua_pop(L, 1); /* the reference keeps the genes alive */
	if (!gs || r->i >= gs->n)
		luaL_error(L, "evo.neat: a gene past its genome's end");
	return &gs->g[r->i];
}

static int gene_index(lua_State *L)
{
	gene *x = ref_gene(L, 1);
	neat_push_gene_field(L, x, gene_key(L, 2));
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
		neat_push_gene_table(L, &gs->g[i]);
		lua_rawseti(L, -2, i + 1);
	}
	return 1;
}

int neat_by_innov(const void *a, const void *b)
{
	lua_Integer x = ((const gene *)a)->innov, y = ((const gene *)b)->innov;
	return (x > y) - (x < y);
}

/* genes(list) -> genes holding a list of gene tables (or a copy of
 * genes), in the list's order. */
int neat_l_genes(lua_State *L)
{
	if (neat_to_genes(L, 1)) {
		genes *src = neat_to_genes(L, 1);
		genes *gs = neat_new_genes(L, src->n);
		memcpy(gs->g, src->g, (size_t)src->n * sizeof *gs->g);
		return 1;
	}
	push_genes_of(L, 1);
	return 1;
}

/* add_gene(g, gene) -> g's genes with `gene` (a gene table) added and
 * sorted by innovation, as g.links (a new block; the old one is left
 * as it was). */
int neat_l_add_gene(lua_State *L)
{
	luaL_checktype(L, 2, LUA_TTABLE);
	lua_settop(L, 2);
	genes *old = neat_genome_genes(L, 1, 0);
	genes *gs = neat_new_genes(L, old->n + 1);
	memcpy(gs->g, old->g, (size_t)old->n * sizeof *gs->g);
	gene_from_table(L, 2, &gs->g[old->n]);
	lua_pushvalue(L, -1);
	rset(L, 1, K_LINKS);
	return 1;
}

/* sort_genes(g): g's genes sorted by innovation (distinct ones). */
int neat_l_sort_genes(lua_State *L)
{
	genes *gs = neat_genome_genes(L, 1, 1);
	int sorted = 1;
	for (int i = 1; i < gs->n && sorted; i++)
		sorted = gs->g[i - 1].innov < gs->g[i].innov;
	if (!sorted)
		qsort(gs->g, (size_t)gs->n, sizeof *gs->g, neat_by_innov);
	return 0;
}

/* Does a path from node `from` reach node `to` over genes gs, enabled or
 * not (neat.lua's reaches)? Its room is a userdata, left on the stack. */
int neat_genes_reach(lua_State *L, const genes *gs, lua_Integer from,
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
int neat_l_reaches(lua_State *L)
{
	lua_Integer from = luaL_checkinteger(L, 2), to = luaL_checkinteger(L, 3);
	genes *gs = neat_genome_genes(L, 1, 0);
	lua_pushboolean(L, neat_genes_reach(L, gs, from, to));
	return 1;
}

const luaL_Reg neat_genes_methods[] = {
    {"__index", genes_index},
    {"__len", genes_len},
    {"plain", genes_plain},
    {"__plain", genes_plain},
    {NULL, NULL},
};

const luaL_Reg neat_gene_methods[] = {
    {"__index", gene_index},
    {"__newindex", gene_newindex},
    {"__eq", gene_eq},
    {NULL, NULL},
};

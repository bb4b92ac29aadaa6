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
 * every call, which cost as much as the kernels' own work.
 *
 * This file makes the module (its keys, metatables and function table)
 * and holds the kernels' scratch memory and list sort; the kernels live by
 * what they do in neat_genes.c, neat_species.c, neat_net.c, neat_dump.c,
 * neat_rng.c, neat_mutate.c and neat_breed.c, sharing
 * sim/learn/neat_internal.h. */
#include "learn/lua_neat.h"

#include <lauxlib.h>
#include <lua.h>
#include <stdlib.h>

#include "learn/neat_internal.h"

const char *const neat_key_names[K_COUNT] = {
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

static int by_key(const void *a, const void *b)
{
	double x = ((const keyed *)a)->key, y = ((const keyed *)b)->key;
	return (x > y) - (x < y);
}

/* Sorts the list at `list` by each element's field `field` (distinct
 * values: innovations, node ids), as table.sort does with a < on them. */
void neat_sort_list(lua_State *L, int list, enum key field)
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
void *neat_scratch(lua_State *L, size_t bytes)
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

/* ------------------------------------------------------------------ */

static const luaL_Reg FUNCS[] = {
    {"rng_next", neat_l_rng_next},
    {"rng_unit", neat_l_rng_unit},
    {"rng_normal", neat_l_rng_normal},
    {"isoline", neat_l_isoline},
    {"mutate_weights", neat_l_mutate_weights},
    {"mutate", neat_l_mutate},
    {"draws", neat_l_draws},
    {"crossover", neat_l_crossover},
    {"breed", neat_l_breed},
    {"add_link", neat_l_add_link},
    {"add_node", neat_l_add_node},
    {"rank", neat_l_rank},
    {"ranked", neat_l_ranked},
    {"tally", neat_l_tally},
    {"share", neat_l_share},
    {"best_of", neat_l_best_of},
    {"assign", neat_l_assign},
    {"distance", neat_l_distance},
    {"speciate", neat_l_speciate},
    {"copy_genome", neat_l_copy_genome},
    {"pack_net", neat_l_pack_net},
    {"to_net", neat_l_to_net},
    {"genes", neat_l_genes},
    {"add_gene", neat_l_add_gene},
    {"sort_genes", neat_l_sort_genes},
    {"reaches", neat_l_reaches},
    {"dump", neat_l_dump},
    {NULL, NULL},
};

/* The kernels' upvalues: the keys, then the genes' metatable (at mt). */
static void push_upvalues(lua_State *L, int mt)
{
	luaL_checkstack(L, N_UPVALUES, "evo.neat's upvalues");
	for (int k = 1; k < K_COUNT; k++)
		lua_pushstring(L, neat_key_names[k]);
	lua_pushvalue(L, mt);
}

static int open_neat(lua_State *L)
{
	if (luaL_newmetatable(L, BUF_TYPE)) {
		lua_pushcfunction(L, neat_free_buffer);
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
	const luaL_Reg *regs[2] = {neat_gene_methods, neat_genes_methods};
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

/* evo — private to the evo.neat kernels (sim/learn/lua_neat.c and
 * sim/learn/neat_*.c): the field keys every kernel looks up through its
 * upvalues, the genes' layout, the option records, the random draw, and
 * what each kernel file offers the others. No other file may use it. */
#ifndef EVO_NEAT_INTERNAL_H
#define EVO_NEAT_INTERNAL_H

#include <lauxlib.h>
#include <lua.h>
#include <math.h>
#include <stdint.h>

#define NET_TYPE "evo.neat.net"
#define BUF_TYPE "evo.neat.buffer"

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

/* Pushes t[key] (t a plain table: no metamethods) and returns its type. */
static inline int rget(lua_State *L, int t, enum key key)
{
	if (t < 0)
		t = lua_gettop(L) + t + 1;
	lua_pushvalue(L, lua_upvalueindex(key));
	return lua_rawget(L, t);
}

/* t[key] = the value on top of the stack, popped. */
static inline void rset(lua_State *L, int t, enum key key)
{
	if (t < 0)
		t = lua_gettop(L) + t + 1;
	lua_pushvalue(L, lua_upvalueindex(key));
	lua_insert(L, -2);
	lua_rawset(L, t);
}

/* Is the value at idx the string `key`? */
static inline int is_key(lua_State *L, int idx, enum key key)
{
	return lua_rawequal(L, idx, lua_upvalueindex(key));
}

/* ------------------------------------------------------------------ */
/* A genome's genes: one userdata of flat arrays */

/* Room in a genome table for its nodes and links and for the fields the
 * loop sets on it (fitness, adjusted, species): no table grows twice
 * every generation. */
#define GENOME_FIELDS 5

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

/* ------------------------------------------------------------------ */
/* Compatibility distance */

/* Field `key` of the table at idx as a number; 0 when it is none. */
static inline double num_field(lua_State *L, int idx, enum key key)
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

/* ------------------------------------------------------------------ */
/* learn.rng's generator: xoshiro256** on the object's four words */

/* xoshiro256**'s step on the four words s: the next word. */
static inline uint64_t xoshiro_next(uint64_t s[4])
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

static inline double unit_of(uint64_t word)
{
	return (double)(word >> 11) * (1.0 / 9007199254740992.0);
}

/* A kernel's generator: learn.rng's (`ours`: its words are read once into
 * s, drawn from in C and written back by neat_rng_done), or a test's own,
 * whose unit method is called for each draw. */
typedef struct rng_src {
	int rng;  /* its stack slot */
	int ours; /* learn.rng's, with rng_unit as its unit */
	int state; /* ours: the stack slot of rng.s */
	uint64_t s[4];
} rng_src;

/* rng:unit() of the kernel's generator. */
static inline double draw(lua_State *L, rng_src *r)
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

/* The options a weight mutation reads. */
typedef struct wm_opts {
	double max; /* weight_max */
	int max_int; /* weight_max is a Lua integer */
	int code; /* weight_mutation is "code" */
	double perturb_prob, severe_prob, perturb_power, replace_power;
} wm_opts;

/* A number field of the table at idx as a key to sort by. */
typedef struct keyed {
	double key;
	int slot; /* the table's index in the list being sorted */
} keyed;

/* The options crossover reads. */
typedef struct cross_opts {
	int tie_smaller;
	double mate_avg_prob, disable_prob;
} cross_opts;

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

/* A genome's nodes read: ids and kinds ('i' input, 'b' bias, 'o'
 * output, 'h' hidden, '?' other), in a userdata left on the stack. */
typedef struct node_list {
	int n;
	lua_Integer *id;
	char *kind;
} node_list;

/* 1 + floor(u * n): a place in a list of n drawn as neat.lua draws it. */
static inline lua_Integer pick(double u, lua_Integer n)
{
	return 1 + (lua_Integer)floor(u * (double)n);
}

/* the module (lua_neat.c): its keys, shared scratch memory and sorting */
extern const char *const neat_key_names[K_COUNT];
void neat_sort_list(lua_State *L, int list, enum key field);
void *neat_scratch(lua_State *L, size_t bytes);

/* a genome's genes (neat_genes.c) */
genes *neat_new_genes(lua_State *L, int n);
genes *neat_to_genes(lua_State *L, int idx);
void neat_push_gene_field(lua_State *L, const gene *x, enum key key);
lua_Integer neat_gene_int(lua_State *L, int idx, const char *what);
void neat_push_gene_table(lua_State *L, const gene *x);
genes *neat_genome_genes(lua_State *L, int g, int store);
int neat_by_innov(const void *a, const void *b);
int neat_l_genes(lua_State *L);
int neat_l_add_gene(lua_State *L);
int neat_l_sort_genes(lua_State *L);
int neat_genes_reach(lua_State *L, const genes *gs, lua_Integer from,
		     lua_Integer to);
int neat_l_reaches(lua_State *L);
extern const luaL_Reg neat_genes_methods[];
extern const luaL_Reg neat_gene_methods[];

/* compatibility distance, species and selection (neat_species.c) */
dist_opts neat_dist_opts_of(lua_State *L, int o);
double neat_distance_of(const genes *a, const genes *b, const dist_opts *o);
int neat_l_distance(lua_State *L);
int neat_l_speciate(lua_State *L);
int neat_l_assign(lua_State *L);
void neat_push_copy(lua_State *L, int g);
int neat_l_copy_genome(lua_State *L);
int neat_l_rank(lua_State *L);
int neat_l_tally(lua_State *L);
int neat_l_share(lua_State *L);
int neat_l_best_of(lua_State *L);
int neat_l_ranked(lua_State *L);

/* networks from genomes (neat_net.c) */
int neat_l_pack_net(lua_State *L);
node_list neat_read_node_list(lua_State *L, int nodes);
int neat_l_to_net(lua_State *L);

/* plain data as text (neat_dump.c) */
int neat_free_buffer(lua_State *L);
int neat_l_dump(lua_State *L);

/* learn.rng's generator (neat_rng.c) */
int neat_l_rng_next(lua_State *L);
int neat_l_rng_unit(lua_State *L);
int neat_l_rng_normal(lua_State *L);
int neat_l_isoline(lua_State *L);
/* A binding's arguments first..last checked to be tables; arguments
 * 1..n checked so and the stack cut to them (neat_rng.c). */
void neat_want_tables(lua_State *L, int first, int last);
void neat_check_tables(lua_State *L, int n);
void neat_rng_begin(lua_State *L, int rng, rng_src *r);
void neat_rng_done(lua_State *L, rng_src *r);

/* weight and structural mutations (neat_mutate.c) */
wm_opts neat_wm_opts_of(lua_State *L, int o);
void neat_mutate_genes(lua_State *L, genes *gs, const wm_opts *w, rng_src *r);
int neat_l_mutate_weights(lua_State *L);
int neat_l_mutate(lua_State *L);
int neat_l_draws(lua_State *L);
struct_opts neat_struct_opts_of(lua_State *L, int o);
void neat_add_link(lua_State *L, int pop, int g, const struct_opts *t,
		   rng_src *r);
void neat_add_node(lua_State *L, int pop, int g, const struct_opts *t,
		   rng_src *r);
int neat_l_add_link(lua_State *L);
int neat_l_add_node(lua_State *L);

/* crossover and a species' offspring (neat_breed.c) */
int neat_l_crossover(lua_State *L);
int neat_l_breed(lua_State *L);

#endif

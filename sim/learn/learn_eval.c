/* evo.learn's batches (sim/learn/learn_internal.h): a batch of networks
 * read from the loop's tables and evaluated (evaluate, with the
 * behaviours MAP-Elites and novelty search read back as descriptors), a
 * team's network and an environment genome set, DPNV's success test. */
#define _POSIX_C_SOURCE 200809L

#include <lauxlib.h>
#include <lua.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "base/err.h"
#include "base/fileio.h"
#include "learn/curve.h"
#include "learn/evaluate.h"
#include "learn/gallery.h"
#include "learn/heatmap.h"
#include "learn/learn_internal.h"
#include "learn/literature.h"
#include "learn/lua_neat.h"
#include "learn/runlog.h"
#include "learn/runopts.h"
#include "lua/lua_evo.h"
#include "mind/net_build.h"

static const char BEHAVIOUR_KEY = 'b'; /* the last batch's behaviours */

double learn_field_num(lua_State *L, int idx, const char *key, double dflt)
{
	lua_getfield(L, idx, key);
	int ok;
	double v = lua_tonumberx(L, -1, &ok);
	lua_pop(L, 1);
	return ok ? v : dflt;
}

/* A whole-number field in lo..hi (missing: 0). A Lua number out of an
 * integer type's range has no C value (the cast is undefined), so it is
 * refused by name: "network 3: id 1e+30 is not a whole number in
 * 0..65535" (which >= 0), or "evo.log: generation ..." (which < 0). */
lua_Integer learn_field_int(lua_State *L, int idx, const char *key,
			     lua_Integer lo, lua_Integer hi, int which)
{
	double v = learn_field_num(L, idx, key, 0);
	if (v >= (double)lo && v <= (double)hi && v < 0x1p63 && v == floor(v))
		return (lua_Integer)v;
	if (which >= 0)
		luaL_error(L, "network %d: %s %f is not a whole number in %I..%I",
			   which, key, (lua_Number)v, lo, hi);
	return luaL_error(L, "evo.log: %s %f is not a whole number in %I..%I",
			  key, (lua_Number)v, lo, hi);
}

/* Push field `key` of network `which` (the table at idx), a list of at
 * most max entries: its length. */
static int push_list(lua_State *L, int idx, const char *key, int max,
		     int which)
{
	lua_getfield(L, idx, key);
	int n = (int)luaL_len(L, -1);
	if (n > max)
		luaL_error(L, "network %d: %d %s (at most %d)", which, n, key,
			   max);
	return n;
}

/* A network table of learn.neat (inputs, outputs, nodes {id, act, bias},
 * outputs_ids, links {from, to, weight}), or a network evo.neat.pack_net
 * packed, as evo's network description (only the nodes and links it has
 * are written). */
static void to_netdesc(lua_State *L, int idx, int which, evo_netdesc *d)
{
	if (evo_lua_net_unpack(L, idx, d))
		return;
	memset(d, 0, offsetof(evo_netdesc, node));
	luaL_checktype(L, idx, LUA_TTABLE);
	d->n_in = (uint16_t)learn_field_int(L, idx, "inputs", 0, UINT16_MAX, which);
	d->n_out = (uint16_t)learn_field_int(L, idx, "outputs", 0, UINT16_MAX, which);
	if (d->n_out > EVO_MAX_SKILL_IO)
		luaL_error(L, "network %d: %d outputs", which, d->n_out);
	int n = push_list(L, idx, "nodes", EVO_NET_MAX_NODES, which);
	for (int i = 1; i <= n; i++) {
		lua_geti(L, -1, i);
		int t = lua_gettop(L);
		evo_netdesc_node *nd = &d->node[d->n_nodes++];
		nd->id = (uint16_t)learn_field_int(L, t, "id", 0, UINT16_MAX, which);
		nd->bias = evo_net_weight_q16(learn_field_num(L, t, "bias", 0));
		nd->line = 0;
		lua_getfield(L, t, "act");
		const char *act = lua_tostring(L, -1);
		unsigned a = 0;
		while (act && evo_act_name(a) && strcmp(evo_act_name(a), act))
			a++;
		if (!act || !evo_act_name(a))
			luaL_error(L, "network %d: unknown activation '%s'",
				   which, act ? act : "nil");
		nd->act = (uint8_t)a;
		lua_pop(L, 2);
	}
	lua_pop(L, 1);
	lua_getfield(L, idx, "outputs_ids");
	for (int i = 1; i <= d->n_out; i++) {
		lua_geti(L, -1, i);
		d->out_id[i - 1] = (uint16_t)lua_tointeger(L, -1);
		lua_pop(L, 1);
	}
	lua_pop(L, 1);
	n = push_list(L, idx, "links", EVO_NET_MAX_LINKS, which);
	for (int i = 1; i <= n; i++) {
		lua_geti(L, -1, i);
		int t = lua_gettop(L);
		evo_netdesc_link *lk = &d->link[d->n_links++];
		lk->from =
		    (uint16_t)learn_field_int(L, t, "from", 0, UINT16_MAX, which);
		lk->to = (uint16_t)learn_field_int(L, t, "to", 0, UINT16_MAX, which);
		lk->weight = evo_net_weight_q16(learn_field_num(L, t, "weight", 0));
		lk->line = 0;
		lua_pop(L, 1);
	}
	lua_pop(L, 1);
}

/* A list of whole numbers 1 .. n at idx as 0-based ints in a userdata
 * left on the stack. */
static int *index_list(lua_State *L, int idx, int n, lua_Integer *len)
{
	luaL_checktype(L, idx, LUA_TTABLE);
	*len = luaL_len(L, idx);
	if (*len < 1 || *len > INT_MAX / (lua_Integer)sizeof(int))
		luaL_error(L, "evo.evaluate: %I team members", *len);
	int *v = lua_newuserdatauv(L, (size_t)*len * sizeof *v, 0);
	for (lua_Integer i = 1; i <= *len; i++) {
		lua_geti(L, idx, i);
		lua_Integer c = lua_tointeger(L, -1);
		if (c < 1 || c > n)
			luaL_error(L,
				   "evo.evaluate: team member %I is %I, not a "
				   "network 1..%d",
				   i, c, n);
		v[i - 1] = (int)(c - 1);
		lua_pop(L, 1);
	}
	return v;
}

/* Keep the batch's behaviours for evo.descriptors: a list, one list of
 * numbers per network; none for a batch without (literature and team
 * tasks). Every behaviour of a run has the same size. */
static void keep_behaviours(lua_State *L, learn *l, const evo_eval_result *res,
			    int n)
{
	for (int i = 0; i < n; i++) {
		int d = res[i].n_behaviour;
		if (l->n_behaviour < 0)
			l->n_behaviour = d;
		if (d != l->n_behaviour)
			luaL_error(L,
				   "evo.evaluate: network %d's behaviour has "
				   "%d values, where the run's had %d: "
				   "env.behaviour must return as many every "
				   "episode",
				   i + 1, d, l->n_behaviour);
	}
	if (n == 0 || l->n_behaviour <= 0) {
		lua_pushnil(L);
		lua_rawsetp(L, LUA_REGISTRYINDEX, &BEHAVIOUR_KEY);
		return;
	}
	lua_createtable(L, n, 0);
	for (int i = 0; i < n; i++) {
		lua_createtable(L, res[i].n_behaviour, 0);
		for (int k = 0; k < res[i].n_behaviour; k++) {
			lua_pushnumber(L, res[i].behaviour[k]);
			lua_rawseti(L, -2, k + 1);
		}
		lua_rawseti(L, -2, i + 1);
	}
	lua_rawsetp(L, LUA_REGISTRYINDEX, &BEHAVIOUR_KEY);
}

/* evo.descriptors() -> the last evo.evaluate's behaviours (what each
 * network's episodes did, docs/lua.md): a list with one list of numbers in
 * [0, 1] per network, in the batch's order, each the mean over the
 * repetitions; nil when the batch had none (literature and team tasks). */
int learn_l_descriptors(lua_State *L)
{
	lua_rawgetp(L, LUA_REGISTRYINDEX, &BEHAVIOUR_KEY);
	return 1;
}

/* One field of each of n results, as a Lua list: fitness, solved,
 * collisions, and for team tasks wins, team fitness and group (1-based). */
enum result_field {
	R_FITNESS, R_SOLVED, R_COLLISIONS, R_WINS, R_TEAM_FITNESS, R_GROUP
};
static void push_results(lua_State *L, const evo_eval_result *res, int n,
			 enum result_field f)
{
	lua_createtable(L, n, 0);
	for (int i = 0; i < n; i++) {
		const evo_eval_result *r = &res[i];
		if (f == R_FITNESS || f == R_TEAM_FITNESS)
			lua_pushnumber(L, f == R_FITNESS ? r->fitness
							 : r->team_fitness);
		else if (f == R_SOLVED)
			lua_pushboolean(L, r->solved);
		else /* Lua integers, as they always were */
			lua_pushinteger(L, f == R_COLLISIONS ? r->collisions
					   : f == R_WINS     ? r->wins
							     : r->group + 1);
		lua_rawseti(L, -2, i + 1);
	}
}

/* evo.evaluate(nets, generation[, groups, team]) -> fitness list,
 * seconds, solved list (booleans: the literature tasks' success
 * criterion), collisions list (ticks the bot spent touching, summed over
 * the repetitions), metrics list (for each network, a list of the
 * environment's metrics in the order of evo.metrics, each the mean over
 * the repetitions), and for team tasks, wins list, team fitness list and
 * the team (1-based) each network was scored in. groups (team tasks): the
 * networks each member of team `team` (1-based) runs, team after team
 * (evo_evaluate_teams); without it, each network is a team of its own. */
int learn_l_evaluate(lua_State *L)
{
	learn *l = learn_ctx(L);
	luaL_checktype(L, 1, LUA_TTABLE);
	int gen = (int)luaL_checkinteger(L, 2);
	lua_Integer len = luaL_len(L, 1);
	if (len < 0 || len > INT_MAX / (lua_Integer)sizeof(evo_netdesc))
		return luaL_error(L, "evo.evaluate: %I networks is too many",
				  len);
	int n = (int)len;
	int team = -1, n_groups = 0;
	int *groups = NULL;
	if (!lua_isnoneornil(L, 3)) {
		team = (int)luaL_checkinteger(L, 4) - 1;
		int size = evo_evaluator_team_size(l->ev, team);
		if (size < 1)
			return luaL_error(L, "evo.evaluate: no team %d",
					  team + 1);
		lua_Integer g;
		groups = index_list(L, 3, n, &g);
		if (g % size)
			return luaL_error(L,
					  "evo.evaluate: %I members are not "
					  "teams of %d",
					  g, size);
		n_groups = (int)(g / size);
	}
	/* The networks go to l->descs, which lasts the run (freed by
	 * evo_learn_run); the other arrays are userdata, so a malformed
	 * network (to_netdesc raises) or a failed batch unwinds through
	 * here and the collector frees them. */
	if (n > l->n_descs) {
		evo_netdesc *grown = realloc(l->descs, (size_t)n * sizeof *grown);
		if (!grown)
			return luaL_error(L, "evo.evaluate: no memory for %d "
					     "networks",
					  n);
		l->descs = grown;
		l->n_descs = n;
	}
	evo_netdesc *nets = l->descs;
	const evo_netdesc **ptr =
	    lua_newuserdatauv(L, (size_t)(n ? n : 1) * sizeof *ptr, 0);
	evo_eval_result *res =
	    lua_newuserdatauv(L, (size_t)(n ? n : 1) * sizeof *res, 0);
	memset(res, 0, (size_t)(n ? n : 1) * sizeof *res);
	for (int i = 0; i < n; i++) {
		lua_geti(L, 1, i + 1);
		to_netdesc(L, lua_gettop(L), i, &nets[i]);
		ptr[i] = &nets[i];
		lua_pop(L, 1);
	}
	evo_err err = {{0}};
	double t0 = learn_now();
	int rc = groups ? evo_evaluate_teams(l->ev, team, ptr, n, groups,
					     n_groups, gen, res, &err)
			: evo_evaluate(l->ev, ptr, n, gen, res, &err);
	double dt = learn_now() - t0;
	if (rc)
		return learn_raise_msg(L, err.msg);
	keep_behaviours(L, l, res, n);
	push_results(L, res, n, R_FITNESS);
	lua_pushnumber(L, dt);
	push_results(L, res, n, R_SOLVED);
	push_results(L, res, n, R_COLLISIONS);
	int nm = evo_evaluator_settings(l->ev)->n_metrics;
	lua_createtable(L, n, 0);
	for (int i = 0; i < n; i++) {
		lua_createtable(L, nm, 0);
		for (int k = 0; k < nm; k++) {
			lua_pushnumber(L, res[i].metric[k]);
			lua_rawseti(L, -2, k + 1);
		}
		lua_rawseti(L, -2, i + 1);
	}
	if (evo_evaluator_n_teams(l->ev) == 0)
		return 5;
	push_results(L, res, n, R_WINS);
	push_results(L, res, n, R_TEAM_FITNESS);
	push_results(L, res, n, R_GROUP);
	return 8;
}

/* evo.set_team_net(team, net): team (1-based) runs net as its learning
 * skill from the next evaluation on (co-evolution). */
int learn_l_set_team_net(lua_State *L)
{
	learn *l = learn_ctx(L);
	int team = (int)luaL_checkinteger(L, 1) - 1;
	evo_netdesc *d = lua_newuserdatauv(L, sizeof *d, 0);
	to_netdesc(L, 2, 1, d);
	evo_err err = {{0}};
	if (evo_evaluator_set_team_net(l->ev, team, d, &err))
		return learn_raise_msg(L, err.msg);
	return 0;
}

/* evo.set_genome(text or nil): the environment genome every episode of
 * the next evo.evaluate runs with (scene:genome(), OPENENDED). */
int learn_l_set_genome(lua_State *L)
{
	const char *g = luaL_optstring(L, 1, NULL);
	evo_err err = {{0}};
	if (evo_evaluator_set_genome(learn_ctx(L)->ev, g, &err))
		return learn_raise_msg(L, err.msg);
	return 0;
}

/* evo.success_test(net) -> solved, generalisation: DPNV's success test
 * (100,000 steps from the start state, then Gruau's 625 starts, on the
 * task's POLEPROTOCOL) for the one network of a generation the loop
 * picked. generalisation is nil when the network did not last the 100,000
 * steps. Present only on DPNV. */
int learn_l_success_test(lua_State *L)
{
	/* A userdata, so an error in the network frees it too. */
	evo_netdesc *d = lua_newuserdatauv(L, sizeof *d, 0);
	to_netdesc(L, 1, 1, d);
	evo_lit_result r;
	evo_err err = {{0}};
	learn *l = learn_ctx(L);
	int pr = evo_lit_protocol_named(
	    evo_simbatch_get(l->task->sb, "POLEPROTOCOL"));
	if (pr < 0)
		return learn_raise_msg(L, "POLEPROTOCOL: not NEAT or GOMEZ");
	if (evo_lit_dpnv_check_for((evo_lit_protocol)pr, d, &r, &err))
		return learn_raise_msg(L, err.msg);
	lua_pushboolean(L, r.solved);
	if (r.generalisation >= 0)
		lua_pushinteger(L, r.generalisation);
	else
		lua_pushnil(L);
	return 2;
}

/* LEARNSIM: the learning loop in Lua (lua/learn/learnsim.lua) over the C
 * evaluator (sim/learn/learn.h, docs/learning.md).
 *
 * The loop runs in a Lua state of its own, apart from the workers' scene
 * states. It reaches C through the `evo.learn` module set up here (the
 * scene scripts have their own `evo` module, sim/lua/lua_evo.c): evaluate a
 * batch of networks, log a generation, save files into the run folder,
 * save the champion, draw the curve (and MAP-Elites' heatmap). */
#define _POSIX_C_SOURCE 200809L
#include "learn/learn.h"

#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "base/err.h"
#include "base/fileio.h"
#include "base/terminal.h"
#include "learn/curve.h"
#include "learn/evaluate.h"
#include "learn/gallery.h"
#include "learn/heatmap.h"
#include "learn/literature.h"
#include "learn/lua_linalg.h"
#include "learn/lua_modcache.h"
#include "learn/lua_neat.h"
#include "learn/lua_novelty.h"
#include "learn/runlog.h"
#include "learn/runopts.h"
#include "lua/lua_evo.h"
#include "mind/net_build.h"

/* The most skills a LEARNSIMCONTINUOUS hierarchy may train. */
#define CONT_MAX_SKILLS 64

typedef struct learn {
	const char *task_path;
	evo_task *task;
	const evo_learn_opts *opts;
	evo_evaluator *ev;
	evo_runlog log;
	int log_open;
	char run_dir[1024];
	char skill[EVO_NAME_MAX];
	double started;
	int first; /* the generation this process started with */
	int tty;
	int n_extra; /* log columns the loop adds after the metrics */
	char extra[6][EVO_RUNLOG_COLUMN_MAX];
	/* LEARNSIMCONTINUOUS: the skills in the order of their turns (their
	 * indices in task->mind), and the evaluator's definition of the
	 * current turn with the networks the other skills run */
	int continuous;
	int openended; /* TYPE:OPENENDED: lua/learn/openended.lua */
	int n_order;
	int order[CONT_MAX_SKILLS];
	evo_net_choice choice[CONT_MAX_SKILLS];
	char choice_path[CONT_MAX_SKILLS][1200];
	evo_eval_def ed;
	/* OPENENDED's development (evo.grow): the grown mind folder's task,
	 * and the names of the skills whose networks are chosen */
	char grown_task[1200];
	char choice_skill[CONT_MAX_SKILLS][EVO_NAME_MAX];
	evo_lua_mem *mem; /* the loop's state's memory (LUAMEMORY) */
	/* evo.evaluate's networks, kept from batch to batch (a batch of
	 * 150 is 8 MB: allocated and cleared anew, it cost more than
	 * evaluating XOR's networks) */
	evo_netdesc *descs;
	int n_descs;
	int n_behaviour; /* the size of every behaviour so far; -1 before */
	/* evo.save's last folder (best/), checked for links and made: a
	 * generation's file then costs its write and rename only */
	char saved_folder[256];
} learn;

static const char LEARN_KEY = 'l';
static const char BEHAVIOUR_KEY = 'b'; /* the last batch's behaviours */

static learn *ctx(lua_State *L)
{
	lua_rawgetp(L, LUA_REGISTRYINDEX, &LEARN_KEY);
	learn *l = lua_touserdata(L, -1);
	lua_pop(L, 1);
	return l;
}

/* An error about a file or a run: its message names the file, so it goes
 * out without the Lua position that luaL_error would put before it. */
static int raise_msg(lua_State *L, const char *msg)
{
	lua_pushstring(L, msg);
	return lua_error(L);
}

static double now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double field_num(lua_State *L, int idx, const char *key, double dflt)
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
static lua_Integer field_int(lua_State *L, int idx, const char *key,
			     lua_Integer lo, lua_Integer hi, int which)
{
	double v = field_num(L, idx, key, 0);
	if (v >= (double)lo && v <= (double)hi && v < 0x1p63 && v == floor(v))
		return (lua_Integer)v;
	if (which >= 0)
		luaL_error(L, "network %d: %s %f is not a whole number in %I..%I",
			   which, key, (lua_Number)v, lo, hi);
	return luaL_error(L, "evo.log: %s %f is not a whole number in %I..%I",
			  key, (lua_Number)v, lo, hi);
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
	d->n_in = (uint16_t)field_int(L, idx, "inputs", 0, UINT16_MAX, which);
	d->n_out = (uint16_t)field_int(L, idx, "outputs", 0, UINT16_MAX, which);
	if (d->n_out > EVO_MAX_SKILL_IO)
		luaL_error(L, "network %d: %d outputs", which, d->n_out);
	lua_getfield(L, idx, "nodes");
	int n = (int)luaL_len(L, -1);
	if (n > EVO_NET_MAX_NODES)
		luaL_error(L, "network %d: %d nodes (at most %d)", which, n,
			   EVO_NET_MAX_NODES);
	for (int i = 1; i <= n; i++) {
		lua_geti(L, -1, i);
		int t = lua_gettop(L);
		evo_netdesc_node *nd = &d->node[d->n_nodes++];
		nd->id = (uint16_t)field_int(L, t, "id", 0, UINT16_MAX, which);
		nd->bias = evo_net_weight_q16(field_num(L, t, "bias", 0));
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
	lua_getfield(L, idx, "links");
	n = (int)luaL_len(L, -1);
	if (n > EVO_NET_MAX_LINKS)
		luaL_error(L, "network %d: %d links (at most %d)", which, n,
			   EVO_NET_MAX_LINKS);
	for (int i = 1; i <= n; i++) {
		lua_geti(L, -1, i);
		int t = lua_gettop(L);
		evo_netdesc_link *lk = &d->link[d->n_links++];
		lk->from =
		    (uint16_t)field_int(L, t, "from", 0, UINT16_MAX, which);
		lk->to = (uint16_t)field_int(L, t, "to", 0, UINT16_MAX, which);
		lk->weight = evo_net_weight_q16(field_num(L, t, "weight", 0));
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
static int l_descriptors(lua_State *L)
{
	lua_rawgetp(L, LUA_REGISTRYINDEX, &BEHAVIOUR_KEY);
	return 1;
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
static int l_evaluate(lua_State *L)
{
	learn *l = ctx(L);
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
	double t0 = now();
	int rc = groups ? evo_evaluate_teams(l->ev, team, ptr, n, groups,
					     n_groups, gen, res, &err)
			: evo_evaluate(l->ev, ptr, n, gen, res, &err);
	double dt = now() - t0;
	if (rc)
		return raise_msg(L, err.msg);
	keep_behaviours(L, l, res, n);
	lua_createtable(L, n, 0);
	for (int i = 0; i < n; i++) {
		lua_pushnumber(L, res[i].fitness);
		lua_rawseti(L, -2, i + 1);
	}
	lua_pushnumber(L, dt);
	lua_createtable(L, n, 0);
	for (int i = 0; i < n; i++) {
		lua_pushboolean(L, res[i].solved);
		lua_rawseti(L, -2, i + 1);
	}
	lua_createtable(L, n, 0);
	for (int i = 0; i < n; i++) {
		lua_pushinteger(L, res[i].collisions);
		lua_rawseti(L, -2, i + 1);
	}
	int nm = evo_evaluator_n_metrics(l->ev);
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
	lua_createtable(L, n, 0);
	for (int i = 0; i < n; i++) {
		lua_pushinteger(L, res[i].wins);
		lua_rawseti(L, -2, i + 1);
	}
	lua_createtable(L, n, 0);
	for (int i = 0; i < n; i++) {
		lua_pushnumber(L, res[i].team_fitness);
		lua_rawseti(L, -2, i + 1);
	}
	lua_createtable(L, n, 0);
	for (int i = 0; i < n; i++) {
		lua_pushinteger(L, res[i].group + 1);
		lua_rawseti(L, -2, i + 1);
	}
	return 8;
}

/* evo.set_team_net(team, net): team (1-based) runs net as its learning
 * skill from the next evaluation on (co-evolution). */
static int l_set_team_net(lua_State *L)
{
	learn *l = ctx(L);
	int team = (int)luaL_checkinteger(L, 1) - 1;
	evo_netdesc *d = lua_newuserdatauv(L, sizeof *d, 0);
	to_netdesc(L, 2, 1, d);
	evo_err err = {{0}};
	if (evo_evaluator_set_team_net(l->ev, team, d, &err))
		return raise_msg(L, err.msg);
	return 0;
}

/* evo.set_genome(text or nil): the environment genome every episode of
 * the next evo.evaluate runs with (scene:genome(), OPENENDED). */
static int l_set_genome(lua_State *L)
{
	const char *g = luaL_optstring(L, 1, NULL);
	evo_err err = {{0}};
	if (evo_evaluator_set_genome(ctx(L)->ev, g, &err))
		return raise_msg(L, err.msg);
	return 0;
}

/* evo.success_test(net) -> solved, generalisation: DPNV's success test
 * (100,000 steps from the start state, then Gruau's 625 starts, on the
 * task's POLEPROTOCOL) for the one network of a generation the loop
 * picked. generalisation is nil when the network did not last the 100,000
 * steps. Present only on DPNV. */
static int l_success_test(lua_State *L)
{
	/* A userdata, so an error in the network frees it too. */
	evo_netdesc *d = lua_newuserdatauv(L, sizeof *d, 0);
	to_netdesc(L, 1, 1, d);
	evo_lit_result r;
	evo_err err = {{0}};
	learn *l = ctx(L);
	int pr = evo_lit_protocol_named(
	    evo_simbatch_get(l->task->sb, "POLEPROTOCOL"));
	if (pr < 0)
		return raise_msg(L, "POLEPROTOCOL: not NEAT or GOMEZ");
	if (evo_lit_dpnv_check_for((evo_lit_protocol)pr, d, &r, &err))
		return raise_msg(L, err.msg);
	lua_pushboolean(L, r.solved);
	if (r.generalisation >= 0)
		lua_pushinteger(L, r.generalisation);
	else
		lua_pushnil(L);
	return 2;
}

static int l_open_log(lua_State *L)
{
	learn *l = ctx(L);
	evo_err err = {{0}};
	l->first = (int)luaL_checkinteger(L, 1);
	const char *names[EVO_SCENE_MAX_METRICS + 8];
	int nm = evo_evaluator_n_metrics(l->ev);
	for (int k = 0; k < nm; k++)
		names[k] = evo_evaluator_metric_name(l->ev, k);
	/* the loop's own columns after the environment's metrics
	 * (LEARNSIMCONTINUOUS: round and turn) */
	l->n_extra = 0;
	if (lua_istable(L, 2)) {
		lua_Integer n = luaL_len(L, 2);
		if (n > 6)
			return luaL_error(L,
					  "evo.open_log: %I columns of the "
					  "loop's own (at most 6)",
					  n);
		for (int k = 0; k < (int)n; k++) {
			lua_geti(L, 2, k + 1);
			snprintf(l->extra[k], sizeof l->extra[k], "%s",
				 luaL_checkstring(L, -1));
			lua_pop(L, 1);
			names[nm++] = l->extra[k];
		}
		l->n_extra = (int)n;
	}
	/* a team task's two columns after the environment's metrics */
	if (evo_evaluator_n_teams(l->ev) > 0) {
		names[nm++] = "team";
		names[nm++] = "win_rate";
	}
	if (evo_runlog_open(&l->log, l->run_dir, l->first, names, nm, &err))
		return raise_msg(L, err.msg);
	l->log_open = 1;
	return 0;
}

/* evo.log{generation, generations, best, mean, best_ever, species,
 * evaluations, seconds, metrics}: a row of log.csv and the progress line.
 * metrics is the list of the environment's metrics for the row (the best
 * candidate's, as evo.evaluate gave them); it may be absent only when
 * the environment has none. */
static int l_log(lua_State *L)
{
	learn *l = ctx(L);
	luaL_checktype(L, 1, LUA_TTABLE);
	if (!l->log_open)
		return luaL_error(L, "evo.log before evo.open_log");
	double metrics[EVO_SCENE_MAX_METRICS + 8];
	int nm = evo_evaluator_n_metrics(l->ev) + l->n_extra +
		 (evo_evaluator_n_teams(l->ev) > 0 ? 2 : 0);
	lua_getfield(L, 1, "metrics");
	if (nm > 0 && (!lua_istable(L, -1) || luaL_len(L, -1) != nm))
		return luaL_error(L, "evo.log: metrics must be a list of %d "
				     "numbers",
				  nm);
	for (int k = 0; k < nm; k++) {
		lua_geti(L, -1, k + 1);
		int ok;
		metrics[k] = lua_tonumberx(L, -1, &ok);
		if (!ok)
			return luaL_error(L, "evo.log: metric %d is %s, not a "
					     "number",
					  k + 1, luaL_typename(L, -1));
		lua_pop(L, 1);
	}
	lua_pop(L, 1);
	evo_gen_stats s = {
		.generation = (int)field_int(L, 1, "generation", 0, INT_MAX, -1),
		.generations =
		    (int)field_int(L, 1, "generations", 0, INT_MAX, -1),
		.best = field_num(L, 1, "best", NAN),
		.mean = field_num(L, 1, "mean", NAN),
		.best_ever = field_num(L, 1, "best_ever", NAN),
		.species = (int)field_int(L, 1, "species", 0, INT_MAX, -1),
		.evaluations =
		    (long)field_int(L, 1, "evaluations", 0, LONG_MAX, -1),
		.solved = (int)field_int(L, 1, "solved", 0, INT_MAX, -1),
		.seconds = field_num(L, 1, "seconds", 0),
		.elapsed = now() - l->started,
		.first = l->first,
		.metrics = nm > 0 ? metrics : NULL,
	};
	char note[128] = "";
	if (lua_getfield(L, 1, "note") == LUA_TSTRING) {
		snprintf(note, sizeof note, "%s", lua_tostring(L, -1));
		s.note = note;
	}
	lua_pop(L, 1);
	/* a team task's row ends with its learning team and win rate */
	if (evo_evaluator_n_teams(l->ev) > 0) {
		int k = (int)metrics[nm - 2] - 1;
		if (k >= 0 && k < l->task->n_teams)
			s.team = l->task->team[k].name;
		s.win_rate = metrics[nm - 1];
	}
	evo_err err = {{0}};
	if (evo_runlog_add(&l->log, &s, &err))
		return raise_msg(L, err.msg);
	char line[512];
	evo_progress_format(line, sizeof line, &s, l->tty);
	if (l->tty)
		printf("\r%s\033[K", line);
	else
		printf("%s\n", line);
	fflush(stdout);
	return 0;
}

/* name is a file of the run folder ("log.csv", "best/gen-0001.net"):
 * relative, with no ".." that would leave the folder. */
static const char *run_file_name(lua_State *L, int idx, const char *fn)
{
	const char *name = luaL_checkstring(L, idx);
	const char *p = name;
	int ok = *name && *name != '/';
	while (ok && *p) {
		size_t n = strcspn(p, "/");
		ok = n > 0 && !(n == 2 && p[0] == '.' && p[1] == '.');
		p += n;
		p += *p == '/';
	}
	if (!ok)
		luaL_error(L, "%s: '%s' is no file of the run folder", fn, name);
	return name;
}

static int l_save(lua_State *L)
{
	learn *l = ctx(L);
	size_t len;
	const char *name = run_file_name(L, 1, "evo.save");
	const char *text = luaL_checklstring(L, 2, &len);
	evo_err err = {{0}};
	if (!l->log_open)
		return luaL_error(L, "evo.save before evo.open_log");
	/* the folders of name (best/) must be the run folder's own; the
	 * file itself is replaced whatever it is (evo_write_file_atomic) */
	const char *slash = strrchr(name, '/');
	if (slash) {
		char folder[1024];
		snprintf(folder, sizeof folder, "%.*s", (int)(slash - name),
			 name);
		if (strcmp(folder, l->saved_folder) != 0) {
			if (evo_folder_check_links(l->run_dir, folder, &err))
				return raise_msg(L, err.msg);
			/* folders of its own (OPENENDED's solvers/ and
			 * Mind/Skills/X), each level made once */
			char path[1200];
			for (char *c = folder;; c++) {
				if (*c != '/' && *c)
					continue;
				char end = *c;
				*c = 0;
				if (evo_path_fmt(path, sizeof path, &err, "%s/%s",
						 l->run_dir, folder))
					return raise_msg(L, err.msg);
				mkdir(path, 0755);
				*c = end;
				if (!end)
					break;
			}
			size_t n = strlen(folder);
			if (n >= sizeof l->saved_folder)
				n = 0; /* too long to keep: checked each time */
			memcpy(l->saved_folder, folder, n);
			l->saved_folder[n] = 0;
		}
	}
	if (evo_runlog_save(&l->log, name, text, len, &err))
		return raise_msg(L, err.msg);
	return 0;
}

/* The __gc of the box l_read reads a file into. */
static int free_file_box(lua_State *L)
{
	char **box = lua_touserdata(L, 1);
	free(*box);
	*box = NULL;
	return 0;
}

static int l_read(lua_State *L)
{
	learn *l = ctx(L);
	char path[1200];
	size_t len;
	evo_err err;
	if (evo_path_fmt(path, sizeof path, &err, "%s/%s", l->run_dir,
			 run_file_name(L, 1, "evo.read")))
		return raise_msg(L, err.msg);
	struct stat st;
	if (stat(path, &st) != 0) {
		lua_pushnil(L);
		return 1;
	}
	/* Something that is there but cannot be read is an error, not a
	 * fresh start that would overwrite the run's log. */
	if (!S_ISREG(st.st_mode))
		return raise_msg(L, lua_pushfstring(L, "%s: not a file", path));
	/* The bytes are held by a userdata whose __gc frees them: making
	 * them a Lua string can fail for want of memory, and that error
	 * unwinds through here. */
	char **box = lua_newuserdatauv(L, sizeof *box, 0);
	*box = NULL;
	if (luaL_newmetatable(L, "evo.learn.file")) {
		lua_pushcfunction(L, free_file_box);
		lua_setfield(L, -2, "__gc");
	}
	lua_setmetatable(L, -2);
	if (evo_read_file_max(path, EVO_RUN_FILE_MAX, box, &len, &err))
		return raise_msg(L, err.msg);
	if (l->mem && l->mem->used + len + 4096 > l->mem->limit)
		return raise_msg(
		    L, lua_pushfstring(L,
				       "%s: reading it (%d MB) would pass the "
				       "learning loop's memory limit of %d MB "
				       "(LUAMEMORY raises it, docs/lua.md)",
				       path, (int)(len >> 20),
				       (int)(l->mem->limit >> 20)));
	lua_pushlstring(L, *box, len);
	free(*box);
	*box = NULL;
	return 1;
}

/* Before a run writes Skills/S/S.net (or a member's S.K.net) over a
 * network it did not make, a shipped one, one trained by hand or by
 * another run, that network is copied into the run folder as
 * replaced-NAME.net: the first one the run replaces, so a resumed run or a
 * later round keeps the network from before the run. *kept is the copy's
 * path, or "" when nothing was kept (no file, or the same text). */
static int keep_replaced(const learn *l, const char *path, const char *text,
			 size_t len, const char *name, char *kept, size_t cap,
			 evo_err *err)
{
	kept[0] = 0;
	if (!evo_file_exists(path))
		return 0;
	char copy[1300];
	if (evo_path_fmt(copy, sizeof copy, err, "%s/replaced-%s.net",
			 l->run_dir, name))
		return -1;
	if (evo_file_exists(copy))
		return 0;
	char *old;
	size_t n;
	if (evo_read_file(path, &old, &n, err))
		return -1;
	int same = n == len && memcmp(old, text, len) == 0;
	int rc = same ? 0 : evo_write_file_atomic(copy, old, n, err);
	free(old);
	if (rc == 0 && !same)
		snprintf(kept, cap, "%s", copy);
	return rc;
}

/* The champion goes into the run folder, which keeps each run's own, and
 * then where DEMOSIM and evo export look for it (not with --no-save). evo.save_champion(text[,
 * team, member, heterogeneous]) in a team task: team (1-based) is the
 * learning team, member k > 1 of a heterogeneous team gets
 * champion-K.net and Skills/S/S.K.net (docs/teams.md); a homogeneous
 * champion removes the members' networks an earlier run left. */
static int l_save_champion(lua_State *L)
{
	learn *l = ctx(L);
	size_t len;
	const char *text = luaL_checklstring(L, 1, &len);
	char kept[1300], path[1400], name[160] = "champion";
	const char *root = l->task->mind->root, *skill = l->skill;
	int member = 1, hetero = 0;
	const char *team_name = NULL; /* of a task with two learning teams */
	evo_err err = {{0}};
	if (!lua_isnoneornil(L, 2) && l->task->n_teams > 0) {
		int team = (int)luaL_checkinteger(L, 2) - 1;
		if (team < 0 || team >= l->task->n_teams)
			return luaL_error(L, "evo.save_champion: no team %d",
					  team + 1);
		const evo_team *tm = &l->task->team[team];
		root = tm->mind->root;
		skill = tm->learning_skill;
		member = (int)luaL_optinteger(L, 3, 1);
		hetero = lua_toboolean(L, 4);
		if (l->task->n_learning > 1) {
			snprintf(name, sizeof name, "champion-%s", tm->name);
			team_name = tm->name;
		}
		if (member > 1) {
			size_t n = strlen(name);
			snprintf(name + n, sizeof name - n, "-%d", member);
		}
	}
	char suffix[24] = "";
	if (member > 1)
		snprintf(suffix, sizeof suffix, ".%d", member);
	if (evo_path_fmt(kept, sizeof kept, &err, "%s/%s.net", l->run_dir,
			 name) ||
	    evo_write_file_atomic(kept, text, len, &err))
		return raise_msg(L, err.msg);
	char folder[200], replaced[1300], what[200];
	snprintf(folder, sizeof folder, "Skills/%s", skill);
	snprintf(what, sizeof what, "%s%s%s%s", team_name ? team_name : "",
		 team_name ? "-" : "", skill, suffix);
	if (evo_path_fmt(path, sizeof path, &err, "%s/Skills/%s/%s%s.net", root,
			 skill, skill, suffix))
		return raise_msg(L, err.msg);
	if (l->opts->no_save) {
		if (l->tty && member == 1)
			printf("\n");
		printf("champion in %s; %s left as it was (--no-save)\n", kept,
		       path);
		return 0;
	}
	if (evo_folder_check_links(root, folder, &err) ||
	    keep_replaced(l, path, text, len, what, replaced, sizeof replaced,
			  &err) ||
	    evo_write_file_atomic(path, text, len, &err))
		return raise_msg(L, lua_pushfstring(L, "%s; the champion is in %s",
						    err.msg, kept));
	/* member networks of an earlier heterogeneous run would run in
	 * place of a homogeneous champion: kept in the run folder, then
	 * removed */
	for (int k = 2; member == 1 && !hetero && l->task->n_teams > 0 &&
			k <= EVO_TEAM_MAX_SIZE;
	     k++) {
		char old[1400], gone[1300], oname[220];
		snprintf(oname, sizeof oname, "%s.%d", what, k);
		if (evo_path_fmt(old, sizeof old, &err,
				 "%s/Skills/%s/%s.%d.net", root, skill, skill,
				 k) ||
		    !evo_file_exists(old) ||
		    keep_replaced(l, old, "", 0, oname, gone, sizeof gone,
				  &err) ||
		    unlink(old) != 0)
			break;
		if (gone[0])
			printf("%s: removed (a homogeneous champion runs in "
			       "every member); kept in %s\n",
			       old, gone);
	}
	if (l->tty && member == 1)
		printf("\n");
	printf("champion saved in %s\n", path);
	if (replaced[0])
		printf("the network it replaced is kept in %s\n", replaced);
	return 0;
}

/* A list of numbers as a userdata left on the stack, so that an error
 * (a second argument that is no table) frees it too. */
static double *number_list(lua_State *L, int idx, int *n)
{
	luaL_checktype(L, idx, LUA_TTABLE);
	lua_Integer len = luaL_len(L, idx);
	if (len < 0 || len > INT_MAX / (lua_Integer)sizeof(double))
		luaL_error(L, "evo.curve: %I values is too many", len);
	*n = (int)len;
	double *v = lua_newuserdatauv(L, (size_t)(*n ? *n : 1) * sizeof *v, 0);
	for (int i = 0; i < *n; i++) {
		lua_geti(L, idx, i + 1);
		v[i] = lua_tonumber(L, -1);
		lua_pop(L, 1);
	}
	return v;
}

/* evo.curve(best, mean[, quiet]): draw curve.png; quiet says nothing (the
 * loop redraws it as it goes and names it once, at the end). */
static int l_curve(lua_State *L)
{
	learn *l = ctx(L);
	int quiet = lua_toboolean(L, 3);
	int nb, nm;
	double *best = number_list(L, 1, &nb), *mean = number_list(L, 2, &nm);
	char path[1200], title[200];
	/* what the picture is of: skill, task, method and seed */
	const char *base = strrchr(l->task_path, '/');
	base = base ? base + 1 : l->task_path;
	const char *dot = strrchr(base, '.');
	int n = dot && dot > base ? (int)(dot - base) : (int)strlen(base);
	const char *method = evo_simbatch_get(l->task->sb, "LEARNINGMETHOD");
	snprintf(title, sizeof title, "%s: %.*s (%s, seed %llu)", l->skill, n,
		 base, method ? method : "?",
		 (unsigned long long)l->opts->seed);
	evo_err err = {{0}};
	if (evo_path_fmt(path, sizeof path, &err, "%s/curve.png", l->run_dir) ||
	    evo_curve_write(path, title, best, mean, nb < nm ? nb : nm, &err))
		return raise_msg(L, err.msg);
	if (!quiet)
		printf("learning curve in %s\n", path);
	return 0;
}

/* evo.heatmap(nx, ny, values[, quiet[, note]]): draw archive.png, the
 * nx x ny grid of values (x + nx * y + 1; NaN where a cell is empty), as
 * evo.curve draws curve.png; note, when given, follows the title (what a
 * CVT archive's picture shows). */
static int l_heatmap(lua_State *L)
{
	/* before ctx, which leaves its box on the stack */
	const char *note = luaL_optstring(L, 5, NULL);
	learn *l = ctx(L);
	lua_Integer nx = luaL_checkinteger(L, 1), ny = luaL_checkinteger(L, 2);
	int quiet = lua_toboolean(L, 4);
	int n;
	if (nx < 1 || ny < 1 || nx > 1000 || ny > 1000)
		return luaL_error(L, "evo.heatmap: %I x %I cells", nx, ny);
	double *v = number_list(L, 3, &n);
	if (n != nx * ny)
		return luaL_error(L, "evo.heatmap: %d values for %I x %I cells",
				  n, nx, ny);
	char path[1200], title[200];
	snprintf(title, sizeof title, "%s: the archive%s%s", l->skill,
		 note ? " " : "", note ? note : "");
	evo_err err = {{0}};
	if (evo_path_fmt(path, sizeof path, &err, "%s/archive.png",
			 l->run_dir) ||
	    evo_heatmap_write(path, title, (int)nx, (int)ny, v, &err))
		return raise_msg(L, err.msg);
	if (!quiet)
		printf("archive heatmap in %s\n", path);
	return 0;
}

/* evo.gallery(title, items): gallery.png of the run folder, a thumbnail
 * of each item, {genome text, caption} (learn/gallery.h; OPENENDED). */
static int l_gallery(lua_State *L)
{
	const char *title = luaL_checkstring(L, 1);
	luaL_checktype(L, 2, LUA_TTABLE);
	evo_gallery_item items[EVO_GALLERY_MAX];
	int n = (int)luaL_len(L, 2);
	if (n < 1 || n > EVO_GALLERY_MAX)
		return luaL_error(L, "evo.gallery: %d items (1 to %d)", n,
				  EVO_GALLERY_MAX);
	luaL_checkstack(L, 2 * n + 4, "evo.gallery");
	for (int k = 0; k < n; k++) {
		lua_geti(L, 2, k + 1);
		luaL_checktype(L, -1, LUA_TTABLE);
		lua_geti(L, -1, 1);
		lua_geti(L, -2, 2);
		items[k].genome = luaL_checkstring(L, -2);
		items[k].caption = luaL_checkstring(L, -1);
		lua_remove(L, -3); /* the strings stay on the stack */
	}
	learn *l = ctx(L);
	char path[1200];
	evo_err err = {{0}};
	evo_task_opts to = {.seed_set = 1, .seed = l->task->seed};
	if (evo_path_fmt(path, sizeof path, &err, "%s/gallery.png", l->run_dir) ||
	    evo_gallery_write(l->task_path, &to, title, items, n, path, &err))
		return raise_msg(L, err.msg);
	return 0;
}

/* evo.clock() -> seconds on a monotonic wall clock (the loop times its
 * checkpoints by it: os.clock counts every thread's CPU). */
static int l_clock(lua_State *L)
{
	lua_pushnumber(L, now());
	return 1;
}

/* evo.save_many(names, texts): files of the run folder, as evo.save
 * writes them but made durable together (one sync for all, not a disk
 * flush each: MAP-Elites' thousands of elites). */
static int l_save_many(lua_State *L)
{
	learn *l = ctx(L);
	luaL_checktype(L, 1, LUA_TTABLE);
	luaL_checktype(L, 2, LUA_TTABLE);
	if (!l->log_open)
		return luaL_error(L, "evo.save_many before evo.open_log");
	lua_Integer n = luaL_len(L, 1);
	if (luaL_len(L, 2) != n)
		return luaL_error(L, "evo.save_many: %I names, %I texts", n,
				  luaL_len(L, 2));
	char checked[1024] = "";
	evo_err err = {{0}};
	for (lua_Integer i = 1; i <= n; i++) {
		lua_geti(L, 1, i);
		lua_geti(L, 2, i);
		const char *name = run_file_name(L, -2, "evo.save_many");
		size_t len;
		const char *text = luaL_checklstring(L, -1, &len);
		const char *slash = strrchr(name, '/');
		char folder[1024] = "";
		if (slash)
			snprintf(folder, sizeof folder, "%.*s",
				 (int)(slash - name), name);
		/* a folder's links are checked once */
		if (slash && strcmp(folder, checked) != 0) {
			char path[1200];
			if (evo_folder_check_links(l->run_dir, folder, &err))
				return raise_msg(L, err.msg);
			if (evo_path_fmt(path, sizeof path, &err, "%s/%s",
					 l->run_dir, folder))
				return raise_msg(L, err.msg);
			mkdir(path, 0755);
			snprintf(checked, sizeof checked, "%s", folder);
		}
		char path[1200];
		if (evo_path_fmt(path, sizeof path, &err, "%s/%s", l->run_dir,
				 name) ||
		    evo_write_file_replace(path, text, len, &err))
			return raise_msg(L, err.msg);
		lua_pop(L, 2);
	}
	evo_sync_all();
	return 0;
}

static int l_print(lua_State *L)
{
	printf("%s\n", luaL_checkstring(L, 1));
	fflush(stdout);
	return 0;
}

/* ---- LEARNSIMCONTINUOUS (docs/learning.md) ----------------------------- */

/* evo.begin_turn(skill, nets): from now on the candidates run as skill (a
 * name of evo.order), and every skill named in nets (skill -> a file of
 * the run folder) runs that network instead of its Skills/ one. The
 * evaluator is made anew for the turn, with the same threads, seed,
 * repetitions and ticks. */
static int l_begin_turn(lua_State *L)
{
	learn *l = ctx(L);
	const char *skill = luaL_checkstring(L, 1);
	luaL_checktype(L, 2, LUA_TTABLE);
	int k = evo_mindfolder_skill(l->task->mind, skill);
	if (k < 0 || !l->task->mind->net[k])
		return luaL_error(L,
				  "evo.begin_turn: %s is no neural skill of "
				  "the hierarchy",
				  skill);
	unsigned n = 0;
	evo_err err = {{0}};
	for (int i = 0; i < l->n_order; i++) {
		const char *name = l->task->mind->skill[l->order[i]].name;
		lua_getfield(L, 2, name);
		const char *file = lua_tostring(L, -1);
		if (file) {
			if (evo_path_fmt(l->choice_path[n],
					 sizeof l->choice_path[n], &err,
					 "%s/%s", l->run_dir, file))
				return raise_msg(L, err.msg);
			l->choice[n].skill = name;
			l->choice[n].source = l->choice_path[n];
			n++;
		}
		lua_pop(L, 1);
	}
	snprintf(l->skill, sizeof l->skill, "%s", skill);
	l->ed.learning_skill = l->skill;
	l->ed.nets = l->choice;
	l->ed.n_nets = n;
	evo_evaluator_destroy(l->ev);
	l->ev = evo_evaluator_create(&l->ed, &err);
	if (!l->ev)
		return raise_msg(L, err.msg);
	lua_pushinteger(L, (lua_Integer)evo_evaluator_n_in(l->ev));
	lua_pushinteger(L, (lua_Integer)evo_evaluator_n_out(l->ev));
	return 2;
}

/* evo.grow(task, skill, nets): OPENENDED's development (docs/openended.md):
 * the evaluator is made anew from task, a .simbatch in the run folder (the
 * grown mind folder's), the candidates running as skill, and every skill
 * named in nets (skill -> a file of the run folder) running that network
 * instead of its Skills/ one; with the same threads, seed, repetitions and
 * ticks, in this process and on every MPI rank. Returns the candidates'
 * inputs and outputs. */
static int l_grow(lua_State *L)
{
	learn *l = ctx(L);
	const char *task = luaL_checkstring(L, 1);
	const char *skill = luaL_checkstring(L, 2);
	luaL_checktype(L, 3, LUA_TTABLE);
	evo_err err = {{0}};
	if (evo_path_fmt(l->grown_task, sizeof l->grown_task, &err, "%s/%s",
			 l->run_dir, task))
		return raise_msg(L, err.msg);
	unsigned n = 0;
	lua_pushnil(L);
	while (lua_next(L, 3)) {
		const char *name = lua_tostring(L, -2);
		const char *file = lua_tostring(L, -1);
		if (!name || !file || n == CONT_MAX_SKILLS)
			return luaL_error(L, "evo.grow: nets must map at most "
					     "%d skills to files",
					  CONT_MAX_SKILLS);
		snprintf(l->choice_skill[n], sizeof l->choice_skill[n], "%s",
			 name);
		if (evo_path_fmt(l->choice_path[n], sizeof l->choice_path[n],
				 &err, "%s/%s", l->run_dir, file))
			return raise_msg(L, err.msg);
		l->choice[n].skill = l->choice_skill[n];
		l->choice[n].source = l->choice_path[n];
		n++;
		lua_pop(L, 1);
	}
	snprintf(l->skill, sizeof l->skill, "%s", skill);
	l->ed.task_path = l->grown_task;
	l->ed.learning_skill = l->skill;
	l->ed.nets = l->choice;
	l->ed.n_nets = n;
	evo_evaluator_destroy(l->ev);
	l->ev = evo_evaluator_create(&l->ed, &err);
	if (!l->ev)
		return raise_msg(L, err.msg);
	/* MPI ranks (sim/cluster/) make theirs anew the same way */
	const evo_eval_spread *sp = l->ed.spread;
	if (sp && sp->remake && sp->remake(sp->ctx, l->ev, &l->ed, &err))
		return raise_msg(L, err.msg);
	lua_pushinteger(L, (lua_Integer)evo_evaluator_n_in(l->ev));
	lua_pushinteger(L, (lua_Integer)evo_evaluator_n_out(l->ev));
	return 2;
}

/* evo.read_skill_net(skill) -> the text of Skills/<skill>/<skill>.net, or
 * nil when there is none. */
static int l_read_skill_net(lua_State *L)
{
	learn *l = ctx(L);
	const char *skill = luaL_checkstring(L, 1);
	char path[1400];
	evo_err err;
	if (evo_path_fmt(path, sizeof path, &err, "%s/Skills/%s/%s.net",
			 l->task->mind->root, skill, skill))
		return raise_msg(L, err.msg);
	struct stat st;
	if (stat(path, &st) != 0) {
		lua_pushnil(L);
		return 1;
	}
	char *text;
	size_t len;
	if (evo_read_file(path, &text, &len, &err))
		return raise_msg(L, err.msg);
	lua_pushlstring(L, text, len);
	free(text);
	return 1;
}

/* evo.save_skill_net(skill, text): the skill's network in its folder,
 * Skills/<skill>/<skill>.net, where DEMOSIM and evo export find it. */
static int l_save_skill_net(lua_State *L)
{
	learn *l = ctx(L);
	const char *skill = luaL_checkstring(L, 1);
	size_t len;
	const char *text = luaL_checklstring(L, 2, &len);
	char path[1400];
	evo_err err;
	char folder[200], replaced[1300];
	if (l->opts->no_save)
		return 0;
	snprintf(folder, sizeof folder, "Skills/%s", skill);
	if (evo_path_fmt(path, sizeof path, &err, "%s/Skills/%s/%s.net",
			 l->task->mind->root, skill, skill) ||
	    evo_folder_check_links(l->task->mind->root, folder, &err) ||
	    keep_replaced(l, path, text, len, skill, replaced, sizeof replaced,
			  &err) ||
	    evo_write_file_atomic(path, text, len, &err))
		return raise_msg(L, err.msg);
	if (replaced[0])
		printf("%s: the network it replaced is kept in %s\n", path,
		       replaced);
	return 0;
}

/* evo.learn.warning(text): a method's warning on the task, counted with
 * the task reader's (evo check ends with how many there were). */
static int l_warning(lua_State *L)
{
	evo_warning("%s", luaL_checkstring(L, 1));
	return 0;
}

static const luaL_Reg learn_fns[] = {
    {"warning", l_warning},
    {"evaluate", l_evaluate},
    {"descriptors", l_descriptors},
    {"set_team_net", l_set_team_net},
    {"set_genome", l_set_genome},
    {"open_log", l_open_log},
    {"log", l_log},
    {"save", l_save},
    {"read", l_read},
    {"save_champion", l_save_champion},
    {"curve", l_curve},
    {"heatmap", l_heatmap},
    {"gallery", l_gallery},
    {"clock", l_clock},
    {"save_many", l_save_many},
    {"print", l_print},
    {"begin_turn", l_begin_turn},
    {"grow", l_grow},
    {"read_skill_net", l_read_skill_net},
    {"save_skill_net", l_save_skill_net},
    {NULL, NULL},
};

/* Push two tables of a task: key -> value, and key -> its line in the
 * file (for messages). */
static void push_task(lua_State *L, const evo_simbatch *sb)
{
	lua_newtable(L);
	lua_newtable(L);
	for (unsigned i = 0; i < sb->n_pairs; i++) {
		lua_pushstring(L, sb->pair[i].value);
		lua_setfield(L, -3, sb->pair[i].key);
		lua_pushinteger(L, sb->pair[i].line);
		lua_setfield(L, -2, sb->pair[i].key);
	}
}

/* evo.teams of a team task (docs/teams.md): heterogeneous, own, alternate,
 * and learning, the learning teams in LEARNINGTEAM's order, each {index
 * (1-based), name, size, skill, inputs, outputs, layers}. */
static void push_teams(lua_State *L, const learn *l)
{
	const evo_task *t = l->task;
	lua_createtable(L, 0, 4);
	lua_pushboolean(L, t->heterogeneous);
	lua_setfield(L, -2, "heterogeneous");
	lua_pushboolean(L, t->own_fitness);
	lua_setfield(L, -2, "own");
	lua_pushinteger(L, t->alternate);
	lua_setfield(L, -2, "alternate");
	lua_createtable(L, t->n_learning, 0);
	for (int i = 0; i < t->n_learning; i++) {
		int k = t->learning[i];
		const evo_team *tm = &t->team[k];
		int sk = evo_mindfolder_skill(tm->mind, tm->learning_skill);
		lua_createtable(L, 0, 7);
		lua_pushinteger(L, k + 1);
		lua_setfield(L, -2, "index");
		lua_pushstring(L, tm->name);
		lua_setfield(L, -2, "name");
		lua_pushinteger(L, tm->size);
		lua_setfield(L, -2, "size");
		lua_pushstring(L, tm->learning_skill);
		lua_setfield(L, -2, "skill");
		lua_pushinteger(L, evo_evaluator_team_n_in(l->ev, k));
		lua_setfield(L, -2, "inputs");
		lua_pushinteger(L, evo_evaluator_team_n_out(l->ev, k));
		lua_setfield(L, -2, "outputs");
		lua_pushinteger(
		    L, sk >= 0 ? (lua_Integer)tm->mind->skill[sk].layers : 1);
		lua_setfield(L, -2, "layers");
		lua_rawseti(L, -2, i + 1);
	}
	lua_setfield(L, -2, "learning");
	lua_setfield(L, -2, "teams");
}

static int open_module(lua_State *L)
{
	learn *l = ctx(L);
	lua_newtable(L);
	luaL_setfuncs(L, learn_fns, 0);
	/* Where each key is, for messages: evo.task_path, evo.task_lines. */
	push_task(L, l->task->sb);
	lua_setfield(L, -3, "task_lines");
	lua_setfield(L, -2, "task");
	lua_pushstring(L, l->task_path);
	lua_setfield(L, -2, "task_path");
	if (evo_evaluator_deferred_success(l->ev)) {
		lua_pushcfunction(L, l_success_test);
		lua_setfield(L, -2, "success_test");
	}
	lua_pushinteger(L, (lua_Integer)l->opts->seed);
	lua_setfield(L, -2, "seed");
	lua_pushinteger(L, (lua_Integer)evo_evaluator_n_in(l->ev));
	lua_setfield(L, -2, "inputs");
	lua_pushinteger(L, (lua_Integer)evo_evaluator_n_out(l->ev));
	lua_setfield(L, -2, "outputs");
	lua_pushboolean(L, l->opts->resume);
	lua_setfield(L, -2, "resume");
	lua_pushstring(L, l->run_dir);
	lua_setfield(L, -2, "run_dir");
	lua_pushstring(L, l->skill); /* the learning skill (nil: none) */
	lua_setfield(L, -2, "skill");
	lua_pushinteger(L, evo_evaluator_reps(l->ev));
	lua_setfield(L, -2, "reps");
	/* the environment script's path, and where its require looks
	 * (OPENENDED loads its generator, in a sandbox of its own) */
	const char *env_path = evo_evaluator_env_path(l->ev);
	if (env_path) {
		lua_pushstring(L, env_path);
		lua_setfield(L, -2, "env_path");
	}
	lua_pushstring(L, l->task->mind->root);
	lua_setfield(L, -2, "mind_dir");
	lua_pushstring(L, evo_lua_dir());
	lua_setfield(L, -2, "lua_dir");
	/* a scene script's limits and require for the generator */
	evo_lua_limits lim;
	evo_err lerr;
	if (l->mem && !evo_lua_limits_read(l->task->sb, l->task_path, &lim,
					   &lerr)) {
		evo_lua_open_guard(L, l->mem, &lim, l->task->mind->root);
		lua_setfield(L, -2, "guard");
	}
	lua_pushinteger(L, (lua_Integer)evo_evaluator_ticks(l->ev));
	lua_setfield(L, -2, "ticks");
	/* the environment's metrics, in the order of evaluate's lists */
	int nm = evo_evaluator_n_metrics(l->ev);
	lua_createtable(L, nm, 0);
	for (int k = 0; k < nm; k++) {
		lua_pushstring(L, evo_evaluator_metric_name(l->ev, k));
		lua_rawseti(L, -2, k + 1);
	}
	lua_setfield(L, -2, "metrics");
	if (l->opts->generations > 0) {
		lua_pushinteger(L, l->opts->generations);
		lua_setfield(L, -2, "generations");
	}
	/* GENETIC and ANNEALING evolve the fixed layered network of the
	 * skill's `layers:` (1 when absent, as the .ades reader says). */
	int k = evo_mindfolder_skill(l->task->mind, l->skill);
	lua_pushinteger(L, k >= 0 ? (lua_Integer)l->task->mind->skill[k].layers
				  : 1);
	lua_setfield(L, -2, "layers");
	if (l->task->n_teams > 0)
		push_teams(L, l);
	if (l->continuous) {
		/* evo.order: the skills of the turns, each {name, inputs,
		 * outputs, layers} */
		lua_createtable(L, l->n_order, 0);
		for (int i = 0; i < l->n_order; i++) {
			const evo_ades *a = &l->task->mind->skill[l->order[i]];
			lua_createtable(L, 0, 4);
			lua_pushstring(L, a->name);
			lua_setfield(L, -2, "name");
			lua_pushinteger(L, (lua_Integer)a->n_in);
			lua_setfield(L, -2, "inputs");
			lua_pushinteger(L, (lua_Integer)a->n_out);
			lua_setfield(L, -2, "outputs");
			lua_pushinteger(L, (lua_Integer)a->layers);
			lua_setfield(L, -2, "layers");
			lua_rawseti(L, -2, i + 1);
		}
		lua_setfield(L, -2, "order");
	}
	return 1;
}

static int run_script(lua_State *L)
{
	learn *l = lua_touserdata(L, 1);
	luaL_openlibs(L);
	lua_pushlightuserdata(L, l);
	lua_rawsetp(L, LUA_REGISTRYINDEX, &LEARN_KEY);
	luaL_requiref(L, "evo.learn", open_module, 0);
	lua_pop(L, 1);
	evo_lua_open_linalg(L); /* evo.linalg: CMA-ES's eigendecomposition */
	evo_lua_open_neat(L);
	evo_lua_open_novelty(L); /* evo.novelty: novelty search's kNN */
	/* the loop's modules are evo's, from lua/ only: a mind folder is
	 * not trusted with the full libraries this state has */
	const char *dir = evo_lua_dir();
	evo_lua_set_path(L, dir);
	evo_lua_modcache_install(L); /* compiled by the options' check */
	evo_lua_open_data(L);
	char path[1200];
	evo_err err;
	if (evo_path_fmt(path, sizeof path, &err, "%s/learn/%s", dir,
			 l->continuous	   ? "continuous.lua"
			 : l->openended ? "openended.lua"
					: "learnsim.lua"))
		return raise_msg(L, err.msg);
	if (luaL_loadfilex(L, path, "t") != LUA_OK)
		return lua_error(L);
	lua_call(L, 0, 0);
	return 0;
}

/* LEARNSIMCONTINUOUS's turns: the neural skills SKILLORDER names, in its
 * order (names joined by ','), else every neural skill of the hierarchy
 * bottom-up, the reverse of the loader's top-down order, so that each
 * skill is trained after its sub-skills. 0, or -1 with err at SKILLORDER's
 * line. */
static int continuous_order(const char *task_path, const evo_task *t,
			    int *order, int *n, evo_err *err)
{
	const evo_mindfolder *m = t->mind;
	*n = 0;
	const char *v = evo_simbatch_get(t->sb, "SKILLORDER");
	if (!v) {
		for (int k = (int)m->n_skills - 1; k >= 0; k--)
			if (m->net[k]) {
				if (*n == CONT_MAX_SKILLS)
					return evo_fail(err,
							"%s: more than %d "
							"neural skills",
							task_path,
							CONT_MAX_SKILLS);
				order[(*n)++] = k;
			}
		if (*n == 0)
			return evo_fail(err,
					"%s: the hierarchy under %s has no "
					"neural skill to train",
					task_path, m->skill[0].name);
		return 0;
	}
	unsigned line = 0;
	for (unsigned i = 0; i < t->sb->n_pairs; i++)
		if (strcmp(t->sb->pair[i].key, "SKILLORDER") == 0)
			line = t->sb->pair[i].line;
	char names[1024] = "";
	for (unsigned k = 0; k < m->n_skills; k++)
		if (m->net[k]) {
			size_t u = strlen(names);
			snprintf(names + u, sizeof names - u, "%s%s",
				 u ? ", " : "", m->skill[k].name);
		}
	const char *p = v;
	for (;;) {
		size_t len = strcspn(p, ",");
		int k = -1;
		for (unsigned j = 0; j < m->n_skills; j++)
			if (strlen(m->skill[j].name) == len &&
			    strncmp(m->skill[j].name, p, len) == 0)
				k = (int)j;
		if (len == 0)
			return evo_fail(err,
					"%s:%u: SKILLORDER: expected skill "
					"names joined by ',', found '%s'",
					task_path, line, v);
		if (k < 0 || !m->net[k])
			return evo_fail(err,
					"%s:%u: SKILLORDER names %.*s, which "
					"is not a neural skill of the "
					"hierarchy under %s (its neural "
					"skills: %s)",
					task_path, line, (int)len, p,
					m->skill[0].name, names);
		for (int i = 0; i < *n; i++)
			if (order[i] == k)
				return evo_fail(err,
						"%s:%u: SKILLORDER names %s "
						"twice",
						task_path, line,
						m->skill[k].name);
		if (*n == CONT_MAX_SKILLS)
			return evo_fail(err,
					"%s:%u: SKILLORDER names more "
					"than %d skills",
					task_path, line, CONT_MAX_SKILLS);
		order[(*n)++] = k;
		if (!p[len])
			return 0;
		p += len + 1;
	}
}

/* evo check on a LEARNSIM task, and evo run before anything starts: the
 * method's options as the loop reads them (common.task_options), each
 * within its range (the module's `ranges`); warnings only when loud. */
static const char CHECK_OPTIONS[] =
    "local method, task, path, lines, quiet, openended = ...\n"
    "local common = require 'learn.common'\n"
    "if openended then require('learn.openended_options').check(task, "
    "path, lines) end\n"
    "common.task_options(require(common.MODULES[method]), task, path, "
    "lines, quiet)\n";

static int check_options(lua_State *L)
{
	const char *task_path = lua_touserdata(L, 1);
	const evo_task *task = lua_touserdata(L, 2);
	int quiet = lua_toboolean(L, 3);
	luaL_openlibs(L);
	evo_lua_set_path(L, evo_lua_dir());
	/* the methods' warnings are counted as under evo run */
	luaL_getsubtable(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
	lua_newtable(L);
	lua_pushcfunction(L, l_warning);
	lua_setfield(L, -2, "warning");
	lua_setfield(L, -2, "evo.learn");
	lua_pop(L, 1);
	evo_lua_modcache_install(L); /* the loop's state reuses them */
	if (luaL_loadbufferx(L, CHECK_OPTIONS, sizeof CHECK_OPTIONS - 1,
			     "=evo check", "t") != LUA_OK)
		return lua_error(L);
	const char *method = evo_simbatch_get(task->sb, "LEARNINGMETHOD");
	lua_pushstring(L, method ? method : "NEAT");
	push_task(L, task->sb);
	lua_pushstring(L, task_path);
	lua_insert(L, -2); /* method, task, path, lines */
	lua_pushboolean(L, quiet);
	lua_pushboolean(L, strcmp(task->type, "OPENENDED") == 0);
	lua_call(L, 6, 0);
	return 0;
}

/* The line of key in the task file, 0 when absent. */
static unsigned task_line(const evo_task *t, const char *key)
{
	for (unsigned i = 0; i < t->sb->n_pairs; i++)
		if (strcmp(t->sb->pair[i].key, key) == 0)
			return t->sb->pair[i].line;
	return 0;
}

/* GENETIC and ANNEALING evolve the whole layered network of skill a (its
 * `layers:`, HIDDEN wide or evo_net_layered_width): it must fit evo's
 * networks, or the first population would be as large as it is before
 * any network is built from it. 0, or -1 with err at HIDDEN's line. */
static int layered_fits(const char *path, const evo_task *t,
			const evo_ades *a, evo_err *err)
{
	const char *method = evo_simbatch_get(t->sb, "LEARNINGMETHOD");
	if (!method || strcasecmp(method, "NEAT") == 0)
		return 0; /* NEAT grows its own, from no hidden node */
	const char *hv = evo_simbatch_get(t->sb, "HIDDEN");
	/* the parser checked HIDDEN's range */
	unsigned width = hv ? (unsigned)strtoul(hv, NULL, 10)
			    : evo_net_layered_width(a->n_in, a->n_out);
	size_t n = evo_net_layered_weight_count(a->n_in, a->n_out, a->layers,
						width);
	evo_status st = EVO_ERR_LIMIT;
	if (n <= EVO_NET_MAX_NODES + EVO_NET_MAX_LINKS) {
		double *w = calloc(n ? n : 1, sizeof *w);
		evo_netdesc *d = malloc(sizeof *d);
		st = w && d ? evo_net_build_layered(a->n_in, a->n_out,
						    a->layers, width, 0, 0, w,
						    d)
			    : EVO_ERR_LIMIT;
		free(w);
		free(d);
	}
	if (st == EVO_OK)
		return 0;
	char where[1200];
	if (hv)
		snprintf(where, sizeof where, "%s:%u: HIDDEN:%s", path,
			 task_line(t, "HIDDEN"), hv);
	else
		snprintf(where, sizeof where, "%s", path);
	return evo_fail(err,
			"%s: %s's network, %u input%s, %u hidden layer%s of %u "
			"nodes and %u output%s, is larger than a network of "
			"evo holds (%d nodes, %d links, %d links into a node): "
			"lower %s",
			where, a->name, a->n_in, a->n_in == 1 ? "" : "s",
			a->layers, a->layers == 1 ? "" : "s", width, a->n_out,
			a->n_out == 1 ? "" : "s", EVO_NET_MAX_NODES,
			EVO_NET_MAX_LINKS, EVO_NET_MAX_FANIN,
			hv ? "HIDDEN" : "the skill's layers: or give HIDDEN");
}

/* Every network the task trains fits (layered_fits). */
static int networks_fit(const char *path, const evo_task *t,
			const int *order, int n_order, evo_err *err)
{
	if (n_order > 0) {
		for (int i = 0; i < n_order; i++)
			if (layered_fits(path, t, &t->mind->skill[order[i]],
					 err))
				return -1;
		return 0;
	}
	if (t->n_teams > 0) {
		for (int i = 0; i < t->n_learning; i++) {
			const evo_team *tm = &t->team[t->learning[i]];
			int k = evo_mindfolder_skill(tm->mind,
						     tm->learning_skill);
			if (k >= 0 &&
			    layered_fits(path, t, &tm->mind->skill[k], err))
				return -1;
		}
		return 0;
	}
	const char *skill = evo_simbatch_get(t->sb, "LEARNINGSKILL");
	int k = skill ? evo_mindfolder_skill(t->mind, skill) : -1;
	return k >= 0 ? layered_fits(path, t, &t->mind->skill[k], err) : 0;
}

/* evo check's and evo run's check of a learning task: its turns, the
 * method's options and the size of its networks. */
static int learn_check(const char *task_path, evo_task *task, int quiet,
		       evo_err *err)
{
	int order[CONT_MAX_SKILLS], n = 0;
	if (strcmp(task->type, "LEARNSIMCONTINUOUS") == 0 &&
	    continuous_order(task_path, task, order, &n, err))
		return -1;
	evo_lua_limits lim;
	if (evo_lua_limits_read(task->sb, task_path, &lim, err))
		return -1;
	evo_lua_mem *mem;
	lua_State *L = evo_lua_state_new(lim.memory, &mem);
	if (!L)
		return evo_fail(err, "cannot create a Lua state");
	lua_pushcfunction(L, check_options);
	lua_pushlightuserdata(L, (void *)task_path);
	lua_pushlightuserdata(L, task);
	lua_pushboolean(L, quiet);
	int rc = 0;
	mem->enforce = 1;
	if (lua_pcall(L, 3, 0, 0) != LUA_OK)
		rc = evo_fail(err, "%s", evo_lua_errstr(L, -1));
	evo_lua_state_close(L, mem);
	if (rc == 0 && networks_fit(task_path, task, order, n, err))
		rc = -1;
	return rc;
}

int evo_learn_check(const char *task_path, evo_task *task, evo_err *err)
{
	return learn_check(task_path, task, 0, err);
}

/* Ctrl-C (SIGINT) and a scheduler's SIGTERM stop a run at once, as they
 * always did; the handler first says how to go on. Every generation's log
 * row is already on disk, and a checkpoint at most a second of the loop's
 * CPU time old (lua/learn/learnsim.lua), written atomically; --resume
 * goes on from it and does the generations after it again, identically. */
static char interrupt_msg[1400];
static size_t interrupt_len;

static void on_interrupt(int sig)
{
	ssize_t n = write(STDERR_FILENO, interrupt_msg, interrupt_len);
	(void)n;
	signal(sig, SIG_DFL);
	raise(sig);
}

static void catch_interrupt(const learn *l, struct sigaction old[2])
{
	char args[200];
	evo_run_record_args(l->opts, args, sizeof args);
	int n = snprintf(interrupt_msg, sizeof interrupt_msg,
			 "\ninterrupted: %s holds the run as of its last "
			 "checkpoint, at most a second of work back; "
			 "%s%s run %s%s --resume%s%s goes on%s\n",
			 l->run_dir, l->opts->spread ? "mpirun -np N " : "",
			 l->opts->argv0 ? l->opts->argv0 : "evo",
			 l->task_path, args,
			 l->opts->run_dir ? " --run " : "",
			 l->opts->run_dir ? l->opts->run_dir : "",
			 l->opts->spread ? ", with any number of ranks N, or "
					   "without mpirun"
					 : "");
	interrupt_len = n < 0 ? 0
		      : (size_t)n < sizeof interrupt_msg ? (size_t)n
							 : sizeof interrupt_msg - 1;
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_interrupt;
	sigemptyset(&sa.sa_mask);
	static const int sigs[2] = {SIGINT, SIGTERM};
	for (int k = 0; k < 2; k++) {
		sigaction(sigs[k], NULL, &old[k]);
		/* A shell runs background jobs with SIGINT ignored; keep that. */
		if (old[k].sa_handler != SIG_IGN)
			sigaction(sigs[k], &sa, NULL);
	}
}

int evo_learn_run(const char *task_path, evo_task *task,
		  const evo_learn_opts *o, evo_err *err)
{
	learn l;
	memset(&l, 0, sizeof l);
	l.task_path = task_path;
	l.task = task;
	l.opts = o;
	l.tty = evo_terminal_output(fileno(stdout));
	l.started = now();
	l.n_behaviour = -1;
	l.continuous = strcmp(task->type, "LEARNSIMCONTINUOUS") == 0;
	l.openended = strcmp(task->type, "OPENENDED") == 0;
	/* every option within its range before a thread, a folder or a
	 * population exists; the loop says the warnings */
	if (learn_check(task_path, task, 1, err))
		return -1;
	if (l.continuous) {
		if (continuous_order(task_path, task, l.order, &l.n_order, err))
			return -1;
		snprintf(l.skill, sizeof l.skill, "%s",
			 task->mind->skill[l.order[0]].name);
	} else {
		snprintf(l.skill, sizeof l.skill, "%s",
			 task->n_teams > 0
			     ? task->team[task->learning[0]].learning_skill
			     : evo_simbatch_get(task->sb, "LEARNINGSKILL"));
	}
	if (evo_learn_run_dir(task_path, task, o, l.run_dir, sizeof l.run_dir,
			      err))
		return -1;
	if (!o->run_dir) {
		/* the run folder is the mind folder's: no link it ships
		 * sends the run elsewhere */
		if (evo_folder_check_links(
			task->mind->root,
			l.run_dir + strlen(task->mind->root) + 1, err))
			return -1;
	}
	l.ed = (evo_eval_def){
		.task_path = task_path,
		.threads = o->threads,
		.seed = o->seed,
		.ticks = o->ticks,
		.spread = o->spread,
		.learning_skill = l.continuous ? l.skill : NULL,
	};
	/* the skill's folder, where the champion goes, is checked again
	 * when it is saved; a link there is better said before training */
	if (task->n_teams == 0) {
		char folder[200];
		snprintf(folder, sizeof folder, "Skills/%s", l.skill);
		if (evo_folder_check_links(task->mind->root, folder, err))
			return -1;
	}
	int lock = evo_runlog_claim(l.run_dir, err);
	if (lock < 0)
		return -1;
	l.ev = evo_evaluator_create(&l.ed, err);
	if (!l.ev) {
		close(lock);
		return -1;
	}
	int threads = evo_evaluator_threads(l.ev);
	int sims = evo_evaluator_remotes(l.ev);
	char where[96];
	if (sims)
		snprintf(where, sizeof where,
			 "%d environment%s on %d remote simulator%s", threads,
			 threads == 1 ? "" : "s", sims, sims == 1 ? "" : "s");
	else
		snprintf(where, sizeof where, "%d thread%s", threads,
			 threads == 1 ? "" : "s");
	if (l.continuous) {
		/* what the run does, defaults included: the order of the
		 * turns, the rounds, the validation evaluations */
		char order[512];
		size_t at = 0;
		for (int i = 0; i < l.n_order && at < sizeof order; i++)
			at += (size_t)snprintf(
			    order + at, sizeof order - at, "%s%s",
			    i == 0		    ? ""
			    : i == l.n_order - 1 ? " and "
						 : ", ",
			    task->mind->skill[l.order[i]].name);
		const char *rounds = evo_simbatch_get(task->sb, "ROUNDS");
		const char *val = evo_simbatch_get(task->sb, "VALIDATION");
		printf("%s: %s of skills %s in turn, %s%s, %s validation "
		       "evaluations, seed %llu, %s, run folder %s\n",
		       task_path, evo_simbatch_get(task->sb, "LEARNINGMETHOD"),
		       order, rounds ? rounds : "rounds until stopped",
		       !rounds ? ""
		       : strcmp(rounds, "1") == 0 ? " round"
						  : " rounds",
		       val ? val : "4", (unsigned long long)o->seed, where,
		       l.run_dir);
	} else
		printf("%s: %s of skill %s, seed %llu, %s, run folder %s\n",
		       task_path,
		       l.openended ? "OPENENDED (NEAT agents)"
				   : evo_simbatch_get(task->sb, "LEARNINGMETHOD"),
		       l.skill, (unsigned long long)o->seed, where, l.run_dir);
	fflush(stdout);
	evo_run_record was = {0};
	if (o->resume && evo_run_record_read(l.run_dir, &was, err) == 0 &&
	    was.found && was.generations != o->generations) {
		if (was.generations)
			printf("the run was started with --generations %d; "
			       "it now runs %d generations\n",
			       was.generations, o->generations);
		else
			printf("the run was started without --generations "
			       "(the task's NUMGEN); it now runs %d "
			       "generations\n",
			       o->generations);
	}
	if ((!o->resume && evo_runlog_set_aside(l.run_dir, err)) ||
	    evo_run_record_write(l.run_dir, o, err)) {
		close(lock);
		evo_evaluator_destroy(l.ev);
		return -1;
	}
	if (o->resume) {
		char args[200];
		evo_run_record_args(o, args, sizeof args);
		printf("resuming %s with the options it was started with:%s\n",
		       l.run_dir, args);
	}
	evo_lua_limits lim;
	if (evo_lua_limits_read(task->sb, task_path, &lim, err)) {
		close(lock);
		evo_evaluator_destroy(l.ev);
		return -1;
	}
	struct sigaction old_sig[2];
	catch_interrupt(&l, old_sig);
	/* The loop is evo's own code, one call that lasts the whole run and
	 * waits in evo.evaluate most of it, so it has no instruction budget
	 * or time limit: SIGINT and SIGTERM end it at once (catch_interrupt),
	 * and what it reads from files, a checkpoint, is read as data
	 * (evo.data). Its memory is bounded (LUAMEMORY, docs/lua.md). */
	evo_lua_mem *mem;
	lua_State *L = evo_lua_state_new(lim.memory, &mem);
	l.mem = L ? mem : NULL;
	int rc = 0;
	if (!L) {
		rc = evo_fail(err, "cannot create a Lua state");
	} else {
		lua_pushcfunction(L, run_script);
		lua_pushlightuserdata(L, &l);
		mem->enforce = 1;
		int r = lua_pcall(L, 1, 0, 0);
		mem->enforce = 0;
		if (r != LUA_OK) {
			if (l.tty)
				printf("\n");
			if (r == LUA_ERRMEM && mem->hit)
				rc = evo_fail(err,
					      "%s: the learning loop's Lua "
					      "state reached its memory limit "
					      "of %zu MB (LUAMEMORY raises it, "
					      "docs/lua.md)",
					      task_path, lim.memory >> 20);
			else
				rc = evo_fail(err, "%s", evo_lua_errstr(L, -1));
		}
		evo_lua_state_close(L, mem);
	}
	if (l.log_open)
		evo_runlog_close(&l.log);
	sigaction(SIGINT, &old_sig[0], NULL);
	sigaction(SIGTERM, &old_sig[1], NULL);
	evo_evaluator_destroy(l.ev);
	free(l.descs);
	close(lock);
	return rc;
}

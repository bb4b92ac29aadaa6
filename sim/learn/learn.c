/* LEARNSIM: the learning loop in Lua (lua/learn/learnsim.lua) over the C
 * evaluator (sim/learn/learn.h, docs/learning.md).
 *
 * The loop runs in a Lua state of its own, apart from the workers' scene
 * states. It reaches C through the `evo.learn` module set up here (the
 * scene scripts have their own `evo` module, sim/lua/lua_evo.c): evaluate a
 * batch of networks, log a generation, save files into the run folder,
 * save the champion, draw the curve (and MAP-Elites' heatmap).
 *
 * This file sets the module up, checks the task's options, runs the
 * script and catches Ctrl-C; the module's functions live by what they
 * touch in learn_eval.c (batches), learn_runfolder.c (the run folder) and
 * learn_skills.c (LEARNSIMCONTINUOUS's turns, OPENENDED's development),
 * sharing sim/learn/learn_internal.h. */
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
#include "learn/learn_internal.h"
#include "learn/literature.h"
#include "learn/lua_linalg.h"
#include "learn/lua_modcache.h"
#include "learn/lua_neat.h"
#include "learn/lua_novelty.h"
#include "learn/runlog.h"
#include "learn/runopts.h"
#include "lua/lua_evo.h"
#include "mind/net_build.h"

/* t[key] = v for the table on top of the stack. */
static void field_int(lua_State *L, const char *key, lua_Integer v)
{
	lua_pushinteger(L, v);
	lua_setfield(L, -2, key);
}

static void field_str(lua_State *L, const char *key, const char *v)
{
	lua_pushstring(L, v);
	lua_setfield(L, -2, key);
}

static void field_bool(lua_State *L, const char *key, int v)
{
	lua_pushboolean(L, v);
	lua_setfield(L, -2, key);
}

static const char LEARN_KEY = 'l';

learn *learn_ctx(lua_State *L)
{
	lua_rawgetp(L, LUA_REGISTRYINDEX, &LEARN_KEY);
	learn *l = lua_touserdata(L, -1);
	lua_pop(L, 1);
	return l;
}

/* An error about a file or a run: its message names the file, so it goes
 * out without the Lua position that luaL_error would put before it. */
int learn_raise_msg(lua_State *L, const char *msg)
{
	lua_pushstring(L, msg);
	return lua_error(L);
}

double learn_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
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
    {"evaluate", learn_l_evaluate},
    {"descriptors", learn_l_descriptors},
    {"set_team_net", learn_l_set_team_net},
    {"set_genome", learn_l_set_genome},
    {"open_log", learn_l_open_log},
    {"log", learn_l_log},
    {"save", learn_l_save},
    {"read", learn_l_read},
    {"save_champion", learn_l_save_champion},
    {"curve", learn_l_curve},
    {"heatmap", learn_l_heatmap},
    {"gallery", learn_l_gallery},
    {"clock", learn_l_clock},
    {"save_many", learn_l_save_many},
    {"print", learn_l_print},
    {"begin_turn", learn_l_begin_turn},
    {"grow", learn_l_grow},
    {"read_skill_net", learn_l_read_skill_net},
    {"save_skill_net", learn_l_save_skill_net},
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
	field_bool(L, "heterogeneous", t->heterogeneous);
	field_bool(L, "own", t->own_fitness);
	field_int(L, "alternate", t->alternate);
	lua_createtable(L, t->n_learning, 0);
	for (int i = 0; i < t->n_learning; i++) {
		int k = t->learning[i];
		const evo_team *tm = &t->team[k];
		int sk = evo_mindfolder_skill(tm->mind, tm->learning_skill);
		lua_createtable(L, 0, 7);
		field_int(L, "index", k + 1);
		field_str(L, "name", tm->name);
		field_int(L, "size", tm->size);
		field_str(L, "skill", tm->learning_skill);
		field_int(L, "inputs", evo_evaluator_team_n_in(l->ev, k));
		field_int(L, "outputs", evo_evaluator_team_n_out(l->ev, k));
		field_int(L, "layers",
			  sk >= 0 ? (lua_Integer)tm->mind->skill[sk].layers : 1);
		lua_rawseti(L, -2, i + 1);
	}
	lua_setfield(L, -2, "learning");
	lua_setfield(L, -2, "teams");
}

static int open_module(lua_State *L)
{
	learn *l = learn_ctx(L);
	lua_newtable(L);
	luaL_setfuncs(L, learn_fns, 0);
	/* Where each key is, for messages: evo.task_path, evo.task_lines. */
	push_task(L, l->task->sb);
	lua_setfield(L, -3, "task_lines");
	lua_setfield(L, -2, "task");
	field_str(L, "task_path", l->task_path);
	if (evo_evaluator_deferred_success(l->ev)) {
		lua_pushcfunction(L, learn_l_success_test);
		lua_setfield(L, -2, "success_test");
	}
	field_int(L, "seed", (lua_Integer)l->opts->seed);
	const evo_eval_settings *set = evo_evaluator_settings(l->ev);
	field_int(L, "inputs", (lua_Integer)set->n_in);
	field_int(L, "outputs", (lua_Integer)set->n_out);
	field_bool(L, "resume", l->opts->resume);
	field_str(L, "run_dir", l->run_dir);
	field_str(L, "skill", l->skill); /* the learning skill (nil: none) */
	field_int(L, "reps", set->reps);
	/* the environment script's path, and where its require looks
	 * (OPENENDED loads its generator, in a sandbox of its own) */
	const char *env_path = evo_evaluator_env_path(l->ev);
	if (env_path)
		field_str(L, "env_path", env_path);
	field_str(L, "mind_dir", l->task->mind->root);
	field_str(L, "lua_dir", evo_lua_dir());
	/* a scene script's limits and require for the generator */
	evo_lua_limits lim;
	evo_err lerr;
	if (l->mem && !evo_lua_limits_read(l->task->sb, l->task_path, &lim,
					   &lerr)) {
		evo_lua_open_guard(L, l->mem, &lim, l->task->mind->root);
		lua_setfield(L, -2, "guard");
	}
	field_int(L, "ticks", (lua_Integer)set->ticks);
	/* the environment's metrics, in the order of evaluate's lists */
	int nm = set->n_metrics;
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
			field_str(L, "name", a->name);
			field_int(L, "inputs", (lua_Integer)a->n_in);
			field_int(L, "outputs", (lua_Integer)a->n_out);
			field_int(L, "layers", (lua_Integer)a->layers);
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
		return learn_raise_msg(L, err.msg);
	if (luaL_loadfilex(L, path, "t") != LUA_OK)
		return lua_error(L);
	lua_call(L, 0, 0);
	return 0;
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
	    learn_continuous_order(task_path, task, order, &n, err))
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
	l.started = learn_now();
	l.n_behaviour = -1;
	l.continuous = strcmp(task->type, "LEARNSIMCONTINUOUS") == 0;
	l.openended = strcmp(task->type, "OPENENDED") == 0;
	/* every option within its range before a thread, a folder or a
	 * population exists; the loop says the warnings */
	if (learn_check(task_path, task, 1, err))
		return -1;
	if (l.continuous) {
		if (learn_continuous_order(task_path, task, l.order, &l.n_order, err))
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
	int threads = evo_evaluator_settings(l.ev)->threads;
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

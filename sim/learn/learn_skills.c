/* evo.learn's skills (sim/learn/learn_internal.h): LEARNSIMCONTINUOUS's
 * order of the skills' turns and each turn's start, OPENENDED's
 * development (evo.grow), and the skill networks they read and save
 * (docs/learning.md, docs/openended.md). */
#define _POSIX_C_SOURCE 200809L

#include <lauxlib.h>
#include <lua.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/err.h"
#include "base/fileio.h"
#include "learn/curve.h"
#include "learn/evaluate.h"
#include "learn/gallery.h"
#include "learn/heatmap.h"
#include "learn/learn_internal.h"
#include "learn/literature.h"
#include "learn/runlog.h"
#include "learn/runopts.h"
#include "lua/lua_evo.h"

/* ---- LEARNSIMCONTINUOUS (docs/learning.md) ----------------------------- */

/* Choice n: skill `name` runs the network of `file` in the run folder. */
static int choose_net(lua_State *L, learn *l, unsigned n, const char *name,
		      const char *file)
{
	evo_err err = {{0}};
	if (evo_path_fmt(l->choice_path[n], sizeof l->choice_path[n], &err,
			 "%s/%s", l->run_dir, file))
		return learn_raise_msg(L, err.msg);
	l->choice[n].skill = name;
	l->choice[n].source = l->choice_path[n];
	return 0;
}

/* The evaluator made anew for the candidates running as `skill`, with the
 * first n choices; with ranks, the MPI ranks' too (sim/cluster/). Pushes
 * the candidates' inputs and outputs: 2. */
static int remake_evaluator(lua_State *L, learn *l, const char *skill,
			    unsigned n, int ranks)
{
	evo_err err = {{0}};
	snprintf(l->skill, sizeof l->skill, "%s", skill);
	l->ed.learning_skill = l->skill;
	l->ed.nets = l->choice;
	l->ed.n_nets = n;
	evo_evaluator_destroy(l->ev);
	l->ev = evo_evaluator_create(&l->ed, &err);
	if (!l->ev)
		return learn_raise_msg(L, err.msg);
	const evo_eval_spread *sp = l->ed.spread;
	if (ranks && sp && sp->remake &&
	    sp->remake(sp->ctx, l->ev, &l->ed, &err))
		return learn_raise_msg(L, err.msg);
	lua_pushinteger(L, (lua_Integer)evo_evaluator_settings(l->ev)->n_in);
	lua_pushinteger(L, (lua_Integer)evo_evaluator_settings(l->ev)->n_out);
	return 2;
}

/* evo.begin_turn(skill, nets): from now on the candidates run as skill (a
 * name of evo.order), and every skill named in nets (skill -> a file of
 * the run folder) runs that network instead of its Skills/ one. The
 * evaluator is made anew for the turn, with the same threads, seed,
 * repetitions and ticks. */
int learn_l_begin_turn(lua_State *L)
{
	learn *l = learn_ctx(L);
	const char *skill = luaL_checkstring(L, 1);
	luaL_checktype(L, 2, LUA_TTABLE);
	int k = evo_mindfolder_skill(l->task->mind, skill);
	if (k < 0 || !l->task->mind->net[k])
		return luaL_error(L,
				  "evo.begin_turn: %s is no neural skill of "
				  "the hierarchy",
				  skill);
	unsigned n = 0;
	for (int i = 0; i < l->n_order; i++) {
		const char *name = l->task->mind->skill[l->order[i]].name;
		lua_getfield(L, 2, name);
		const char *file = lua_tostring(L, -1);
		if (file)
			choose_net(L, l, n++, name, file);
		lua_pop(L, 1);
	}
	return remake_evaluator(L, l, skill, n, 0);
}

/* evo.grow(task, skill, nets): OPENENDED's development (docs/openended.md):
 * the evaluator is made anew from task, a .simbatch in the run folder (the
 * grown mind folder's), the candidates running as skill, and every skill
 * named in nets (skill -> a file of the run folder) running that network
 * instead of its Skills/ one; with the same threads, seed, repetitions and
 * ticks, in this process and on every MPI rank. Returns the candidates'
 * inputs and outputs. */
int learn_l_grow(lua_State *L)
{
	learn *l = learn_ctx(L);
	const char *task = luaL_checkstring(L, 1);
	const char *skill = luaL_checkstring(L, 2);
	luaL_checktype(L, 3, LUA_TTABLE);
	evo_err err = {{0}};
	if (evo_path_fmt(l->grown_task, sizeof l->grown_task, &err, "%s/%s",
			 l->run_dir, task))
		return learn_raise_msg(L, err.msg);
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
		choose_net(L, l, n, l->choice_skill[n], file);
		n++;
		lua_pop(L, 1);
	}
	l->ed.task_path = l->grown_task;
	/* MPI ranks (sim/cluster/) make theirs anew the same way */
	return remake_evaluator(L, l, skill, n, 1);
}

/* evo.read_skill_net(skill) -> the text of Skills/<skill>/<skill>.net, or
 * nil when there is none. */
int learn_l_read_skill_net(lua_State *L)
{
	learn *l = learn_ctx(L);
	const char *skill = luaL_checkstring(L, 1);
	char path[1400];
	evo_err err;
	if (evo_path_fmt(path, sizeof path, &err, "%s/Skills/%s/%s.net",
			 l->task->mind->root, skill, skill))
		return learn_raise_msg(L, err.msg);
	struct stat st;
	if (stat(path, &st) != 0) {
		lua_pushnil(L);
		return 1;
	}
	char *text;
	size_t len;
	if (evo_read_file(path, &text, &len, &err))
		return learn_raise_msg(L, err.msg);
	lua_pushlstring(L, text, len);
	free(text);
	return 1;
}

/* evo.save_skill_net(skill, text): the skill's network in its folder,
 * Skills/<skill>/<skill>.net, where DEMOSIM and evo export find it. */
int learn_l_save_skill_net(lua_State *L)
{
	learn *l = learn_ctx(L);
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
	    learn_keep_replaced(l, path, text, len, skill, replaced, sizeof replaced,
			  &err) ||
	    evo_write_file_atomic(path, text, len, &err))
		return learn_raise_msg(L, err.msg);
	if (replaced[0])
		printf("%s: the network it replaced is kept in %s\n", path,
		       replaced);
	return 0;
}

/* LEARNSIMCONTINUOUS's turns: the neural skills SKILLORDER names, in its
 * order (names joined by ','), else every neural skill of the hierarchy
 * bottom-up, the reverse of the loader's top-down order, so that each
 * skill is trained after its sub-skills. 0, or -1 with err at SKILLORDER's
 * line. */
int learn_continuous_order(const char *task_path, const evo_task *t,
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

/* evo.learn's run folder (sim/learn/learn_internal.h): the log and the
 * progress line, the files the loop saves and reads back (checkpoints
 * among them), the champion (a network it replaces kept aside), the
 * curve, MAP-Elites' heatmap and OPENENDED's gallery, the loop's clock and
 * print. */
#define _POSIX_C_SOURCE 200809L

#include <lauxlib.h>
#include <lua.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

int learn_l_open_log(lua_State *L)
{
	learn *l = learn_ctx(L);
	evo_err err = {{0}};
	l->first = (int)luaL_checkinteger(L, 1);
	const char *names[EVO_SCENE_MAX_METRICS + 8];
	int nm = evo_evaluator_settings(l->ev)->n_metrics;
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
		return learn_raise_msg(L, err.msg);
	l->log_open = 1;
	return 0;
}

/* evo.log{generation, generations, best, mean, best_ever, species,
 * evaluations, seconds, metrics}: a row of log.csv and the progress line.
 * metrics is the list of the environment's metrics for the row (the best
 * candidate's, as evo.evaluate gave them); it may be absent only when
 * the environment has none. */
int learn_l_log(lua_State *L)
{
	learn *l = learn_ctx(L);
	luaL_checktype(L, 1, LUA_TTABLE);
	if (!l->log_open)
		return luaL_error(L, "evo.log before evo.open_log");
	double metrics[EVO_SCENE_MAX_METRICS + 8];
	int nm = evo_evaluator_settings(l->ev)->n_metrics + l->n_extra +
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
		.generation = (int)learn_field_int(L, 1, "generation", 0, INT_MAX, -1),
		.generations =
		    (int)learn_field_int(L, 1, "generations", 0, INT_MAX, -1),
		.best = learn_field_num(L, 1, "best", NAN),
		.mean = learn_field_num(L, 1, "mean", NAN),
		.best_ever = learn_field_num(L, 1, "best_ever", NAN),
		.species = (int)learn_field_int(L, 1, "species", 0, INT_MAX, -1),
		.evaluations =
		    (long)learn_field_int(L, 1, "evaluations", 0, LONG_MAX, -1),
		.solved = (int)learn_field_int(L, 1, "solved", 0, INT_MAX, -1),
		.seconds = learn_field_num(L, 1, "seconds", 0),
		.elapsed = learn_now() - l->started,
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
		return learn_raise_msg(L, err.msg);
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

int learn_l_save(lua_State *L)
{
	learn *l = learn_ctx(L);
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
				return learn_raise_msg(L, err.msg);
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
					return learn_raise_msg(L, err.msg);
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
		return learn_raise_msg(L, err.msg);
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

int learn_l_read(lua_State *L)
{
	learn *l = learn_ctx(L);
	char path[1200];
	size_t len;
	evo_err err;
	if (evo_path_fmt(path, sizeof path, &err, "%s/%s", l->run_dir,
			 run_file_name(L, 1, "evo.read")))
		return learn_raise_msg(L, err.msg);
	struct stat st;
	if (stat(path, &st) != 0) {
		lua_pushnil(L);
		return 1;
	}
	/* Something that is there but cannot be read is an error, not a
	 * fresh start that would overwrite the run's log. */
	if (!S_ISREG(st.st_mode))
		return learn_raise_msg(L, lua_pushfstring(L, "%s: not a file", path));
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
		return learn_raise_msg(L, err.msg);
	if (l->mem && l->mem->used + len + 4096 > l->mem->limit)
		return learn_raise_msg(
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
int learn_keep_replaced(const learn *l, const char *path, const char *text,
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
int learn_l_save_champion(lua_State *L)
{
	learn *l = learn_ctx(L);
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
		return learn_raise_msg(L, err.msg);
	char folder[200], replaced[1300], what[200];
	snprintf(folder, sizeof folder, "Skills/%s", skill);
	snprintf(what, sizeof what, "%s%s%s%s", team_name ? team_name : "",
		 team_name ? "-" : "", skill, suffix);
	if (evo_path_fmt(path, sizeof path, &err, "%s/Skills/%s/%s%s.net", root,
			 skill, skill, suffix))
		return learn_raise_msg(L, err.msg);
	if (l->opts->no_save) {
		if (l->tty && member == 1)
			printf("\n");
		printf("champion in %s; %s left as it was (--no-save)\n", kept,
		       path);
		return 0;
	}
	if (evo_folder_check_links(root, folder, &err) ||
	    learn_keep_replaced(l, path, text, len, what, replaced, sizeof replaced,
			  &err) ||
	    evo_write_file_atomic(path, text, len, &err))
		return learn_raise_msg(L, lua_pushfstring(L, "%s; the champion is in %s",
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
		    learn_keep_replaced(l, old, "", 0, oname, gone, sizeof gone,
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
int learn_l_curve(lua_State *L)
{
	learn *l = learn_ctx(L);
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
		return learn_raise_msg(L, err.msg);
	if (!quiet)
		printf("learning curve in %s\n", path);
	return 0;
}

/* evo.heatmap(nx, ny, values[, quiet[, note]]): draw archive.png, the
 * nx x ny grid of values (x + nx * y + 1; NaN where a cell is empty), as
 * evo.curve draws curve.png; note, when given, follows the title (what a
 * CVT archive's picture shows). */
int learn_l_heatmap(lua_State *L)
{
	/* before ctx, which leaves its box on the stack */
	const char *note = luaL_optstring(L, 5, NULL);
	learn *l = learn_ctx(L);
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
		return learn_raise_msg(L, err.msg);
	if (!quiet)
		printf("archive heatmap in %s\n", path);
	return 0;
}

/* evo.gallery(title, items): gallery.png of the run folder, a thumbnail
 * of each item, {genome text, caption} (learn/gallery.h; OPENENDED). */
int learn_l_gallery(lua_State *L)
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
	learn *l = learn_ctx(L);
	char path[1200];
	evo_err err = {{0}};
	evo_task_opts to = {.seed_set = 1, .seed = l->task->seed};
	if (evo_path_fmt(path, sizeof path, &err, "%s/gallery.png", l->run_dir) ||
	    evo_gallery_write(l->task_path, &to, title, items, n, path, &err))
		return learn_raise_msg(L, err.msg);
	return 0;
}

/* evo.clock() -> seconds on a monotonic wall clock (the loop times its
 * checkpoints by it: os.clock counts every thread's CPU). */
int learn_l_clock(lua_State *L)
{
	lua_pushnumber(L, learn_now());
	return 1;
}

/* evo.save_many(names, texts): files of the run folder, as evo.save
 * writes them but made durable together (one sync for all, not a disk
 * flush each: MAP-Elites' thousands of elites). */
int learn_l_save_many(lua_State *L)
{
	learn *l = learn_ctx(L);
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
				return learn_raise_msg(L, err.msg);
			if (evo_path_fmt(path, sizeof path, &err, "%s/%s",
					 l->run_dir, folder))
				return learn_raise_msg(L, err.msg);
			mkdir(path, 0755);
			snprintf(checked, sizeof checked, "%s", folder);
		}
		char path[1200];
		if (evo_path_fmt(path, sizeof path, &err, "%s/%s", l->run_dir,
				 name) ||
		    evo_write_file_replace(path, text, len, &err))
			return learn_raise_msg(L, err.msg);
		lua_pop(L, 2);
	}
	evo_sync_all();
	return 0;
}

int learn_l_print(lua_State *L)
{
	printf("%s\n", luaL_checkstring(L, 1));
	fflush(stdout);
	return 0;
}

/* The keys and defaults the docs list are the ones evo has.
 *
 * Every table of docs/ with a `default` column is checked against evo
 * itself, at run time, both ways: each key or option the table documents
 * is one evo reads, each one evo reads is documented, and each documented
 * default is the value evo uses when the key is left out.
 *   - docs/learning.md, the NEAT, GENETIC, ANNEALING, CMA-ES and NOVELTY
 *     tables: the method's module (lua/learn/neat.lua, ...) is loaded and
 *     its task_keys and defaults tables read;
 *   - the same tables' `range` column: each key's range as the method's
 *     `ranges` table gives it (in common.range_text's words), or as
 *     core's table of keys does (evo_simbatch_key_range);
 *   - docs/formats.md's .simbatch keys and docs/learning.md's task keys:
 *     the key list is core's evo_simbatch_key_defs; a key is required when a
 *     task without it does not load (evo_task_load); EVALREP, TICKLIM,
 *     SEED and THREADS are what `evo run` says it uses on a learning task
 *     that leaves them out; each key is also found read in sim/ or lua/
 *     (grep: a second opinion);
 *   - docs/lua.md's option table and the options in its method tables:
 *     a scene is built through the `evo` module from a bot model and an
 *     environment that leave every option out, and its structs are read;
 *     the options a function takes are those its "unknown option" error
 *     lists, for every method of the scene and of a bot that has one;
 *   - docs/world.md's "`option` (default V)" in its sensor table, the same
 *     way.
 * A table with a `default` column that this test does not know fails it,
 * so a new one cannot go unchecked. Last, evo warns about every .simbatch
 * key it ignores, in one form, in `evo run` and `evo check` alike.
 *
 * Run from the repository root (make test does). Ends with "N passed, N
 * failed" and exits non-zero on a failure. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "evo/formats.h"
#include "learn/literature.h"
#include "lua/lua_evo.h"
#include "mind/mindfolder.h"
#include "mind/net_build.h"
#include "mind/task.h"
#include "remote/link.h"
#include "remote/session.h"
#include "support/cli.h"
#include "world2d/scene.h"

/* Tests (sections) passed and failed, and the checks of the one under
 * way: each documented key or option is a few checks of one test. */
static int passed, failed;
static int section_checks, section_failures;

/* One check: quiet when it passes, a FAIL line saying what when not. */
static void result(int ok, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
static void result(int ok, const char *fmt, ...)
{
	section_checks++;
	if (ok)
		return;
	section_failures++;
	va_list ap;
	va_start(ap, fmt);
	printf("  ");
	vprintf(fmt, ap);
	printf("\n");
	va_end(ap);
}

/* Ends a test: "ok   NAME (N checks)", or "FAIL NAME" after its failed
 * checks' lines. */
static void section_end(const char *fmt, ...)
    __attribute__((format(printf, 1, 2)));
static void section_end(const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	printf("%s ", section_failures ? "FAIL" : "ok  ");
	vprintf(fmt, ap);
	va_end(ap);
	if (section_failures)
		printf(": %d of %d checks failed (above)\n", section_failures,
		       section_checks);
	else
		printf(" (%d checks)\n", section_checks);
	if (section_failures)
		failed++;
	else
		passed++;
	section_checks = section_failures = 0;
}

/* ---- tables of the docs -------------------------------------------------- */

#define MAX_ROWS  96
#define MAX_CELLS 4
#define CELL_MAX  512
#define NAME_LEN  64
#define MAX_NAMES 24

typedef struct doc_row {
	int line;
	char cell[MAX_CELLS][CELL_MAX];
} doc_row;

typedef struct doc_table {
	const char *file;
	const char *heading;
	int line; /* of its header row */
	int key_col, default_col;
	int range_col; /* -1 when the table has no `range` column */
	int n;
	doc_row row[MAX_ROWS];
} doc_table;

/* The cells of a table line "| a | b |" (at most MAX_CELLS), trimmed. */
static int split_cells(const char *line, char cell[][CELL_MAX])
{
	int n = 0;
	const char *p = line;
	if (*p != '|')
		return 0;
	p++;
	while (*p && *p != '\n' && n < MAX_CELLS) {
		const char *end = p;
		while (*end && *end != '\n' &&
		       !(*end == '|' && end[-1] != '\\'))
			end++;
		if (*end != '|')
			break;
		while (p < end && *p == ' ')
			p++;
		const char *e = end;
		while (e > p && e[-1] == ' ')
			e--;
		snprintf(cell[n], CELL_MAX, "%.*s", (int)(e - p), p);
		n++;
		p = end + 1;
	}
	return n;
}

static int heading_of(const char *line, char *out, size_t cap)
{
	if (line[0] != '#')
		return 0;
	while (*line == '#')
		line++;
	while (*line == ' ')
		line++;
	size_t n = strcspn(line, "\n");
	snprintf(out, cap, "%.*s", (int)n, line);
	return 1;
}

/* A header row: a table line followed by its |---| line. */
static int is_header(const char *line)
{
	const char *next = strchr(line, '\n');
	return line[0] == '|' && next && strncmp(next + 1, "|---", 4) == 0;
}

/* The first table under the heading t->heading of t->file, with a `default`
 * column. 0, or -1 (after a FAIL) when the file or table is not there. */
static int read_table(doc_table *t)
{
	char *text = cli_read("%s", t->file);
	if (!text) {
		result(0, "%s: cannot read it", t->file);
		return -1;
	}
	char heading[256] = "";
	int line = 1, found = 0;
	t->n = 0;
	for (const char *p = text; *p; line++) {
		const char *eol = strchr(p, '\n');
		if (!found) {
			heading_of(p, heading, sizeof heading);
			if (strcmp(heading, t->heading) == 0 && is_header(p)) {
				char cell[MAX_CELLS][CELL_MAX];
				int n = split_cells(p, cell);
				t->key_col = 0;
				t->default_col = -1;
				t->range_col = -1;
				for (int i = 0; i < n; i++) {
					if (strcmp(cell[i], "default") == 0)
						t->default_col = i;
					if (strcmp(cell[i], "range") == 0)
						t->range_col = i;
				}
				if (t->default_col > 0) {
					found = 1;
					t->line = line;
					if (eol) { /* the |---| line */
						p = eol + 1;
						line++;
						eol = strchr(p, '\n');
					}
				}
			}
		} else if (p[0] == '|') {
			if (t->n < MAX_ROWS) {
				doc_row *r = &t->row[t->n++];
				memset(r->cell, 0, sizeof r->cell);
				split_cells(p, r->cell);
				r->line = line;
			} else {
				result(
				    0,
				    "%s:%d: more than %d rows: raise MAX_ROWS",
				    t->file, line, MAX_ROWS);
			}
		} else {
			break;
		}
		if (!eol)
			break;
		p = eol + 1;
	}
	free(text);
	if (!found) {
		result(0,
		       "%s: no table with a default column under the heading "
		       "'%s'",
		       t->file, t->heading);
		return -1;
	}
	return 0;
}

/* The `quoted` names of a cell, in order; *aliases is set when they are
 * joined by " or " (several names of one key) rather than by ", " (several
 * keys). */
static int names_of(const char *cell, char names[][NAME_LEN], int *aliases)
{
	int n = 0;
	if (aliases)
		*aliases = strstr(cell, "` or `") != NULL;
	for (const char *p = strchr(cell, '`'); p; p = strchr(p + 1, '`')) {
		const char *end = strchr(p + 1, '`');
		if (!end)
			break;
		if (n < MAX_NAMES)
			snprintf(names[n++], NAME_LEN, "%.*s",
				 (int)(end - p - 1), p + 1);
		p = end;
	}
	return n;
}

/* A documented default as the test compares it: without the remarks in
 * parentheses, the backticks and the spaces at either end. */
static void plain_value(const char *cell, char *out, size_t cap)
{
	size_t k = 0;
	int depth = 0;
	for (const char *p = cell; *p && k + 1 < cap; p++) {
		if (*p == '(' && (p == cell || p[-1] == ' '))
			depth++;
		else if (*p == ')' && depth > 0)
			depth--;
		else if (depth == 0 && *p != '`')
			out[k++] = *p;
	}
	out[k] = 0;
	while (k > 0 && out[k - 1] == ' ')
		out[--k] = 0;
	size_t lead = strspn(out, " ");
	memmove(out, out + lead, strlen(out + lead) + 1);
}

/* A cell without its backticks: what a reader sees. */
static void unticked(const char *cell, char *out, size_t cap)
{
	size_t k = 0;
	for (const char *p = cell; *p && k + 1 < cap; p++)
		if (*p != '`')
			out[k++] = *p;
	out[k] = 0;
}

/* The default of option i of n in a row's default cell: "a, b, c" gives
 * one to each option, a single value all of them. 0, or -1 when the cell
 * holds neither one value nor n of them. */
static int nth_value(const char *value, int i, int n, char *out, size_t cap)
{
	if (n == 1) {
		snprintf(out, cap, "%s", value);
		return 0;
	}
	int parts = 1;
	for (const char *p = value; (p = strstr(p, ", ")); p += 2)
		parts++;
	if (parts == 1) {
		snprintf(out, cap, "%s", value);
		return 0;
	}
	if (parts != n)
		return -1;
	const char *p = value;
	for (int k = 0; k < i; k++)
		p = strstr(p, ", ") + 2;
	const char *end = strstr(p, ", ");
	snprintf(out, cap, "%.*s", (int)(end ? end - p : (long)strlen(p)), p);
	return 0;
}

/* Whole text a number? */
static int number_of(const char *s, double *v)
{
	char *end;
	if (!*s)
		return 0;
	*v = strtod(s, &end);
	return *end == 0;
}

/* The documented value and evo's are the same: equal numbers (to a
 * degree's conversion), or equal text. */
static int same_value(const char *doc, const char *code)
{
	double a, b;
	if (number_of(doc, &a) && number_of(code, &b))
		return fabs(a - b) <= 1e-9 * fmax(1.0, fabs(b));
	return strcmp(doc, code) == 0;
}

static int in_list(const char *name, char list[][NAME_LEN], int n)
{
	for (int i = 0; i < n; i++)
		if (strcmp(list[i], name) == 0)
			return 1;
	return 0;
}

/* A number as the docs write it: the shortest of %.15g and %.17g that
 * reads back as the same double. */
static void fmt_num(char *out, size_t cap, double v)
{
	snprintf(out, cap, "%.15g", v);
	if (strtod(out, NULL) != v)
		snprintf(out, cap, "%.17g", v);
}

/* Add name to list (of n, at most max) unless it is there. */
static void add_name_max(char list[][NAME_LEN], int *n, int max,
			 const char *name)
{
	if (!in_list(name, list, *n) && *n < max)
		snprintf(list[(*n)++], NAME_LEN, "%.*s", NAME_LEN - 1, name);
}

static void add_name(char list[][NAME_LEN], int *n, const char *name)
{
	add_name_max(list, n, MAX_NAMES, name);
}

/* ---- the learning methods (lua/learn/) ----------------------------------- */

static lua_State *learn_L;

/* A module of lua/learn, at the top of learn_L's stack. */
static int push_module(const char *module)
{
	lua_getglobal(learn_L, "require");
	lua_pushstring(learn_L, module);
	if (lua_pcall(learn_L, 1, 1, 0) != LUA_OK) {
		result(0, "require '%s': %s", module,
		       evo_lua_errstr(learn_L, -1));
		lua_pop(learn_L, 1);
		return -1;
	}
	return 0;
}

/* A Lua value as the docs write it. */
static void render_lua(lua_State *L, int idx, char *out, size_t cap)
{
	if (lua_type(L, idx) == LUA_TBOOLEAN)
		snprintf(out, cap, "%s",
			 lua_toboolean(L, idx) ? "true" : "false");
	else if (lua_type(L, idx) == LUA_TNUMBER)
		fmt_num(out, cap, lua_tonumber(L, idx));
	else if (lua_type(L, idx) == LUA_TSTRING)
		snprintf(out, cap, "%s", lua_tostring(L, idx));
	else
		snprintf(out, cap, "(%s)", luaL_typename(L, idx));
}

/* The range a method's option takes, as the docs' `range` column must say
 * it: common.range_text of its range, "a number" for a number without
 * one, "true or false"; for a word, the cell itself when each `word` it
 * names is taken and a word it does not name is not. */
static const char RANGE_OF[] =
    "local m, key, cell = ...\n"
    "local common = require 'learn.common'\n"
    "local option = m.task_keys[key]\n"
    "local default = m.defaults[option]\n"
    "if type(default) == 'number' then\n"
    "  local r = m.ranges[option]\n"
    "  return r and common.range_text(r) or 'a number'\n"
    "elseif type(default) == 'boolean' then return 'true or false' end\n"
    "local n = 0\n"
    "for w in cell:gmatch('`([^`]+)`') do\n"
    "  n = n + 1\n"
    "  if not pcall(m.options_from_task, { [key] = w }) then\n"
    "    return 'words ' .. key .. ' takes, not ' .. w end\n"
    "end\n"
    "if n == 0 then return 'the words ' .. key .. ' takes, each quoted' end\n"
    "if pcall(m.options_from_task, { [key] = 'no_such_word' }) then\n"
    "  return 'any word: ' .. key .. ' takes no_such_word' end\n"
    "return cell\n";

/* Row r's range cell against the range module m (at index mod) gives
 * key. */
static void check_method_range(doc_table *t, const doc_row *row, int mod,
			       const char *key)
{
	if (t->range_col < 0)
		return;
	const char *cell = row->cell[t->range_col];
	if (luaL_loadbufferx(learn_L, RANGE_OF, sizeof RANGE_OF - 1,
			     "=range", "t") != LUA_OK) {
		result(0, "range chunk: %s", lua_tostring(learn_L, -1));
		lua_pop(learn_L, 1);
		return;
	}
	lua_pushvalue(learn_L, mod);
	lua_pushstring(learn_L, key);
	lua_pushstring(learn_L, cell);
	if (lua_pcall(learn_L, 3, 1, 0) != LUA_OK) {
		result(0, "%s:%d: %s: %s", t->file, row->line, key,
		       lua_tostring(learn_L, -1));
		lua_pop(learn_L, 1);
		return;
	}
	char code[CELL_MAX];
	snprintf(code, sizeof code, "%s", lua_tostring(learn_L, -1));
	lua_pop(learn_L, 1);
	result(strcmp(code, cell) == 0,
	       "%s:%d: %s: the range column says '%s', evo's range is '%s'",
	       t->file, row->line, key, cell, code);
}

/* A method's table of docs/learning.md against its module: each key is in
 * task_keys, each default is defaults[option], every key of task_keys is
 * documented, and every option of defaults has a key. */
static void check_method_table(doc_table *t, const char *module)
{
	if (read_table(t) || push_module(module)) {
		section_end("%s: %s against %s", t->file, t->heading, module);
		return;
	}
	int mod = lua_gettop(learn_L);
	result(t->range_col > 0, "%s:%d: the table has no range column",
	       t->file, t->line);
	lua_getfield(learn_L, mod, "task_keys");
	lua_getfield(learn_L, mod, "defaults");
	int keys = mod + 1, defaults = mod + 2;
	static char documented[MAX_ROWS * 3][NAME_LEN];
	int n_documented = 0;
	for (int r = 0; r < t->n; r++) {
		const doc_row *row = &t->row[r];
		char names[MAX_NAMES][NAME_LEN], value[CELL_MAX], one[CELL_MAX];
		int aliases;
		int n = names_of(row->cell[t->key_col], names, &aliases);
		plain_value(row->cell[t->default_col], value, sizeof value);
		char first_option[NAME_LEN] = "";
		for (int i = 0; i < n; i++) {
			add_name_max(documented, &n_documented, MAX_ROWS * 3,
				     names[i]);
			lua_getfield(learn_L, keys, names[i]);
			char option[NAME_LEN] = "";
			if (lua_isstring(learn_L, -1))
				snprintf(option, sizeof option, "%s",
					 lua_tostring(learn_L, -1));
			lua_pop(learn_L, 1);
			result(option[0] != 0,
			       "%s:%d: %s is documented, but %s does not read "
			       "it (not in its task_keys)",
			       t->file, row->line, names[i], module);
			if (!option[0])
				continue;
			check_method_range(t, row, mod, names[i]);
			if (i == 0)
				snprintf(first_option, sizeof first_option,
					 "%s", option);
			else if (aliases)
				result(strcmp(option, first_option) == 0,
				       "%s:%d: %s and %s are documented as one "
				       "key, but %s sets %s with one and %s "
				       "with the other",
				       t->file, row->line, names[0], names[i],
				       module, first_option, option);
			if (nth_value(value, aliases ? 0 : i, aliases ? 1 : n,
				      one, sizeof one)) {
				result(0,
				       "%s:%d: '%s' is not one default or one "
				       "for each of the %d keys",
				       t->file, row->line, value, n);
				continue;
			}
			char code[CELL_MAX];
			lua_getfield(learn_L, defaults, option);
			render_lua(learn_L, -1, code, sizeof code);
			lua_pop(learn_L, 1);
			result(same_value(one, code),
			       "%s:%d: %s: the docs say %s, %s.defaults.%s is "
			       "%s",
			       t->file, row->line, names[i], one, module,
			       option, code);
		}
	}
	/* the other way: every key the module reads is documented, and every
	 * option can be set from a task */
	lua_pushnil(learn_L);
	while (lua_next(learn_L, keys)) {
		const char *key = lua_tostring(learn_L, -2);
		result(in_list(key, documented, n_documented),
		       "%s: %s reads the key %s, which the table under '%s' "
		       "does not document",
		       t->file, module, key, t->heading);
		lua_pop(learn_L, 1);
	}
	lua_pushnil(learn_L);
	while (lua_next(learn_L, defaults)) {
		const char *option = lua_tostring(learn_L, -2);
		int keyed = 0;
		lua_pushnil(learn_L);
		while (lua_next(learn_L, keys)) {
			keyed |= lua_isstring(learn_L, -1) &&
				 strcmp(lua_tostring(learn_L, -1), option) == 0;
			lua_pop(learn_L, 1);
		}
		result(keyed,
		       "%s: option %s of %s has no .simbatch key, so a task "
		       "cannot set it",
		       t->file, option, module);
		lua_pop(learn_L, 1);
	}
	lua_settop(learn_L, mod - 1);
	section_end("%s:%d: %s against %s", t->file, t->line, t->heading,
		    module);
}

/* ---- the task's keys (core, sim/mind, sim/cmd, sim/learn) ---------------- */

/* What `evo run` said on a learning task that gives no EVALREP, TICKLIM,
 * SEED or THREADS. */
static struct {
	int ran;
	unsigned long long seed;
	int threads;
	int reps;
	long ticks;
} run;

static const char *const DEMO_TASK[] = {"TYPE:DEMOSIM", "BOTMODEL:BotType8",
					"MASTERSKILL:Avoid", "ENV:Open", NULL};
static const char *const LEARN_TASK[] = {"TYPE:LEARNSIM",
					 "BOTMODEL:BotType8",
					 "MASTERSKILL:Avoid",
					 "ENV:Open",
					 "LEARNINGSKILL:Avoid",
					 "LEARNINGMETHOD:NEAT",
					 "NUMGEN:1",
					 NULL};

/* The task `lines` without the key `omit` (may be NULL) plus the text
 * `more`, as Tasks/name.simbatch of the copy of minds/Avoid. */
static int write_task(const char *name, const char *const *lines,
		      const char *omit, const char *more)
{
	char text[2048] = "";
	size_t n = omit ? strlen(omit) : 0;
	for (int i = 0; lines[i]; i++) {
		if (omit && strncmp(lines[i], omit, n) == 0 &&
		    lines[i][n] == ':')
			continue;
		strcat(text, lines[i]);
		strcat(text, "\n");
	}
	strcat(text, more ? more : "");
	return cli_write(text, "%s/Avoid/Tasks/%s.simbatch", cli_tmp, name);
}

/* 1 when the task of `lines` without `omit` loads; *t is then loaded
 * (the caller frees it) when t is given. */
static int task_loads(const char *const *lines, const char *omit, evo_task *t)
{
	char path[512];
	evo_task local;
	evo_err err;
	if (write_task("Probe", lines, omit, NULL))
		return 0;
	snprintf(path, sizeof path, "%s/Avoid/Tasks/Probe.simbatch", cli_tmp);
	if (!t)
		t = &local;
	if (evo_task_load(path, t, &err) != 0)
		return 0;
	if (t == &local)
		evo_task_free(t);
	return 1;
}

/* What a team task (docs/teams.md) gets without `key`, one of the team
 * keys: loaded from a task of one team of the copy of minds/Avoid. 0, or
 * -1 when `key` is not one of them. */
static int render_team_default(const char *key, char *out, size_t cap)
{
	static const char *const demo[] = {"TYPE:DEMO2DSIMMULTI", "ENV:Open",
					   "TEAM:A:Avoid:BotType8:2:Avoid",
					   NULL};
	static const char *const learn[] = {
	    "TYPE:LEARN2DSIMMULTI",
	    "ENV:Open",
	    "TEAM:A:Avoid:BotType8:2:Avoid:Avoid",
	    "LEARNINGMETHOD:NEAT",
	    "NUMGEN:1",
	    NULL};
	if (strcmp(key, "TEAM") == 0) {
		int need = !task_loads(demo, "TEAM", NULL) &&
			   !task_loads(learn, "TEAM", NULL) &&
			   task_loads(demo, NULL, NULL) &&
			   task_loads(learn, NULL, NULL);
		snprintf(out, cap, "%s",
			 need ? "required of DEMO2DSIMMULTI and LEARN2DSIMMULTI"
			      : "not required");
		return 0;
	}
	if (strcmp(key, "LEARNINGTEAM") && strcmp(key, "TEAMGENOME") &&
	    strcmp(key, "TEAMFITNESS") && strcmp(key, "ALTERNATE"))
		return -1;
	evo_task t;
	if (!task_loads(learn, key, &t))
		return -1;
	if (strcmp(key, "LEARNINGTEAM") == 0)
		snprintf(out, cap, "%s",
			 t.n_learning == 1 && t.learning[0] == 0
			     ? "the only team, when there is one"
			     : "another team");
	else if (strcmp(key, "TEAMGENOME") == 0)
		snprintf(out, cap, "%s",
			 t.heterogeneous ? "HETEROGENEOUS" : "HOMOGENEOUS");
	else if (strcmp(key, "TEAMFITNESS") == 0)
		snprintf(out, cap, "%s", t.own_fitness ? "OWN" : "TEAM");
	else
		snprintf(out, cap, "%d", t.alternate);
	evo_task_free(&t);
	return 0;
}

/* What a LEARNSIMCONTINUOUS run (docs/learning.md) does without
 * SKILLORDER, ROUNDS and VALIDATION, as it says: a copy of minds/Collect
 * with a task of one generation of 4 networks, run until its first turn
 * ends and stopped. The header and that turn's line, or -1. */
static struct {
	int ran; /* 1 ran, -1 could not */
	char header[1024], turn[512];
	evo_mindfolder *mind;
} cont;

static int continuous_run(void)
{
	if (cont.ran)
		return cont.ran > 0 ? 0 : -1;
	cont.ran = -1;
	if (cli_sh("rm -rf %s/cont && mkdir -p %s/cont && cp -r minds/Collect "
		   "%s/cont/ && printf 'TYPE:LEARNSIMCONTINUOUS\\nBOTMODEL:"
		   "BotType8\\nBOTNAME:Collect\\nMASTERSKILL:Collect\\nENV:"
		   "EXP_Collect\\nLEARNINGMETHOD:NEAT\\nNUMGEN:1\\nEVALREP:1\\n"
		   "TICKLIM:20\\nPOPSIZE:4\\n' > "
		   "%s/cont/Collect/Tasks/Probe.simbatch",
		   cli_tmp, cli_tmp, cli_tmp, cli_tmp))
		return -1;
	/* without ROUNDS it runs until stopped: stopped after a turn */
	cli_sh("o=%s/cont/out.txt; %s run %s/cont/Collect/Tasks/Probe.simbatch "
	       "--seed 1 --threads 1 --run %s/cont/run > $o 2>&1 & p=$!; "
	       "i=0; while ! grep -q 'validation evaluations: ' $o && "
	       "[ $i -lt 600 ]; do sleep 0.1; i=$((i+1)); done; kill $p; "
	       "wait $p 2>/dev/null",
	       cli_tmp, cli_evo, cli_tmp, cli_tmp);
	char *out = cli_read("%s/cont/out.txt", cli_tmp);
	const char *h = out ? strstr(out, " in turn, ") : NULL;
	const char *v = out ? strstr(out, " validation evaluations: ") : NULL;
	if (h && v) {
		while (h > out && h[-1] != '\n')
			h--;
		while (v > out && v[-1] != '\n')
			v--;
		snprintf(cont.header, sizeof cont.header, "%.*s",
			 (int)strcspn(h, "\n"), h);
		snprintf(cont.turn, sizeof cont.turn, "%.*s",
			 (int)strcspn(v, "\n"), v);
		evo_mindfolder_opts opts = {0};
		evo_err err;
		char path[512];
		snprintf(path, sizeof path, "%s/cont/Collect", cli_tmp);
		opts.master = "Collect";
		cont.mind = evo_mindfolder_load(path, &opts, &err);
		if (cont.mind)
			cont.ran = 1;
	}
	free(out);
	return cont.ran > 0 ? 0 : -1;
}

/* The skills a continuous run names in its header, "of skills A, B and
 * C in turn", checked against the hierarchy: "every neural skill,
 * bottom-up" when they are all its neural skills and each comes after
 * every neural skill it influences; else what they are. */
static void continuous_order_default(char *out, size_t cap)
{
	const evo_mindfolder *m = cont.mind;
	const char *p = strstr(cont.header, "of skills ");
	const char *end = strstr(cont.header, " in turn, ");
	char list[512];
	snprintf(list, sizeof list, "%.*s",
		 p && end > p ? (int)(end - p - 10) : 0, p ? p + 10 : "");
	/* "A, B and C" into names */
	char names[64][NAME_LEN];
	int n = 0;
	for (char *s = list; *s && n < 64;) {
		size_t len = strcspn(s, ",");
		char *and = strstr(s, " and ");
		if (and && (size_t)(and - s) < len)
			len = (size_t)(and - s);
		snprintf(names[n++], NAME_LEN, "%.*s", (int)len, s);
		s += len;
		s += strspn(s, ", ");
		if (strncmp(s, "and ", 4) == 0)
			s += 4;
	}
	int ok = n > 0, neural = 0;
	for (unsigned k = 0; k < m->n_skills; k++) {
		if (!m->net[k])
			continue;
		neural++;
		int at = -1;
		for (int i = 0; i < n; i++)
			if (strcmp(names[i], m->skill[k].name) == 0)
				at = i;
		ok &= at >= 0;
		/* every neural sub-skill it influences comes before it */
		const evo_ades *a = &m->skill[k];
		for (unsigned o = 0; o < a->n_out && at >= 0; o++) {
			if (a->out[o].type != EVO_OUT_SK)
				continue;
			for (int i = at; i < n; i++)
				ok &= strcmp(names[i], a->out[o].name) != 0;
		}
	}
	ok &= n == neural;
	if (ok)
		snprintf(out, cap, "every neural skill, bottom-up");
	else
		snprintf(out, cap, "%.200s", cont.header);
}

/* What a LEARNSIMCONTINUOUS task gets without `key`; 0, or -1 when `key`
 * is not one of its keys or the run could not tell. */
static int render_continuous_default(const char *key, char *out, size_t cap)
{
	if (strcmp(key, "SKILLORDER") && strcmp(key, "ROUNDS") &&
	    strcmp(key, "VALIDATION"))
		return -1;
	if (continuous_run())
		return -1;
	if (strcmp(key, "SKILLORDER") == 0)
		continuous_order_default(out, cap);
	else if (strcmp(key, "ROUNDS") == 0)
		snprintf(out, cap, "%.200s",
			 strstr(cont.header, " rounds until stopped, ")
			     ? "none"
			     : cont.header);
	else {
		/* "... on N validation evaluations: kept" */
		const char *on = strstr(cont.turn, " on ");
		int v = 0;
		if (!on || sscanf(on, " on %d validation", &v) != 1)
			return -1;
		snprintf(out, cap, "%d", v);
	}
	return 0;
}

/* Lua: genetic.width(n_in, n_out) with no HIDDEN, or -1. */
static int genetic_width(int n_in, int n_out)
{
	if (push_module("learn.genetic"))
		return -1;
	lua_getfield(learn_L, -1, "width");
	lua_pushinteger(learn_L, n_in);
	lua_pushinteger(learn_L, n_out);
	int w = -1;
	if (lua_pcall(learn_L, 2, 1, 0) == LUA_OK && lua_isinteger(learn_L, -1))
		w = (int)lua_tointeger(learn_L, -1);
	lua_pop(learn_L, 2);
	return w;
}

/* 1 when some learning method reads `key` (its task_keys has it). */
static int a_method_reads(const char *key)
{
	static const char *const modules[] = {"learn.neat", "learn.genetic",
					      "learn.annealing", "learn.cmaes",
					      "learn.novelty", "learn.mapelites"};
	int found = 0;
	for (unsigned i = 0; i < sizeof modules / sizeof modules[0]; i++) {
		if (push_module(modules[i]))
			continue;
		lua_getfield(learn_L, -1, "task_keys");
		lua_getfield(learn_L, -1, key);
		found |= !lua_isnil(learn_L, -1);
		lua_pop(learn_L, 3);
	}
	return found;
}

/* What a task that leaves `key` out gets, in the words of the docs'
 * tables; in_learning: the table is docs/learning.md's, where a key only
 * a learning task needs is just "required". 0, or -1 when this test
 * cannot tell (teach it). */
static int render_task_default(const char *key, int in_learning, char *out,
			       size_t cap)
{
	if (strcmp(key, "NEAT_*") == 0 || strcmp(key, "GA_*") == 0 ||
	    strcmp(key, "SA_*") == 0 || strcmp(key, "CMAES_*") == 0 ||
	    strcmp(key, "NOVELTY_*") == 0 || strcmp(key, "MAPELITES_*") == 0 ||
	    strcmp(key, "OPEN_*") == 0) {
		/* the reader keeps every key with the prefix, for the method */
		char text[64];
		evo_simbatch sb;
		evo_diag err;
		int n = snprintf(text, sizeof text, "%.*sX:1\n",
				 (int)strlen(key) - 1, key);
		char want[16];
		snprintf(want, sizeof want, "%.*sX", (int)strlen(key) - 1, key);
		int kept = evo_simbatch_parse(text, (size_t)n, "p", &sb,
					      &err) == EVO_OK &&
			   sb.n_warnings == 0 && evo_simbatch_get(&sb, want);
		snprintf(out, cap, "%s", kept ? "the method's" : "dropped");
		return 0;
	}
	if (render_team_default(key, out, cap) == 0 ||
	    render_continuous_default(key, out, cap) == 0)
		return 0;
	int demo = task_loads(DEMO_TASK, key, NULL);
	int learn = task_loads(LEARN_TASK, key, NULL);
	if (!demo && !learn) {
		snprintf(out, cap, "required");
		return 0;
	}
	if (!learn) {
		snprintf(out, cap, "%s",
			 in_learning ? "required" : "required to learn");
		return 0;
	}
	if (!demo) {
		snprintf(out, cap, "required of DEMOSIM only");
		return 0;
	}
	if (strcmp(key, "EVALREP") == 0 && run.ran)
		snprintf(out, cap, "%d", run.reps);
	else if (strcmp(key, "TICKLIM") == 0 && run.ran)
		snprintf(out, cap, "%ld", run.ticks);
	else if (strcmp(key, "SEED") == 0 && run.ran)
		snprintf(out, cap, "%llu", run.seed);
	else if (strcmp(key, "THREADS") == 0 && run.ran) {
		long cores = sysconf(_SC_NPROCESSORS_ONLN);
		if (run.threads == (cores < 1	   ? 1
				    : cores > 1024 ? 1024
						   : cores))
			snprintf(out, cap, "one per core");
		else
			snprintf(out, cap, "%d", run.threads);
	} else if (strcmp(key, "BOTNAME") == 0 ||
		   strcmp(key, "ROOTFOLDER") == 0) {
		evo_task t;
		char root[256];
		snprintf(root, sizeof root, "%s/Avoid", cli_tmp);
		if (!task_loads(DEMO_TASK, NULL, &t))
			return -1;
		int named = strcmp(t.mind->bot_name, "Avoid") == 0;
		int rooted = strcmp(t.mind->root, root) == 0;
		evo_task_free(&t);
		if (strcmp(key, "BOTNAME") == 0)
			snprintf(out, cap, "%s",
				 named ? "the mind folder's name"
				       : "another name");
		else
			snprintf(out, cap, "%s",
				 rooted
				     ? "the folder that holds the task's Tasks/"
				     : "another folder");
	} else if (strcmp(key, "POPSIZE") == 0) {
		snprintf(out, cap, "%s",
			 a_method_reads("POPSIZE") ? "the method's" : "unread");
	} else if (strcmp(key, "HIDDEN") == 0) {
		int larger = evo_net_layered_width(2, 7) == 7 &&
			     evo_net_layered_width(7, 2) == 7 &&
			     genetic_width(2, 7) == 7 &&
			     genetic_width(7, 2) == 7;
		snprintf(out, cap, "%s",
			 larger ? "the larger of the skill's inputs and outputs"
				: "another width");
	} else if (strcmp(key, "LCMURL") == 0) {
		snprintf(out, cap, "LCM's own, %s",
			 EVO_LINK_DEFAULT_URL);
	} else if (strcmp(key, "REMOTENAME") == 0) {
		/* no name: remote/session.c takes the remotes that present
		 * the task's key, and refuses a task with neither */
		snprintf(out, cap, "any remote that presents the task's key");
	} else if (strcmp(key, "LCMKEYFILE") == 0) {
		/* no key file: remote/link.c seals nothing */
		snprintf(out, cap, "none");
	} else if (strcmp(key, "CANURL") == 0) {
		/* no CANURL: remote/robot.c reaches the robot over LCM */
		snprintf(out, cap, "none");
	} else if (strcmp(key, "REMOTETIMEOUT") == 0) {
		snprintf(out, cap, "%g", EVO_REMOTE_DEFAULT_TIMEOUT);
	} else if (strcmp(key, "LUABUDGET") == 0) {
		snprintf(out, cap, "%g", evo_lua_default_limits().budget_scale);
	} else if (strcmp(key, "LUAMEMORY") == 0) {
		snprintf(out, cap, "%zu", evo_lua_default_limits().memory >> 20);
	} else if (strcmp(key, "POLEPROTOCOL") == 0) {
		/* no key: the protocol literature.c takes for NULL */
		int pr = evo_lit_protocol_named(NULL);
		snprintf(out, cap, "%s",
			 pr < 0 ? "none" : evo_lit_protocol_name(pr));
	} else if (strcmp(key, "TARGETFITNESS") == 0) {
		/* no target: a run goes all its generations */
		snprintf(out, cap, "none");
	} else {
		return -1;
	}
	return 0;
}

/* A table of .simbatch keys: each is one of core's evo_simbatch_key_defs
 * (or the methods' prefixes), read somewhere in sim/ or lua/, its default
 * is what evo does without it, and its range, where the table has a
 * `range` column, is the one evo_simbatch_key_range says; all_keys: every
 * key of evo_simbatch_key_defs must be in the table, with a range
 * (docs/formats.md lists them all). */
static void check_task_table(doc_table *t, int in_learning, int all_keys)
{
	if (read_table(t)) {
		section_end("%s: %s", t->file, t->heading);
		return;
	}
	static char documented[MAX_ROWS][NAME_LEN];
	int n_documented = 0;
	for (int r = 0; r < t->n; r++) {
		const doc_row *row = &t->row[r];
		char names[MAX_NAMES][NAME_LEN], value[CELL_MAX];
		int n = names_of(row->cell[t->key_col], names, NULL);
		plain_value(row->cell[t->default_col], value, sizeof value);
		for (int i = 0; i < n; i++) {
			const char *key = names[i];
			add_name_max(documented, &n_documented, MAX_ROWS, key);
			int prefix = key[strlen(key) - 1] == '*';
			const evo_simbatch_key_def *def =
			    evo_simbatch_key_find(key);
			result(prefix || def,
			       "%s:%d: %s is documented, but the .simbatch "
			       "reader does not know it "
			       "(evo_simbatch_key_defs)",
			       t->file, row->line, key);
			if (t->range_col >= 0) {
				char doc[CELL_MAX], code[CELL_MAX];
				unticked(row->cell[t->range_col], doc,
					 sizeof doc);
				if (def)
					evo_simbatch_key_range(def, code,
							       sizeof code);
				else
					snprintf(code, sizeof code,
						 "the method's: "
						 "docs/learning.md");
				result(strcmp(doc, code) == 0,
				       "%s:%d: %s: the range column says "
				       "'%s', evo's range is '%s'",
				       t->file, row->line, key, doc, code);
			}
			if (!prefix)
				result(
				    cli_sh("grep -rqE "
					   "'\"%s\"|task\\.%s\\b|\\b%s = \"' "
					   "sim lua",
					   key, key, key) == 0,
				    "%s:%d: %s: nothing in sim/ or lua/ reads "
				    "it (grep)",
				    t->file, row->line, key);
			char code[CELL_MAX];
			if (render_task_default(key, in_learning, code,
						sizeof code)) {
				result(0,
				       "%s:%d: %s: this test cannot tell evo's "
				       "default; teach render_task_default",
				       t->file, row->line, key);
				continue;
			}
			result(same_value(value, code),
			       "%s:%d: %s: the docs say '%s', evo's is '%s'",
			       t->file, row->line, key, value, code);
		}
	}
	/* every key has its range documented (docs/formats.md) */
	result(!all_keys || t->range_col > 0,
	       "%s:%d: the table has no range column", t->file, t->line);
	for (int k = 0; all_keys && evo_simbatch_key_defs[k].name; k++)
		result(in_list(evo_simbatch_key_defs[k].name, documented,
			       n_documented),
		       "%s: the .simbatch reader knows %s, which the table "
		       "under '%s' does not document",
		       t->file, evo_simbatch_key_defs[k].name, t->heading);
	section_end("%s:%d: %s against the .simbatch reader and evo run",
		    t->file, t->line, t->heading);
}

/* Runs `evo run` on a learning task that leaves out every key with a
 * default, with keys it must warn about, and reads what it says it uses;
 * then checks that every ignored key gets a warning in one form, the
 * same from `evo check`. */
static void learning_run(void)
{
	static char out[1 << 15], check[1 << 15];
	/* no control function: an episode ends at TICKLIM's default */
	if (cli_write("local env = {}\n"
		      "function env.init(scene, task) scene:bot{} end\n"
		      "return env\n",
		      "%s/Avoid/Envs/Open.lua", cli_tmp) ||
	    write_task(
		"T", LEARN_TASK, NULL,
		"POPSIZE:2\nNUMGENS:3\nNEAT_SURVIVALL:0.2\nGA_POPSIZE:3\n"
		"SA_T0:5\n")) {
		result(0, "cannot write the learning task");
		return;
	}
	int rc =
	    cli_capture(out, sizeof out, "%s run %s/Avoid/Tasks/T.simbatch",
			cli_evo, cli_tmp);
	const char *s = strstr(out, ", seed ");
	const char *r = strstr(out, "replay on unseen episodes (");
	run.ran =
	    rc == 0 && s && r &&
	    sscanf(s, ", seed %llu, %d thread", &run.seed, &run.threads) == 2 &&
	    sscanf(r, "replay on unseen episodes (%d x %ld ticks", &run.reps,
		   &run.ticks) == 2;
	result(run.ran,
	       "evo run on a learning task with no EVALREP, TICKLIM, "
	       "SEED or THREADS (exit %d) said:\n%s",
	       rc, out);

	/* every key evo ignores: a warning at its line, "warning: FILE:LINE: "
	 * as the task reader's own, from evo run and evo check alike */
	cli_capture(check, sizeof check, "%s check %s/Avoid/Tasks/T.simbatch",
		    cli_evo, cli_tmp);
	static const struct {
		const char *key;
		int line;
	} ignored[] = {{"NUMGENS", 9},
		       {"NEAT_SURVIVALL", 10},
		       {"GA_POPSIZE", 11},
		       {"SA_T0", 12}};
	for (unsigned i = 0; i < sizeof ignored / sizeof ignored[0]; i++) {
		char want[512];
		snprintf(want, sizeof want,
			 "warning: %s/Avoid/Tasks/T.simbatch:%d: ", cli_tmp,
			 ignored[i].line);
		const char *a = strstr(out, want), *b = strstr(check, want);
		result(
		    a && b && strstr(a, ignored[i].key) &&
			strstr(a, "ignored") && strstr(b, ignored[i].key),
		    "%s: no warning '%s... %s ... ignored' from both evo run "
		    "and evo check; they said:\n%s\n%s",
		    ignored[i].key, want, ignored[i].key, out, check);
		if (a && b) {
			size_t la = strcspn(a, "\n"), lb = strcspn(b, "\n");
			result(la == lb && strncmp(a, b, la) == 0,
			       "%s: evo run warns '%.*s', evo check '%.*s'",
			       ignored[i].key, (int)la, a, (int)lb, b);
		}
	}
	/* ANNEALING has no population: POPSIZE is ignored, with a warning */
	if (write_task("SA", LEARN_TASK, "LEARNINGMETHOD",
		       "LEARNINGMETHOD:ANNEALING\nPOPSIZE:4\n") == 0) {
		cli_capture(check, sizeof check,
			    "%s check %s/Avoid/Tasks/SA.simbatch", cli_evo,
			    cli_tmp);
		char want[512];
		snprintf(
		    want, sizeof want,
		    "warning: %s/Avoid/Tasks/SA.simbatch:8: POPSIZE ignored",
		    cli_tmp);
		result(strstr(check, want) != NULL,
		       "POPSIZE in an ANNEALING task: no '%s', evo check "
		       "said:\n%s",
		       want, check);
	}
	section_end("evo run and evo check: the defaults a learning task gets, "
		    "a warning for every key they ignore");
}

/* ---- the scene scripts' options (sim/lua, sim/world2d) ------------------- */

/* Each method of a scene and of a bot that takes an option table, and the
 * options it takes, as its "unknown option" error lists them. */
#define MAX_FUNCS 48
static struct {
	char fn[NAME_LEN];
	int n;
	char opt[MAX_NAMES][NAME_LEN];
} code_fn[MAX_FUNCS];
static int n_code_fn;

static evo_scene *probe_scene;
static evo_lua *probe_lua;

static void probe_close(void)
{
	evo_lua_destroy(probe_lua);
	evo_scene_destroy(probe_scene);
	probe_lua = NULL;
	probe_scene = NULL;
}

/* Builds a scene from an environment whose init is `body` (it has a bot,
 * `bot`, of the bot model Probe, made first); 0, or -1 with err set. */
static int probe_env(const char *body, evo_err *err)
{
	char mind[256];
	snprintf(mind, sizeof mind, "%s/Avoid", cli_tmp);
	char text[2048];
	snprintf(text, sizeof text,
		 "local env = {}\n"
		 "function env.init(scene, task)\n"
		 "\tlocal bot = scene:bot{}\n"
		 "%s\n"
		 "end\n"
		 "return env\n",
		 body);
	if (cli_write(text, "%s/Envs/Probe.lua", mind) != 0)
		return evo_fail(err, "cannot write Envs/Probe.lua");
	probe_close();
	probe_scene = evo_scene_create();
	evo_lua_def def = {
	    .scene = probe_scene,
	    .mind_dir = mind,
	    .lua_dir = getenv("EVO_LUA_DIR") ? getenv("EVO_LUA_DIR") : "lua",
	    .botmodel = "Probe"};
	probe_lua = probe_scene ? evo_lua_create(&def, err) : NULL;
	if (!probe_lua)
		return -1;
	return evo_lua_init_env(probe_lua, "Probe", err);
}

/* The options of the call `call` (a call that passes `{ ["?"] = 1 }`), or
 * -1 when it raised anything but an unknown option. */
static int probe_options(const char *fn, const char *call)
{
	evo_err err = {{0}};
	if (probe_env(call, &err) == 0 || n_code_fn >= MAX_FUNCS)
		return -1;
	const char *known = strstr(err.msg, "unknown option '?' (known: ");
	if (!known)
		return -1;
	known += strlen("unknown option '?' (known: ");
	int f = -1;
	for (int i = 0; i < n_code_fn; i++)
		if (strcmp(code_fn[i].fn, fn) == 0)
			f = i;
	if (f < 0) {
		f = n_code_fn++;
		snprintf(code_fn[f].fn, NAME_LEN, "%s", fn);
		code_fn[f].n = 0;
	}
	while (*known && *known != ')') {
		size_t len = strcspn(known, ",)");
		char name[NAME_LEN];
		snprintf(name, sizeof name, "%.*s", (int)len, known);
		if (!in_list(name, code_fn[f].opt, code_fn[f].n) &&
		    code_fn[f].n < MAX_NAMES)
			snprintf(code_fn[f].opt[code_fn[f].n++], NAME_LEN, "%s",
				 name);
		known += len;
		known += strspn(known, ", ");
	}
	return 0;
}

/* Every method of the scene and of a bot that takes options: the names
 * of their methods from the metatables (__methods: __index is a function
 * that suggests a name for a misspelt one), each then called with an
 * option it cannot know. */
static void probe_all_options(void)
{
	evo_err err = {{0}};
	probe_env(
	    "\tlocal t = {}\n"
	    "\tfor k in pairs(getmetatable(scene).__methods) do t[#t + 1] = "
	    "'scene:' .. k end\n"
	    "\tfor k in pairs(getmetatable(bot).__methods) do t[#t + 1] = "
	    "'bot:' .. k end\n"
	    "\terror('METHODS ' .. table.concat(t, ' ') .. ' END', 0)",
	    &err);
	const char *m = strstr(err.msg, "METHODS ");
	if (!m) {
		result(0, "cannot list the methods of scene and bot: %s",
		       err.msg);
		return;
	}
	for (m += 8; strncmp(m, "END", 3) != 0;) {
		char fn[NAME_LEN], call[256];
		size_t len = strcspn(m, " ");
		snprintf(fn, sizeof fn, "%.*s", (int)len, m);
		m += len + 1;
		const char *colon = strchr(fn, ':');
		const char *obj =
		    strncmp(fn, "scene:", 6) == 0 ? "scene" : "bot";
		if (strcmp(fn, "scene:reward") == 0 ||
		    strcmp(fn, "scene:control") == 0) {
			/* a named function's options, and a Lua function's */
			snprintf(call, sizeof call, "\t%s(%s, { ['?'] = 1 })",
				 fn,
				 strcmp(fn, "scene:reward") == 0
				     ? "'StepReward'"
				     : "'NextOnTimeout'");
			probe_options(fn, call);
			snprintf(call, sizeof call,
				 "\t%s(function() end, { ['?'] = 1 })", fn);
			probe_options(fn, call);
			continue;
		}
		snprintf(call, sizeof call, "\t%s:%s{ ['?'] = 1 }", obj,
			 colon + 1);
		probe_options(fn, call);
	}
	/* a bot model's body table */
	probe_options("body", "\tscene:bot{ model = 'BadBody' }");
}

/* Bot models: Probe adds one sensor or actuator of each kind, named after
 * its method, with no option but its name; BadBody has a body option no
 * one knows. */
static const char *const BOT_PARTS[] = {
    "proximity",       "distance", "zone",   "bearing",	 "presence",
    "object_detector", "movement", "random", "constant", "holding",
    "radar",	       "bumper",   "wheel",  "claw",	 "speed_wheel",
    "drive",	       "light",	   "ground", "rab",	 "broadcast",
    "camera",	       "azimuth", NULL};

static int write_bot_models(void)
{
	char text[2048] = "return {\n\tbody = {},\n\tbuild = function(bot)\n";
	for (int i = 0; BOT_PARTS[i]; i++) {
		char line[128];
		snprintf(line, sizeof line, "\t\tbot:%s{ name = '%s' }\n",
			 BOT_PARTS[i], BOT_PARTS[i]);
		strcat(text, line);
	}
	strcat(text, "\tend,\n}\n");
	return cli_sh("mkdir -p %s/Avoid/Bots", cli_tmp) ||
	       cli_write(text, "%s/Avoid/Bots/Probe.lua", cli_tmp) ||
	       cli_write("return { body = { ['?'] = 1 }, build = function(bot) "
			 "end }\n",
			 "%s/Avoid/Bots/BadBody.lua", cli_tmp);
}

static void render_target(char *out, size_t cap, int target)
{
	if (target == EVO_TARGET_NONE)
		snprintf(out, cap, "none");
	else if (target == EVO_TARGET_NEAREST_OBJECT)
		snprintf(out, cap, "\"nearest_object\"");
	else
		snprintf(out, cap, "element %d", target);
}

/* The scene built with every option left out (the defaults scene), and
 * whether `bot:KIND{}` without a name fails for each part. */
static int defaults_built;
static int name_required[24];
static int wall_ends_required; /* scene:wall{} fails */

static const evo_sensor *probe_sensor(const char *name)
{
	const evo_bot *b = &probe_scene->bot[0];
	for (int i = 0; i < b->n_sensors; i++)
		if (strcmp(b->sensor[i].name, name) == 0)
			return &b->sensor[i];
	return NULL;
}

static const evo_actuator *probe_actuator(const char *name)
{
	const evo_bot *b = &probe_scene->bot[0];
	for (int i = 0; i < b->n_actuators; i++)
		if (strcmp(b->actuator[i].name, name) == 0)
			return &b->actuator[i];
	return NULL;
}

static void build_defaults_scene(void)
{
	evo_err err = {{0}};
	for (int i = 0; BOT_PARTS[i]; i++) {
		char call[128];
		snprintf(call, sizeof call, "\tbot:%s{}", BOT_PARTS[i]);
		name_required[i] = probe_env(call, &err) != 0 &&
				   strstr(err.msg, "needs a name") != NULL;
	}
	wall_ends_required = probe_env("\tscene:wall{}", &err) != 0 &&
			     strstr(err.msg, "must be a number") != NULL;
	defaults_built =
	    probe_env(
		"\tscene:bot{}\n"
		"\tscene:cylinder{} scene:box{} scene:zone{} scene:object{}\n"
		"\tscene:grid{}\n"
		"\tscene:light{} scene:patch{}\n"
		"\tscene:reward('StepReward') scene:control('NextOnTimeout')\n"
		"\tscene:reward(function() return 0 end)\n"
		"\tscene:control(function() return false end)",
		&err) == 0 &&
	    probe_scene->n_bots == 2 && probe_scene->n_elements == 4 &&
	    probe_scene->n_rewards == 2 && probe_scene->n_controls == 2;
	result(defaults_built, "cannot build the scene of defaults: %s",
	       err.msg);
}

/* evo's default of option `opt` of `fn`, in the words of docs/lua.md's
 * table. 0, or -1 when this test cannot tell (teach it). */
static int render_option_default(const char *fn, const char *opt, char *out,
				 size_t cap)
{
	const evo_scene *sc = probe_scene;
	const double deg = M_PI / 180.0;
	if (!defaults_built)
		return -1;
	if (strcmp(fn, "scene:bot") == 0) {
		const evo_bot *b = &sc->bot[0];
		if (strcmp(opt, "x") == 0)
			fmt_num(out, cap, b->def.x);
		else if (strcmp(opt, "y") == 0)
			fmt_num(out, cap, b->def.y);
		else if (strcmp(opt, "angle") == 0)
			fmt_num(out, cap, b->def.yaw / deg);
		else if (strcmp(opt, "name") == 0)
			snprintf(out, cap, "%s",
				 strcmp(sc->bot[0].name, "bot1") == 0 &&
					 strcmp(sc->bot[1].name, "bot2") == 0
				     ? "\"botN\", N the bot's number"
				     : sc->bot[0].name);
		else if (strcmp(opt, "model") == 0)
			snprintf(out, cap, "%s",
				 probe_sensor("proximity")
				     ? "the task's BOTMODEL"
				     : "another model");
		else if (strcmp(opt, "team") == 0)
			snprintf(out, cap, "%s",
				 b->team < 0 ? "none" : "a team");
		else
			return -1;
		return 0;
	}
	if (strcmp(fn, "body") == 0) {
		const evo_bbody_def *d = &sc->bot[0].def.body;
		const evo_bshape *s = &d->shape[0];
		if (strcmp(opt, "shape") == 0)
			snprintf(out, cap, "%s",
				 s->type == EVO_SHAPE_CIRCLE ? "\"circle\""
							     : "\"box\"");
		else if (strcmp(opt, "sleep") == 0)
			snprintf(out, cap, "%s",
				 d->allow_sleep ? "true" : "false");
		else if (strcmp(opt, "collision") == 0)
			snprintf(out, cap, "%s",
				 d->kinematic ? "\"undo\"" : "\"physics\"");
		else {
			const double v =
			    strcmp(opt, "radius") == 0	      ? s->radius
			    : strcmp(opt, "half_width") == 0  ? s->half[0]
			    : strcmp(opt, "half_height") == 0 ? s->half[1]
			    : strcmp(opt, "density") == 0     ? d->density
			    : strcmp(opt, "friction") == 0    ? s->friction
			    : strcmp(opt, "restitution") == 0 ? s->restitution
			    : strcmp(opt, "linear_damping") == 0
				? d->linear_damping
			    : strcmp(opt, "angular_damping") == 0
				? d->angular_damping
				: NAN;
			if (isnan(v))
				return -1;
			fmt_num(out, cap, v);
		}
		return 0;
	}
	static const char *const elements[] = {"scene:cylinder", "scene:box",
					       "scene:zone", "scene:object"};
	for (int k = 0; k < 4; k++) {
		if (strcmp(fn, elements[k]) != 0)
			continue;
		const evo_element *e = &sc->element[k];
		if (strcmp(opt, "name") == 0) {
			snprintf(out, cap, "%s", e->name[0] ? e->name : "none");
			return 0;
		}
		const double v =
		    strcmp(opt, "x") == 0		 ? e->x
		    : strcmp(opt, "y") == 0		 ? e->y
		    : strcmp(opt, "angle") == 0		 ? e->angle / deg
		    : strcmp(opt, "radius") == 0	 ? e->size
		    : strcmp(opt, "size") == 0		 ? e->size
		    : strcmp(opt, "half_width") == 0	 ? e->half_w
		    : strcmp(opt, "half_height") == 0	 ? e->half_h
		    : strcmp(opt, "density") == 0	 ? e->def.density
		    : strcmp(opt, "friction") == 0	 ? e->def.friction
		    : strcmp(opt, "restitution") == 0	 ? e->def.restitution
		    : strcmp(opt, "linear_damping") == 0 ? e->def.linear_damping
		    : strcmp(opt, "angular_damping") == 0
			? e->def.angular_damping
			: NAN;
		if (isnan(v))
			return -1;
		fmt_num(out, cap, v);
		return 0;
	}
	if (strcmp(fn, "scene:wall") == 0) {
		snprintf(out, cap, "%s",
			 wall_ends_required ? "required" : "optional");
		return 0;
	}
	if (strcmp(fn, "scene:grid") == 0) {
		const evo_grid_def *g = &sc->grid;
		if (strcmp(opt, "shapes") == 0) {
			snprintf(out, cap, "%s",
				 g->boxes == 0	 ? "\"cylinders\""
				 : g->boxes == 1 ? "\"boxes\""
						 : "\"mixed\"");
			return 0;
		}
		const double v = strcmp(opt, "x0") == 0		? g->x0
				 : strcmp(opt, "y0") == 0	? g->y0
				 : strcmp(opt, "x1") == 0	? g->x1
				 : strcmp(opt, "y1") == 0	? g->y1
				 : strcmp(opt, "spacing") == 0	? g->spacing
				 : strcmp(opt, "jitter") == 0	? g->jitter
				 : strcmp(opt, "min_size") == 0 ? g->min_size
				 : strcmp(opt, "size_variability") == 0
				     ? g->size_variability
				 : strcmp(opt, "clearance") == 0 ? g->clearance
								 : NAN;
		if (isnan(v))
			return -1;
		fmt_num(out, cap, v);
		return 0;
	}
	if (strcmp(fn, "scene:reward") == 0 ||
	    strcmp(fn, "scene:control") == 0) {
		int reward = strcmp(fn, "scene:reward") == 0;
		const evo_reward_def *rd = &sc->reward[0].def;
		const evo_control_def *cd = &sc->control[0].def;
		int bot = reward ? rd->bot : cd->bot;
		if (strcmp(opt, "bot") == 0)
			snprintf(out, cap, "%s",
				 bot == 0 ? "the first bot" : "another bot");
		else if (strcmp(opt, "team") == 0)
			/* one reward or control, for the first bot, which is of
			 * no team: paid to that bot */
			snprintf(out, cap, "%s",
				 rd->scope == EVO_SCOPE_BOT &&
					 sc->bot[bot].team < 0
				     ? "none"
				     : "a team");
		else if (strcmp(opt, "target") == 0)
			render_target(out, cap,
				      reward ? rd->target : cd->target);
		else if (strcmp(opt, "threshold") == 0)
			fmt_num(out, cap,
				reward ? rd->threshold : cd->threshold);
		else if (strcmp(opt, "reset") == 0) /* the Lua one was added */
			snprintf(out, cap, "none");
		else if (reward && strcmp(opt, "k") == 0)
			fmt_num(out, cap, rd->k);
		else if (reward && strcmp(opt, "k2") == 0)
			fmt_num(out, cap, rd->k2);
		else if (reward && strcmp(opt, "sensors") == 0)
			snprintf(out, cap, "%s",
				 rd->n_sensors ? "some" : "none");
		else if (!reward && strcmp(opt, "ticks") == 0)
			snprintf(out, cap, "%ld", cd->ticks);
		else if (!reward && strcmp(opt, "sensor") == 0)
			snprintf(out, cap, "%s",
				 cd->sensor < 0 ? "none" : "some");
		else
			return -1;
		return 0;
	}
	if (strcmp(fn, "scene:light") == 0 && sc->swarm.n_lights == 1) {
		const evo_light *l = &sc->swarm.light[0];
		if (strcmp(opt, "colour") == 0) {
			snprintf(out, cap, "%s",
				 sc->swarm.n_blobs ? "a colour" : "none");
			return 0;
		}
		const double v = strcmp(opt, "x") == 0		 ? l->pos[0]
				 : strcmp(opt, "y") == 0	 ? l->pos[1]
				 : strcmp(opt, "intensity") == 0 ? l->intensity
								 : NAN;
		if (isnan(v))
			return -1;
		fmt_num(out, cap, v);
		return 0;
	}
	if (strcmp(fn, "scene:patch") == 0 && sc->swarm.n_patches == 1) {
		const evo_patch *p = &sc->swarm.patch[0];
		if (strcmp(opt, "radius") == 0) {
			snprintf(out, cap, "%s",
				 p->circle ? "a circle" : "none");
			return 0;
		}
		const double v = strcmp(opt, "x") == 0		   ? p->x
				 : strcmp(opt, "y") == 0	   ? p->y
				 : strcmp(opt, "angle") == 0	   ? p->yaw / deg
				 : strcmp(opt, "half_width") == 0  ? p->hx
				 : strcmp(opt, "half_height") == 0 ? p->hy
				 : strcmp(opt, "grey") == 0	   ? p->grey
								   : NAN;
		if (isnan(v))
			return -1;
		fmt_num(out, cap, v);
		return 0;
	}
	if (strncmp(fn, "bot:", 4) != 0)
		return -1;
	const char *part = fn + 4;
	if (strcmp(opt, "name") == 0) {
		for (int i = 0; BOT_PARTS[i]; i++)
			if (strcmp(BOT_PARTS[i], part) == 0) {
				snprintf(out, cap, "%s",
					 name_required[i] ? "required"
							  : "optional");
				return 0;
			}
		return -1;
	}
	const evo_sensor *s = probe_sensor(part);
	if (s) {
		const evo_sensor_def *d = &s->def;
		if (strcmp(opt, "sees") == 0) {
			snprintf(out, cap, "{");
			static const struct {
				unsigned cat;
				const char *name;
			} seen[] = {{EVO_CAT_OBSTACLE, "obstacles"},
				    {EVO_CAT_BOT, "bots"},
				    {EVO_CAT_OBJECT, "objects"}};
			for (int i = 0; i < 3; i++)
				if (d->mask & seen[i].cat)
					snprintf(out + strlen(out),
						 cap - strlen(out), "%s\"%s\"",
						 out[1] ? ", " : "",
						 seen[i].name);
			snprintf(out + strlen(out), cap - strlen(out), "}");
			return 0;
		}
		if (strcmp(opt, "target") == 0) {
			render_target(out, cap, d->target);
			return 0;
		}
		const evo_swarm_sensor *w = &d->swarm;
		if (d->kind == EVO_SENSE_RAB || d->kind == EVO_SENSE_CAMERA) {
			static const char *const reads[] = {
			    "\"range\"", "\"bearing\"", "\"value\"", "\"count\"",
			    "\"colour\""};
			if (strcmp(opt, "read") == 0)
				snprintf(out, cap, "%s", reads[w->read]);
			else if (strcmp(opt, "occluded") == 0)
				snprintf(out, cap, "%s",
					 w->occluded ? "true" : "false");
			else if (strcmp(opt, "range") == 0)
				fmt_num(out, cap, w->range);
			else if (strcmp(opt, "scale") == 0)
				fmt_num(out, cap, w->scale);
			else if (strcmp(opt, "slot") == 0)
				fmt_num(out, cap, w->slot);
			else if (strcmp(opt, "index") == 0)
				fmt_num(out, cap, w->index + 1);
			else if (strcmp(opt, "colour") == 0)
				snprintf(out, cap, "%s",
					 w->colour < 0
					     ? "any"
					     : evo_colour_name(w->colour));
			else
				return -1;
			return 0;
		}
		if (strcmp(opt, "aperture") == 0) {
			fmt_num(out, cap, w->aperture / deg);
			return 0;
		}
		const double v = strcmp(opt, "x") == 0		? d->x
				 : strcmp(opt, "y") == 0	? d->y
				 : strcmp(opt, "angle") == 0	? d->angle / deg
				 : strcmp(opt, "range") == 0	? d->range
				 : strcmp(opt, "arc") == 0	? d->arc / deg
				 : strcmp(opt, "rays") == 0	? d->rays
				 : strcmp(opt, "deadzone") == 0 ? d->deadzone
				 : strcmp(opt, "scale") == 0	? d->scale
				 : strcmp(opt, "reach") == 0	? d->reach
				 : strcmp(opt, "value") == 0	? d->value
								: NAN;
		if (isnan(v))
			return -1;
		fmt_num(out, cap, v);
		return 0;
	}
	const evo_actuator *a = probe_actuator(part);
	if (a) {
		if (strcmp(opt, "turn") == 0) {
			snprintf(out, cap, "%s", a->def.turn ? "true" : "false");
			return 0;
		}
		const double v =
		    strcmp(opt, "max_speed") == 0 ? a->def.max_speed
		    : strcmp(opt, "accel") == 0	  ? a->def.accel
		    : strcmp(opt, "x") == 0	    ? a->def.x
		    : strcmp(opt, "y") == 0	    ? a->def.y
		    : strcmp(opt, "angle") == 0	    ? a->def.angle / deg
		    : strcmp(opt, "max_force") == 0 ? a->def.max_force
		    : strcmp(opt, "reach") == 0	    ? a->def.reach
						    : NAN;
		if (isnan(v))
			return -1;
		fmt_num(out, cap, v);
		return 0;
	}
	return -1;
}

static int find_code_fn(const char *fn)
{
	for (int i = 0; i < n_code_fn; i++)
		if (strcmp(code_fn[i].fn, fn) == 0)
			return i;
	return -1;
}

/* What docs/lua.md says a function takes: the options of its rows in the
 * table of defaults, and those its method tables list, as in
 * `scene:cylinder{x, y, radius, name}` or in the list under "Options of
 * `body`". */
static struct {
	char fn[NAME_LEN];
	int n_table, n_sig;
	char table[MAX_NAMES][NAME_LEN];
	char sig[MAX_NAMES][NAME_LEN];
} doc_fn[MAX_FUNCS];
static int n_doc_fn;

static int doc_fn_index(const char *fn)
{
	for (int i = 0; i < n_doc_fn; i++)
		if (strcmp(doc_fn[i].fn, fn) == 0)
			return i;
	if (n_doc_fn >= MAX_FUNCS)
		return -1;
	snprintf(doc_fn[n_doc_fn].fn, NAME_LEN, "%s", fn);
	return n_doc_fn++;
}

/* The options in docs/lua.md's method tables and body list. */
static void read_signatures(const char *file)
{
	char *text = cli_read("%s", file);
	if (!text) {
		result(0, "%s: cannot read it", file);
		return;
	}
	int in_body = 0, bullets = 0;
	for (char *p = text; p && *p;) {
		char *eol = strchr(p, '\n');
		if (eol)
			*eol = 0;
		/* the list under "Options of `body`:", up to its end */
		if (strncmp(p, "Options of `body`", 17) == 0)
			in_body = 1;
		else if (in_body && strncmp(p, "- ", 2) == 0)
			bullets++;
		else if (in_body && strncmp(p, "  ", 2) != 0 &&
			 (p[0] || bullets))
			in_body = 0;
		if (in_body && strncmp(p, "- ", 2) == 0) {
			char names[MAX_NAMES][NAME_LEN];
			int n = names_of(p, names, NULL);
			int f = doc_fn_index("body");
			for (int i = 0; i < n && f >= 0; i++)
				if (!strchr(names[i], '"')) /* not a value */
					add_name(doc_fn[f].sig,
						 &doc_fn[f].n_sig, names[i]);
		}
		/* `scene:grid{x0, ...}`: each span of a table line that
		 * calls a method with an option table */
		for (char *q = p[0] == '|' ? strchr(p, '`') : NULL; q;
		     q = strchr(q + 1, '`')) {
			char *q_end = strchr(q + 1, '`');
			if (!q_end)
				break;
			char s[CELL_MAX];
			snprintf(s, sizeof s, "%.*s", (int)(q_end - q - 1),
				 q + 1);
			q = q_end;
			{
				size_t fn_len = strcspn(s, "{(");
				char *brace = strrchr(s, '{');
				if ((strncmp(s, "scene:", 6) != 0 &&
				     strncmp(s, "bot:", 4) != 0) ||
				    !brace)
					continue;
				char fn[NAME_LEN];
				snprintf(fn, sizeof fn, "%.*s", (int)fn_len, s);
				int f = doc_fn_index(fn);
				for (char *o = brace + 1;
				     f >= 0 && *o && *o != '}';) {
					size_t len = strcspn(o, ",}");
					char opt[NAME_LEN];
					snprintf(opt, sizeof opt, "%.*s",
						 (int)len, o);
					add_name(doc_fn[f].sig,
						 &doc_fn[f].n_sig, opt);
					o += len;
					o += strspn(o, ", ");
				}
			}
		}
		p = eol ? eol + 1 : NULL;
	}
	free(text);
}

/* docs/lua.md's table of defaults and its method tables against the
 * scene the `evo` module builds. */
static void check_lua_options(doc_table *t)
{
	read_signatures(t->file);
	if (read_table(t)) {
		section_end("%s: %s", t->file, t->heading);
		return;
	}
	for (int r = 0; r < t->n; r++) {
		const doc_row *row = &t->row[r];
		char fns[MAX_NAMES][NAME_LEN], opts[MAX_NAMES][NAME_LEN];
		char value[CELL_MAX];
		int n_fn = names_of(row->cell[0], fns, NULL);
		int n_opt = names_of(row->cell[1], opts, NULL);
		plain_value(row->cell[t->default_col], value, sizeof value);
		for (int f = 0; f < n_fn; f++) {
			int d = doc_fn_index(fns[f]);
			int c = find_code_fn(fns[f]);
			result(c >= 0,
			       "%s:%d: %s is documented, but evo has no such "
			       "function with options",
			       t->file, row->line, fns[f]);
			for (int o = 0; o < n_opt; o++) {
				if (d >= 0)
					add_name(doc_fn[d].table,
						 &doc_fn[d].n_table, opts[o]);
				if (c < 0)
					continue;
				if (!in_list(opts[o], code_fn[c].opt,
					     code_fn[c].n)) {
					result(0,
					       "%s:%d: %s: option %s is "
					       "documented, but "
					       "evo does not take it",
					       t->file, row->line, fns[f],
					       opts[o]);
					continue;
				}
				char one[CELL_MAX], code[CELL_MAX];
				if (nth_value(value, o, n_opt, one,
					      sizeof one)) {
					result(
					    0,
					    "%s:%d: '%s' is not one default or "
					    "one for each of the %d options",
					    t->file, row->line, value, n_opt);
					break;
				}
				if (render_option_default(fns[f], opts[o], code,
							  sizeof code)) {
					result(0,
					       "%s:%d: %s %s: this test cannot "
					       "tell evo's default; teach "
					       "render_option_default",
					       t->file, row->line, fns[f],
					       opts[o]);
					continue;
				}
				result(same_value(one, code),
				       "%s:%d: %s %s: the docs say '%s', evo's "
				       "is '%s'",
				       t->file, row->line, fns[f], opts[o], one,
				       code);
			}
		}
	}
	/* the other way: every option evo takes is in the table of defaults
	 * and in the method tables; every option those list is one evo takes */
	for (int c = 0; c < n_code_fn; c++) {
		int d = doc_fn_index(code_fn[c].fn);
		for (int o = 0; d >= 0 && o < code_fn[c].n; o++) {
			const char *opt = code_fn[c].opt[o];
			result(
			    in_list(opt, doc_fn[d].table, doc_fn[d].n_table),
			    "%s: %s takes the option %s, which the table under "
			    "'%s' does not document",
			    t->file, code_fn[c].fn, opt, t->heading);
			result(in_list(opt, doc_fn[d].sig, doc_fn[d].n_sig),
			       "%s: %s takes the option %s, which its method "
			       "table (or the list of body options) does not "
			       "name",
			       t->file, code_fn[c].fn, opt);
		}
	}
	for (int d = 0; d < n_doc_fn; d++) {
		int c = find_code_fn(doc_fn[d].fn);
		if (doc_fn[d].n_sig == 0)
			continue;
		for (int o = 0; c >= 0 && o < doc_fn[d].n_sig; o++)
			result(
			    in_list(doc_fn[d].sig[o], code_fn[c].opt,
				    code_fn[c].n),
			    "%s: the method table names option %s of %s, which "
			    "evo does not take",
			    t->file, doc_fn[d].sig[o], doc_fn[d].fn);
		result(c >= 0,
		       "%s: the method table names %s with options, which "
		       "evo does not have",
		       t->file, doc_fn[d].fn);
	}
	section_end("%s:%d: %s and the method tables against the evo module "
		    "(%d functions with options)",
		    t->file, t->line, t->heading, n_code_fn);
}

/* docs/world.md's sensor and actuator tables: each "`option` (default V)"
 * or "`option` (V)" of kind K's row, V a number, is bot:K's default. */
static void check_world_mentions(const char *file)
{
	char *text = cli_read("%s", file);
	if (!text) {
		result(0, "%s: cannot read it", file);
		section_end("%s", file);
		return;
	}
	char heading[256] = "";
	int line = 1, n = 0;
	for (char *p = text; p && *p; line++) {
		char *eol = strchr(p, '\n');
		if (eol)
			*eol = 0;
		heading_of(p, heading, sizeof heading);
		char cell[MAX_CELLS][CELL_MAX];
		if ((strcmp(heading, "Sensors") == 0 ||
		     strcmp(heading, "Actuators") == 0) &&
		    split_cells(p, cell) >= 2 && cell[0][0] == '`') {
			char kind[MAX_NAMES][NAME_LEN], fn[NAME_LEN + 8];
			names_of(cell[0], kind, NULL);
			snprintf(fn, sizeof fn, "bot:%s", kind[0]);
			for (char *q = strchr(cell[1], '`'); q;
			     q = strchr(q + 1, '`')) {
				char *end = strchr(q + 1, '`');
				if (!end)
					break;
				char opt[NAME_LEN], code[64];
				double v;
				snprintf(opt, sizeof opt, "%.*s",
					 (int)(end - q - 1), q + 1);
				const char *after = end + 1;
				q = end;
				if (strncmp(after, " (", 2) != 0)
					continue;
				after += 2;
				if (strncmp(after, "default ", 8) == 0)
					after += 8;
				char *num_end;
				v = strtod(after, &num_end);
				if (num_end == after)
					continue;
				n++;
				if (render_option_default(fn, opt, code,
							  sizeof code)) {
					result(0,
					       "%s:%d: %s %s: this test cannot "
					       "tell evo's default",
					       file, line, fn, opt);
					continue;
				}
				char doc[64];
				snprintf(doc, sizeof doc, "%.17g", v);
				result(same_value(doc, code),
				       "%s:%d: %s %s: the docs say %s, evo's "
				       "is %s",
				       file, line, fn, opt, doc, code);
			}
		}
		p = eol ? eol + 1 : NULL;
	}
	free(text);
	result(n > 0,
	       "%s: no \"`option` (default V)\" found in its sensor "
	       "table",
	       file);
	section_end("%s: the %d defaults its sensor and actuator tables give",
		    file, n);
}

/* ---- every table of defaults is one this test checks --------------------- */

static doc_table neat_t = {.file = "docs/learning.md",
			   .heading = "NEAT's parameters"};
static doc_table genetic_t = {.file = "docs/learning.md",
			      .heading = "GENETIC's parameters"};
static doc_table annealing_t = {.file = "docs/learning.md",
				.heading = "ANNEALING's parameters"};
static doc_table cmaes_t = {.file = "docs/learning.md",
			    .heading = "CMA-ES's parameters"};
static doc_table novelty_t = {.file = "docs/learning.md",
			      .heading = "NOVELTY's parameters"};
static doc_table mapelites_t = {.file = "docs/learning.md",
				.heading = "MAP-Elites's parameters"};
static doc_table openended_t = {.file = "docs/openended.md",
				.heading = "OPENENDED's parameters"};
static doc_table task_keys_t = {.file = "docs/learning.md",
				.heading = "The task's keys"};
static doc_table simbatch_t = {.file = "docs/formats.md",
			       .heading = "`.simbatch` — a task"};
static doc_table lua_t = {.file = "docs/lua.md",
			  .heading = "Options and their defaults"};
static doc_table teams_t = {.file = "docs/teams.md", .heading = "A team task"};
static doc_table continuous_t = {
    .file = "docs/learning.md",
    .heading = "Training the whole hierarchy (LEARNSIMCONTINUOUS)"};

static doc_table *const checked[] = {
    &neat_t,	  &genetic_t, &annealing_t, &cmaes_t,	&novelty_t,
    &mapelites_t, &openended_t, &task_keys_t, &simbatch_t, &lua_t,	&teams_t,
    &continuous_t};

/* Every table header of docs/ with a `default` column is one of
 * `checked`. */
static void every_table_is_checked(void)
{
	DIR *d = opendir("docs");
	struct dirent *e;
	int tables = 0;
	while (d && (e = readdir(d)) != NULL) {
		size_t len = strlen(e->d_name);
		if (len < 4 || strcmp(e->d_name + len - 3, ".md") != 0)
			continue;
		char file[300];
		snprintf(file, sizeof file, "docs/%s", e->d_name);
		char *text = cli_read("%s", file);
		char heading[256] = "";
		int line = 1;
		for (char *p = text; p && *p; line++) {
			char cell[MAX_CELLS][CELL_MAX];
			heading_of(p, heading, sizeof heading);
			if (is_header(p)) {
				int n = split_cells(p, cell), has_default = 0;
				for (int i = 0; i < n; i++)
					has_default |=
					    strcmp(cell[i], "default") == 0;
				int known = 0;
				for (unsigned k = 0;
				     k < sizeof checked / sizeof checked[0];
				     k++)
					known |= strcmp(checked[k]->file,
							file) == 0 &&
						 strcmp(checked[k]->heading,
							heading) == 0;
				if (has_default) {
					tables++;
					result(
					    known,
					    "%s:%d: a table of defaults under "
					    "'%s' that this test does not "
					    "check",
					    file, line, heading);
				}
			}
			char *eol = strchr(p, '\n');
			p = eol ? eol + 1 : NULL;
		}
		free(text);
	}
	if (d)
		closedir(d);
	result(tables == (int)(sizeof checked / sizeof checked[0]),
	       "docs/: %d tables of defaults, this test checks %d", tables,
	       (int)(sizeof checked / sizeof checked[0]));
	section_end("docs/: every table with a default column is one this "
		    "test checks");
}

int main(void)
{
	if (cli_setup("defaults") ||
	    cli_sh("cp -r minds/Avoid %s/ && mkdir -p %s/Avoid/Envs", cli_tmp,
		   cli_tmp) ||
	    write_bot_models()) {
		printf("cannot set up a copy of minds/Avoid\n0 passed, 1 "
		       "failed\n");
		return 1;
	}
	learn_L = luaL_newstate();
	luaL_openlibs(learn_L);
	const char *lua_dir =
	    getenv("EVO_LUA_DIR") ? getenv("EVO_LUA_DIR") : "lua";
	lua_getglobal(learn_L, "package");
	lua_pushfstring(learn_L, "%s/?.lua", lua_dir);
	lua_setfield(learn_L, -2, "path");
	lua_pop(learn_L, 1);

	every_table_is_checked();
	check_method_table(&neat_t, "learn.neat");
	check_method_table(&genetic_t, "learn.genetic");
	check_method_table(&annealing_t, "learn.annealing");
	check_method_table(&cmaes_t, "learn.cmaes");
	check_method_table(&novelty_t, "learn.novelty");
	check_method_table(&mapelites_t, "learn.mapelites");
	check_method_table(&openended_t, "learn.openended_options");
	learning_run();
	check_task_table(&task_keys_t, 1, 0);
	check_task_table(&simbatch_t, 0, 1);
	check_task_table(&teams_t, 0, 0);
	check_task_table(&continuous_t, 0, 0);
	probe_all_options();
	build_defaults_scene();
	check_lua_options(&lua_t);
	check_world_mentions("docs/world.md");

	probe_close();
	evo_mindfolder_free(cont.mind);
	lua_close(learn_L);
	cli_cleanup();
	printf("%d passed, %d failed\n", passed, failed);
	return failed != 0;
}

#define _DEFAULT_SOURCE /* realpath */
#define _POSIX_C_SOURCE 200809L
#include "mind/task.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/fileio.h"

/* Keys a task type cannot run without. */
static const char *const demo_keys[] = {"MASTERSKILL", "BOTMODEL", "ENV",
					NULL};
static const char *const learn_keys[] = {"MASTERSKILL", "LEARNINGSKILL",
					 "LEARNINGMETHOD", "BOTMODEL", "ENV",
					 "NUMGEN", NULL};

/* A remote task's world is the remote's (docs/remote.md): BOTMODEL and
 * ENV are for `evo serve` of it, not for the mind's side. */
static const char *const remote_demo_keys[] = {"MASTERSKILL", NULL};
static const char *const remote_learn_keys[] = {
    "MASTERSKILL", "LEARNINGSKILL", "LEARNINGMETHOD", "NUMGEN", NULL};

static const char *const *required_keys(const char *type)
{
	if (strstr(type, "REMOTE"))
		return strncmp(type, "LEARN", 5) == 0 ? remote_learn_keys
						      : remote_demo_keys;
	if (strncmp(type, "LEARN", 5) == 0)
		return learn_keys;
	if (strncmp(type, "DEMO", 4) == 0)
		return demo_keys;
	return NULL;
}

/* The line of a key of the task file, 0 when absent. */
static uint32_t key_line(const evo_simbatch *sb, const char *key)
{
	for (unsigned i = 0; i < sb->n_pairs; i++)
		if (strcmp(sb->pair[i].key, key) == 0)
			return sb->pair[i].line;
	return 0;
}

static int upper_eq(const char *a, const char *b)
{
	for (; *a && *b; a++, b++)
		if ((*a >= 'a' && *a <= 'z' ? *a - 32 : *a) != *b)
			return 0;
	return *a == *b;
}

/* The mind folder of a task file: the parent of its Tasks/ folder. */
static int mind_folder(const char *path, const evo_simbatch *sb, char *out,
		       size_t cap, evo_err *err)
{
	char dir[1024];
	if (evo_path_fmt(dir, sizeof dir, err, "%s", path))
		return -1;
	char *slash = strrchr(dir, '/');
	if (slash)
		*slash = 0;
	else
		snprintf(dir, sizeof dir, ".");
	const char *base = strrchr(dir, '/');
	base = base ? base + 1 : dir;
	if (strcmp(base, "Tasks") == 0) {
		if (base == dir)
			snprintf(out, cap, ".");
		else
			snprintf(out, cap, "%.*s", (int)(base - dir - 1), dir);
		return 0;
	}
	/* "T.simbatch" run from inside Tasks/, or a path through "..":
	 * the folder's real name decides. */
	char *real = realpath(dir, NULL);
	if (real) {
		const char *rbase = strrchr(real, '/');
		int in_tasks = rbase && strcmp(rbase + 1, "Tasks") == 0;
		free(real);
		if (in_tasks) {
			int n = strcmp(dir, ".") == 0
				    ? snprintf(out, cap, "..")
				    : snprintf(out, cap, "%s/..", dir);
			if ((size_t)n >= cap)
				return evo_fail(err, "%s: path too long", path);
			return 0;
		}
	}
	const char *root = evo_simbatch_get(sb, "ROOTFOLDER");
	if (!root)
		return evo_fail(err,
				"%s: the task is not in a mind folder's Tasks/ "
				"folder and has no ROOTFOLDER key naming its "
				"mind folder",
				path);
	return evo_path_fmt(out, cap, err, "%s", root);
}

int evo_task_load(const char *path, evo_task *t, evo_err *err)
{
	return evo_task_load_opts(path, NULL, t, err);
}

int evo_task_load_opts(const char *path, const evo_task_opts *o, evo_task *t,
		       evo_err *err)
{
	memset(t, 0, sizeof *t);
	char *data;
	size_t len;
	if (evo_read_file(path, &data, &len, err) != 0)
		return -1;
	t->sb = calloc(1, sizeof *t->sb);
	if (!t->sb) {
		free(data);
		return evo_fail(err, "out of memory");
	}
	evo_diag diag;
	evo_status st = evo_simbatch_parse(data, len, path, t->sb, &diag);
	free(data);
	if (st != EVO_OK) {
		evo_task_free(t);
		return evo_fail(err, "%s", diag.msg);
	}
	for (unsigned i = 0; i < t->sb->n_warnings && i < EVO_MAX_WARNINGS;
	     i++)
		fprintf(stderr, "warning: %s\n", t->sb->warning[i].msg);
	t->type = evo_simbatch_get(t->sb, "TYPE");
	if (!t->type) {
		evo_task_free(t);
		return evo_fail(err,
				"%s: no TYPE key: a task says what to run, "
				"e.g. TYPE:DEMOSIM or TYPE:LEARNSIM",
				path);
	}
	/* TYPE is matched without regard to case (the parser refused an
	 * unknown one): from here on it is the canonical upper-case name. */
	for (unsigned i = 0; evo_task_types[i]; i++)
		if (strcasecmp(t->type, evo_task_types[i]) == 0)
			t->type = evo_task_types[i];
	const char *const *req = required_keys(t->type);
	for (unsigned i = 0; req && req[i]; i++)
		if (!evo_simbatch_get(t->sb, req[i])) {
			evo_fail(err, "%s: a %s task needs the key %s", path,
				 t->type, req[i]);
			evo_task_free(t);
			return -1;
		}
	const char *method = evo_simbatch_get(t->sb, "LEARNINGMETHOD");
	if (method && !upper_eq(method, "NEAT") &&
	    !upper_eq(method, "GENETIC") && !upper_eq(method, "ANNEALING")) {
		evo_fail(err,
			 "%s:%u: LEARNINGMETHOD must be NEAT, GENETIC or "
			 "ANNEALING, found '%s'",
			 path, (unsigned)key_line(t->sb, "LEARNINGMETHOD"),
			 method);
		evo_task_free(t);
		return -1;
	}
	char root[1024];
	if (mind_folder(path, t->sb, root, sizeof root, err) != 0) {
		evo_task_free(t);
		return -1;
	}
	/* SEED was checked by the parser: a whole number that fits. */
	const char *sv = evo_simbatch_get(t->sb, "SEED");
	t->seed = o && o->seed_set ? o->seed
		  : sv		   ? strtoull(sv, NULL, 10)
				   : 1;
	evo_mindfolder_opts opts = {
		.master = evo_simbatch_get(t->sb, "MASTERSKILL"),
		.learning_skill = strncmp(t->type, "LEARN", 5) == 0
					  ? evo_simbatch_get(t->sb,
							     "LEARNINGSKILL")
					  : NULL,
		.nets = o ? o->nets : NULL,
		.n_nets = o ? o->n_nets : 0,
		.seed = t->seed,
	};
	t->mind = evo_mindfolder_load(root, &opts, err);
	if (!t->mind) {
		evo_task_free(t);
		return -1;
	}
	if (opts.learning_skill) {
		int k = evo_mindfolder_skill(t->mind, opts.learning_skill);
		if (k < 0 || t->mind->skill[k].kind != EVO_SKILL_NEURAL) {
			evo_fail(err,
				 "%s: LEARNINGSKILL %s is not a neural skill "
				 "of the hierarchy under %s",
				 path, opts.learning_skill, opts.master);
			evo_task_free(t);
			return -1;
		}
	}
	/* The mind folder is the agent: a BOTNAME that names another one is
	 * most likely a task copied from another folder. */
	const char *botname = evo_simbatch_get(t->sb, "BOTNAME");
	if (botname && strcmp(botname, t->mind->bot_name) != 0) {
		fprintf(stderr,
			"warning: %s:%u: BOTNAME is %s, but the task's mind "
			"folder is %s (%s); evo runs that folder\n",
			path, (unsigned)key_line(t->sb, "BOTNAME"), botname,
			t->mind->bot_name, t->mind->root);
	}
	return 0;
}

void evo_task_free(evo_task *t)
{
	evo_mindfolder_free(t->mind);
	free(t->sb);
	memset(t, 0, sizeof *t);
}

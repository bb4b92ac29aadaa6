#define _DEFAULT_SOURCE /* realpath */
#define _POSIX_C_SOURCE 200809L
#include "mind/task.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/err.h"
#include "base/fileio.h"
#include "mind/names.h"

/* Keys a task type cannot run without. */
static const char *const demo_keys[] = {"MASTERSKILL", "BOTMODEL", "ENV",
					NULL};
static const char *const learn_keys[] = {"MASTERSKILL", "LEARNINGSKILL",
					 "LEARNINGMETHOD", "BOTMODEL", "ENV",
					 "NUMGEN", NULL};

/* LEARNSIMCONTINUOUS trains every neural skill in turn: no LEARNINGSKILL. */
static const char *const continuous_keys[] = {
    "MASTERSKILL", "LEARNINGMETHOD", "BOTMODEL", "ENV", "NUMGEN", NULL};

/* OPENENDED's agents are NEAT genomes of LEARNINGSKILL; its ENV is an
 * environment generator (docs/openended.md). */
static const char *const openended_keys[] = {
    "MASTERSKILL", "LEARNINGSKILL", "BOTMODEL", "ENV", "NUMGEN", NULL};

/* A remote task's world is the remote's (docs/remote.md): BOTMODEL and
 * ENV are for `evo serve` of it, not for the mind's side. */
static const char *const remote_demo_keys[] = {"MASTERSKILL", NULL};
static const char *const remote_learn_keys[] = {
    "MASTERSKILL", "LEARNINGSKILL", "LEARNINGMETHOD", "NUMGEN", NULL};

/* A team task's: its teams and its world (docs/teams.md). */
static const char *const team_demo_keys[] = {"TEAM", "ENV", NULL};
static const char *const team_learn_keys[] = {"TEAM", "ENV", "LEARNINGMETHOD",
					      "NUMGEN", NULL};

int evo_task_type_has_teams(const char *type)
{
	return strcmp(type, "DEMO2DSIMMULTI") == 0 ||
	       strcmp(type, "LEARN2DSIMMULTI") == 0 ||
	       strcmp(type, "DEMO3DSIMMULTI") == 0 ||
	       strcmp(type, "LEARN3DSIMMULTI") == 0;
}

static const char *const *required_keys(const char *type)
{
	if (evo_task_type_has_teams(type))
		return strncmp(type, "LEARN", 5) == 0 ? team_learn_keys
						      : team_demo_keys;
	if (strstr(type, "REMOTE"))
		return strncmp(type, "LEARN", 5) == 0 ? remote_learn_keys
						      : remote_demo_keys;
	if (strcmp(type, "LEARNSIMCONTINUOUS") == 0)
		return continuous_keys;
	if (strcmp(type, "OPENENDED") == 0)
		return openended_keys;
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

/* ---- teams (docs/teams.md) ---------------------------------------------- */

/* A team's name: letters, digits and '_', not starting with a digit. */
static int team_name_ok(const char *s)
{
	if (!s[0] || (s[0] >= '0' && s[0] <= '9'))
		return 0;
	for (; *s; s++)
		if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') ||
		      (*s >= '0' && *s <= '9') || *s == '_'))
			return 0;
	return 1;
}

/* Copy field f of a ':'-split value into out (cap bytes); -1 when it does
 * not fit or is empty. */
static int copy_field(char *out, size_t cap, const char *f, size_t n)
{
	if (n == 0 || n >= cap)
		return -1;
	memcpy(out, f, n);
	out[n] = 0;
	return 0;
}

#define TEAM_FORM "NAME:MIND:BOTMODEL:SIZE:MASTERSKILL[:LEARNINGSKILL]"

/* One TEAM line into tm (its mind not loaded yet) and its MIND field
 * into mind (cap bytes). */
static int parse_team(const evo_simbatch_pair *p, const char *path,
		      evo_team *tm, char *mind, size_t cap, evo_err *err)
{
	const char *f[7];
	size_t len[7];
	int n = 0;
	const char *v = p->value;
	while (n < 7) {
		const char *c = strchr(v, ':');
		f[n] = v;
		len[n] = c ? (size_t)(c - v) : strlen(v);
		n++;
		if (!c)
			break;
		v = c + 1;
	}
	memset(tm, 0, sizeof *tm);
	tm->line = p->line;
	int bad = n < 5 || n > 6;
	for (int i = 0; i < n && !bad; i++)
		bad = len[i] == 0;
	if (bad)
		return evo_fail(
		    err, "%s:%u: TEAM: expected " TEAM_FORM ", found '%s'",
		    path, (unsigned)p->line, p->value);
	if (copy_field(tm->name, sizeof tm->name, f[0], len[0]) ||
	    !team_name_ok(tm->name))
		return evo_fail(err,
				"%s:%u: TEAM: expected a team name of letters, "
				"digits and _, not starting with a digit, at "
				"most %d characters, found '%.*s'",
				path, (unsigned)p->line, EVO_TEAM_NAME_MAX - 1,
				(int)len[0], f[0]);
	if (copy_field(mind, cap, f[1], len[1]) ||
	    copy_field(tm->botmodel, sizeof tm->botmodel, f[2], len[2]) ||
	    copy_field(tm->master, sizeof tm->master, f[4], len[4]) ||
	    (n == 6 && copy_field(tm->learning_skill, sizeof tm->learning_skill,
				  f[5], len[5])))
		return evo_fail(err,
				"%s:%u: TEAM %s: a name is longer than "
				"%d characters in '%s'",
				path, (unsigned)p->line, tm->name,
				EVO_NAME_MAX - 1, p->value);
	long size = 0;
	int digits = len[3] > 0 && len[3] <= 9;
	for (size_t i = 0; i < len[3] && digits; i++) {
		digits = f[3][i] >= '0' && f[3][i] <= '9';
		size = size * 10 + (f[3][i] - '0');
	}
	if (!digits || size < 1 || size > EVO_TEAM_MAX_SIZE)
		return evo_fail(
		    err,
		    "%s:%u: TEAM %s: expected a size of 1..%d bots, "
		    "found '%.*s'",
		    path, (unsigned)p->line, tm->name, EVO_TEAM_MAX_SIZE,
		    (int)len[3], f[3]);
	tm->size = (int)size;
	return 0;
}

/* The teams' names, "Red, Green and Blue", for messages. */
static void team_list(const evo_task *t, char *out, size_t cap)
{
	size_t n = 0;
	out[0] = 0;
	for (int i = 0; i < t->n_teams && n < cap; i++)
		n += (size_t)snprintf(out + n, cap - n, "%s%s",
				      i == 0		    ? ""
				      : i == t->n_teams - 1 ? " and "
							    : ", ",
				      t->team[i].name);
}

static int find_team(const evo_task *t, const char *name)
{
	for (int i = 0; i < t->n_teams; i++)
		if (strcmp(t->team[i].name, name) == 0)
			return i;
	return -1;
}

/* The folder that holds a mind folder: where a team's MIND is found.
 * Returns what snprintf does. */
static int parent_of(const char *root, char *out, size_t cap)
{
	const char *slash = strrchr(root, '/');
	if (strcmp(root, ".") == 0)
		return snprintf(out, cap, "..");
	if (strcmp(root, "..") == 0 || (slash && strcmp(slash + 1, "..") == 0))
		return snprintf(out, cap, "%s/..", root);
	if (slash == root)
		return snprintf(out, cap, "/");
	if (slash)
		return snprintf(out, cap, "%.*s", (int)(slash - root), root);
	return snprintf(out, cap, ".");
}

/* LEARNINGTEAM (one name, or several joined by ','), or the only team. */
static int learning_teams(evo_task *t, const char *path, evo_err *err)
{
	const char *v = evo_simbatch_get(t->sb, "LEARNINGTEAM");
	uint32_t line = key_line(t->sb, "LEARNINGTEAM");
	if (!v) {
		if (t->n_teams > 1) {
			char names[600];
			team_list(t, names, sizeof names);
			return evo_fail(err,
					"%s: a LEARN2DSIMMULTI task of several "
					"teams names the one that learns: "
					"LEARNINGTEAM:NAME (the teams are %s)",
					path, names);
		}
		t->learning[t->n_learning++] = 0;
		t->team[0].learns = 1;
		return 0;
	}
	while (*v) {
		const char *c = strchr(v, ',');
		size_t n = c ? (size_t)(c - v) : strlen(v);
		char name[EVO_TEAM_NAME_MAX + 1];
		int k = -1;
		if (n > 0 && n < sizeof name) {
			memcpy(name, v, n);
			name[n] = 0;
			k = find_team(t, name);
		} else {
			snprintf(name, sizeof name, "%.*s",
				 (int)(n < sizeof name ? n : sizeof name - 1),
				 v);
		}
		if (k < 0) {
			char names[600];
			const char *list[EVO_MAX_TEAMS];
			for (int i = 0; i < t->n_teams; i++)
				list[i] = t->team[i].name;
			const char *c2 = evo_closest_name(
			    name, list, (size_t)t->n_teams, NULL);
			team_list(t, names, sizeof names);
			return evo_fail(
			    err,
			    "%s:%u: LEARNINGTEAM: no team named %s; "
			    "the teams are %s (did you mean %s?)",
			    path, (unsigned)line, name, names, c2 ? c2 : "?");
		}
		if (t->team[k].learns)
			return evo_fail(
			    err, "%s:%u: LEARNINGTEAM: %s is named twice", path,
			    (unsigned)line, name);
		t->team[k].learns = 1;
		t->learning[t->n_learning++] = k;
		if (!c)
			break;
		v = c + 1;
	}
	return 0;
}

/* TEAMGENOME, TEAMFITNESS and ALTERNATE. */
static void team_options(evo_task *t)
{
	const char *g = evo_simbatch_get(t->sb, "TEAMGENOME");
	const char *f = evo_simbatch_get(t->sb, "TEAMFITNESS");
	const char *a = evo_simbatch_get(t->sb, "ALTERNATE");
	/* the parser checked both words (evo_simbatch_key_defs) */
	t->heterogeneous = g && upper_eq(g, "HETEROGENEOUS");
	t->own_fitness = f && upper_eq(f, "OWN");
	/* the parser checked its range */
	t->alternate = a ? (int)strtol(a, NULL, 10) : 5;
}

/* At most this many skills of a member run networks of its own. */
#define MEMBER_NETS_MAX 16

/* The networks of a team's members of their own: Skills/S/S.K.net for
 * member K >= 2 of each neural skill S. A member with any gets a mind of
 * its own, the team's folder with those networks. */
static int load_members(evo_task *t, evo_team *tm, const char *dir,
			const char *path, evo_err *err)
{
	const evo_mindfolder *m = tm->mind;
	for (int k = 2; k <= tm->size; k++) {
		evo_net_choice choice[MEMBER_NETS_MAX];
		char files[MEMBER_NETS_MAX][1600];
		unsigned n = 0;
		for (unsigned i = 0; i < m->n_skills && n < MEMBER_NETS_MAX;
		     i++) {
			if (m->skill[i].kind != EVO_SKILL_NEURAL)
				continue;
			int len = snprintf(
			    files[n], sizeof files[n], "%s/Skills/%s/%s.%d.net",
			    dir, m->skill[i].name, m->skill[i].name, k);
			if (len < 0 || (size_t)len >= sizeof files[n] ||
			    !evo_file_exists(files[n]))
				continue;
			choice[n].skill = m->skill[i].name;
			choice[n].source = files[n];
			n++;
		}
		if (n == 0)
			continue;
		if (!tm->member && !(tm->member = calloc((size_t)tm->size,
							 sizeof *tm->member)))
			return evo_fail(err, "out of memory");
		evo_mindfolder_opts opts = {
		    .master = tm->master,
		    .nets = choice,
		    .n_nets = n,
		    .seed = t->seed,
		};
		evo_err inner = {{0}};
		tm->member[k - 1] = evo_mindfolder_load(dir, &opts, &inner);
		if (!tm->member[k - 1])
			return evo_fail(err, "%s:%u: TEAM %s, member %d: %s",
					path, (unsigned)tm->line, tm->name, k,
					inner.msg);
	}
	return 0;
}

/* Parse the TEAM lines, check them and load each team's mind folder. */
static int load_teams(evo_task *t, const char *path, const char *root,
		      evo_err *err)
{
	int n = 0;
	for (unsigned i = 0; i < t->sb->n_pairs; i++)
		n += strcmp(t->sb->pair[i].key, "TEAM") == 0;
	if (n > EVO_MAX_TEAMS)
		return evo_fail(err, "%s: %d teams; a task has at most %d",
				path, n, EVO_MAX_TEAMS);
	t->team = calloc((size_t)n, sizeof *t->team);
	if (!t->team)
		return evo_fail(err, "out of memory");
	char minds[1024], dirs[EVO_MAX_TEAMS][EVO_VALUE_MAX];
	int pn = parent_of(root, minds, sizeof minds);
	if (pn < 0 || (size_t)pn >= sizeof minds)
		return evo_fail(err, "%s: path too long", root);
	for (unsigned i = 0; i < t->sb->n_pairs; i++) {
		const evo_simbatch_pair *p = &t->sb->pair[i];
		if (strcmp(p->key, "TEAM") != 0)
			continue;
		evo_team *tm = &t->team[t->n_teams];
		if (parse_team(p, path, tm, dirs[t->n_teams], sizeof dirs[0],
			       err))
			return -1;
		int k = find_team(t, tm->name);
		if (k >= 0)
			return evo_fail(err,
					"%s:%u: TEAM: a second team named %s "
					"(first on line %u)",
					path, (unsigned)p->line, tm->name,
					(unsigned)t->team[k].line);
		t->n_teams++;
	}
	static const char *const ignored[] = {"BOTMODEL", "BOTNAME",
					      "MASTERSKILL", NULL};
	for (int i = 0; ignored[i]; i++)
		if (evo_simbatch_get(t->sb, ignored[i]))
			evo_warning("%s:%u: %s is ignored in a %s task: "
				    "each TEAM line names its own",
				path, (unsigned)key_line(t->sb, ignored[i]),
				ignored[i], t->type);
	int learn = strncmp(t->type, "LEARN", 5) == 0;
	team_options(t);
	if (learn && learning_teams(t, path, err))
		return -1;
	const char *skill = evo_simbatch_get(t->sb, "LEARNINGSKILL");
	for (int i = 0; i < t->n_teams; i++) {
		evo_team *tm = &t->team[i];
		if (!tm->learning_skill[0] && skill)
			snprintf(tm->learning_skill, sizeof tm->learning_skill,
				 "%s", skill);
		if (tm->learns && !tm->learning_skill[0])
			return evo_fail(err,
					"%s:%u: TEAM %s learns, but names no "
					"skill to train: a sixth field "
					"(..:MASTERSKILL:LEARNINGSKILL) or the "
					"key LEARNINGSKILL",
					path, (unsigned)tm->line, tm->name);
		char dir[1400];
		if (evo_path_fmt(dir, sizeof dir, err, "%s/%s", minds, dirs[i]))
			return -1;
		evo_mindfolder_opts opts = {
		    .master = tm->master,
		    .learning_skill = tm->learns ? tm->learning_skill : NULL,
		    .seed = t->seed,
		};
		evo_err inner = {{0}};
		tm->mind = evo_mindfolder_load(dir, &opts, &inner);
		if (!tm->mind)
			return evo_fail(err, "%s:%u: TEAM %s: %s", path,
					(unsigned)tm->line, tm->name,
					inner.msg);
		if (!tm->learns && load_members(t, tm, dir, path, err))
			return -1;
		if (tm->learns) {
			int k =
			    evo_mindfolder_skill(tm->mind, tm->learning_skill);
			if (k < 0 ||
			    tm->mind->skill[k].kind != EVO_SKILL_NEURAL)
				return evo_fail(
				    err,
				    "%s:%u: TEAM %s: its learning skill %s is "
				    "not a neural skill of the hierarchy under "
				    "%s (%s)",
				    path, (unsigned)tm->line, tm->name,
				    tm->learning_skill, tm->master, dir);
		}
	}
	int first = learn ? t->learning[0] : 0;
	t->mind = t->team[first].mind;
	return 0;
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
		evo_warning("%s", t->sb->warning[i].msg);
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
	/* Every value was checked against its key's range by the parser
	 * (evo_simbatch_key_defs), LEARNINGMETHOD's word included. */
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
	if (evo_task_type_has_teams(t->type)) {
		if (o && o->n_nets) {
			evo_fail(err,
				 "%s: --net chooses a network for a one-agent "
				 "task; a %s task runs its teams' own",
				 path, t->type);
			evo_task_free(t);
			return -1;
		}
		if (load_teams(t, path, root, err)) {
			evo_task_free(t);
			return -1;
		}
		return 0;
	}
	evo_mindfolder_opts opts = {
		.master = evo_simbatch_get(t->sb, "MASTERSKILL"),
		.learning_skill = strncmp(t->type, "LEARN", 5) == 0
					  ? evo_simbatch_get(t->sb,
							     "LEARNINGSKILL")
					  : NULL,
		.nets = o ? o->nets : NULL,
		.n_nets = o ? o->n_nets : 0,
		.seed = t->seed,
		.untrained_ok = o ? o->untrained_ok : 0,
	};
	/* a misspelt MASTERSKILL at its line, with the skill meant */
	if (evo_task_check_master(t->sb, path, root, err)) {
		evo_task_free(t);
		return -1;
	}
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
		evo_warning("%s:%u: BOTNAME is %s, but the task's mind "
			    "folder is %s (%s); evo runs that folder",
			path, (unsigned)key_line(t->sb, "BOTNAME"), botname,
			t->mind->bot_name, t->mind->root);
	}
	return 0;
}

void evo_task_free(evo_task *t)
{
	if (t->team) {
		/* t->mind is one of the teams' */
		for (int i = 0; i < t->n_teams; i++) {
			evo_mindfolder_free(t->team[i].mind);
			for (int k = 0;
			     t->team[i].member && k < t->team[i].size; k++)
				evo_mindfolder_free(t->team[i].member[k]);
			free(t->team[i].member);
		}
		free(t->team);
		t->mind = NULL;
	}
	evo_mindfolder_free(t->mind);
	free(t->sb);
	memset(t, 0, sizeof *t);
}

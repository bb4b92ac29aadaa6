/* A mind folder read (mind/mindfolder.h, docs/mind.md): its .botdesc and
 * .vardesc, every skill reachable from the master skill, walked top down
 * with cycles named, and the mind image built from them and opened.
 * mindfolder_nets.c resolves the skills' names and loads their networks
 * (mind/mindfolder_internal.h between them). */
#define _DEFAULT_SOURCE /* realpath */
#define _POSIX_C_SOURCE 200809L
#include "mind/mindfolder.h"
#include "mind/mindfolder_internal.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/fileio.h"
#include "base/rng.h"
#include "mind/net_build.h"

/* What the loader knows of one skill while it walks the hierarchy. */
typedef struct skill_entry {
	char name[EVO_NAME_MAX];
	char path[1024]; /* its .ades, as messages show it */
	evo_ades *ades;
	int mark; /* 0 unvisited, 1 on the walk's path, 2 done */
} skill_entry;

typedef struct loader {
	const char *root;
	skill_entry entry[MAX_SKILLS];
	unsigned n_entries;
	unsigned order[MAX_SKILLS]; /* post-order of the walk */
	unsigned n_order;
	unsigned path[MAX_SKILLS]; /* the walk's current path, for cycles */
	unsigned depth;
	evo_err *err;
} loader;

/* ---- reading skills -------------------------------------------------- */

static int parse_file(const char *path, evo_err *err,
		      evo_status (*parse)(const char *, size_t, const char *,
					  void *, evo_diag *),
		      void *out)
{
	char *data;
	size_t len;
	if (evo_read_file(path, &data, &len, err) != 0)
		return -1;
	evo_diag diag;
	evo_status st = parse(data, len, path, out, &diag);
	free(data);
	if (st != EVO_OK)
		return evo_fail(err, "%s", diag.msg);
	return 0;
}

/* parse_file takes any parser through a void * output; these adapt the
 * typed ones. */
#define ANY_PARSER(name, parse, type)                                          \
	static evo_status name(const char *b, size_t n, const char *f,         \
			       void *o, evo_diag *d)                           \
	{                                                                      \
		return parse(b, n, f, (type *)o, d);                           \
	}
ANY_PARSER(parse_ades_any, evo_ades_parse, evo_ades)
ANY_PARSER(parse_botdesc_any, evo_botdesc_parse, evo_botdesc)
ANY_PARSER(parse_vardesc_any, evo_vardesc_parse, evo_vardesc)
ANY_PARSER(parse_net_any, evo_netdesc_parse, evo_netdesc)
#undef ANY_PARSER

int evo_mindfolder_read_net(const char *path, evo_netdesc *d, evo_err *err)
{
	return parse_file(path, err, parse_net_any, d);
}

/* The longest root whose "/Skills/NAME/NAME.ades" fits a 1024-byte path
 * (skill_entry's) with names of EVO_NAME_MAX - 1 bytes. */
#define ROOT_MAX (1023 - (sizeof "/Skills//.ades" - 1) - 2 * (EVO_NAME_MAX - 1))

void evo_mindfolder_skill_path(char *out, size_t cap, const char *root,
			       const char *name, const char *ext)
{
	snprintf(out, cap, "%s/Skills/%s/%s.%s", root, name, name, ext);
}

/* The entry for skill name, read on first use. where/line say who asked,
 * for the message when the skill has no file. */
static int entry_for(loader *ld, const char *name, const char *where,
		     uint32_t line)
{
	for (unsigned i = 0; i < ld->n_entries; i++)
		if (strcmp(ld->entry[i].name, name) == 0)
			return (int)i;
	if (ld->n_entries == MAX_SKILLS)
		return evo_fail(ld->err, "%s:%u: more than %d skills", where,
				line, MAX_SKILLS);
	/* A skill's name is its folder's and its files' (Skills/S/S.ades,
	 * where its champion is saved as S.net): a '/' or a name of "." or
	 * ".." would reach outside Skills/. */
	if (strchr(name, '/') || strcmp(name, ".") == 0 ||
	    strcmp(name, "..") == 0) {
		if (where)
			return evo_fail(ld->err,
					"%s:%u: SK:%s: a skill's name is the "
					"name of its folder, which holds no "
					"'/' and is not '.' or '..'",
					where, line, name);
		return evo_fail(ld->err,
				"master skill %s: a skill's name is the name "
				"of its folder, which holds no '/' and is not "
				"'.' or '..'",
				name);
	}
	skill_entry *e = &ld->entry[ld->n_entries];
	snprintf(e->name, sizeof e->name, "%s", name);
	evo_mindfolder_skill_path(e->path, sizeof e->path, ld->root, name,
				  "ades");
	if (!evo_file_exists(e->path)) {
		if (where)
			return evo_fail(ld->err,
					"%s:%u: SK:%s names a skill that does "
					"not exist: no file %s",
					where, line, name, e->path);
		return evo_fail(ld->err, "master skill %s: no file %s", name,
				e->path);
	}
	e->ades = malloc(sizeof *e->ades);
	if (!e->ades)
		return evo_fail(ld->err, "out of memory");
	if (parse_file(e->path, ld->err, parse_ades_any, e->ades) != 0) {
		free(e->ades);
		e->ades = NULL;
		return -1;
	}
	if (strcmp(e->ades->name, name) != 0) {
		evo_fail(ld->err,
			 "%s:%u: the skill is named '%s' but its file is "
			 "for '%s' (Skills/%s/%s.ades)",
			 e->path, e->ades->name_line, e->ades->name, name, name,
			 name);
		free(e->ades);
		e->ades = NULL;
		return -1;
	}
	ld->n_entries++;
	return (int)(ld->n_entries - 1);
}

/* "P -> Q -> P": the walk's path from skill c back to c, for the cycle
 * message. A cycle can be up to MAX_SKILLS long names, far more than a
 * message holds, so names that do not fit become "... -> " and the text
 * still ends with the name that closes the cycle. */
static void cycle_text(char *out, size_t cap, const loader *ld, unsigned c)
{
	/* Room kept for "... -> ", the closing name and the NUL; cap is
	 * larger, so every write below fits. */
	const size_t tail = sizeof "... -> " - 1 + EVO_NAME_MAX;
	size_t n = 0;
	unsigned k = 0;
	while (ld->path[k] != c)
		k++;
	for (; k < ld->depth; k++) {
		const char *name = ld->entry[ld->path[k]].name;
		size_t len = strlen(name) + sizeof " -> " - 1;
		if (n + len + tail > cap) {
			n += (size_t)snprintf(out + n, cap - n, "... -> ");
			break;
		}
		n += (size_t)snprintf(out + n, cap - n, "%s -> ", name);
	}
	snprintf(out + n, cap - n, "%s", ld->entry[c].name);
}

/* Depth-first from a skill along its SK outputs; the reverse post-order
 * is the top-down order: every skill before its sub-skills. */
static int walk(loader *ld, unsigned idx)
{
	skill_entry *e = &ld->entry[idx];
	if (e->mark == 2)
		return 0;
	e->mark = 1;
	ld->path[ld->depth++] = idx;
	/* Sub-skills are visited last to first, so that in the reversed
	 * post-order they come in the order the .ades lists them. */
	for (unsigned j = e->ades->n_out; j-- > 0;) {
		const evo_ades_io *o = &ld->entry[idx].ades->out[j];
		if (o->type != EVO_OUT_SK)
			continue;
		int c = entry_for(ld, o->name, ld->entry[idx].path, o->line);
		if (c < 0)
			return -1;
		e = &ld->entry[idx];
		if (ld->entry[c].mark == 1) {
			char cycle[512];
			cycle_text(cycle, sizeof cycle, ld, (unsigned)c);
			return evo_fail(ld->err,
					"%s:%u: SK:%s makes a cycle among "
					"skills: %s",
					e->path, o->line, o->name, cycle);
		}
		if (walk(ld, (unsigned)c) != 0)
			return -1;
	}
	ld->depth--;
	ld->entry[idx].mark = 2;
	ld->order[ld->n_order++] = idx;
	return 0;
}

/* The skill of Skills/ that no other skill names, when there is one. */
static int find_master(loader *ld, char *out, size_t cap)
{
	char dir[1200];
	snprintf(dir, sizeof dir, "%s/Skills", ld->root);
	DIR *d = opendir(dir);
	if (!d)
		return evo_fail(ld->err, "%s: cannot open the Skills folder",
				dir);
	struct dirent *de;
	char names[MAX_SKILLS][EVO_NAME_MAX];
	unsigned n = 0;
	while ((de = readdir(d)) != NULL && n < MAX_SKILLS) {
		if (de->d_name[0] == '.' || strlen(de->d_name) >= EVO_NAME_MAX)
			continue;
		char path[1400];
		evo_mindfolder_skill_path(path, sizeof path, ld->root,
					  de->d_name, "ades");
		if (evo_file_exists(path))
			memcpy(names[n++], de->d_name,
			       strlen(de->d_name) + 1); /* < EVO_NAME_MAX */
	}
	closedir(d);
	qsort(names, n, sizeof names[0],
	      (int (*)(const void *, const void *))strcmp);
	for (unsigned i = 0; i < n; i++)
		if (entry_for(ld, names[i], NULL, 0) < 0)
			return -1;
	const char *root_skill = NULL;
	unsigned roots = 0;
	char list[512] = "";
	size_t used = 0;
	for (unsigned i = 0; i < ld->n_entries; i++) {
		int named = 0;
		for (unsigned k = 0; k < ld->n_entries && !named; k++) {
			const evo_ades *a = ld->entry[k].ades;
			for (unsigned j = 0; j < a->n_out; j++)
				if (a->out[j].type == EVO_OUT_SK &&
				    strcmp(a->out[j].name, ld->entry[i].name) ==
					0)
					named = 1;
		}
		if (!named) {
			roots++;
			root_skill = ld->entry[i].name;
			if (used < sizeof list)
				used += (size_t)snprintf(
				    list + used, sizeof list - used, "%s%s",
				    roots > 1 ? ", " : "", root_skill);
		}
	}
	if (roots != 1)
		return evo_fail(ld->err,
				"%s: %u skills are no other skill's sub-skill "
				"(%s); say which is the master skill "
				"(MASTERSKILL, or --master)",
				dir, roots, list);
	snprintf(out, cap, "%s", root_skill);
	return 0;
}

/* ---- building the model ---------------------------------------------- */

uint32_t evo_names_hash_of(const evo_botdesc *b, const evo_vardesc *v)
{
	const char *s[EVO_MAX_SENSORS], *a[EVO_MAX_ACTUATORS],
	    *n[EVO_MAX_VARIABLES];
	for (unsigned i = 0; i < b->n_sensors; i++)
		s[i] = b->sensor[i].name;
	for (unsigned i = 0; i < b->n_actuators; i++)
		a[i] = b->actuator[i].name;
	unsigned nv = v ? v->n_vars : 0;
	for (unsigned i = 0; i < nv; i++)
		n[i] = v->var[i].name;
	return evo_names_hash(s, b->n_sensors, a, b->n_actuators, n, nv);
}

int evo_mindfolder_skill(const evo_mindfolder *l, const char *name)
{
	for (unsigned i = 0; i < l->n_skills; i++)
		if (strcmp(l->skill[i].name, name) == 0)
			return (int)i;
	return -1;
}

/* Resolved io of every skill, kept for rebuilding. */
static int build_image(evo_mindfolder *l, evo_image_io *io, evo_err *err)
{
	const evo_botdesc *b = l->botdesc;
	const evo_vardesc *v = l->vardesc;
	const char *sn[EVO_MAX_SENSORS], *an[EVO_MAX_ACTUATORS],
	    *vn[EVO_MAX_VARIABLES];
	uint8_t vt[EVO_MAX_VARIABLES];
	for (unsigned i = 0; i < b->n_sensors; i++)
		sn[i] = b->sensor[i].name;
	for (unsigned i = 0; i < b->n_actuators; i++)
		an[i] = b->actuator[i].name;
	for (unsigned i = 0; i < v->n_vars; i++) {
		vn[i] = v->var[i].name;
		vt[i] = v->var[i].type;
	}
	evo_build_skill *bs = calloc(l->n_skills, sizeof *bs);
	evo_net_compile_ws *ws = malloc(sizeof *ws);
	if (!bs || !ws) {
		free(bs);
		free(ws);
		return evo_fail(err, "out of memory");
	}
	size_t pos = 0;
	for (unsigned i = 0; i < l->n_skills; i++) {
		const evo_ades *a = &l->skill[i];
		bs[i].name = a->name;
		bs[i].kind = a->kind;
		bs[i].n_in = (uint16_t)a->n_in;
		bs[i].n_out = (uint16_t)a->n_out;
		bs[i].in = io + pos;
		pos += a->n_in;
		bs[i].out = io + pos;
		pos += a->n_out;
		bs[i].net = l->net[i];
		bs[i].hc_class = a->hc_class;
	}
	evo_build build = {
	    .n_sensors = (uint16_t)b->n_sensors,
	    .n_actuators = (uint16_t)b->n_actuators,
	    .n_vars = (uint16_t)v->n_vars,
	    .n_skills = (uint16_t)l->n_skills,
	    .sensor_name = sn,
	    .actuator_name = an,
	    .var_name = vn,
	    .var_type = vt,
	    .skill = bs,
	};
	size_t len = 0;
	evo_status st = evo_image_write(&build, ws, NULL, 0, &len);
	free(l->image);
	l->image = NULL;
	if (st == EVO_ERR_NOMEM) {
		l->image = malloc(len);
		st = l->image ? evo_image_write(&build, ws, l->image, len, &len)
			      : EVO_ERR_NOMEM;
	}
	free(bs);
	free(ws);
	if (st != EVO_OK)
		return evo_fail(err, "%s: cannot build the mind image: %s",
				l->root, evo_status_str(st));
	l->image_len = len;
	st = evo_mind_open(l->image, len, l->names_hash, &l->mind);
	if (st != EVO_OK)
		return evo_fail(err, "%s: the mind image does not open: %s",
				l->root, evo_status_str(st));
	return 0;
}

/* The io arrays live after the loaded struct's skills; see load. */
typedef struct loaded_private {
	evo_mindfolder pub;
	evo_image_io *io;
} loaded_private;

int evo_mindfolder_rebuild(evo_mindfolder *l, evo_err *err)
{
	return build_image(l, ((loaded_private *)l)->io, err);
}

void evo_mindfolder_free(evo_mindfolder *l)
{
	if (!l)
		return;
	for (unsigned i = 0; i < l->n_skills; i++)
		free(l->net ? l->net[i] : NULL);
	free(l->net);
	free(l->untrained);
	free(l->skill);
	free(l->botdesc);
	free(l->vardesc);
	free(l->image);
	free(l->root);
	free(l->bot_name);
	free(((loaded_private *)l)->io);
	free(l);
}

/* A mind folder copied under another name keeps its NAME.botdesc and
 * NAME.vardesc: when the folder holds no botdesc named after it, its one
 * .botdesc names the bot (l->bot_name becomes NAME, the stem of both
 * files). Two or more are ambiguous, none is no mind folder. */
static int find_botdesc(evo_mindfolder *l, evo_err *err)
{
	char path[1200];
	snprintf(path, sizeof path, "%s/%s.botdesc", l->root, l->bot_name);
	if (evo_file_exists(path))
		return 0;
	DIR *d = opendir(l->root);
	char found[2][EVO_NAME_MAX];
	int n = 0;
	struct dirent *e;
	while (d && (e = readdir(d)) != NULL) {
		size_t len = strlen(e->d_name);
		if (len <= 8 || len - 8 >= EVO_NAME_MAX ||
		    strcmp(e->d_name + len - 8, ".botdesc") != 0)
			continue;
		if (n < 2)
			snprintf(found[n], sizeof found[n], "%.*s",
				 (int)(len - 8), e->d_name);
		n++;
	}
	if (d)
		closedir(d);
	if (n == 1) {
		char *name = strdup(found[0]);
		if (!name)
			return evo_fail(err, "out of memory");
		free(l->bot_name);
		l->bot_name = name;
		return 0;
	}
	if (n > 1)
		return evo_fail(err,
				"%s: no %s.botdesc, and %d .botdesc files "
				"(%s.botdesc, %s.botdesc%s): evo cannot tell "
				"which describes this mind's bot; name it "
				"%s.botdesc (and its .vardesc %s.vardesc), or "
				"remove the others",
				l->root, l->bot_name, n, found[0], found[1],
				n > 2 ? ", ..." : "", l->bot_name, l->bot_name);
	return evo_fail(err,
			"%s: not a mind folder: no %s.botdesc (a mind "
			"folder holds <Name>.botdesc, named after the "
			"folder)",
			l->root, l->bot_name);
}

static int load(evo_mindfolder *l, loader *ld, const evo_mindfolder_opts *o,
		evo_err *err)
{
	char path[1200];
	if (find_botdesc(l, err))
		return -1;
	snprintf(path, sizeof path, "%s/%s.botdesc", l->root, l->bot_name);
	l->botdesc = calloc(1, sizeof *l->botdesc);
	l->vardesc = calloc(1, sizeof *l->vardesc);
	if (!l->botdesc || !l->vardesc)
		return evo_fail(err, "out of memory");
	if (parse_file(path, err, parse_botdesc_any, l->botdesc) != 0)
		return -1;
	snprintf(path, sizeof path, "%s/%s.vardesc", l->root, l->bot_name);
	if (evo_file_exists(path) &&
	    parse_file(path, err, parse_vardesc_any, l->vardesc) != 0)
		return -1;
	l->names_hash = evo_names_hash_of(l->botdesc, l->vardesc);

	char master[EVO_NAME_MAX];
	if (o && o->master)
		snprintf(master, sizeof master, "%s", o->master);
	else if (find_master(ld, master, sizeof master) != 0)
		return -1;
	int m = entry_for(ld, master, NULL, 0);
	if (m < 0)
		return -1;
	if (walk(ld, (unsigned)m) != 0)
		return -1;

	l->n_skills = ld->n_order;
	l->skill = calloc(l->n_skills, sizeof *l->skill);
	l->net = calloc(l->n_skills, sizeof *l->net);
	l->untrained = calloc(l->n_skills, sizeof *l->untrained);
	const char **paths = calloc(l->n_skills, sizeof *paths);
	if (!l->skill || !l->net || !l->untrained || !paths) {
		free(paths);
		return evo_fail(err, "out of memory");
	}
	for (unsigned i = 0; i < l->n_skills; i++) {
		skill_entry *e = &ld->entry[ld->order[l->n_skills - 1 - i]];
		l->skill[i] = *e->ades;
		paths[i] = e->path;
	}
	if (evo_mindfolder_check_choices(l, o, err) != 0) {
		free(paths);
		return -1;
	}
	size_t n_io = 0;
	for (unsigned i = 0; i < l->n_skills; i++)
		n_io += l->skill[i].n_in + l->skill[i].n_out;
	evo_image_io *io = calloc(n_io ? n_io : 1, sizeof *io);
	((loaded_private *)l)->io = io;
	if (!io) {
		free(paths);
		return evo_fail(err, "out of memory");
	}
	int rc = 0;
	size_t pos = 0;
	for (unsigned i = 0; i < l->n_skills && rc == 0; i++) {
		const evo_ades *a = &l->skill[i];
		for (unsigned j = 0; j < a->n_in && rc == 0; j++)
			rc = evo_mindfolder_resolve_input(
			    l, paths[i], &a->in[j], &io[pos++], err);
		for (unsigned j = 0; j < a->n_out && rc == 0; j++)
			rc = evo_mindfolder_resolve_output(
			    l, paths[i], &a->out[j], &io[pos++], err);
		if (rc == 0 && a->kind == EVO_SKILL_HARDCODED)
			rc = evo_mindfolder_check_hardcoded(a, paths[i], err);
		if (rc == 0 && a->kind == EVO_SKILL_NEURAL)
			rc = evo_mindfolder_load_net(l, i, paths[i], o, err);
	}
	free(paths);
	if (rc != 0)
		return -1;
	return build_image(l, io, err);
}

evo_mindfolder *evo_mindfolder_load(const char *root,
				    const evo_mindfolder_opts *opts,
				    evo_err *err)
{
	loaded_private *p = calloc(1, sizeof *p);
	loader *ld = calloc(1, sizeof *ld);
	if (!p || !ld) {
		free(p);
		free(ld);
		evo_fail(err, "out of memory");
		return NULL;
	}
	evo_mindfolder *l = &p->pub;
	l->root = strdup(root);
	if (!l->root) {
		free(p);
		free(ld);
		evo_fail(err, "out of memory");
		return NULL;
	}
	size_t n = strlen(l->root);
	while (n > 1 && l->root[n - 1] == '/')
		l->root[--n] = 0;
	/* Every file's path is the root's and a suffix, the longest
	 * "/Skills/NAME/NAME.ades" (ROOT_MAX); a longer root would cut them. */
	if (n > ROOT_MAX) {
		free(ld);
		evo_fail(err,
			 "%.80s...: path too long (%zu bytes; at most %zu)",
			 l->root, n, (size_t)ROOT_MAX);
		evo_mindfolder_free(l);
		return NULL;
	}
	const char *slash = strrchr(l->root, '/');
	const char *name = slash ? slash + 1 : l->root;
	/* "." or ".." (a task run from inside its mind folder): the name is
	 * the folder's own. Other paths keep the name as typed, so that a
	 * symbolic link to a mind folder is named after the link. */
	char *abs = NULL;
	if (strcmp(name, ".") == 0 || strcmp(name, "..") == 0) {
		abs = realpath(l->root, NULL);
		const char *s = abs ? strrchr(abs, '/') : NULL;
		if (s && s[1])
			name = s + 1;
	}
	l->bot_name = strdup(name);
	free(abs);
	if (!l->bot_name) {
		free(ld);
		evo_mindfolder_free(l);
		evo_fail(err, "out of memory");
		return NULL;
	}
	ld->root = l->root;
	ld->err = err;
	int rc = load(l, ld, opts, err);
	for (unsigned i = 0; i < ld->n_entries; i++)
		free(ld->entry[i].ades);
	free(ld);
	if (rc != 0) {
		evo_mindfolder_free(l);
		return NULL;
	}
	return l;
}

/* evo info and evo tick of a mind image, the task types evo run runs and
 * the check evo check adds to loading a task, and the report of a
 * hierarchy's untrained skills with a task that trains each
 * (sim/cmd/mindinfo.h). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/mindinfo.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/fileio.h"
#include "evo/image.h"
#include "evo/status.h"
#include "learn/learn.h"
#include "learn/literature.h"
#include "remote/robot.h"
#include "tasksim/tasksim.h"

int evo_is_image_path(const char *path)
{
	size_t n = strlen(path);
	return n > 4 && strcasecmp(path + n - 4, ".bin") == 0;
}

int evo_image_load(const char *path, void **buf, evo_mind *m, evo_err *err)
{
	char *data;
	size_t len;
	*buf = NULL;
	if (evo_read_file(path, &data, &len, err))
		return -1;
	/* evo_mind_open wants the image 4-byte aligned */
	void *img = aligned_alloc(8, (len + 7) & ~(size_t)7);
	if (!img) {
		free(data);
		return evo_fail(err, "out of memory");
	}
	memcpy(img, data, len);
	free(data);
	uint32_t hash = 0;
	if (len >= sizeof(evo_image_header))
		hash = ((const evo_image_header *)img)->names_hash;
	evo_status st = evo_mind_open(img, len, hash, m);
	if (st != EVO_OK) {
		free(img);
		return evo_fail(err,
				"%s: not a mind image evo can run: %s (evo "
				"export writes one; docs/mind-image.md)",
				path, evo_status_str(st));
	}
	*buf = img;
	return 0;
}

void evo_image_info(const char *path, const evo_mind *m)
{
	printf("mind image %s: %u sensors, %u actuators, %u variables, %u "
	       "skills\n",
	       path, m->n_sensors, m->n_actuators, m->n_vars, m->n_skills);
	printf("tick order (master first, parents before sub-skills):\n");
	for (unsigned i = 0; i < m->n_skills; i++) {
		const evo_image_skill *s = &m->skill[i];
		int neural = s->kind == EVO_SKILL_NEURAL;
		printf("  %2u %-16s %-9s in %-2u out %-2u", i,
		       evo_mind_skill_name(m, i),
		       neural ? "neural" : "hardCoded", s->n_in, s->n_out);
		if (!neural) {
			const evo_hc_class *c = evo_hc_find_hash(s->hc_class);
			printf(" class:%s", c ? c->name : "?");
		} else {
			const evo_image_net *n = &m->net[s->slot];
			printf(" network: %u nodes, %u links",
			       (unsigned)n->n_nodes,
			       (unsigned)n->n_links);
		}
		int first = 1;
		for (unsigned j = 0; j < s->n_out; j++) {
			const evo_image_io *o = &m->io[s->out_start + j];
			if (o->type != EVO_OUT_SK)
				continue;
			printf("%s%s", first ? " -> " : ", ",
			       evo_mind_skill_name(m, o->index));
			first = 0;
		}
		printf("\n");
	}
	printf("mind image: %u bytes; mind state: %zu bytes\n", m->length,
	       evo_state_size(m));
}

int evo_run_supports(const char *type)
{
	return strcmp(type, "DEMOSIM") == 0 || strcmp(type, "LEARNSIM") == 0 ||
	       strcmp(type, "DEMO3DSIM") == 0 ||
	       strcmp(type, "LEARN3DSIM") == 0 ||
	       strcmp(type, "LEARNSIMCONTINUOUS") == 0 ||
	       strcmp(type, "DEMO2DSIMMULTI") == 0 ||
	       strcmp(type, "LEARN2DSIMMULTI") == 0 ||
	       strcmp(type, "DEMO3DSIMMULTI") == 0 ||
	       strcmp(type, "LEARN3DSIMMULTI") == 0 ||
	       strcmp(type, "DEMOREMOTESIM") == 0 ||
	       strcmp(type, "LEARNREMOTESIM") == 0 ||
	       strcmp(type, "DEMOREMOTE") == 0 ||
	       strcmp(type, "OPENENDED") == 0;
}

int evo_task_check(const char *path, evo_task *task, evo_err *err)
{
	if (!evo_run_supports(task->type))
		return evo_fail(
		    err,
		    "%s: evo run does not run %s tasks yet (it runs "
		    "DEMOSIM, LEARNSIM, LEARNSIMCONTINUOUS, DEMO3DSIM, "
		    "LEARN3DSIM, DEMO2DSIMMULTI, LEARN2DSIMMULTI, "
		    "DEMO3DSIMMULTI, LEARN3DSIMMULTI, "
		    "DEMOREMOTESIM, "
		    "LEARNREMOTESIM and DEMOREMOTE)",
		    path, task->type);
	if ((strncmp(task->type, "LEARN", 5) == 0 ||
	     strcmp(task->type, "OPENENDED") == 0) &&
	    evo_learn_check(path, task, err) != 0)
		return -1;
	if (evo_robot_task_check(task->sb, task->type, path, err))
		return -1;
	const char *env = evo_simbatch_get(task->sb, "ENV");
	if (strcmp(task->type, "LEARNSIM") == 0 &&
	    evo_lit_task_named(env ? env : "") != EVO_LIT_NONE)
		return 0; /* a literature task: no scene */
	/* a remote task's world is the remote's; one that names a bot model
	 * and an environment can be served by `evo serve`, so they are
	 * checked */
	if (strstr(task->type, "REMOTE") &&
	    (!env || !evo_simbatch_get(task->sb, "BOTMODEL")))
		return 0;
	evo_sim *s = evo_sim_create_task(task, path, err);
	if (!s)
		return -1;
	evo_sim_destroy(s);
	return 0;
}

/* Whether the task file text has the line LEARNINGSKILL:skill. */
static int trains(const char *text, const char *skill)
{
	char want[EVO_NAME_MAX + 20];
	snprintf(want, sizeof want, "LEARNINGSKILL:%s", skill);
	for (const char *p = strstr(text, want); p; p = strstr(p + 1, want)) {
		char after = p[strlen(want)];
		if ((p == text || p[-1] == '\n') &&
		    (after == '\n' || after == '\r' || after == 0 ||
		     after == ' '))
			return 1;
	}
	return 0;
}

/* The problems evo check finds in the task at path, tried quietly: its
 * warnings, or -1 when it fails to load or check (why into err). */
static long task_problems(const char *path, evo_err *err)
{
	evo_task t;
	evo_task_opts to = {.untrained_ok = 1};
	evo_warning_quiet(1);
	int rc = evo_task_load_opts(path, &to, &t, err);
	if (rc == 0) {
		rc = evo_task_check(path, &t, err);
		evo_task_free(&t);
	}
	unsigned warned = evo_warning_quiet(0);
	return rc ? -1 : (long)warned;
}

/* The task of root/Tasks to train skill with (a LEARNINGSKILL:skill line)
 * into out: of those that pass evo check, SKILL-NEAT.simbatch, else the
 * one with the fewest warnings, the first by name among equals. 1 when
 * there is one; 0 when there is none, or -1 when none passes (the first
 * one's error into err). */
static int task_for(const char *root, const char *skill, char *out, size_t cap,
		    evo_err *err)
{
	char dir[1200], neat[EVO_NAME_MAX + 20];
	snprintf(dir, sizeof dir, "%s/Tasks", root);
	snprintf(neat, sizeof neat, "%s-NEAT.simbatch", skill);
	struct dirent **names;
	int n = scandir(dir, &names, NULL, alphasort);
	if (n < 0)
		return 0;
	int found = 0;
	long best = -1;
	for (int k = 0; k < n; k++) {
		const char *name = names[k]->d_name;
		size_t len = strlen(name);
		char path[1500], *text;
		size_t tlen;
		snprintf(path, sizeof path, "%s/%s", dir, name);
		if (len < 10 || strcasecmp(name + len - 9, ".simbatch") != 0 ||
		    evo_read_file(path, &text, &tlen, NULL))
			continue;
		int yes = trains(text, skill);
		free(text);
		if (!yes)
			continue;
		evo_err why = {{0}};
		long p = task_problems(path, &why);
		if (p < 0) {
			if (!found)
				snprintf(err->msg, sizeof err->msg, "%s",
					 why.msg);
			found = found ? found : -1;
			continue;
		}
		/* SKILL-NEAT counts as having no warnings when it has none */
		long rank = 2 * p + (strcmp(name, neat) != 0);
		if (found == 1 && rank >= best)
			continue;
		if ((size_t)snprintf(out, cap, "Tasks/%s", name) >= cap)
			continue;
		found = 1;
		best = rank;
	}
	for (int k = 0; k < n; k++)
		free(names[k]);
	free(names);
	return found;
}

int evo_untrained_count(const evo_mindfolder *l)
{
	int n = 0;
	for (unsigned i = 0; i < l->n_skills; i++)
		n += l->untrained && l->untrained[i] == 1;
	return n;
}

int evo_untrained_report(const evo_mindfolder *l, FILE *f)
{
	int n = evo_untrained_count(l);
	if (n == 0)
		return 0;
	fprintf(f, "not trained yet (no Skills/S/S.net): ");
	for (unsigned i = 0, k = 0; i < l->n_skills; i++)
		if (l->untrained[i] == 1)
			fprintf(f, "%s%s", k++ ? ", " : "", l->skill[i].name);
	fprintf(f, "\ntrain the hierarchy bottom-up, sub-skills before the "
		   "skills that call them:\n");
	/* the tick order has parents before sub-skills: backwards, it is
	 * an order in which each skill's sub-skills are trained first */
	for (unsigned i = l->n_skills, step = 1; i-- > 0;) {
		const evo_ades *a = &l->skill[i];
		if (a->kind != EVO_SKILL_NEURAL)
			continue;
		char task[300];
		evo_err why = {{0}};
		int has = l->untrained[i] == 1
				  ? task_for(l->root, a->name, task,
					     sizeof task, &why)
				  : 0;
		fprintf(f, "  %u. %-16s %s", step++, a->name,
			l->untrained[i] == 2   ? "no network yet: this task "
						 "trains it"
			: l->untrained[i] ? "no network yet"
					  : "has its network");
		if (has == 1)
			fprintf(f, ": evo run %s/%s", l->root, task);
		else if (has < 0)
			fprintf(f, ": no task of %s/Tasks that trains it passes "
				   "evo check (%s)",
				l->root, why.msg);
		else if (l->untrained[i] == 1)
			fprintf(f, ": a LEARNSIM task with LEARNINGSKILL:%s "
				   "(docs/learning.md)",
				a->name);
		fprintf(f, "\n");
	}
	return n;
}

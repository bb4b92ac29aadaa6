/* evo info and evo tick of a mind image, and the report of a hierarchy's
 * untrained skills (sim/cmd/mindinfo.h). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/mindinfo.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/fileio.h"
#include "evo/image.h"
#include "evo/status.h"

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

/* A task of root/Tasks that trains skill (a LEARNINGSKILL:skill line),
 * its file name into out; 0 when there is none. */
static int task_for(const char *root, const char *skill, char *out, size_t cap)
{
	char dir[1200], want[EVO_NAME_MAX + 20];
	snprintf(dir, sizeof dir, "%s/Tasks", root);
	snprintf(want, sizeof want, "LEARNINGSKILL:%s", skill);
	DIR *d = opendir(dir);
	if (!d)
		return 0;
	int found = 0;
	struct dirent *e;
	while (!found && (e = readdir(d)) != NULL) {
		size_t n = strlen(e->d_name);
		if (n < 10 || strcasecmp(e->d_name + n - 9, ".simbatch") != 0)
			continue;
		char path[1500], *text;
		size_t len;
		snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
		if (evo_read_file(path, &text, &len, NULL))
			continue;
		for (char *p = strstr(text, want); p && !found;
		     p = strstr(p + 1, want)) {
			char after = p[strlen(want)];
			found = (p == text || p[-1] == '\n') &&
				(after == '\n' || after == '\r' || after == 0 ||
				 after == ' ');
		}
		free(text);
		if (found && (size_t)snprintf(out, cap, "Tasks/%s",
					       e->d_name) >= cap)
			found = 0;
	}
	closedir(d);
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
		fprintf(f, "  %u. %-16s %s", step++, a->name,
			l->untrained[i] == 2   ? "no network yet: this task "
						 "trains it"
			: l->untrained[i] ? "no network yet"
					  : "has its network");
		if (l->untrained[i] == 1 && task_for(l->root, a->name, task,
						 sizeof task))
			fprintf(f, ": evo run %s/%s", l->root, task);
		else if (l->untrained[i] == 1)
			fprintf(f, ": a LEARNSIM task with LEARNINGSKILL:%s "
				   "(docs/learning.md)",
				a->name);
		fprintf(f, "\n");
	}
	return n;
}

/* A mind folder's names and networks (mind/mindfolder_internal.h): each
 * skill's inputs and outputs resolved against the botdesc and vardesc
 * (an unknown name gets the nearest one), HARDCODED skills checked, and
 * each neural skill's network: a chosen one (--net), its .net, or a
 * placeholder for the skill being trained. mindfolder.c reads the skills
 * and builds the image. */
#define _POSIX_C_SOURCE 200809L
#include "mind/mindfolder_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/fileio.h"
#include "base/rng.h"
#include "mind/names.h"
#include "mind/net_build.h"

/* ---- names ----------------------------------------------------------- */

/* "; did you mean X?" for the closest of names, or "" when none is near. */
static void suggest(char *out, size_t cap, const char *word,
		    const char *const *names, unsigned n)
{
	unsigned best;
	const char *pick = evo_closest_name(word, names, n, &best);
	size_t wl = strlen(word);
	if (pick && best <= (wl < 4 ? 1u : wl / 3 + 1))
		snprintf(out, cap, "; did you mean %s?", pick);
	else
		out[0] = 0;
}

/* The names an io entry can refer to, with the words a message uses. */
typedef struct name_kind {
	const char *what; /* "sensor" */
	const char *file; /* "botdesc" */
	const char *name[EVO_MAX_SENSORS];
	unsigned n;
} name_kind;

static void sensors_of(const evo_mindfolder *l, name_kind *k)
{
	*k = (name_kind){.what = "sensor", .file = "botdesc"};
	for (unsigned i = 0; i < l->botdesc->n_sensors; i++)
		k->name[k->n++] = l->botdesc->sensor[i].name;
}

static void actuators_of(const evo_mindfolder *l, name_kind *k)
{
	*k = (name_kind){.what = "actuator", .file = "botdesc"};
	for (unsigned i = 0; i < l->botdesc->n_actuators; i++)
		k->name[k->n++] = l->botdesc->actuator[i].name;
}

static void variables_of(const evo_mindfolder *l, name_kind *k)
{
	*k = (name_kind){.what = "variable", .file = "vardesc"};
	for (unsigned i = 0; i < l->vardesc->n_vars; i++)
		k->name[k->n++] = l->vardesc->var[i].name;
}

/* The index of io's name among k's names, or -1 with err saying where. */
static int lookup(const evo_mindfolder *l, const name_kind *k, const char *file,
		  const evo_ades_io *io, evo_err *err)
{
	for (unsigned i = 0; i < k->n; i++)
		if (strcmp(k->name[i], io->name) == 0)
			return (int)i;
	char hint[128];
	suggest(hint, sizeof hint, io->name, k->name, k->n);
	return evo_fail(err, "%s:%u: unknown %s '%s': %s.%s has no such %s%s",
			file, io->line, k->what, io->name, l->bot_name, k->file,
			k->what, hint);
}

/* ---- resolving names ------------------------------------------------- */

int evo_mindfolder_resolve_input(const evo_mindfolder *l, const char *file,
				 const evo_ades_io *io, evo_image_io *out,
				 evo_err *err)
{
	name_kind k;
	if (io->type == EVO_IN_SE || io->type == EVO_IN_SD)
		sensors_of(l, &k);
	else
		variables_of(l, &k);
	int idx = lookup(l, &k, file, io, err);
	*out = (evo_image_io){.type = io->type, .index = (uint16_t)idx};
	return idx < 0 ? -1 : 0;
}

int evo_mindfolder_resolve_output(const evo_mindfolder *l, const char *file,
				  const evo_ades_io *io, evo_image_io *out,
				  evo_err *err)
{
	name_kind k;
	int idx;
	if (io->type == EVO_OUT_SK) {
		idx = evo_mindfolder_skill(l, io->name);
		if (idx < 0) /* the walk has read every SK target */
			return evo_fail(err, "%s:%u: unknown skill '%s'", file,
					io->line, io->name);
	} else {
		if (io->type == EVO_OUT_MO)
			actuators_of(l, &k);
		else
			variables_of(l, &k);
		idx = lookup(l, &k, file, io, err);
	}
	*out = (evo_image_io){.type = io->type, .index = (uint16_t)idx};
	return idx < 0 ? -1 : 0;
}

int evo_mindfolder_check_hardcoded(const evo_ades *a, const char *file,
				   evo_err *err)
{
	const evo_hc_class *c = evo_hc_find(a->hc_class);
	if (!c) {
		const char *names[64];
		unsigned n = 0;
		char known[512] = "";
		size_t k = 0;
		for (unsigned i = 0; i < evo_hc_class_count && n < 64; i++) {
			names[n++] = evo_hc_classes[i].name;
			k += (size_t)snprintf(known + k, sizeof known - k,
					      "%s%s", i ? ", " : "",
					      evo_hc_classes[i].name);
			if (k >= sizeof known)
				k = sizeof known - 1;
		}
		char hint[128];
		suggest(hint, sizeof hint, a->hc_class, names, n);
		return evo_fail(err,
				"%s:%u: unknown hard-coded class '%s'%s "
				"(known classes: %s)",
				file, a->kind_line, a->hc_class, hint, known);
	}
	if (c->n_in >= 0 && (unsigned)c->n_in != a->n_in)
		return evo_fail(err,
				"%s:%u: hard-coded class %s reads %d inputs, "
				"but the skill declares %u",
				file, a->kind_line, c->name, c->n_in, a->n_in);
	if (c->n_out >= 0 && (unsigned)c->n_out != a->n_out)
		return evo_fail(err,
				"%s:%u: hard-coded class %s writes %d outputs, "
				"but the skill declares %u",
				file, a->kind_line, c->name, c->n_out,
				a->n_out);
	return 0;
}

/* A layered network for skill a (the shape GENETIC and ANNEALING train):
 * weights all zero (every output 0.5; the placeholder of a skill being
 * trained that has no usable network), or, with r, drawn as GENETIC draws
 * its first generation: normal(0, 1), clamped to [-8, 8]. */
static int layered_net(const evo_ades *a, const char *ades_path, evo_rng *r,
		       evo_netdesc *d, evo_err *err)
{
	unsigned width = evo_net_layered_width(a->n_in, a->n_out);
	size_t nw =
	    evo_net_layered_weight_count(a->n_in, a->n_out, a->layers, width);
	double *w = calloc(nw ? nw : 1, sizeof *w);
	if (!w)
		return evo_fail(err, "out of memory");
	for (size_t i = 0; r && i < nw; i++) {
		/* Box-Muller: u1 in (0, 1], so the log is finite */
		double u1 = 1.0 - evo_rng_unit(r), u2 = evo_rng_unit(r);
		double x = sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
		w[i] = x > 8.0 ? 8.0 : x < -8.0 ? -8.0 : x;
	}
	memset(d, 0, sizeof *d);
	int rc = evo_net_build_layered(a->n_in, a->n_out, a->layers, width,
				       EVO_ACT_SIGMOID, EVO_ACT_SIGMOID, w, d);
	free(w);
	if (rc != 0)
		return evo_fail(err,
				"%s:%u: skill %s is too large for a layered "
				"network",
				ades_path, a->kind_line, a->name);
	return 0;
}

/* The network chosen for skill name, or NULL. */
static const evo_net_choice *choice_for(const evo_mindfolder_opts *o,
					const char *name)
{
	for (unsigned i = 0; o && i < o->n_nets; i++)
		if (strcmp(o->nets[i].skill, name) == 0)
			return &o->nets[i];
	return NULL;
}

/* Skill i's network from a chosen source (evo_net_choice). */
static int chosen_net(evo_mindfolder *l, unsigned i, const char *ades_path,
		      const evo_net_choice *c, uint64_t seed, evo_err *err)
{
	const evo_ades *a = &l->skill[i];
	evo_netdesc *d = l->net[i];
	if (strcmp(c->source, "zero") == 0)
		return layered_net(a, ades_path, NULL, d, err);
	if (strcmp(c->source, "random") == 0) {
		evo_rng r = evo_rng_for(seed, 4, i, 0);
		return layered_net(a, ades_path, &r, d, err);
	}
	if (!evo_file_exists(c->source))
		return evo_fail(err,
				"%s: no such network file (chosen for skill "
				"%s; a .net file, random or zero)",
				c->source, a->name);
	if (evo_mindfolder_read_net(c->source, d, err) != 0)
		return -1;
	if (d->n_in != a->n_in || d->n_out != a->n_out)
		return evo_fail(err,
				"%s:1: the network has %u inputs and %u "
				"outputs, but skill %s declares %u and %u (%s)",
				c->source, d->n_in, d->n_out, a->name, a->n_in,
				a->n_out, ades_path);
	return 0;
}

/* The network of neural skill i: a chosen one, its .net, or for the
 * learning skill a placeholder when it has none yet or one that no longer
 * fits. */
int evo_mindfolder_load_net(evo_mindfolder *l, unsigned i,
			    const char *ades_path, const evo_mindfolder_opts *o,
			    evo_err *err)
{
	const evo_ades *a = &l->skill[i];
	char path[1200];
	evo_mindfolder_skill_path(path, sizeof path, l->root, a->name, "net");
	evo_netdesc *d = calloc(1, sizeof *d);
	if (!d)
		return evo_fail(err, "out of memory");
	l->net[i] = d;
	const evo_net_choice *c = choice_for(o, a->name);
	if (c)
		return chosen_net(l, i, ades_path, c, o->seed, err);
	int learning =
	    o && o->learning_skill && strcmp(o->learning_skill, a->name) == 0;
	if (!evo_file_exists(path)) {
		if (o && o->untrained_ok && !learning) {
			l->untrained[i] = 1;
			return layered_net(a, ades_path, NULL, d, err);
		}
		if (!learning)
			return evo_fail(err,
					"%s:%u: neural skill %s has no trained "
					"network: expected %s (train it with a "
					"LEARNSIM task, or run it with --net "
					"%s=random)",
					ades_path, a->kind_line, a->name, path,
					a->name);
		l->untrained[i] = 2;
		return layered_net(a, ades_path, NULL, d, err);
	}
	if (evo_mindfolder_read_net(path, d, err) != 0)
		return -1;
	if (d->n_in != a->n_in || d->n_out != a->n_out) {
		/* The skill being trained changed its inputs or outputs since
		 * its network was saved: training replaces the network, so it
		 * starts from a placeholder instead of refusing to start. */
		if (learning) {
			fprintf(stderr,
				"warning: %s:1: the network has %u inputs and "
				"%u outputs, but skill %s now declares %u and "
				"%u; training starts afresh and will replace "
				"it\n",
				path, d->n_in, d->n_out, a->name, a->n_in,
				a->n_out);
			return layered_net(a, ades_path, NULL, d, err);
		}
		return evo_fail(err,
				"%s:1: the network has %u inputs and %u "
				"outputs, but skill %s declares %u and %u",
				path, d->n_in, d->n_out, a->name, a->n_in,
				a->n_out);
	}
	return 0;
}

/* Every chosen network names a neural skill of the hierarchy, once. */
int evo_mindfolder_check_choices(const evo_mindfolder *l,
				 const evo_mindfolder_opts *o, evo_err *err)
{
	const char *neural[MAX_SKILLS];
	unsigned n = 0;
	char list[512] = "";
	size_t k = 0;
	for (unsigned i = 0; i < l->n_skills; i++) {
		if (l->skill[i].kind != EVO_SKILL_NEURAL)
			continue;
		neural[n++] = l->skill[i].name;
		k += (size_t)snprintf(list + k, sizeof list - k, "%s%s",
				      n > 1 ? ", " : "", l->skill[i].name);
		if (k >= sizeof list)
			k = sizeof list - 1;
	}
	for (unsigned c = 0; o && c < o->n_nets; c++) {
		const char *name = o->nets[c].skill;
		for (unsigned j = 0; j < c; j++)
			if (strcmp(o->nets[j].skill, name) == 0)
				return evo_fail(err,
						"--net %s: a network is "
						"chosen twice for skill %s",
						name, name);
		int s = evo_mindfolder_skill(l, name);
		if (s >= 0 && l->skill[s].kind == EVO_SKILL_NEURAL)
			continue;
		char hint[128];
		suggest(hint, sizeof hint, name, neural, n);
		return evo_fail(err,
				"--net %s: %s%s (the neural skills under the "
				"master skill: %s)",
				name,
				s >= 0 ? "a hard-coded skill has no network"
				       : "no such skill in the hierarchy",
				hint, n ? list : "none");
	}
	return 0;
}

/* Graphviz drawings of a mind (sim/cmd/info_dot.h). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/info_dot.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "evo/fixed.h"

/* A DOT identifier for a name of a mind: quoted, with quotes and
 * backslashes escaped (names are letters, digits and _ in practice). */
static void quoted(FILE *f, const char *prefix, const char *name)
{
	fputc('"', f);
	fputs(prefix, f);
	for (const char *c = name; *c; c++) {
		if (*c == '"' || *c == '\\')
			fputc('\\', f);
		fputc(*c, f);
	}
	fputc('"', f);
}

static void node(FILE *f, const char *prefix, const char *name,
		 const char *attrs)
{
	fputs("  ", f);
	quoted(f, prefix, name);
	fprintf(f, " [label=");
	quoted(f, "", name);
	fprintf(f, ", %s];\n", attrs);
}

/* Does some skill read sensor (or variable) `name`? Sensors no skill
 * reads are left out of the drawing. */
static int read_by_a_skill(const evo_mindfolder *l, const char *name)
{
	for (unsigned k = 0; k < l->n_skills; k++)
		for (unsigned j = 0; j < l->skill[k].n_in; j++)
			if (strcmp(l->skill[k].in[j].name, name) == 0)
				return 1;
	return 0;
}

static void edge(FILE *f, const char *p0, const char *n0, const char *p1,
		 const char *n1, const char *attrs)
{
	fputs("  ", f);
	quoted(f, p0, n0);
	fputs(" -> ", f);
	quoted(f, p1, n1);
	fprintf(f, "%s%s%s;\n", attrs[0] ? " [" : "", attrs,
		attrs[0] ? "]" : "");
}

void evo_dot_hierarchy(FILE *f, const evo_mindfolder *l)
{
	fprintf(f, "digraph ");
	quoted(f, "", l->bot_name);
	fprintf(f, " {\n  rankdir=TB;\n  node [fontname=\"Helvetica\"];\n"
		   "  edge [fontname=\"Helvetica\", fontsize=10];\n");
	const evo_botdesc *b = l->botdesc;
	fprintf(f, "  { rank=source;\n");
	for (unsigned i = 0; i < b->n_sensors; i++)
		if (read_by_a_skill(l, b->sensor[i].name))
			node(f, "sensor:", b->sensor[i].name,
		     "shape=ellipse, style=filled, fillcolor=\"#DDEEFF\"");
	fprintf(f, "  }\n  { rank=sink;\n");
	for (unsigned i = 0; i < b->n_actuators; i++)
		node(f, "actuator:", b->actuator[i].name,
		     "shape=ellipse, style=filled, fillcolor=\"#FFE6CC\"");
	fprintf(f, "  }\n");
	for (unsigned i = 0; l->vardesc && i < l->vardesc->n_vars; i++)
		node(f, "variable:", l->vardesc->var[i].name,
		     "shape=diamond, style=filled, fillcolor=\"#EEEEEE\"");
	for (unsigned k = 0; k < l->n_skills; k++) {
		const evo_ades *a = &l->skill[k];
		fputs("  ", f);
		quoted(f, "skill:", a->name);
		fprintf(f, " [label=");
		quoted(f, "", a->name);
		if (a->kind == EVO_SKILL_NEURAL)
			fprintf(f, " + \"\\nneural\", shape=box, "
				   "style=\"rounded,filled,bold\", "
				   "fillcolor=\"#E8F4E8\"];\n");
		else
			fprintf(f, " + \"\\nhardCoded %s\", shape=box, "
				   "style=dashed];\n",
				a->hc_class);
	}
	for (unsigned k = 0; k < l->n_skills; k++) {
		const evo_ades *a = &l->skill[k];
		for (unsigned j = 0; j < a->n_in; j++) {
			int var = a->in[j].type == EVO_IN_VA ||
				  a->in[j].type == EVO_IN_VD;
			edge(f, var ? "variable:" : "sensor:", a->in[j].name,
			     "skill:", a->name,
			     "style=dotted, color=\"#7799BB\", arrowsize=0.5");
		}
		for (unsigned j = 0; j < a->n_out; j++) {
			const char *to = a->out[j].type == EVO_OUT_SK
					     ? "skill:"
				       : a->out[j].type == EVO_OUT_VA
					     ? "variable:"
					     : "actuator:";
			edge(f, "skill:", a->name, to, a->out[j].name,
			     a->out[j].type == EVO_OUT_SK
				 ? "penwidth=2"
				 : "color=\"#BB7733\"");
		}
	}
	fprintf(f, "}\n");
}

/* Node id's DOT name and label in skill a's network n. */
static void net_node_name(char *buf, size_t cap, unsigned id)
{
	snprintf(buf, cap, "n%u", id);
}

static const evo_netdesc_node *node_of(const evo_netdesc *n, unsigned id)
{
	for (unsigned i = 0; i < n->n_nodes; i++)
		if (n->node[i].id == id)
			return &n->node[i];
	return NULL;
}

int evo_dot_net(FILE *f, const evo_mindfolder *l, unsigned k, evo_err *err)
{
	const evo_ades *a = &l->skill[k];
	const evo_netdesc *n = l->net[k];
	if (a->kind != EVO_SKILL_NEURAL || !n)
		return evo_fail(err,
				"evo info --dot %s: %s is a hard-coded skill "
				"(class %s); it has no network to draw",
				a->name, a->name, a->hc_class);
	fprintf(f, "digraph ");
	quoted(f, "", a->name);
	fprintf(f, " {\n  rankdir=LR;\n  label=");
	char title[200];
	snprintf(title, sizeof title, "%s: %u inputs, %u hidden, %u outputs, "
				      "%u links",
		 a->name, n->n_in, n->n_nodes - n->n_out, n->n_out,
		 n->n_links);
	quoted(f, "", title);
	fprintf(f, ";\n  labelloc=t;\n  node [fontname=\"Helvetica\"];\n"
		   "  edge [fontname=\"Helvetica\", fontsize=9];\n"
		   "  { rank=source;\n");
	char id[16], label[160];
	for (unsigned i = 0; i < n->n_in; i++) {
		net_node_name(id, sizeof id, i);
		snprintf(label, sizeof label, "%s:%s",
			 evo_input_type_name(a->in[i].type), a->in[i].name);
		fprintf(f, "    %s [label=", id);
		quoted(f, "", label);
		fprintf(f, ", shape=box, style=filled, "
			   "fillcolor=\"#DDEEFF\"];\n");
	}
	fprintf(f, "  }\n  { rank=sink;\n");
	for (unsigned o = 0; o < n->n_out; o++) {
		const evo_netdesc_node *d = node_of(n, n->out_id[o]);
		net_node_name(id, sizeof id, n->out_id[o]);
		snprintf(label, sizeof label, "%s:%s\\n%s %+.3g",
			 evo_output_type_name(a->out[o].type), a->out[o].name,
			 d ? evo_act_name(d->act) : "?",
			 d ? evo_q16_to_double(d->bias) : 0.0);
		fprintf(f, "    %s [label=\"%s\", shape=box, "
			   "style=\"rounded,filled\", "
			   "fillcolor=\"#FFE6CC\"];\n",
			id, label);
	}
	fprintf(f, "  }\n");
	for (unsigned i = 0; i < n->n_nodes; i++) {
		const evo_netdesc_node *d = &n->node[i];
		int is_out = 0;
		for (unsigned o = 0; o < n->n_out; o++)
			is_out |= n->out_id[o] == d->id;
		if (is_out)
			continue;
		net_node_name(id, sizeof id, d->id);
		fprintf(f, "  %s [label=\"%u\\n%s %+.3g\", shape=ellipse, "
			   "fontsize=9];\n",
			id, d->id, evo_act_name(d->act),
			evo_q16_to_double(d->bias));
	}
	for (unsigned i = 0; i < n->n_links; i++) {
		const evo_netdesc_link *e = &n->link[i];
		double w = evo_q16_to_double(e->weight);
		char a0[16], a1[16];
		net_node_name(a0, sizeof a0, e->from);
		net_node_name(a1, sizeof a1, e->to);
		fprintf(f,
			"  %s -> %s [label=\"%.3g\", color=\"%s\", "
			"penwidth=%.2f];\n",
			a0, a1, w, w >= 0 ? "#2F6FD0" : "#D03030",
			0.5 + fmin(fabs(w), 8.0) / 2);
	}
	fprintf(f, "}\n");
	return 0;
}

/* The extension of path after its last '.', or "". */
static const char *extension(const char *path)
{
	const char *slash = strrchr(path, '/');
	const char *dot = strrchr(path, '.');
	return dot && (!slash || dot > slash) ? dot + 1 : "";
}

int evo_dot_write(const char *path, const evo_mindfolder *l, int skill,
		  evo_err *err)
{
	const char *ext = extension(path);
	int text = strcmp(ext, "dot") == 0 || strcmp(ext, "gv") == 0;
	if (!text && strcmp(ext, "png") && strcmp(ext, "svg") &&
	    strcmp(ext, "pdf"))
		return evo_fail(err,
				"evo info -o %s: the file's name ends in .dot "
				"(DOT text) or .png, .svg or .pdf (drawn by "
				"Graphviz's dot)",
				path);
	if (!text && system("command -v dot > /dev/null 2>&1") != 0)
		return evo_fail(err,
				"evo info -o %s: drawing a .%s needs Graphviz's "
				"dot, which is not installed (Debian: apt-get "
				"install graphviz); -o FILE.dot writes the DOT "
				"text without it",
				path, ext);
	char cmd[1400];
	FILE *f;
	if (text) {
		f = fopen(path, "w");
	} else {
		/* the path goes to the shell quoted, with its quotes
		 * escaped */
		size_t at = (size_t)snprintf(cmd, sizeof cmd, "dot -T%s -o '",
					     ext);
		for (const char *c = path; *c && at + 8 < sizeof cmd; c++)
			at += (size_t)(*c == '\''
					   ? snprintf(cmd + at, sizeof cmd - at,
						      "'\\''")
					   : snprintf(cmd + at, sizeof cmd - at,
						      "%c", *c));
		snprintf(cmd + at, sizeof cmd - at, "'");
		f = popen(cmd, "w");
	}
	if (!f)
		return evo_fail(err, "evo info -o %s: cannot write it", path);
	int rc = 0;
	if (skill < 0)
		evo_dot_hierarchy(f, l);
	else
		rc = evo_dot_net(f, l, (unsigned)skill, err);
	int st = text ? fclose(f) : pclose(f);
	if (rc)
		return -1;
	if (text ? st != 0 : !(WIFEXITED(st) && WEXITSTATUS(st) == 0))
		return evo_fail(err, "evo info -o %s: %s", path,
				text ? "cannot write it"
				     : "Graphviz's dot failed (its message "
				       "is above)");
	return 0;
}

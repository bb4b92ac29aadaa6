/* `evo export --format c` (sim/cmd/export_c.h). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/export_c.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Text inside a C comment: a "*" followed by "/" would end it early, a
 * line end would leave the comment's layout. */
static int put_comment_text(FILE *f, const char *s)
{
	int n = 0;
	for (; *s; s++, n++) {
		int c = (unsigned char)*s;
		if (c < 0x20 || c == 0x7f)
			c = '?';
		else if (c == '/' && n > 0 && s[-1] == '*')
			c = '|';
		fputc(c, f);
	}
	return n;
}

/* Text inside a C string literal. */
static void put_string_text(FILE *f, const char *s)
{
	for (; *s; s++) {
		if (*s == '"' || *s == '\\' || *s == '?') /* ? for trigraphs */
			fputc('\\', f);
		if ((unsigned char)*s < 0x20 || *s == 0x7f)
			fprintf(f, "\\%03o", (unsigned char)*s);
		else
			fputc(*s, f);
	}
}

/* One comment line listing names, wrapped at about 76 columns. */
static void name_list(FILE *f, const char *what, unsigned n,
		      const char *(*name)(const evo_mind *, unsigned),
		      const evo_mind *m)
{
	int col = fprintf(f, " * %s (%u):", what, n);
	for (unsigned i = 0; i < n; i++) {
		const char *s = name(m, i);
		if (col + 1 + (int)strlen(s) > 76)
			col = fprintf(f, "\n *   ");
		fputc(' ', f);
		col += 1 + put_comment_text(f, s);
	}
	fprintf(f, "\n");
}

char *evo_export_c(const evo_mindfolder *l, size_t *len, evo_err *err)
{
	char *text = NULL;
	FILE *f = open_memstream(&text, len);
	if (!f) {
		evo_fail(err, "%s: out of memory", l->root);
		return NULL;
	}
	const evo_mind *m = &l->mind;
	const unsigned char *img = l->image;
	fputs("/* Mind image of ", f);
	put_comment_text(f, l->bot_name);
	fputs(" (", f);
	put_comment_text(f, l->root);
	fprintf(f,
		"), written by `evo export --format c`.\n"
		" * %zu bytes, names hash 0x%08lx; the firmware refuses it "
		"unless its\n"
		" * sensors, actuators and variables are these, in this "
		"order.\n",
		l->image_len, (unsigned long)l->names_hash);
	name_list(f, "sensors", m->n_sensors, evo_mind_sensor_name, m);
	name_list(f, "actuators", m->n_actuators, evo_mind_actuator_name, m);
	name_list(f, "variables", m->n_vars, evo_mind_var_name, m);
	name_list(f, "skills, tick order", m->n_skills, evo_mind_skill_name,
		  m);
	fprintf(f,
		" * Do not edit: export the mind folder again. docs/firmware.md, "
		"docs/mind-image.md. */\n"
		"#ifndef EVO_MIND_IMAGE_H\n"
		"#define EVO_MIND_IMAGE_H\n\n"
		"#include <stdint.h>\n\n"
		"#define EVO_MIND_IMAGE_NAME \"");
	put_string_text(f, l->bot_name);
	fprintf(f,
		"\"\n"
		"#define EVO_MIND_IMAGE_LEN %zuu\n"
		"#define EVO_MIND_IMAGE_NAMES_HASH 0x%08lxu\n\n"
		"#ifndef EVO_MIND_IMAGE_ATTR\n"
		"#define EVO_MIND_IMAGE_ATTR\n"
		"#endif\n\n"
		"EVO_MIND_IMAGE_ATTR _Alignas(4) static const uint8_t\n"
		"\tevo_mind_image[EVO_MIND_IMAGE_LEN] = {\n",
		l->image_len, (unsigned long)l->names_hash);
	for (size_t i = 0; i < l->image_len; i++)
		fprintf(f, "%s0x%02x,%s", i % 12 == 0 ? "\t" : " ", img[i],
			i % 12 == 11 || i + 1 == l->image_len ? "\n" : "");
	fprintf(f, "};\n\n#endif\n");
	if (fclose(f) != 0) {
		free(text);
		evo_fail(err, "%s: out of memory", l->root);
		return NULL;
	}
	return text;
}

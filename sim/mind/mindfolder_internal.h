/* evo — private to sim/mind/: what the two files of the mind folder
 * loader share (mindfolder.c reads the folder's files, walks the skills
 * and builds the image; mindfolder_nets.c resolves the skills' names and
 * loads their networks). No other folder may include it. */
#ifndef EVO_MINDFOLDER_INTERNAL_H
#define EVO_MINDFOLDER_INTERNAL_H

#include <stddef.h>

#include "mind/mindfolder.h"

#define MAX_SKILLS 256

/* ROOT/Skills/NAME/NAME.EXT into out. */
void evo_mindfolder_skill_path(char *out, size_t cap, const char *root,
			       const char *name, const char *ext);

/* Read and parse the .net at path into d: 0, or -1 with err set. */
int evo_mindfolder_read_net(const char *path, evo_netdesc *d, evo_err *err);

/* An input or output of a skill's .ades (file, for messages) as the image
 * says it: an index among the botdesc's sensors or actuators, the
 * vardesc's variables or the skills. 0, or -1 with err saying where, with
 * the nearest name when there is one. */
int evo_mindfolder_resolve_input(const evo_mindfolder *l, const char *file,
				 const evo_ades_io *io, evo_image_io *out,
				 evo_err *err);
int evo_mindfolder_resolve_output(const evo_mindfolder *l, const char *file,
				  const evo_ades_io *io, evo_image_io *out,
				  evo_err *err);

/* A HARDCODED skill's class is one evo knows (else the nearest is named),
 * reading and writing as many values as the skill declares. */
int evo_mindfolder_check_hardcoded(const evo_ades *a, const char *file,
				   evo_err *err);

/* The network of neural skill i: a chosen one, its .net, or for the
 * learning skill a placeholder when it has none yet or one that no longer
 * fits. */
int evo_mindfolder_load_net(evo_mindfolder *l, unsigned i,
			    const char *ades_path, const evo_mindfolder_opts *o,
			    evo_err *err);

/* Every chosen network names a neural skill of the hierarchy, once. */
int evo_mindfolder_check_choices(const evo_mindfolder *l,
				 const evo_mindfolder_opts *o, evo_err *err);

#endif

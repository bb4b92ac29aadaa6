/* `evo info MIND --dot [SKILL]`: a mind's hierarchy, or one skill's
 * network, as a Graphviz DOT graph (docs/running.md, "Drawing a mind"),
 * and its rendering to PNG or SVG by Graphviz's `dot` when it is
 * installed. */
#ifndef EVO_INFO_DOT_H
#define EVO_INFO_DOT_H

#include <stdio.h>

#include "base/err.h"
#include "mind/mindfolder.h"

/* The hierarchy: sensors, skills (neural, or hard-coded with their class)
 * with an edge to each sub-skill they influence, the variables and
 * actuators they write and the sensors and variables they read. */
void evo_dot_hierarchy(FILE *f, const evo_mindfolder *l);

/* Skill k's network: its inputs (named as its .ades names them), hidden
 * nodes with their activation, outputs, and every link with its weight
 * (blue positive, red negative, wider for a larger weight). 0, or -1
 * with err when the skill is hard-coded. */
int evo_dot_net(FILE *f, const evo_mindfolder *l, unsigned k, evo_err *err);

/* Write the graph that `draw` writes at path: DOT text for a path ending
 * in .dot, else rendered by `dot -T<ext>` (.png, .svg, .pdf). 0, or -1
 * with err (Graphviz missing, dot failing, a path that cannot be
 * written). */
int evo_dot_write(const char *path, const evo_mindfolder *l, int skill,
		  evo_err *err);

#endif

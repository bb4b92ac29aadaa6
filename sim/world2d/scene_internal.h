/* evo — private to world2d/: what scene.c, grid.c and step.c share and no
 * other folder may use. */
#ifndef EVO_SCENE_INTERNAL_H
#define EVO_SCENE_INTERNAL_H

#include <math.h>
#include <stdint.h>

#include "world2d/scene.h"

/* Add a static obstacle to the world and the scene's list; its index, or
 * -1 with sc->err set. */
int evo_scene_add_obstacle(evo_scene *sc, const evo_obstacle *o);

/* Read the body's pose into the bot's cached frame (x, y, angle, c, s).
 * Inline: the step does it for every bot every tick. */
static inline void evo_bot_refresh_pose(evo_scene *sc, evo_bot *b)
{
	evo_pose p = evo_body_pose(sc->world, b->body);
	b->x = p.x;
	b->y = p.y;
	b->angle = p.angle;
	b->c = cos(p.angle);
	b->s = sin(p.angle);
}

/* Put back the elements' obstacles and build the grid from seed;
 * world_new: the world was just made again (evo_world_reset), with no
 * obstacles. */
void evo_grid_rebuild(evo_scene *sc, uint64_t seed, int world_new);

#endif

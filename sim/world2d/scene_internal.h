/* evo — private to world2d/: what its files share and no other folder
 * may use. */
#ifndef EVO_SCENE_INTERNAL_H
#define EVO_SCENE_INTERNAL_H

#include <math.h>
#include <stdint.h>

#include "world2d/scene.h"

/* How the scene model reads a 2D scene (rewards.c), and what it asks of
 * one (dim2d.c). */
extern const evo_score_ops evo_score_ops_2d;
extern const evo_scene_dim evo_scene_dim_2d;

/* 0 when target may be a sensor's, reward's or control's: an element,
 * none, or the nearest object, opponent or teammate; else -1 with sc->err
 * set, naming what (scene.c). */
int evo_scene_check_target(evo_scene *sc, int target, const char *what);

/* step.c: before the physics step, every bot's actuators act; after it,
 * the bots' poses, movement history and contacts, and the objects'
 * poses, read back. */
void evo_scene_act(evo_scene_core *c);
void evo_scene_read_back(evo_scene_core *c);

/* Add a static obstacle to the world and the scene's list; its index, or
 * -1 with sc->err set. */
int evo_scene_add_obstacle(evo_scene *sc, const evo_obstacle *o);

/* Read the body's pose into the bot's cached frame (x, y, angle, c, s).
 * Inline: the step does it for every bot every tick. */
static inline void evo_bot_refresh_pose(evo_scene *sc, evo_bot *b)
{
	evo_bpose p = sc->be->pose(sc->bw, b->body);
	b->x = p.pos[0];
	b->y = p.pos[1];
	b->angle = p.yaw;
	b->c = p.R[0]; /* cos(yaw) */
	b->s = p.R[3]; /* sin(yaw) */
}

/* The shapes of the world in the box [x0, x1] x [y0, y1] (the backend's
 * query_box): writes at most cap, returns how many there are. */
static inline int evo_scene_query(const evo_scene *sc, double x0, double y0,
				  double x1, double y1, uint16_t mask,
				  evo_shape_info *out, int cap)
{
	return sc->be->query_box(sc->bw, (const double[3]){x0, y0, 0},
				 (const double[3]){x1, y1, 0}, mask, out, cap);
}

/* Put back the elements' obstacles and build the grid from seed;
 * world_new: the world was just made again (evo_world_reset), with no
 * obstacles. */
void evo_grid_rebuild(evo_scene *sc, uint64_t seed, int world_new);

#endif

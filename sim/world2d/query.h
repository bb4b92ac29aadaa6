/* evo — element queries of the 2D world: read-only questions about a
 * scene that the sensors, the actuators, the rewards and the viewer ask.
 * They sit below the pieces that run each tick and call nothing of them,
 * so one tick flows downward (docs/architecture.md). */
#ifndef EVO_QUERY_H
#define EVO_QUERY_H

#include "world2d/scene.h"

/* World position of a point given in bot's frame. */
void evo_bot_to_world(const evo_scene *sc, int bot, double bx, double by,
		      double *wx, double *wy);
/* Centre of a target (element index or EVO_TARGET_NEAREST_OBJECT seen from
 * bot); 0 when there is none. */
int evo_scene_target_pos(const evo_scene *sc, int bot, int target, double *x,
			 double *y);
/* The object detector's test, which the claw shares: the nearest active
 * object no claw holds whose surface is within reach of (px, py) and whose
 * centre is within arc (radians) of the unit direction (ux, uy). Its
 * element index, or -1. */
int evo_scene_object_in_reach(const evo_scene *sc, double px, double py,
			      double ux, double uy, double reach, double arc);

/* The bot whose body has this index, or -1; the object element, or -1
 * (scene.c keeps who owns each body). */
int evo_scene_bot_of_body(const evo_scene *sc, int body_index);
int evo_scene_object_of_body(const evo_scene *sc, int body_index);

/* 1 when the world point lies inside zone element z. */
int evo_zone_contains(const evo_element *z, double x, double y);

#endif

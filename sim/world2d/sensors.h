/* evo — the sensors of the 2D world (the one evo_sensor of scene/sensor.h,
 * its kinds scene/kinds.h's, docs/world.md): each samples the scene into a
 * value in [0, 1]. */
#ifndef EVO_SENSORS_H
#define EVO_SENSORS_H

#include "world2d/scene.h"

/* Sample one sensor; returns its value in [0, 1] and
 * stores it (and a proximity sensor's rays). */
double evo_sensor_sample(evo_scene *sc, int bot, int sensor);
/* Sample every sensor of a bot, sharing one area query among its
 * proximity sensors. */
void evo_bot_sense(evo_scene *sc, int bot);

/* Sample every sensor of every bot, in the bots' order (what
 * evo_scene_sense calls): the same values as evo_bot_sense of each, with
 * one area query for the bots of each cell of the world instead of one
 * per bot. */
void evo_sense_all(evo_scene *sc);

#endif

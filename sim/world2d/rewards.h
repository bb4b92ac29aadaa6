/* evo — the reward and control functions of the 2D world (docs/world.md):
 * rewards add to the episode's score after each step, controls decide
 * whether the episode goes on. They are the scene model's
 * (scene/scoring.h, which computes them); rewards.c says how they read a
 * 2D scene and computes the kinds only 2D has. */
#ifndef EVO_REWARDS_H
#define EVO_REWARDS_H

#include "world2d/scene.h"

/* One reward's value for the step just taken (0 on a hook
 * error, which sets sc->err and returns through *failed). */
double evo_reward_compute(evo_scene *sc, evo_reward *r, int *failed);
/* 1: end the episode; 0: go on; -1: hook error. */
int evo_control_check(evo_scene *sc, evo_control *c);

/* evo_reward_reset and evo_control_reset, and the names users write, are
 * the scene model's (scene/scoring.h, scene/kinds.h). */

#endif

/* evo — a 3D scene: one ODE world (world3d.h) with its elements, its bots
 * with their sensors and actuators, and the reward and control functions
 * of an episode. The 3D twin of world2d/scene.h, built from Lua in the
 * same style (sim/lua/lua_scene3d.c, docs/world3d.md).
 *
 * Frame: right-handed, z up, the ground at z = 0; a bot's own frame has x
 * ahead, y to its left, z up. Angles are radians here (degrees in Lua);
 * yaw turns counter-clockwise seen from above.
 *
 * The world is made again from the scene's definitions at every reset, so
 * an episode depends only on its seeds, never on the episodes before it
 * nor on the thread that runs it.
 *
 * The tick (DESIGN.md): evo_scene3d_sense, then the caller steps each
 * bot's mind and writes actuator commands, then evo_scene3d_step
 * (actuators act and the physics steps, `substeps` times; rewards add up;
 * control functions decide whether the episode goes on). A body that
 * explodes ends the episode with a message in `fault` and the fault
 * penalty added to the reward. The order is the scene model's
 * (sim/scene/tick.c), this world's parts of it dim3d.c's; its bots
 * (scene/bot.h, one struct for both worlds) and what it keeps beside them
 * are the scene model's core (scene/core.h), its first member. */
#ifndef EVO_SCENE3D_H
#define EVO_SCENE3D_H

#include <stdint.h>

#include "base/err.h"
#include "base/rng.h"
#include "scene/actuator.h"
#include "scene/bot.h"
#include "scene/core.h"
#include "scene/element.h"
#include "scene/kinds.h"
#include "scene/scoring.h"
#include "scene/sensor.h"
#include "scene/store.h"
#include "scene/swarm.h"
#include "world3d/world3d.h"

/* -std=c11 leaves it out of <math.h>. */
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define EVO3D_NAME_MAX EVO_PIECE_NAME_MAX
#define EVO3D_FALSE	     0.2
#define EVO3D_TRUE	     0.8
#define EVO3D_TARGET_NONE    (-1)

/* ---- elements ------------------------------------------------------- */

/* evo_element_def and evo_element are the scene model's
 * (scene/element.h), one for both worlds; a 3D element's kind is an
 * EVO_PIECE_BOX (static), EVO_PIECE_CYLINDER (static, upright),
 * EVO_PIECE_SPHERE (static), EVO_PIECE_ZONE (a trigger volume: a box, no
 * body), EVO_PIECE_TARGET (a point to reach: a sphere, no body) or
 * EVO_PIECE_OBJECT (a dynamic box or sphere). An element set off
 * (element:set_active) is seen by no sensor and pays no reward, and an
 * object set off leaves the world, until the next reset. */

/* A static obstacle as the viewer and the tests see it: an element's, or
 * one of the episode's (evo_scene3d_add_episode_obstacle). */
typedef evo_shape3d evo_obstacle3d;

/* ---- sensors ---------------------------------------------------------- */

/* evo_sensor_def and evo_sensor are the scene model's (scene/sensor.h),
 * their kinds scene/kinds.h's evo_sense_kind. The 3D defaults: one ray of
 * 3 m seeing bots, obstacles and objects; a distance's scale 20 m. */
evo_sensor_def evo_default_sensor3d_def(evo_sense_kind kind);

/* ---- actuators: the scene model's (scene/actuator.h) ------------------ */

/* ---- bots ------------------------------------------------------------- */

/* evo_bot_def and evo_bot are the scene model's, one for both worlds
 * (scene/bot.h); a 3D bot reads the fields marked "3D" or "both". */

/* A box of half sides 0.2 x 0.15 x 0.05 m, 2 kg, friction 0.3, of no
 * team (scene3d.c). */
evo_bot_def evo_default_bot_def3d(void);

/* ---- rewards, controls, metrics, hooks ---------------------------------- */

/* The scene model's (scene/scoring.h): evo_reward_def, evo_reward,
 * evo_control_def, evo_control, evo_metric and evo_scene_hooks, one
 * definition for both dimensions. A kind whose row of scene/kinds.c lacks
 * EVO_DIM_3D is refused when added. A 3D target is an element or
 * EVO_TARGET_NONE; a reward's scope is its bot's (and so its team's), a
 * team's or the scene's, as in 2D (docs/teams.md). NextOnTimeout's `ticks` ends the episode at tick `ticks`
 * in 3D, as it always has (2D's ends one later, the tutorial's rule): the
 * control keeps ticks - 1 for the shared count. */

/* ---- the scene -------------------------------------------------------- */

typedef struct evo_scene3d_def {
	evo_bworld_def world; /* ODE's; its step is substeps' length */
	int substeps;	      /* physics steps per tick (2: a tick is 1/30 s) */
	double fault_penalty; /* added when a body explodes (-1000) */
} evo_scene3d_def;

evo_scene3d_def evo_default_scene3d_def(void);

typedef struct evo_scene3d {
	/* What both dimensions keep (scene/core.h), first: the physics
	 * through the backend interface (be is evo_backend_ode and bw its
	 * world, made again at every reset), the tick, rng, rewards and
	 * controls, the episode's figures and teams (a fault's penalty is
	 * the scene's), the fault, metrics, hooks, swarm and error, each by
	 * its own name (sc->tick) and all together as sc->core. */
	EVO_SCENE_CORE;
	evo_scene3d_def def;
	/* The same world as ODE's own API sees it, for the 3D view and the
	 * tests. */
	evo_world3d *world;
	int n_obstacles; /* the bots and elements are the core's */
	int n_fixed_obstacles; /* the elements'; the episode's follow */
	int cap_obstacles;
	evo_obstacle3d *obstacle;
} evo_scene3d;

evo_scene3d *evo_scene3d_create(const evo_scene3d_def *def);

/* New settings for an empty scene (no bot or element yet); 0, or -1 with
 * sc->err set. */
int evo_scene3d_set_def(evo_scene3d *sc, const evo_scene3d_def *def);
void evo_scene3d_destroy(evo_scene3d *sc);

/* Each add returns the new index, or -1 with sc->err set (a bad value, an
 * unknown bot or sensor, a name used twice). */
int evo_scene3d_add_element(evo_scene3d *sc, const evo_element_def *def);
int evo_scene3d_add_bot(evo_scene3d *sc, const evo_bot_def *def);
int evo_scene3d_add_sensor(evo_scene3d *sc, int bot,
			   const evo_sensor_def *def);
int evo_scene3d_add_actuator(evo_scene3d *sc, int bot,
			     const evo_actuator_def *def);
/* Rewards and controls are the scene model's (scene/core.h). */
#define evo_scene3d_add_reward(sc, d)  evo_core_add_reward(&(sc)->core, d)
#define evo_scene3d_add_control(sc, d) evo_core_add_control(&(sc)->core, d)

/* An environment's metrics (scene/core.h). */
#define evo_scene3d_add_metric(sc, n)	 evo_core_add_metric(&(sc)->core, n)
#define evo_scene3d_set_metric(sc, k, v) evo_core_set_metric(&(sc)->core, k, v)
#define evo_scene3d_find_metric(sc, n)	 evo_core_find_metric(&(sc)->core, n)

/* A static obstacle for this episode only (an environment's reset adds
 * them): the next reset removes it. Its category is EVO_CAT3D_GROUND for a
 * piece of uneven ground, anything else making it an obstacle. Its index,
 * or -1 with sc->err set. */
int evo_scene3d_add_episode_obstacle(evo_scene3d *sc, const evo_obstacle3d *o);

/* Lookups by name: scene/core.h's evo_scene_find_element and
 * evo_scene_find_bot, and evo_bot_find_sensor and evo_bot_find_actuator
 * (scene/bot.h), for either world. */

/* Start an episode: a new world with every element and bot where it
 * starts, neutral commands, rewards and controls cleared, the episode's
 * obstacles gone, the rng seeded from episode_seed. Returns 0, or -1 with
 * sc->err set (out of memory). */
int evo_scene3d_reset(evo_scene3d *sc, uint64_t grid_seed,
		      uint64_t episode_seed);

/* Move a bot to a new start pose (an environment's reset): the world's
 * bodies are made again there. */
int evo_scene3d_place_bot(evo_scene3d *sc, int bot, const double pos[3],
			  double yaw);
/* Move a target or zone (not a body) to pos. */
void evo_scene3d_place_element(evo_scene3d *sc, int element,
			       const double pos[3]);

/* Switch an element off (on 0) or back on until the next reset, which
 * switches every element on: one set off is no sensor's or reward's
 * target and no camera's blob, and an object set off leaves the world (no
 * contact, ray or step sees it) and comes back where it was. A cylinder,
 * box or sphere set off stays an obstacle, as in 2D. */
void evo_scene3d_set_active(evo_scene3d *sc, int element, int on);

/* Step 1 of the tick: every sensor of every bot samples (sensors3d.c;
 * evo_core_sense runs it). */
void evo_scene3d_sense(evo_scene3d *sc);

/* Steps 3-5, the scene model's (scene/core.h, sim/scene/tick.c):
 * actuators act and the physics steps, rewards add up, the post-step hook
 * runs, the controls decide. 1 when a control function or a fault ends
 * the episode, 0 when it goes on, -1 with sc->err set when a hook
 * failed. */
#define evo_scene3d_step(sc) evo_core_step(&(sc)->core)

/* Sample one sensor now (sensors3d.c). */
double evo_sensor3d_sample(evo_scene3d *sc, int bot, int sensor);

/* Turn v of the bot's frame into the world's, and back. */
void evo_bot3d_to_world(const evo_bot *b, const double v[3], double out[3]);
void evo_bot3d_to_body(const evo_bot *b, const double v[3], double out[3]);

#endif

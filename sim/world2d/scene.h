/* evo — a 2D scene: one physics world with its world elements, any number
 * of bots with their sensors and actuators, and the reward and control
 * functions of an episode.
 *
 * Everything here is C and runs every tick; Lua (sim/lua/) only creates
 * the pieces and may add hooks. The structs are open so that the
 * viewer and the tests can read them; they are changed only through the
 * functions below.
 *
 * Frame. evo keeps EvoAgents' frame: world x to the right and y downward
 * on screen, angles in radians growing clockwise on screen. In a bot's own
 * frame x points ahead and +y to its right-hand side, so MotR sits at
 * (0, +1) and a sensor at +90 degrees looks to the right. docs/world.md.
 *
 * The tick (DESIGN.md): evo_scene_sense, then the caller steps each bot's
 * mind and writes actuator commands, then evo_scene_step (actuators act,
 * physics steps, rewards add up, control functions decide whether the
 * episode goes on). Their order is the scene model's (sim/scene/tick.c,
 * the same for a 3D scene); this world's parts of them are step.c's and
 * sensors.c's, through dim2d.c, and drive the pieces of sensors.h,
 * actuators.h and rewards.h; those read the scene and ask query.h, and
 * call nothing back (sim/world2d/README.md). Its bots (scene/bot.h, one
 * struct for both worlds) and what it keeps beside them are the scene
 * model's core (scene/core.h), its first member. */
#ifndef EVO_SCENE_H
#define EVO_SCENE_H

#include <stddef.h>
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
#include "world2d/world.h"

#define EVO_SCENE_NAME_MAX EVO_PIECE_NAME_MAX
/* EVO_REWARD_MAX_SENSORS, EVO_SCENE_MAX_METRICS, EVO_METRIC_NAME_MAX and
 * EVO_SCENE_MAX_TEAMS are the scene model's (scene/scoring.h). */

/* -std=c11 leaves these out of <math.h>. */
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#ifndef M_SQRT2
#define M_SQRT2 1.41421356237309504880
#endif

/* Boolean signals (DESIGN.md). */
#define EVO_FALSE 0.2
#define EVO_TRUE 0.8

/* ---- world elements ------------------------------------------------ */

/* evo_element_def and evo_element are the scene model's
 * (scene/element.h), one for both worlds; a 2D element's kind is an
 * EVO_PIECE_CYLINDER (radius size), EVO_PIECE_BOX (half sides half_w x
 * half_h), EVO_PIECE_ZONE (a square of half side size, no body) or
 * EVO_PIECE_OBJECT (a dynamic circle of radius size, can be carried). */

/* A static obstacle as the viewer and the sensors see it. The grid's
 * obstacles are not elements: there are hundreds, rebuilt every episode. */
typedef struct evo_obstacle {
	evo_shape_type shape;
	double x, y, angle;
	double radius;	       /* circle */
	double half_w, half_h; /* box */
	double x2, y2;	       /* segment: from (x, y) to (x2, y2) */
} evo_obstacle;

/* The tutorial's obstacle grid: one obstacle per cell of a square grid
 * over the area, each moved by up to `jitter` on each axis, of size
 * min_size + [0, size_variability). Cells too close to a bot's start,
 * a zone or an object are left empty. Rebuilt at every reset from the
 * grid seed given to evo_scene_reset. */
typedef struct evo_grid_def {
	int enabled;
	double x0, y0, x1, y1; /* area */
	double spacing, jitter;
	double min_size, size_variability;
	int boxes;	  /* 0: cylinders; 1: boxes; 2: a mix */
	double clearance; /* free space kept around starts, zones, objects */
} evo_grid_def;

/* EvoAgents' defaults: min size 1.0, variability 2.0, spacing 18. */
evo_grid_def evo_default_grid_def(void);

/* ---- sensors -------------------------------------------------------- */

/* evo_sensor_def and evo_sensor are the scene model's (scene/sensor.h),
 * their kinds scene/kinds.h's evo_sense_kind. */

/* What a distance, zone, bearing or presence sensor looks at: an element,
 * or one of scene/scoring.h's EVO_TARGET_* (the nearest bot of another
 * team or of the bot's own is looked for within EVO_TEAM_SEARCH metres,
 * through the broad phase). */
#define EVO_TEAM_SEARCH 160.0

/* The 2D defaults (EvoAgents' values): 9 rays of 12 m over 6 degrees each
 * side, seeing obstacles and bots; scale 100 (movement 1.5); an object
 * detector, radar or bumper 45 degrees each side. */
evo_sensor_def evo_default_sensor_def(evo_sense_kind kind);

/* ---- actuators: the scene model's (scene/actuator.h) ---------------- */

/* ---- bots ------------------------------------------------------------ */

/* evo_bot_def and evo_bot are the scene model's, one for both worlds
 * (scene/bot.h); a 2D bot reads the fields marked "2D" or "both". */

/* BotType8: a dynamic circle of radius 1, density 2, friction 0, damping
 * 5 / 20, never sleeping, of no team (world2d/defaults.c). */
evo_bot_def evo_default_bot_def(void);

/* ---- reward and control functions, metrics, hooks ------------------ */

/* The scene model's (scene/scoring.h): evo_reward_def, evo_reward,
 * evo_control_def, evo_control, evo_scope, evo_metric and
 * evo_scene_hooks, with the kinds and their names of scene/kinds.h. */

/* ---- the scene ------------------------------------------------------- */

typedef struct evo_scene evo_scene;

struct evo_scene {
	/* What both dimensions keep (scene/core.h), first: the physics
	 * through the backend interface (be is evo_backend_box2d and bw its
	 * world), the tick, rng, rewards and controls, the episode's figures
	 * and teams, metrics, hooks, swarm and error, each by its own name
	 * (sc->tick) and all together as sc->core. */
	EVO_SCENE_CORE;
	/* The same world as Box2D's own API sees it, for what is 2D only
	 * outside world2d/ (the viewer, the Lua bot binding, the tests). */
	evo_world *world;
	int n_obstacles; /* the bots and elements are the core's */
	int cap_obstacles;
	int n_objects, cap_objects;
	int *object; /* the element indices of the objects, in order */
	evo_obstacle *obstacle; /* every static obstacle: elements', grid's */
	int n_fixed_obstacles;	/* the first ones, from elements; the grid follows */
	int n_walls;		/* of them, walls (evo_scene_add_wall) */
	evo_grid_def grid;
	/* the bot (>= 0) or object element (-(e + 2)) of each body index,
	 * -1 for none: what the broad phase finds, named */
	int *body_owner;
	int cap_body_owner;
	/* evo_scene_sense's buffers, kept from one tick to the next
	 * (sensors.c) */
	void *sense_mem;
	size_t sense_cap;
	void *sense_shapes;
	size_t sense_shapes_cap;
};

evo_scene *evo_scene_create(void);
void evo_scene_destroy(evo_scene *sc);

/* Each add returns the new index, or -1 with sc->err set (bad value,
 * unknown bot or sensor index, a name used twice). */
int evo_scene_add_element(evo_scene *sc, const evo_element_def *def);
int evo_scene_add_bot(evo_scene *sc, const evo_bot_def *def);
int evo_scene_add_sensor(evo_scene *sc, int bot, const evo_sensor_def *def);
int evo_scene_add_actuator(evo_scene *sc, int bot,
			   const evo_actuator_def *def);
/* Rewards and controls are the scene model's (scene/core.h). */
#define evo_scene_add_reward(sc, def)  evo_core_add_reward(&(sc)->core, def)
#define evo_scene_add_control(sc, def) evo_core_add_control(&(sc)->core, def)
void evo_scene_set_grid(evo_scene *sc, const evo_grid_def *def);

/* A wall of no thickness from (x1, y1) to (x2, y2), for the whole run (the
 * mazes' segments): a static obstacle that bots bump into and rays see.
 * Added before the first reset. Its obstacle index, or -1 with sc->err
 * set (a value that is not a number, two ends closer than 5 mm). */
int evo_scene_add_wall(evo_scene *sc, double x1, double y1, double x2,
		       double y2);

/* Declare a metric: a name of letters, digits and '_' that does not start
 * with a digit, at most EVO_METRIC_NAME_MAX - 1 characters; at most
 * EVO_SCENE_MAX_METRICS of them. Returns its index (the one it already has
 * when the name is declared), or -1 with sc->err set. */
#define evo_scene_add_metric(sc, name) evo_core_add_metric(&(sc)->core, name)

/* Set this episode's value of a metric. Returns 0, or -1 with sc->err set
 * when the value is not finite (the metric keeps its value). */
#define evo_scene_set_metric(sc, k, v) evo_core_set_metric(&(sc)->core, k, v)

/* Lookups by name; -1 when absent (elements and bots: scene/core.h's
 * evo_scene_find_element and evo_scene_find_bot, for either world). */
#define evo_scene_find_metric(sc, name) evo_core_find_metric(&(sc)->core, name)

/* ---- the episode and the tick (step.c) -------------------------------- */

/* Start an episode: bots back at their starts with no speed and neutral
 * commands, claws open, objects back and active, rewards and controls
 * cleared, every metric 0, the grid rebuilt from grid_seed, the rng
 * reseeded from episode_seed. */
void evo_scene_reset(evo_scene *sc, uint64_t grid_seed, uint64_t episode_seed);

/* The tick, the scene model's (scene/core.h, sim/scene/tick.c): step 1,
 * every sensor of every bot samples; steps 3-5, actuators act on their
 * commands, the physics steps, rewards add up into step_reward and
 * episode_reward, the post-step hook runs, the controls decide. The step
 * returns 1 when a control function ends the episode, 0 when it goes on,
 * -1 with sc->err set when a hook failed. */
#define evo_scene_sense(sc) evo_core_sense(&(sc)->core)
#define evo_scene_step(sc)  evo_core_step(&(sc)->core)

/* A static obstacle for this episode only, after the elements' and the
 * grid's: the next reset removes it. An environment's own obstacle
 * generator adds its obstacles so (the tutorial's
 * generateObstaclesParameters). Its index, or -1 with sc->err set. */
int evo_scene_add_episode_obstacle(evo_scene *sc, const evo_obstacle *o);

/* Place a bot (pose and zero speed) or an element; used by environments
 * (scene.c). */
void evo_scene_place_bot(evo_scene *sc, int bot, double x, double y,
			 double angle);
void evo_scene_place_element(evo_scene *sc, int element, double x, double y);

/* Switch an element on or off until the next reset (element:set_active;
 * step.c),
 * as evo_scene3d_set_active does in 3D: one set off is no sensor's or
 * reward's target and no camera's blob; an object set off is dropped by
 * a claw that held it and leaves the world (no contact, query or ray
 * sees it). */
void evo_scene_set_active(evo_scene *sc, int element, int on);

#endif

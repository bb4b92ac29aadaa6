/* evo — what a scene of either dimension keeps beside its obstacles
 * (docs/architecture.md, "Where the layout is going", step 4): its physics
 * through the backend interface, its bots (scene/bot.h, added by
 * evo_core_add_bot below) and elements (scene/element.h), the episode's
 * figures (tick, step and episode reward, what each team was paid, the
 * winner, the fault that ended it), its rewards and controls, metrics, hooks, swarm, randomness
 * and error; with the functions that keep them, written once: the adds of
 * rewards and controls with their checks, the metrics, the reset of the
 * figures, paying the rewards, and the bots seen alike in both worlds
 * (view.c).
 *
 * The 2D scene (world2d/scene.h) and the 3D one (world3d/scene3d.h) each
 * hold one as their first member, EVO_SCENE_CORE: an anonymous union of
 * `core` and the same fields unnamed, so that `sc->tick` reads as before
 * and `&sc->core` is what the functions below take. Being first, a
 * scene's core and the scene share one address: a dimension's functions
 * turn the core they are given back into their scene.
 *
 * What differs between the dimensions is said once, in an evo_scene_dim
 * each fills (world2d/scene.c, world3d/scene3d.c). */
#ifndef EVO_SCENE_CORE_H
#define EVO_SCENE_CORE_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"
#include "base/rng.h"
#include "scene/backend.h"
#include "scene/bot.h"
#include "scene/element.h"
#include "scene/kinds.h"
#include "scene/scoring.h"
#include "scene/swarm.h"

typedef struct evo_scene_dim evo_scene_dim;

/* The fields, once: the named struct and the scenes' anonymous one. */
#define EVO_SCENE_CORE_FIELDS                                                  \
	/* The physics, through the backend interface (scene/backend.h) */     \
	const evo_backend *be;                                                 \
	evo_bworld *bw;                                                        \
	const evo_scene_dim *dim; /* what differs by dimension */              \
	int n_bots, n_elements;                                                \
	/* the bots (scene/bot.h), added by evo_core_add_bot */                \
	evo_bot *bot;                                                          \
	int cap_bots;                                                          \
	/* the elements (scene/element.h), stored by evo_element_store */      \
	evo_element *element;                                                  \
	int cap_elements;                                                      \
	/* the backend's static index of obstacle 0 (2D: 0; 3D: set by         \
	 * evo_scene3d_build_world): element e's is first_static +             \
	 * e.obstacle */                                                       \
	int first_static;                                                      \
	/* a NextOnCollisionWithTarget asks what the bots touch: each tick     \
	 * begins with the backend's forget_touches */                         \
	int keeps_touches;                                                     \
	long tick;	    /* ticks since the reset */                        \
	evo_rng rng;	    /* the episode's randomness (RANDOM sensors) */    \
	uint64_t grid_seed; /* the last reset's: episode obstacles */          \
	int n_rewards, n_controls;                                             \
	int cap_rewards, cap_controls;                                         \
	evo_reward *reward;                                                    \
	evo_control *control;                                                  \
	double step_reward;    /* what the rewards gave in the last step */    \
	double episode_reward; /* since the reset */                           \
	/* Teams (docs/teams.md): one more than the highest team of a bot;     \
	 * what each team was paid since the reset (its bots' own and its      \
	 * team rewards; a fault's penalty is the scene's); the episode's      \
	 * winner (-1: none yet) */                                            \
	int n_teams;                                                           \
	double team_reward[EVO_SCENE_MAX_TEAMS];                               \
	int winner;                                                            \
	/* what ended the episode early, in words (a body that exploded);      \
	 * "" while nothing did */                                             \
	char fault[256];                                                       \
	evo_swarm swarm; /* lights and floor patches (scene/swarm.h) */        \
	int n_metrics;	 /* declared, in the order they were */                \
	evo_metric metric[EVO_SCENE_MAX_METRICS];                              \
	evo_scene_hooks hooks; /* Lua's (sim/lua/lua_hooks.c), or a test's */  \
	evo_err err;

typedef struct evo_scene_core {
	EVO_SCENE_CORE_FIELDS
} evo_scene_core;

/* A scene's first member: `core`, and its fields by their own names. */
#define EVO_SCENE_CORE                                                         \
	union {                                                                \
		evo_scene_core core;                                           \
		struct {                                                       \
			EVO_SCENE_CORE_FIELDS                                  \
		};                                                             \
	}

/* What a dimension says of its scene, for the functions below. Each
 * function takes the core, which is its scene's first member. */
struct evo_scene_dim {
	const char *name; /* "2D" or "3D", for messages */
	unsigned dims;	  /* EVO_DIM_2D or EVO_DIM_3D: the kinds it has */
	/* how its rewards and controls read it (scene/scoring.h) */
	const evo_score_ops *score;
	/* 0 when target may be a reward's or control's (an element, or
	 * what else the dimension allows), else -1 with c->err set */
	int (*check_target)(evo_scene_core *c, int target, const char *what);
	/* the checks of a reward in one dimension alone (a 2D Collect needs
	 * a zone); NULL: none */
	int (*check_reward)(evo_scene_core *c, const evo_reward_def *d);
	/* 3D's NextOnTimeout ends the episode at tick `ticks`, one tick
	 * before 2D's (the tutorial's rule): its control keeps ticks - 1 */
	long timeout_shift;

	/* The tick's parts, in the order evo_core_sense and evo_core_step
	 * (tick.c) run them. */
	/* step 1: every sensor of every bot samples */
	void (*sense)(evo_scene_core *c);
	/* before the physics (NULL: nothing) */
	void (*begin)(evo_scene_core *c);
	/* physics steps in a tick (NULL: one) */
	int (*substeps)(const evo_scene_core *c);
	/* before each physics step: every bot's actuators act */
	void (*act)(evo_scene_core *c);
	/* after each physics step (NULL: nothing) */
	void (*after_substep)(evo_scene_core *c);
	/* after the last: the bots' and objects' poses read back, contacts
	 * counted */
	void (*read_back)(evo_scene_core *c);
	/* a body exploded: say which in c->fault; the penalty paid (NULL
	 * where the engine never reports one) */
	double (*fault)(evo_scene_core *c, const evo_bfault *f);

	/* What a task's simulation asks (sim/tasksim/tasksim.c). */
	/* start an episode (the scene's reset): 0, or -1 with c->err set */
	int (*reset)(evo_scene_core *c, uint64_t grid_seed,
		     uint64_t episode_seed);
	/* widen box (x0, y0, x1, y1) over the static obstacles the
	 * environment built (evo_sim_behaviour's arena) */
	void (*arena)(const evo_scene_core *c, double box[4]);
};

/* A scene's (2D, 3D, or its core's) element or bot by name; -1 when
 * absent (scene/store.h). */
#define evo_scene_find_element(s, k) EVO_FIND(s, element, evo_element, k)
#define evo_scene_find_bot(s, k)     EVO_FIND(s, bot, evo_bot, k)

/* A new core: its backend and world, its dimension, the rng seeded with 1,
 * no winner. */
void evo_core_init(evo_scene_core *c, const evo_backend *be, evo_bworld *bw,
		   const evo_scene_dim *dim);
/* Free what the core owns: the bots with their sensors and actuators, the
 * elements, the rewards, controls and swarm (not the world: its scene's,
 * which it frees after). */
void evo_core_free(evo_scene_core *c);

/* Add a reward or control after the checks of both dimensions and the
 * scene's own: its index, or -1 with c->err set (a kind of the other
 * dimension, no such bot, target, team or sensor, a value not a
 * number). */
int evo_core_add_reward(evo_scene_core *c, const evo_reward_def *d);
int evo_core_add_control(evo_scene_core *c, const evo_control_def *d);

/* An environment's metrics (scene/scoring.h's evo_metric_add, _set and
 * _find on the core's). */
int evo_core_add_metric(evo_scene_core *c, const char *name);
int evo_core_set_metric(evo_scene_core *c, int metric, double value);
int evo_core_find_metric(const evo_scene_core *c, const char *name);

/* Check and store a new bot (scene/bot.h), as both worlds do: its pose a
 * number, its name not used by another bot, its team -1 to
 * EVO_SCENE_MAX_TEAMS - 1. The new bot (not yet counted in c->n_bots)
 * has its name (d->name, or when that is NULL or "", dflt and its index
 * + 1; "" when dflt is NULL too), its def, team and start pose, no body;
 * its team joins c's teams. Its world then makes its body and counts
 * it. NULL with c->err set. */
evo_bot *evo_core_add_bot(evo_scene_core *c, const evo_bot_def *d,
			  const char *dflt);

/* A bot's team joins the scene's teams: n_teams grows to hold it. */
void evo_core_note_team(evo_scene_core *c, int team);

/* The figures of a new episode: rewards and controls cleared, every metric
 * and team 0, no winner nor fault, tick 0, the rng seeded from
 * episode_seed, grid_seed remembered (an environment's obstacles draw
 * from it). */
void evo_core_reset(evo_scene_core *c, uint64_t grid_seed,
		    uint64_t episode_seed);

/* The tick (tick.c). Step 1: every sensor of every bot samples. */
void evo_core_sense(evo_scene_core *c);
/* Steps 3 to 5, after the caller wrote the commands: the actuators act
 * and the physics steps (substeps times), the tick counts, the poses are
 * read back, then the rewards are paid, the post-step hook runs and the
 * controls decide (evo_core_score). A body that explodes ends the episode
 * with the fault's penalty as the step's reward. 1 when a control or a
 * fault ends the episode (a scene whose episode a fault ended stays
 * ended), 0 when it goes on, -1 with c->err set when a hook failed. */
int evo_core_step(evo_scene_core *c);

/* ---- the bots, seen from outside their dimension (view.c) ------------- */

/* out[i] = the last sample of b's sensor map[i]; b's actuator map[i]'s
 * command = in[i]: what a task's minds read and write each tick. */
void evo_bot_read_sensors(const evo_bot *b, const int *map, unsigned n,
			  double *out);
void evo_bot_write_actuators(evo_bot *b, const int *map, unsigned n,
			     const double *in);
/* Wake the sensors the rewards and controls read. */
void evo_core_wake_scored(evo_scene_core *c);
/* Step 5 of the tick, after the physics: the rewards paid, the post-step
 * hook, the controls (evo_score_step). 1 when a control ends the episode,
 * 0 when it goes on, -1 with c->err set when a hook failed. */
int evo_core_score(evo_scene_core *c);

#endif

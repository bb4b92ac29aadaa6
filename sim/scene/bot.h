/* evo — a bot, one struct for both worlds (docs/architecture.md, "Where
 * the layout is going", step 4): its definition (evo_bot_def: where it
 * starts, its team, its body) and its state in a scene (evo_bot: its
 * body in the world, its sensors and actuators, its pose after the last
 * step, its contacts and what it was paid). Each field says which world
 * reads it: "both", "2D" or "3D".
 *
 * The bots of a scene are the scene model's core's (scene/core.h:
 * c->bot, c->n_bots), added through core.h's evo_core_add_bot, which checks
 * and stores what both worlds repeat (the pose a number, the name once,
 * the team in range); each world then makes the bot's body, which is its
 * own (world2d/scene.c: one Box2D body; world3d/scene3d.c: a hull and a
 * body and hinge for each wheel).
 *
 * Frame: the world's (docs/world.md, docs/world3d.md). The pose is pos
 * (x, y, z) and yaw, a turn about the frame's third axis in the frame's
 * own sense: clockwise on the 2D screen (z is 0 there), counter-clockwise
 * seen from above in 3D.
 *
 * Defaults: one per world, since a 2D bot is EvoAgents' BotType8 (a
 * Box2D circle of 1 m) and a 3D one a 40 cm box of 2 kg:
 * evo_default_bot_def() (world2d/scene.h) and evo_default_bot_def3d()
 * (world3d/scene3d.h). */
#ifndef EVO_SCENE_BOT_H
#define EVO_SCENE_BOT_H

#include "scene/actuator.h"
#include "scene/backend.h"
#include "scene/place.h"
#include "scene/sensor.h"
#include "scene/store.h"

/* ticks of positions the movement sensor spreads over (one simulated
 * second in either world) */
#define EVO_DOF_HISTORY 30

typedef struct evo_bot_def {
	const char *name; /* both: NULL or "" for none (2D) or "botN" (3D) */
	int team;	  /* both: -1 none; else 0 .. EVO_SCENE_MAX_TEAMS - 1 */
	/* both: the start pose; 2D reads x, y and leaves z 0 */
	EVO_POSITION;
	double yaw;
	/* 2D: the body, a dynamic circle: radius 1, density 2, friction
	 * 0, damping 5 / 20, never sleeps (BotType8); its pose is pos and
	 * yaw */
	evo_bbody_def body;
	/* 3D: the hull, a box of half sides half[] or, with radius > 0, a
	 * sphere, of mass (2 kg) and friction (0.3) */
	double half[3];
	double radius;
	double mass;
	double friction;
	/* 3D: a frictionless ball under the hull (a caster), when radius
	 * > 0 */
	double caster_pos[3], caster_radius;
	/* 3D: buoyancy as a fraction of the bot's weight (its hull's;
	 * wheels weigh on), pushing up at cob (body frame); drag against
	 * the hull's motion in water or air: -(linear + quadratic |v|) v
	 * and -angular omega. 0 for a robot on the ground. */
	double buoyancy, cob[3];
	double drag_linear, drag_quadratic, drag_angular;
} evo_bot_def;

typedef struct evo_bot {
	char name[EVO_PIECE_NAME_MAX]; /* both */
	evo_bot_def def;	       /* both; def.name is NULL */
	/* both: its body in the world (3D: the hull's; the wheels' are
	 * their actuators') */
	evo_body_id body;
	int team; /* both: def.team */
	/* both: this episode's start pose (3D: an environment's
	 * evo_scene3d_place_bot moves it; 2D: def's) */
	double start[3], start_yaw;
	int n_sensors, n_actuators; /* both */
	evo_sensor *sensor;	/* both: owned (scene/sensor.h) */
	evo_actuator *actuator; /* both: owned (scene/actuator.h) */
	/* both: its centre after the last step or placement (2D: x, y;
	 * z 0) */
	EVO_POSITION;
	/* 2D: its turn then, with its cosine and sine: worked out once and
	 * read by the sensors, the actuators and the rewards of the tick
	 * (the pose changes only there) */
	double angle, c, s;
	/* 3D: its turn (row-major, world = R body), speed and spin then */
	double R[9], v[3], omega[3];
	double radius; /* 2D: bounding radius */
	/* both: movement, a ring of the last EVO_DOF_HISTORY positions
	 * (x, y: the ground's plane in 3D) */
	double hist_x[EVO_DOF_HISTORY], hist_y[EVO_DOF_HISTORY];
	int hist_n, hist_i;
	/* both: contacts this tick (3D: with anything but the ground,
	 * counted over the tick's substeps) */
	int touching;
	int collisions; /* both: ticks spent touching since the reset */
	int delivered;	/* 2D: objects it carried into a zone since the reset */
	int gathered;	/* 2D: objects it gathered (reward Gather) since then */
	double reward;	/* both: what was paid to it since the reset (its own) */
} evo_bot;

/* A bot's sensor or actuator by name; -1 when absent (scene/store.h). */
#define evo_bot_find_sensor(b, k)   EVO_FIND(b, sensor, evo_sensor, k)
#define evo_bot_find_actuator(b, k) EVO_FIND(b, actuator, evo_actuator, k)

/* The ring of a bot's last places (scene/bot.c), which the movement
 * sensor reads: emptied at a reset, b's x and y added after each tick's
 * physics; the spread of what it holds, sqrt(var x + var y) (0 for
 * fewer than two places). */
void evo_bot_forget_places(evo_bot *b);
void evo_bot_remember_place(evo_bot *b);
double evo_bot_spread(const evo_bot *b);

#endif

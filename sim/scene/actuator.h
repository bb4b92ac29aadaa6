/* evo — a bot's actuators, one definition for both worlds (docs/world.md,
 * docs/world3d.md): the kinds are scene/kinds.h's evo_act_kind, whose rows
 * say which world has each (a wheel in both, a claw, speed wheel and drive
 * in 2D, a propeller in 3D, a broadcast in both). Each field below says
 * which world reads it; the other world leaves it at its default.
 *
 * Adding one is written here once (evo_actuator_store: the checks, the
 * name, the storage, the state a new actuator starts with); how an
 * actuator acts on its world's bodies is that world's
 * (sim/world2d/actuators.c pushes a Box2D body at a point, claws weld;
 * sim/world3d/actuators3d.c drives ODE hinges and pushes in the body's
 * frame), each on this one struct. A command is in [0, 1] and 0.5 is
 * neutral everywhere. */
#ifndef EVO_SCENE_ACTUATOR_H
#define EVO_SCENE_ACTUATOR_H

#include <math.h>

#include "base/err.h"
#include "scene/kinds.h"
#include "scene/place.h"
#include "scene/store.h"
#include "scene/swarm.h"

typedef struct evo_actuator_def {
	evo_act_kind kind;
	const char *name; /* may be NULL */
	/* both: where it is, in the bot's frame (2D reads x and y; in 3D the
	 * wheel's hub, the propeller) */
	EVO_POSITION;
	/* 2D: the direction it pushes or grabs, radians from the heading */
	double angle;
	/* 2D wheel: force (2c - 1) * max_force along angle (80) */
	double max_force;
	/* 2D claw: how far from (x, y) it grabs (1.5) */
	double reach;
	/* 2D speed wheel, drive: the top speed, m/s (a turning drive:
	 * rad/s), 1 */
	double max_speed;
	/* 2D drive: 0, the command sets the speed to (2c - 1) * max_speed;
	 * above 0, it changes the speed by (2c - 1) * accel each step,
	 * within +-max_speed */
	double accel;
	int turn; /* 2D drive: 1 turns (+ clockwise on screen), 0 drives ahead
		   */
	/* 3D propeller: the direction of its thrust (made unit when added;
	 * (1, 0, 0)) and its thrust at c = 1, N (10) */
	double axis[3];
	double max_thrust;
	/* 3D wheel, a body on a hinge: radius, half its width, mass, friction
	 * (0.08, 0.02, 0.2, 1); driven to (2c - 1) * max_rate rad/s (15) with
	 * at most max_torque N m (2), or with torque_mode 1 by
	 * (2c - 1) * max_torque */
	double radius, half_width, mass, friction;
	int torque_mode;
	double max_rate, max_torque;
} evo_actuator_def;

/* A command as every actuator of either world reads it: into [0, 1],
 * and one that is not a number neutral (0.5) rather than full reverse. */
static inline double evo_command01(double c)
{
	return isnan(c) ? 0.5 : c < 0 ? 0 : c > 1 ? 1 : c;
}

/* The defaults of every field above, for a kind of either world. */
evo_actuator_def evo_default_actuator_def(evo_act_kind kind);

typedef struct evo_actuator {
	char name[EVO_PIECE_NAME_MAX];
	evo_actuator_def def; /* def.name is NULL: the name is name */
	/* both: [0, 1], written by the caller before the scene's step */
	double command;
	/* 2D: the command of the previous step (claw edges) */
	double previous;
	int held;     /* 2D claw: element index held, or -1 */
	int joint;    /* 2D claw: the weld's id in the world, or -1 */
	double speed; /* 2D speed wheel, drive: the speed it set last step */
	double dir_c, dir_s; /* 2D: cos and sin of def.angle */
	int body;	     /* 3D wheel: its body in the world, or -1 */
	int hinge;	     /* 3D wheel: its hinge, or -1 */
} evo_actuator;

/* Adding an actuator, both worlds' part: checks d for world dim
 * (EVO_DIM_2D or EVO_DIM_3D: a kind of that world by its row of kinds.c,
 * numbers, a speed wheel's or drive's max_speed and accel, a propeller's
 * axis and thrust, a 3D wheel's body and drive, a name not used by the
 * first n actuators of *arr) and stores it as actuator n of *arr (a bot's
 * actuators, which grow 8 at a time), named d->name or, unnamed, dflt
 * and its number ("actuator3"; "" when dflt is NULL), neutral (command
 * 0.5, nothing held, no body yet; a propeller's axis made unit). bot
 * names the bot in the messages. The new actuator, or NULL with err set;
 * the caller makes what its world needs (a 3D wheel's body) and counts
 * it. */
evo_actuator *evo_actuator_store(evo_actuator **arr, int n,
				 const evo_actuator_def *d, unsigned dim,
				 const char *bot, const char *dflt,
				 evo_err *err);

/* What a bot of n actuators a broadcasts, as range-and-bearing sensors
 * hear it: its broadcast actuators' commands, in the order it has them,
 * into out's values (its position is the caller's). 1 when it has a
 * broadcast actuator, 0 when none (it is not heard). */
int evo_actuator_broadcasts(const evo_actuator *a, int n, evo_swarm_peer *out);

#endif

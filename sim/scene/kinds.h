/* evo — the kinds of the one scene model (docs/architecture.md, "Where the
 * layout is going"): for each kind, the name users write and the worlds
 * it exists in. What is only 2D or only 3D is said here, in its row of
 * kinds.c, and nowhere else: a scene of the other dimension refuses the
 * kind by that row, with its name.
 *
 * So far the reward and control functions (EvoAgents' RW_ and CF_
 * classes, tutorial sections 6.3 and 6.4); the elements, sensors and
 * actuators follow when the two scenes become one. */
#ifndef EVO_KINDS_H
#define EVO_KINDS_H

/* The worlds a kind exists in: a mask of these. */
#define EVO_DIM_2D   1u
#define EVO_DIM_3D   2u
#define EVO_DIM_BOTH (EVO_DIM_2D | EVO_DIM_3D)

typedef enum evo_reward_kind {
	EVO_RW_CLOSING_ON_TARGET = 0, /* k * (previous distance - distance) */
	EVO_RW_SENSOR_OVER,  /* k * sum(v - threshold) over v > threshold */
	EVO_RW_SENSOR_UNDER, /* k * sum(threshold - v) over v <= threshold */
	EVO_RW_PUNISH_ON_COLLISION, /* k every tick the bot touches anything (k
				       < 0) */
	EVO_RW_FORWARD_MOTION,	    /* k moving forward, k2 moving backward */
	EVO_RW_SPEED,		    /* k * speed^2 */
	EVO_RW_STEP,		    /* k every tick */
	EVO_RW_COLLECT, /* k for each object delivered into the target zone */
	EVO_RW_FORWARD_SPEED, /* k * speed along the heading (< 0 backing) */
	EVO_RW_GATHER,	 /* k for each object the bot touches, which leaves */
	EVO_RW_LUA,	 /* a Lua function (sim/lua/lua_hooks.c) */
	EVO_RW_DISTANCE, /* k * distance to the target */
	EVO_RW_FINAL_DISTANCE, /* sums to k2 + k * the distance at the end */
	EVO_RW_EFFORT,	       /* k * sum of (2c - 1)^2 over the bot's wheels */
	EVO_RW_KIND_COUNT
} evo_reward_kind;

typedef enum evo_control_kind {
	EVO_CF_NEXT_ON_TIMEOUT = 0, /* after `ticks` ticks */
	EVO_CF_NEXT_ON_COLLISION,   /* when the bot touches anything */
	EVO_CF_NEXT_ON_COLLISION_AND_TIMEOUT, /* either */
	EVO_CF_NEXT_ON_COLLISION_WITH_TARGET, /* when the bot touches the target
						 element */
	EVO_CF_NEXT_ON_SENSOR_BELOW, /* when sensor's value < threshold */
	EVO_CF_LUA,
	EVO_CF_NEXT_ON_TARGET_REACHED, /* the bot's centre within threshold of
					  the target's */
	EVO_CF_KIND_COUNT
} evo_control_kind;

/* The names users write (RW_ClosingOnTarget or ClosingOnTarget, and the
 * shorter spellings SensorOver, SensorUnder, Step, NextOnSensorBelow; case
 * matters); -1 when unknown. */
int evo_reward_kind_by_name(const char *name);
int evo_control_kind_by_name(const char *name);

/* The unprefixed name ("ClosingOnTarget"); NULL for a kind out of range. */
const char *evo_reward_kind_name(int kind);
const char *evo_control_kind_name(int kind);

/* The worlds kind exists in (EVO_DIM_*); 0 for a kind out of range. */
unsigned evo_reward_kind_dims(int kind);
unsigned evo_control_kind_dims(int kind);

/* The name of the kind of dimension dim closest to word, for "did you
 * mean"; NULL when none is close. */
const char *evo_reward_kind_closest(const char *word, unsigned dim);
const char *evo_control_kind_closest(const char *word, unsigned dim);

#endif

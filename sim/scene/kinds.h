/* evo — the kinds of the one scene model (docs/architecture.md, "Where the
 * layout is going"): for each kind, the name users write and the worlds
 * it exists in. What is only 2D or only 3D is said here, in its row of
 * kinds.c, and nowhere else: a scene of the other dimension refuses the
 * kind by that row, with its name.
 *
 * The reward and control functions (EvoAgents' RW_ and CF_ classes,
 * tutorial sections 6.3 and 6.4), and what a scene script adds: the
 * scene's pieces (scene:NAME: elements, walls, the obstacle grid, an
 * episode's obstacle, the physics), a bot's sensors and its actuators
 * (bot:NAME). Each piece's row also lists the options it takes in each
 * world (sim/lua/ checks a script's tables by them). */
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

/* ---- what a scene script adds: scene:NAME{...} and bot:NAME{...} ------ */

/* The pieces scene:NAME adds: elements (the first ones, up to
 * EVO_PIECE_LAST_ELEMENT), and the scene's other parts. */
typedef enum evo_piece_kind {
	EVO_PIECE_CYLINDER = 0, /* a static cylinder (a circle in 2D) */
	EVO_PIECE_BOX,		/* a static box */
	EVO_PIECE_ZONE,		/* a trigger zone, no body */
	EVO_PIECE_OBJECT,	/* a dynamic object */
	EVO_PIECE_SPHERE,	/* a static sphere */
	EVO_PIECE_TARGET,	/* a point to reach, no body */
	EVO_PIECE_LAST_ELEMENT = EVO_PIECE_TARGET,
	EVO_PIECE_WALL,		/* a wall of no thickness */
	EVO_PIECE_GRID,		/* the tutorial's obstacle grid */
	EVO_PIECE_OBSTACLE,	/* a static obstacle of one episode */
	EVO_PIECE_PHYSICS,	/* the world's physics settings */
	EVO_PIECE_KIND_COUNT
} evo_piece_kind;

/* The sensors bot:NAME adds. */
typedef enum evo_sense_kind {
	EVO_SENSE_PROXIMITY = 0,
	EVO_SENSE_DISTANCE,
	EVO_SENSE_ZONE,
	EVO_SENSE_BEARING, /* also bot:azimuth */
	EVO_SENSE_PRESENCE,
	EVO_SENSE_OBJECT_DETECTOR,
	EVO_SENSE_MOVEMENT,
	EVO_SENSE_RANDOM,
	EVO_SENSE_CONSTANT,
	EVO_SENSE_HOLDING,
	EVO_SENSE_RADAR,
	EVO_SENSE_BUMPER,
	EVO_SENSE_LIGHT,
	EVO_SENSE_GROUND,
	EVO_SENSE_RAB,
	EVO_SENSE_CAMERA,
	EVO_SENSE_ELEVATION,
	EVO_SENSE_TARGET_SENSOR, /* the tutorial's TargetSensor:axis */
	EVO_SENSE_KIND_COUNT
} evo_sense_kind;

/* The actuators bot:NAME adds. */
typedef enum evo_act_kind {
	EVO_ACT_WHEEL = 0,
	EVO_ACT_CLAW,
	EVO_ACT_SPEED_WHEEL,
	EVO_ACT_DRIVE,
	EVO_ACT_BROADCAST,
	EVO_ACT_PROPELLER,
	EVO_ACT_KIND_COUNT
} evo_act_kind;

/* A row of the piece, sensor and actuator tables. */
typedef struct evo_kind_row {
	const char *name; /* scene:NAME or bot:NAME */
	unsigned dims;	  /* EVO_DIM_*: the worlds it exists in */
	/* the options it takes in 2D ([0]) and in 3D ([1]), NULL ended;
	 * NULL in a world it does not exist in */
	const char *const *keys[2];
} evo_kind_row;

/* The row of a kind; NULL for one out of range. */
const evo_kind_row *evo_piece_kind_row(int kind);
const evo_kind_row *evo_sense_kind_row(int kind);
const evo_kind_row *evo_act_kind_row(int kind);

/* The kind named name (a sensor's other names too: "azimuth" is the
 * bearing sensor), or -1. */
int evo_piece_kind_by_name(const char *name);
int evo_sense_kind_by_name(const char *name);
int evo_act_kind_by_name(const char *name);

/* The i-th other name of a sensor kind (its kind in *kind), NULL past
 * the last: the binding makes a method of each. */
const char *evo_sense_kind_alias(int i, int *kind);

/* The options of a row in dimension dim (EVO_DIM_2D or EVO_DIM_3D);
 * NULL when the kind is not of that world. */
const char *const *evo_kind_keys(const evo_kind_row *row, unsigned dim);

#endif

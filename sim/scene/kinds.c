/* The kinds of the scene model, their names and their worlds
 * (sim/scene/kinds.h): one row per kind. */
#include "scene/kinds.h"

#include <stddef.h>
#include <string.h>

#include "evo/formats.h"

/* A reward's or control's row: the tutorial's class name without RW_ /
 * CF_, and its worlds (it takes no options table of its own). */
typedef evo_kind_row kind_row;

static const kind_row reward_rows[EVO_RW_KIND_COUNT] = {
    [EVO_RW_CLOSING_ON_TARGET] = {"ClosingOnTarget", EVO_DIM_BOTH},
    [EVO_RW_SENSOR_OVER] = {"SensorOverThreshold", EVO_DIM_BOTH},
    [EVO_RW_SENSOR_UNDER] = {"SensorUnderThreshold", EVO_DIM_BOTH},
    [EVO_RW_PUNISH_ON_COLLISION] = {"PunishOnCollision", EVO_DIM_BOTH},
    [EVO_RW_FORWARD_MOTION] = {"ForwardMotion", EVO_DIM_BOTH},
    [EVO_RW_SPEED] = {"Speed", EVO_DIM_BOTH},
    [EVO_RW_STEP] = {"StepReward", EVO_DIM_BOTH},
    /* objects carried or gathered: 3D objects are not carried */
    [EVO_RW_COLLECT] = {"Collect", EVO_DIM_2D},
    [EVO_RW_FORWARD_SPEED] = {"ForwardSpeed", EVO_DIM_BOTH},
    [EVO_RW_GATHER] = {"Gather", EVO_DIM_2D},
    [EVO_RW_LUA] = {"Lua", EVO_DIM_BOTH},
    [EVO_RW_DISTANCE] = {"Distance", EVO_DIM_BOTH},
    [EVO_RW_FINAL_DISTANCE] = {"FinalDistance", EVO_DIM_BOTH},
    [EVO_RW_EFFORT] = {"Effort", EVO_DIM_BOTH},
};

static const kind_row control_rows[EVO_CF_KIND_COUNT] = {
    [EVO_CF_NEXT_ON_TIMEOUT] = {"NextOnTimeout", EVO_DIM_BOTH},
    [EVO_CF_NEXT_ON_COLLISION] = {"NextOnCollision", EVO_DIM_BOTH},
    [EVO_CF_NEXT_ON_COLLISION_AND_TIMEOUT] = {"NextOnCollisionAndTimeout",
					      EVO_DIM_BOTH},
    /* a contact with an element's body or obstacle */
    [EVO_CF_NEXT_ON_COLLISION_WITH_TARGET] = {"NextOnCollisionWithTarget",
					      EVO_DIM_BOTH},
    [EVO_CF_NEXT_ON_SENSOR_BELOW] = {"NextOnSensorBelowThreshold",
				     EVO_DIM_BOTH},
    [EVO_CF_LUA] = {"Lua", EVO_DIM_BOTH},
    [EVO_CF_NEXT_ON_TARGET_REACHED] = {"NextOnTargetReached", EVO_DIM_BOTH},
};

/* Shorter spellings also accepted (evo's own enum names, and 3D's
 * first ones). */
typedef struct kind_alias {
	const char *name;
	int kind;
} kind_alias;

static const kind_alias reward_aliases[] = {
    {"SensorOver", EVO_RW_SENSOR_OVER},
    {"SensorUnder", EVO_RW_SENSOR_UNDER},
    {"Step", EVO_RW_STEP},
    {NULL, 0},
};

static const kind_alias control_aliases[] = {
    {"NextOnSensorBelow", EVO_CF_NEXT_ON_SENSOR_BELOW},
    {NULL, 0},
};

static int row_by_name(const char *name, const evo_kind_row *rows, int n,
		       const kind_alias *aliases);

/* The kind of name (after an optional prefix) among rows[0..n) and the
 * aliases, or -1. */
static int by_name(const char *name, const char *prefix, const kind_row *rows,
		   int n, const kind_alias *aliases)
{
	size_t plen = strlen(prefix);
	if (name && strncmp(name, prefix, plen) == 0)
		name += plen;
	return row_by_name(name, rows, n, aliases);
}

/* The closest name among the rows of dimension dim. */
static const char *closest(const char *word, unsigned dim, const kind_row *rows,
			   int n)
{
	const char *names[EVO_RW_KIND_COUNT + EVO_CF_KIND_COUNT];
	size_t m = 0;
	for (int k = 0; k < n; k++)
		if (rows[k].dims & dim)
			names[m++] = rows[k].name;
	return evo_closest_name(word, names, m, NULL);
}

int evo_reward_kind_by_name(const char *name)
{
	return by_name(name, "RW_", reward_rows, EVO_RW_KIND_COUNT,
		       reward_aliases);
}

int evo_control_kind_by_name(const char *name)
{
	return by_name(name, "CF_", control_rows, EVO_CF_KIND_COUNT,
		       control_aliases);
}

const char *evo_reward_kind_name(int kind)
{
	return kind >= 0 && kind < EVO_RW_KIND_COUNT ? reward_rows[kind].name
						     : NULL;
}

const char *evo_control_kind_name(int kind)
{
	return kind >= 0 && kind < EVO_CF_KIND_COUNT ? control_rows[kind].name
						     : NULL;
}

unsigned evo_reward_kind_dims(int kind)
{
	return kind >= 0 && kind < EVO_RW_KIND_COUNT ? reward_rows[kind].dims
						     : 0;
}

unsigned evo_control_kind_dims(int kind)
{
	return kind >= 0 && kind < EVO_CF_KIND_COUNT ? control_rows[kind].dims
						     : 0;
}

const char *evo_reward_kind_closest(const char *word, unsigned dim)
{
	return closest(word, dim, reward_rows, EVO_RW_KIND_COUNT);
}

const char *evo_control_kind_closest(const char *word, unsigned dim)
{
	return closest(word, dim, control_rows, EVO_CF_KIND_COUNT);
}

/* ---- what a scene script adds (scene:NAME, bot:NAME) ------------------- */

/* Each piece's options, as docs/lua.md and docs/world3d.md list them:
 * what a 2D scene takes, then a 3D one. A kind only one world has has
 * NULL for the other's. */
#define K(...) ((const char *const[]){__VA_ARGS__, NULL})

static const evo_kind_row piece_rows[EVO_PIECE_KIND_COUNT] = {
    [EVO_PIECE_CYLINDER] = {"cylinder",
			    EVO_DIM_BOTH,
			    {K("x", "y", "radius", "name"),
			     K("name", "x", "y", "z", "radius", "height",
			       "friction", "ground")}},
    [EVO_PIECE_BOX] = {"box",
		       EVO_DIM_BOTH,
		       {K("x", "y", "half_width", "half_height", "angle",
			  "name"),
			K("name", "x", "y", "z", "yaw", "hx", "hy", "hz",
			  "friction", "ground")}},
    [EVO_PIECE_ZONE] = {"zone",
			EVO_DIM_BOTH,
			{K("x", "y", "size", "angle", "name"),
			 K("name", "x", "y", "z", "yaw", "hx", "hy", "hz")}},
    [EVO_PIECE_OBJECT] = {"object",
			  EVO_DIM_BOTH,
			  {K("x", "y", "radius", "name", "density", "friction",
			     "restitution", "linear_damping",
			     "angular_damping"),
			   K("name", "x", "y", "z", "yaw", "radius", "hx",
			     "hy", "hz", "mass", "friction")}},
    /* ODE's shapes: Box2D's world is flat */
    [EVO_PIECE_SPHERE] = {"sphere",
			  EVO_DIM_3D,
			  {NULL, K("name", "x", "y", "z", "radius", "friction",
				   "ground")}},
    [EVO_PIECE_TARGET] = {"target",
			  EVO_DIM_3D,
			  {NULL, K("name", "x", "y", "z", "radius")}},
    /* a segment, and the tutorial's grid: 2D's obstacles */
    [EVO_PIECE_WALL] = {"wall",
			EVO_DIM_2D,
			{K("x1", "y1", "x2", "y2"), NULL}},
    [EVO_PIECE_GRID] = {"grid",
			EVO_DIM_2D,
			{K("x0", "y0", "x1", "y1", "spacing", "jitter",
			   "min_size", "size_variability", "shapes",
			   "clearance"),
			 NULL}},
    /* 2D's episode obstacles come from env.obstacles */
    [EVO_PIECE_OBSTACLE] = {"obstacle",
			    EVO_DIM_3D,
			    {NULL, K("shape", "x", "y", "z", "yaw", "hx", "hy",
				     "hz", "radius", "height", "friction",
				     "ground")}},
    /* ODE's settings (Box2D's are fixed: docs/world.md) */
    [EVO_PIECE_PHYSICS] = {"physics",
			   EVO_DIM_3D,
			   {NULL, K("substeps", "step", "gravity", "erp",
				    "cfm", "max_speed", "max_spin",
				    "fault_penalty", "ground_friction")}},
};

/* The options a target-tracking sensor takes. */
#define TRACKER2 K("name", "target")
#define TRACKER3 K("name", "x", "y", "z", "target")
#define SWARM_RAB K("name", "range", "slot", "read", "index", "occluded", \
		    "scale")
#define SWARM_CAMERA K("name", "range", "slot", "read", "colour", \
		       "occluded", "scale")

static const evo_kind_row sense_rows[EVO_SENSE_KIND_COUNT] = {
    [EVO_SENSE_PROXIMITY] = {"proximity",
			     EVO_DIM_BOTH,
			     {K("name", "x", "y", "angle", "range", "arc",
				"rays", "deadzone", "sees"),
			      K("name", "x", "y", "z", "yaw", "pitch", "range",
				"arc", "rays", "sees")}},
    [EVO_SENSE_DISTANCE] = {"distance",
			    EVO_DIM_BOTH,
			    {K("name", "x", "y", "target", "scale"),
			     K("name", "x", "y", "z", "target", "scale")}},
    [EVO_SENSE_ZONE] = {"zone", EVO_DIM_BOTH, {TRACKER2, TRACKER2}},
    [EVO_SENSE_BEARING] = {"bearing", EVO_DIM_BOTH, {TRACKER2, TRACKER3}},
    /* an element switched off (element:set_active) */
    [EVO_SENSE_PRESENCE] = {"presence", EVO_DIM_BOTH, {TRACKER2, TRACKER2}},
    /* objects carried by a claw, and Box2D's contacts and broad phase */
    [EVO_SENSE_OBJECT_DETECTOR] = {"object_detector",
				   EVO_DIM_2D,
				   {K("name", "x", "y", "angle", "reach",
				      "arc"),
				    NULL}},
    [EVO_SENSE_MOVEMENT] = {"movement",
			    EVO_DIM_BOTH,
			    {K("name", "scale"), K("name", "scale")}},
    [EVO_SENSE_RANDOM] = {"random", EVO_DIM_BOTH, {K("name"), K("name")}},
    [EVO_SENSE_CONSTANT] = {"constant",
			    EVO_DIM_BOTH,
			    {K("name", "value"), K("name", "value")}},
    [EVO_SENSE_HOLDING] = {"holding", EVO_DIM_2D, {K("name"), NULL}},
    [EVO_SENSE_RADAR] = {"radar",
			 EVO_DIM_BOTH,
			 {K("name", "target", "angle", "arc"),
			  K("name", "target", "yaw", "arc")}},
    [EVO_SENSE_BUMPER] = {"bumper",
			  EVO_DIM_2D,
			  {K("name", "angle", "arc", "reach", "sees"), NULL}},
    [EVO_SENSE_LIGHT] = {"light",
			 EVO_DIM_BOTH,
			 {K("name", "x", "y", "angle", "aperture"),
			  K("name", "x", "y", "z", "yaw", "aperture")}},
    [EVO_SENSE_GROUND] = {"ground",
			  EVO_DIM_BOTH,
			  {K("name", "x", "y"), K("name", "x", "y", "z")}},
    [EVO_SENSE_RAB] = {"rab", EVO_DIM_BOTH, {SWARM_RAB, SWARM_RAB}},
    [EVO_SENSE_CAMERA] = {"camera",
			  EVO_DIM_BOTH,
			  {SWARM_CAMERA, SWARM_CAMERA}},
    /* up or down to a target: a flat world has neither */
    [EVO_SENSE_ELEVATION] = {"elevation", EVO_DIM_3D, {NULL, TRACKER3}},
    [EVO_SENSE_TARGET_SENSOR] = {"target_sensor",
				 EVO_DIM_3D,
				 {NULL, K("name", "x", "y", "z", "target",
					  "axis")}},
};

static const evo_kind_row act_rows[EVO_ACT_KIND_COUNT] = {
    /* a force at a point in 2D; a wheel on a hinge in 3D */
    [EVO_ACT_WHEEL] = {"wheel",
		       EVO_DIM_BOTH,
		       {K("name", "x", "y", "angle", "max_force"),
			K("name", "x", "y", "z", "radius", "width", "mass",
			  "friction", "mode", "max_rate", "max_torque")}},
    /* Box2D's welds: 3D objects are not carried */
    [EVO_ACT_CLAW] = {"claw",
		      EVO_DIM_2D,
		      {K("name", "x", "y", "angle", "reach"), NULL}},
    /* the mazes' robots, which set their speed (docs/world.md) */
    [EVO_ACT_SPEED_WHEEL] = {"speed_wheel",
			     EVO_DIM_2D,
			     {K("name", "x", "y", "max_speed"), NULL}},
    [EVO_ACT_DRIVE] = {"drive",
		       EVO_DIM_2D,
		       {K("name", "turn", "max_speed", "accel"), NULL}},
    [EVO_ACT_BROADCAST] = {"broadcast", EVO_DIM_BOTH, {K("name"), K("name")}},
    /* thrust along an axis: the blimps and boats of 3D */
    [EVO_ACT_PROPELLER] = {"propeller",
			   EVO_DIM_3D,
			   {NULL, K("name", "x", "y", "z", "axis",
				    "max_thrust")}},
};

static const kind_alias sense_aliases[] = {
    {"azimuth", EVO_SENSE_BEARING}, /* 3D's first name of it */
    {NULL, 0},
};
static const kind_alias no_aliases[] = {{NULL, 0}};

static int row_by_name(const char *name, const evo_kind_row *rows, int n,
		       const kind_alias *aliases)
{
	if (!name)
		return -1;
	for (int k = 0; k < n; k++)
		if (strcmp(name, rows[k].name) == 0)
			return k;
	for (const kind_alias *a = aliases; a->name; a++)
		if (strcmp(name, a->name) == 0)
			return a->kind;
	return -1;
}

const evo_kind_row *evo_piece_kind_row(int kind)
{
	return kind >= 0 && kind < EVO_PIECE_KIND_COUNT ? &piece_rows[kind]
							: NULL;
}

const evo_kind_row *evo_sense_kind_row(int kind)
{
	return kind >= 0 && kind < EVO_SENSE_KIND_COUNT ? &sense_rows[kind]
							: NULL;
}

const evo_kind_row *evo_act_kind_row(int kind)
{
	return kind >= 0 && kind < EVO_ACT_KIND_COUNT ? &act_rows[kind] : NULL;
}

int evo_piece_kind_by_name(const char *name)
{
	return row_by_name(name, piece_rows, EVO_PIECE_KIND_COUNT, no_aliases);
}

int evo_sense_kind_by_name(const char *name)
{
	return row_by_name(name, sense_rows, EVO_SENSE_KIND_COUNT,
			   sense_aliases);
}

int evo_act_kind_by_name(const char *name)
{
	return row_by_name(name, act_rows, EVO_ACT_KIND_COUNT, no_aliases);
}

const char *evo_sense_kind_alias(int i, int *kind)
{
	if (i < 0 || i >= (int)(sizeof sense_aliases / sizeof *sense_aliases) ||
	    !sense_aliases[i].name)
		return NULL;
	*kind = sense_aliases[i].kind;
	return sense_aliases[i].name;
}

const char *const *evo_kind_keys(const evo_kind_row *row, unsigned dim)
{
	if (!row || !(row->dims & dim))
		return NULL;
	return row->keys[dim == EVO_DIM_3D];
}

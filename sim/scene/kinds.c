/* The kinds of the scene model, their names and their worlds
 * (sim/scene/kinds.h): one row per kind. */
#include "scene/kinds.h"

#include <stddef.h>
#include <string.h>

#include "evo/formats.h"

typedef struct kind_row {
	const char *name; /* the tutorial's class name without RW_ / CF_ */
	unsigned dims;	  /* EVO_DIM_* */
} kind_row;

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
    /* a contact with an element's body or obstacle: the 3D scene does
     * not keep which obstacle an element is */
    [EVO_CF_NEXT_ON_COLLISION_WITH_TARGET] = {"NextOnCollisionWithTarget",
					      EVO_DIM_2D},
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

/* The kind of name (after an optional prefix) among rows[0..n) and the
 * aliases, or -1. */
static int by_name(const char *name, const char *prefix, const kind_row *rows,
		   int n, const kind_alias *aliases)
{
	if (!name)
		return -1;
	size_t plen = strlen(prefix);
	if (strncmp(name, prefix, plen) == 0)
		name += plen;
	for (int k = 0; k < n; k++)
		if (strcmp(name, rows[k].name) == 0)
			return k;
	for (const kind_alias *a = aliases; a->name; a++)
		if (strcmp(name, a->name) == 0)
			return a->kind;
	return -1;
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

/* The 2D scene as the scene model (sim/scene/core.h) asks of it: its
 * evo_scene_dim, with the checks of rewards and controls only 2D makes
 * (a target may be the nearest object, opponent or teammate; Collect
 * needs a zone), whom a bot's reward is paid to, and the tick's parts
 * (sensors.c, and step.c's act and read-back), which sim/scene/tick.c
 * runs in their order. */
#include "world2d/scene.h"
#include "world2d/scene_internal.h"
#include "world2d/sensors.h"

/* ---- the checks at adding ------------------------------------------------ */

static int n_sensors(const evo_scene_core *c, int bot)
{
	return ((const evo_scene *)c)->bot[bot].n_sensors;
}

/* A 2D target is an element, none, or the nearest object, opponent or
 * teammate. */
static int target_ok(evo_scene_core *c, int target, const char *what)
{
	return evo_scene_check_target((evo_scene *)c, target, what);
}

static int zone(const evo_scene *sc, int target)
{
	return target >= 0 && sc->element[target].kind == EVO_ELEM_ZONE;
}

static int check_reward(evo_scene_core *c, const evo_reward_def *d)
{
	if (d->kind == EVO_RW_COLLECT && !zone((evo_scene *)c, d->target))
		return evo_fail(&c->err, "reward Collect needs a zone");
	return 0;
}

static int check_control(evo_scene_core *c, const evo_control_def *d)
{
	if (d->kind == EVO_CF_NEXT_ON_COLLISION_WITH_TARGET &&
	    (d->target < 0 || zone((evo_scene *)c, d->target)))
		return evo_fail(&c->err, "control NextOnCollisionWithTarget "
					 "needs a solid element");
	return 0;
}

static double *bot_account(evo_scene_core *c, int bot, int *team)
{
	evo_bot *b = &((evo_scene *)c)->bot[bot];
	*team = b->team;
	return &b->reward;
}

/* ---- the tick ------------------------------------------------------------ */

static void sense(evo_scene_core *c)
{
	evo_sense_all((evo_scene *)c);
}

static void act(evo_scene_core *c)
{
	evo_scene_act((evo_scene *)c);
}

static void read_back(evo_scene_core *c)
{
	evo_scene_read_back((evo_scene *)c);
}

/* ---- the table ----------------------------------------------------------- */

const evo_scene_dim evo_scene_dim_2d = {
    .name = "2D",
    .dims = EVO_DIM_2D,
    .score = &evo_score_ops_2d,
    .n_sensors = n_sensors,
    .check_target = target_ok,
    .check_reward = check_reward,
    .check_control = check_control,
    .bot_account = bot_account,
    .sense = sense,
    .act = act,
    .read_back = read_back,
};

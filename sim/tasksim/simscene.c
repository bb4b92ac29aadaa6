/* The two sides of a task's scene interface (sim/tasksim/simscene.h): the
 * 2D scene's and the 3D scene's. Each function only reads or calls its
 * scene; what differs between the worlds is here and nowhere in
 * tasksim.c. */
#include "tasksim/simscene.h"

#include <math.h>

#include "world2d/scene.h"
#include "world3d/scene3d.h"

/* Widen b (x0, y0, x1, y1) to hold the box of half sizes hx, hy at x, y. */
static void widen(double *b, double x, double y, double hx, double hy)
{
	b[0] = fmin(b[0], x - hx);
	b[1] = fmin(b[1], y - hy);
	b[2] = fmax(b[2], x + hx);
	b[3] = fmax(b[3], y + hy);
}

/* What both scenes have in the same fields (a bot's name, sensors and
 * actuators, the tick, the rewards, the collisions): one body for both
 * types, written once until the two scenes are one (docs/architecture.md,
 * step 3). */
#define EVO_SIMSCENE_COMMON(SFX, SCENE, BOT)                                   \
	static int n_bots_##SFX(const void *sc)                                \
	{                                                                      \
		return ((const SCENE *)sc)->n_bots;                            \
	}                                                                      \
	static const char *bot_name_##SFX(const void *sc, int bot)             \
	{                                                                      \
		return ((const SCENE *)sc)->bot[bot].name;                     \
	}                                                                      \
	static int n_parts_##SFX(const void *sc, int bot, int sensors)         \
	{                                                                      \
		const BOT *b = &((const SCENE *)sc)->bot[bot];                 \
		return sensors ? b->n_sensors : b->n_actuators;                \
	}                                                                      \
	static const char *part_name_##SFX(const void *sc, int bot,            \
					   int sensors, int i)                 \
	{                                                                      \
		const BOT *b = &((const SCENE *)sc)->bot[bot];                 \
		return sensors ? b->sensor[i].name : b->actuator[i].name;      \
	}                                                                      \
	static void read_##SFX(const void *sc, int bot, const int *map,        \
			       unsigned n, double *values)                     \
	{                                                                      \
		const BOT *b = &((const SCENE *)sc)->bot[bot];                 \
		for (unsigned i = 0; i < n; i++)                               \
			values[i] = b->sensor[map[i]].value;                   \
	}                                                                      \
	static void write_##SFX(void *sc, int bot, const int *map, unsigned n, \
				const double *commands)                        \
	{                                                                      \
		BOT *b = &((SCENE *)sc)->bot[bot];                             \
		for (unsigned i = 0; i < n; i++)                               \
			b->actuator[map[i]].command = commands[i];             \
	}                                                                      \
	static long ticks_##SFX(const void *sc)                                \
	{                                                                      \
		return ((const SCENE *)sc)->tick;                              \
	}                                                                      \
	static double episode_reward_##SFX(const void *sc)                     \
	{                                                                      \
		return ((const SCENE *)sc)->episode_reward;                    \
	}                                                                      \
	static int collisions_##SFX(const void *sc, int bot)                   \
	{                                                                      \
		return ((const SCENE *)sc)->bot[bot].collisions;               \
	}                                                                      \
	static double bot_reward_##SFX(const void *sc, int bot)                \
	{                                                                      \
		return ((const SCENE *)sc)->bot[bot].reward;                   \
	}                                                                      \
	static double team_reward_##SFX(const void *sc, int team)              \
	{                                                                      \
		return ((const SCENE *)sc)->team_reward[team];                 \
	}                                                                      \
	static int winner_##SFX(const void *sc)                                \
	{                                                                      \
		return ((const SCENE *)sc)->winner;                            \
	}

EVO_SIMSCENE_COMMON(2d, evo_scene, evo_bot)
EVO_SIMSCENE_COMMON(3d, evo_scene3d, evo_bot3d)

/* ---- the 2D scene ------------------------------------------------------- */

static int reset_2d(void *sc, uint64_t grid_seed, uint64_t episode_seed,
		    evo_err *err)
{
	(void)err;
	evo_scene_reset(sc, grid_seed, episode_seed);
	return 0;
}

static void sense_2d(void *sc)
{
	evo_scene_sense((evo_scene *)sc);
}

static int step_2d(void *v, evo_err *err)
{
	evo_scene *sc = v;
	int r = evo_scene_step(sc);
	if (r < 0)
		evo_fail(err, "%s", sc->err.msg);
	return r;
}

static int bot_team_2d(const void *sc, int bot)
{
	return ((const evo_scene *)sc)->bot[bot].team;
}

static int find_part_2d(const void *sc, int bot, int sensors, const char *name)
{
	const evo_bot *b = &((const evo_scene *)sc)->bot[bot];
	return sensors ? evo_bot_find_sensor(b, name)
		       : evo_bot_find_actuator(b, name);
}

static void set_idle_2d(void *sc, int bot, int sensor, int idle)
{
	((evo_scene *)sc)->bot[bot].sensor[sensor].idle = idle;
}

static void wake_scored_2d(void *v)
{
	evo_scene *sc = v;
	for (int i = 0; i < sc->n_rewards; i++) {
		const evo_reward_def *d = &sc->reward[i].def;
		for (int k = 0; k < d->n_sensors; k++)
			sc->bot[d->bot].sensor[d->sensor[k]].idle = 0;
	}
	for (int i = 0; i < sc->n_controls; i++) {
		const evo_control_def *d = &sc->control[i].def;
		if (d->sensor >= 0)
			sc->bot[d->bot].sensor[d->sensor].idle = 0;
	}
}

static int n_metrics_2d(const void *sc)
{
	return ((const evo_scene *)sc)->n_metrics;
}

static const char *metric_name_2d(const void *sc, int k)
{
	return ((const evo_scene *)sc)->metric[k].name;
}

static double metric_2d(const void *sc, int k)
{
	return ((const evo_scene *)sc)->metric[k].value;
}

static const char *fault_2d(const void *sc)
{
	(void)sc;
	return "";
}

static void ground_pos_2d(const void *sc, int bot, double now[2],
			  double start[2])
{
	const evo_bot *b = &((const evo_scene *)sc)->bot[bot];
	now[0] = b->x, now[1] = b->y;
	start[0] = b->def.x, start[1] = b->def.y;
}

/* The elements' and walls' obstacles and the obstacle grid's area. */
static void arena_2d(const void *v, double *b)
{
	const evo_scene *sc = v;
	for (int i = 0; i < sc->n_fixed_obstacles; i++) {
		const evo_obstacle *o = &sc->obstacle[i];
		double c = fabs(cos(o->angle)), sn = fabs(sin(o->angle));
		if (o->shape == EVO_SHAPE_CIRCLE) {
			widen(b, o->x, o->y, o->radius, o->radius);
		} else if (o->shape == EVO_SHAPE_SEGMENT) {
			/* a wall: (x, y) is one end, not its middle */
			widen(b, o->x, o->y, 0, 0);
			widen(b, o->x2, o->y2, 0, 0);
		} else
			widen(b, o->x, o->y, c * o->half_w + sn * o->half_h,
			      sn * o->half_w + c * o->half_h);
	}
	if (sc->grid.enabled) {
		const evo_grid_def *g = &sc->grid;
		widen(b, (g->x0 + g->x1) / 2, (g->y0 + g->y1) / 2,
		      fabs(g->x1 - g->x0) / 2, fabs(g->y1 - g->y0) / 2);
	}
}

/* ---- the 3D scene ------------------------------------------------------- */

static int reset_3d(void *v, uint64_t grid_seed, uint64_t episode_seed,
		    evo_err *err)
{
	evo_scene3d *sc = v;
	if (evo_scene3d_reset(sc, grid_seed, episode_seed))
		return evo_fail(err, "%s", sc->err.msg);
	return 0;
}

static void sense_3d(void *sc)
{
	evo_scene3d_sense(sc);
}

/* A fault ends the episode; a hook that fails fails the step. */
static int step_3d(void *v, evo_err *err)
{
	evo_scene3d *sc = v;
	int r = evo_scene3d_step(sc);
	if (r < 0)
		evo_fail(err, "%s", sc->err.msg);
	return r;
}

static int bot_team_3d(const void *sc, int bot)
{
	return ((const evo_scene3d *)sc)->bot[bot].def.team;
}

static int find_part_3d(const void *sc, int bot, int sensors, const char *name)
{
	const evo_bot3d *b = &((const evo_scene3d *)sc)->bot[bot];
	return sensors ? evo_bot3d_find_sensor(b, name)
		       : evo_bot3d_find_actuator(b, name);
}

/* A 3D scene samples every sensor every tick: nothing is idle. */
static void set_idle_3d(void *sc, int bot, int sensor, int idle)
{
	(void)sc, (void)bot, (void)sensor, (void)idle;
}

static void wake_scored_3d(void *sc)
{
	(void)sc;
}

static int n_metrics_3d(const void *sc)
{
	return ((const evo_scene3d *)sc)->n_metrics;
}

static const char *metric_name_3d(const void *sc, int k)
{
	return ((const evo_scene3d *)sc)->metric[k].name;
}

static double metric_3d(const void *sc, int k)
{
	return ((const evo_scene3d *)sc)->metric[k].value;
}

static const char *fault_3d(const void *sc)
{
	return ((const evo_scene3d *)sc)->fault;
}

static void ground_pos_3d(const void *sc, int bot, double now[2],
			  double start[2])
{
	const evo_bot3d *b = &((const evo_scene3d *)sc)->bot[bot];
	now[0] = b->pos[0], now[1] = b->pos[1];
	start[0] = b->start[0], start[1] = b->start[1];
}

/* The static boxes, cylinders and spheres that are not ground. */
static void arena_3d(const void *v, double *b)
{
	const evo_scene3d *sc = v;
	for (int i = 0; i < sc->n_elements; i++) {
		const evo_element3d_def *d = &sc->element[i].def;
		if (d->kind > EVO3D_ELEM_SPHERE || d->ground)
			continue;
		double c = fabs(cos(d->yaw)), sn = fabs(sin(d->yaw));
		if (d->kind == EVO3D_ELEM_BOX)
			widen(b, d->pos[0], d->pos[1],
			      c * d->half[0] + sn * d->half[1],
			      sn * d->half[0] + c * d->half[1]);
		else
			widen(b, d->pos[0], d->pos[1], d->radius, d->radius);
	}
}

/* ---- the two interfaces ------------------------------------------------- */

#define EVO_SIMSCENE(SFX, NAME, TEAMS)                                         \
	const evo_simscene evo_simscene_##SFX = {                              \
	    .name = NAME,                                                      \
	    .teams = TEAMS,                                                    \
	    .reset = reset_##SFX,                                              \
	    .sense = sense_##SFX,                                              \
	    .step = step_##SFX,                                                \
	    .n_bots = n_bots_##SFX,                                            \
	    .bot_name = bot_name_##SFX,                                        \
	    .bot_team = bot_team_##SFX,                                        \
	    .n_parts = n_parts_##SFX,                                          \
	    .part_name = part_name_##SFX,                                      \
	    .find_part = find_part_##SFX,                                      \
	    .read = read_##SFX,                                                \
	    .write = write_##SFX,                                              \
	    .set_idle = set_idle_##SFX,                                        \
	    .wake_scored = wake_scored_##SFX,                                  \
	    .ticks = ticks_##SFX,                                              \
	    .episode_reward = episode_reward_##SFX,                            \
	    .collisions = collisions_##SFX,                                    \
	    .bot_reward = bot_reward_##SFX,                                    \
	    .team_reward = team_reward_##SFX,                                  \
	    .winner = winner_##SFX,                                            \
	    .n_metrics = n_metrics_##SFX,                                      \
	    .metric_name = metric_name_##SFX,                                  \
	    .metric = metric_##SFX,                                            \
	    .fault = fault_##SFX,                                              \
	    .ground_pos = ground_pos_##SFX,                                    \
	    .arena = arena_##SFX,                                              \
	}

EVO_SIMSCENE(2d, "2D", 1);
EVO_SIMSCENE(3d, "3D", 1);

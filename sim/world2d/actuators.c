/* evo — the actuators of a bot (sim/world2d/scene.h): wheels push, claws grab and
 * let go. evo_scene_step calls evo_actuator_act on each one before the
 * physics steps; a command is in [0, 1] and 0.5 is neutral. */
#include "world2d/actuators.h"

#include <assert.h>
#include <math.h>

#include "world2d/query.h"

/* The claw takes what lies within ±45 degrees of its direction. */
#define CLAW_ARC (M_PI / 4)

/* Force (2c - 1) * max_force along the bot's heading turned by the
 * wheel's angle, at the wheel's point. A command that is not a number
 * pushes with no force rather than full reverse. */
static void wheel(evo_scene *sc, const evo_bot *b, const evo_actuator *a)
{
	double c = a->command;
	c = isnan(c) ? 0.5 : c < 0 ? 0 : c > 1 ? 1 : c;
	double f = (2 * c - 1) * a->def.max_force;
	if (f == 0)
		return;
	double wx = b->x + b->c * a->def.x - b->s * a->def.y;
	double wy = b->y + b->s * a->def.x + b->c * a->def.y;
	/* the heading turned by the wheel's angle */
	double ux = b->c * a->dir_c - b->s * a->dir_s;
	double uy = b->s * a->dir_c + b->c * a->dir_s;
	evo_body_apply_force(sc->world, b->body, f * ux, f * uy, wx, wy);
}

static void claw_grab(evo_scene *sc, int bot, evo_actuator *a)
{
	evo_bot *b = &sc->bot[bot];
	double px = b->x + b->c * a->def.x - b->s * a->def.y;
	double py = b->y + b->s * a->def.x + b->c * a->def.y;
	double ux = b->c * a->dir_c - b->s * a->dir_s;
	double uy = b->s * a->dir_c + b->c * a->dir_s;
	int k = evo_scene_object_in_reach(sc, px, py, ux, uy, a->def.reach,
				CLAW_ARC);
	if (k < 0)
		return;
	evo_element *e = &sc->element[k];
	int joint = evo_world_weld(sc->world, b->body, e->body);
	if (joint < 0)
		return;
	a->held = k;
	a->joint = joint;
	e->held_by = bot;
}

static void claw_open(evo_scene *sc, evo_actuator *a)
{
	if (a->held < 0)
		return;
	evo_world_unweld(sc->world, a->joint);
	if (a->held < sc->n_elements)
		sc->element[a->held].held_by = -1;
	a->held = -1;
	a->joint = -1;
}

void evo_actuator_act(evo_scene *sc, int bot, int actuator)
{
	assert(bot >= 0 && bot < sc->n_bots);
	evo_bot *b = &sc->bot[bot];
	assert(actuator >= 0 && actuator < b->n_actuators);
	evo_actuator *a = &b->actuator[actuator];
	switch (a->def.kind) {
	case EVO_ACTUATOR_WHEEL:
		wheel(sc, b, a);
		break;
	case EVO_ACTUATOR_CLAW:
		/* Edges, not levels: a claw held shut does not keep
		 * grabbing, and one that was opened from outside (a
		 * delivery) waits for the next closing. */
		if (a->previous <= 0.5 && a->command > 0.5 && a->held < 0)
			claw_grab(sc, bot, a);
		else if (a->previous >= 0.5 && a->command < 0.5)
			claw_open(sc, a);
		break;
	case EVO_ACTUATOR_KIND_COUNT:
		break;
	}
	a->previous = a->command;
}

void evo_bot_release(evo_scene *sc, int bot)
{
	assert(bot >= 0 && bot < sc->n_bots);
	evo_bot *b = &sc->bot[bot];
	for (int i = 0; i < b->n_actuators; i++)
		if (b->actuator[i].def.kind == EVO_ACTUATOR_CLAW)
			claw_open(sc, &b->actuator[i]);
}

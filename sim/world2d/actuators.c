/* evo — the actuators of a bot (sim/world2d/scene.h): wheels push, claws grab
 * and let go. evo_scene_step calls evo_actuator_act on each one before the
 * physics steps; a command is in [0, 1] and 0.5 is neutral. */
#include "world2d/actuators.h"

#include <assert.h>
#include <math.h>

#include "world2d/query.h"
#include "world2d/scene_internal.h"

/* The claw takes what lies within ±45 degrees of its direction. */
#define CLAW_ARC (M_PI / 4)

/* Force (2c - 1) * max_force along the bot's heading turned by the
 * wheel's angle, at the wheel's point. A command that is not a number
 * pushes with no force rather than full reverse. */
static void wheel(evo_scene *sc, const evo_bot *b, const evo_actuator *a)
{
	double f = (2 * evo_command01(a->command) - 1) * a->def.max_force;
	if (f == 0)
		return;
	double wx = b->x + b->c * a->def.x - b->s * a->def.y;
	double wy = b->y + b->s * a->def.x + b->c * a->def.y;
	/* the heading turned by the wheel's angle */
	double ux = b->c * a->dir_c - b->s * a->dir_s;
	double uy = b->s * a->dir_c + b->c * a->dir_s;
	sc->be->apply_force_at(sc->bw, b->body,
			       (const double[3]){f * ux, f * uy, 0},
			       (const double[3]){wx, wy, 0}, 0);
}

/* A speed wheel's or drive's speed for this step (a->speed). */
static void set_speed(evo_actuator *a)
{
	double u = 2 * evo_command01(a->command) - 1;
	const evo_actuator_def *d = &a->def;
	if (d->kind == EVO_ACT_SPEED_WHEEL || d->accel <= 0) {
		a->speed = u * d->max_speed;
		return;
	}
	double v = a->speed + u * d->accel;
	a->speed = v > d->max_speed    ? d->max_speed
		   : v < -d->max_speed ? -d->max_speed
				       : v;
}

void evo_bot_drive(evo_scene *sc, int bot)
{
	assert(bot >= 0 && bot < sc->n_bots);
	evo_bot *b = &sc->bot[bot];
	/* Forward speed v and turn rate w: the drives' own, plus what fits
	 * the speed wheels best (least squares of v - w y = speed over the
	 * wheels at their sides y; for two at -h and +h, v is their mean
	 * and w = (left - right) / 2h). */
	double v = 0, w = 0, sum_s = 0, sum_ys = 0, sum_yy = 0;
	int wheels = 0, driven = 0;
	for (int i = 0; i < b->n_actuators; i++) {
		const evo_actuator *a = &b->actuator[i];
		if (a->def.kind == EVO_ACT_DRIVE) {
			driven = 1;
			if (a->def.turn)
				w += a->speed;
			else
				v += a->speed;
		} else if (a->def.kind == EVO_ACT_SPEED_WHEEL) {
			wheels++;
			sum_s += a->speed;
			sum_ys += a->def.y * a->speed;
			sum_yy += a->def.y * a->def.y;
		}
	}
	if (!driven && !wheels)
		return;
	if (wheels) {
		v += sum_s / wheels;
		if (sum_yy > 0)
			w -= sum_ys / sum_yy;
	}
	sc->be->set_velocity(sc->bw, b->body,
			     (const double[3]){v * b->c, v * b->s, 0},
			     (const double[3]){0, 0, w});
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
	int joint = sc->be->weld(sc->bw, b->body, e->body);
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
	sc->be->unweld(sc->bw, a->joint);
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
	case EVO_ACT_WHEEL:
		wheel(sc, b, a);
		break;
	case EVO_ACT_CLAW:
		/* Edges, not levels: a claw held shut does not keep
		 * grabbing, and one that was opened from outside (a
		 * delivery) waits for the next closing. */
		if (a->previous <= 0.5 && a->command > 0.5 && a->held < 0)
			claw_grab(sc, bot, a);
		else if (a->previous >= 0.5 && a->command < 0.5)
			claw_open(sc, a);
		break;
	case EVO_ACT_SPEED_WHEEL:
	case EVO_ACT_DRIVE:
		set_speed(a); /* evo_bot_drive sets the velocity */
		break;
	case EVO_ACT_BROADCAST: /* heard through its command */
	case EVO_ACT_PROPELLER: /* 3D only: refused when added */
	case EVO_ACT_KIND_COUNT:
		break;
	}
	a->previous = a->command;
}

void evo_bot_release(evo_scene *sc, int bot)
{
	assert(bot >= 0 && bot < sc->n_bots);
	evo_bot *b = &sc->bot[bot];
	for (int i = 0; i < b->n_actuators; i++)
		if (b->actuator[i].def.kind == EVO_ACT_CLAW)
			claw_open(sc, &b->actuator[i]);
}
